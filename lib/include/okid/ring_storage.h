/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file ring_storage.h
 * \brief NOT API: the ring of the last vectors that an identifier keeps (the pipeline's sample
 *        window and the instruments' past inputs), for okid/identifier_storage.h and the stages.
 */
#ifndef OKID_RING_STORAGE_H
#define OKID_RING_STORAGE_H

#include "okid/types.h"

/* A ring of the last `depth` vectors of `width` values: the sample window (r + m, p) and the
   instruments' past inputs (r, L; depth 0 without instruments). */
typedef struct okid_ring_ {
    okid_real *data;   /* width x depth, in the workspace */
    int width, depth;
    int head;          /* slot of the newest vector */
    int fill;          /* vectors held, up to depth */
} okid_ring_;

#endif

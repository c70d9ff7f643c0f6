/* SPDX-License-Identifier: Apache-2.0 */
/* Modal analysis on workspace views, shared by okid_modal_analysis() and the identifier. */
#ifndef OKID_MODAL_INTERNAL_H
#define OKID_MODAL_INTERNAL_H

#include "okid/modal.h"

/* Scratch of one modal analysis of an n-state model (see OKID__PHASE_MODAL_BYTES). */
typedef struct okid_modal_scratch {
    okid_real *a_copy; /* n x n */
    okid_real *vr;     /* n x n */
    okid_real *wr, *wi;/* n */
    okid_real *work;   /* OKID__LWORK_GEEV(n) */
} okid_modal_scratch;

/*
 * Arguments are trusted (checked by the callers). shapes holds n * 3m complex values: the
 * sensor shape (m) and the eq. 64 shape (2m) of each mode, which the modes point into.
 */
okid_status okid_modal_compute(int n, int m, const okid_real *a, int lda, const okid_real *c, int ldc,
                               okid_real dt, okid_sensing sensing, const okid_modal_scratch *scratch,
                               okid_complex *shapes, okid_mode *modes, int *num_modes, unsigned *warnings);

/* Unit 2-norm, largest-modulus component real and positive: the canonical representative of a shape. */
void okid_normalise_shape(okid_complex *v, int len);

#endif

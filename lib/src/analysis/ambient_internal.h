/* SPDX-License-Identifier: Apache-2.0 */
/* What okid_ambient's other files (ambient_stabilization.c) read of its workspace. */
#ifndef OKID_AMBIENT_INTERNAL_H
#define OKID_AMBIENT_INTERNAL_H

#include "okid/ambient.h"
#include "pipeline/era.h"

#define OKID_AMBIENT_MAGIC_ 0x6f6b616du /* "okam": an initialised okid_ambient */

/* The ERA scratch of amb's workspace (Hankel, column scales, SVD work); t and vt are left NULL
   (V' is sized for amb's order: a table of higher orders brings its own). */
void okid_ambient_era_scratch_(const okid_ambient *amb, okid_era_scratch *era);

/*
 * ERA's channel scales of everything pushed: each reference's RMS, then each output's (1 for a
 * zero channel); scales holds nref + m values. OKID_E_DATA_RANGE for an RMS out of range.
 */
okid_status okid_ambient_scales_(const okid_ambient *amb, okid_real *scales);

#endif

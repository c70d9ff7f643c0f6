/* SPDX-License-Identifier: Apache-2.0 */
/* Configuration checks, derived sizes and the workspace layout of an identifier. */
#ifndef OKID_WORKSPACE_LAYOUT_H
#define OKID_WORKSPACE_LAYOUT_H

#include <stdint.h>

#include "okid/identifier.h"
#include "pipeline/era.h"

/* Check cfg and derive the sizes. OKID_OK or the specific configuration error; issue (may be
   NULL) then names the field, its value and its valid range. */
okid_status okid_layout_dims(const okid_config *cfg, okid_dims_ *dims, okid_config_issue *issue);

/*
 * Lay the workspace out for dims (views into base) and return the bytes used, counted in 64 bits.
 * With base NULL it only computes the size: this one function is the definition of
 * okid_workspace_size(). combined and scaled: OKID_REALIZATION_COMBINED and OKID_SCALING_AUTO.
 * Call it with a base only after okid_layout_size() accepted the size.
 */
uint64_t okid_layout_carve(const okid_dims_ *dims, int combined, int scaled, unsigned char *base, okid_views_ *views);

/* The workspace bytes of dims as a size_t: OKID_OK, or OKID_E_BAD_SIZE when they exceed SIZE_MAX
   (32-bit targets: dimensions that are each accepted can together need more than 4 GiB). */
okid_status okid_layout_size(const okid_dims_ *dims, int combined, int scaled, size_t *bytes);

/*
 * ERA of the identifier's configuration on the Markov parameters (and scales) of res: its problem
 * (order 0 = the configured one) and its scratch, the Hankel matrix and V' in the strict lower
 * triangle of factor (R or identify's copy of it) when they fit there (era_in_r).
 */
void okid_layout_era(const okid_identifier *id, const okid_result_views_ *res, okid_real *factor,
                     okid_era_problem *problem, okid_era_scratch *scratch);

#endif

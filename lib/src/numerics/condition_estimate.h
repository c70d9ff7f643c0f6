/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Incremental condition estimation (Bischof 1990): the cases and formulas of LAPACK's xLAIC1
 * (modified BSD licence), the step with which xGELSY takes its rank. Shared by the core's
 * triangular solve and the Eigen backend's xGELSY.
 */
#ifndef OKID_CONDITION_ESTIMATE_H
#define OKID_CONDITION_ESTIMATE_H

#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct okid_ice_step {
    okid_real sest, s, c; /* the new estimate; x becomes [s x; c] */
} okid_ice_step;

/*
 * x (unit norm) has |R' x| = sest, the estimate of the largest singular value of the j x j
 * upper-triangular R. For R extended by the column [w; gamma] (alpha = x' w): the new estimate and
 * the sine and cosine that extend x.
 */
okid_ice_step okid_ice_largest(okid_real sest, okid_real alpha, okid_real gamma);

/* The same for the smallest singular value. */
okid_ice_step okid_ice_smallest(okid_real sest, okid_real alpha, okid_real gamma);

#ifdef __cplusplus
}
#endif

#endif

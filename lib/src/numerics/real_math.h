/* SPDX-License-Identifier: Apache-2.0 */
/* Math functions and constants for okid_real, so the core compiles as double or float. */
#ifndef OKID_REAL_MATH_H
#define OKID_REAL_MATH_H

#include <float.h>
#include <math.h>

#include "okid/types.h"

#if OKID_REAL_IS_FLOAT
#define OKID_R(x) x##f
#define okid_sqrt sqrtf
#define okid_fabs fabsf
#define okid_log logf
#define okid_exp expf
#define okid_atan2 atan2f
#define okid_cos cosf
#define okid_sin sinf
#define okid_pow powf
#define okid_copysign copysignf
#define okid_fma fmaf
#define OKID_EPSILON FLT_EPSILON
#define OKID_REAL_MIN FLT_MIN
#define OKID_REAL_MAX FLT_MAX
#else
#define OKID_R(x) x
#define okid_sqrt sqrt
#define okid_fabs fabs
#define okid_log log
#define okid_exp exp
#define okid_atan2 atan2
#define okid_cos cos
#define okid_sin sin
#define okid_pow pow
#define okid_copysign copysign
#define okid_fma fma
#define OKID_EPSILON DBL_EPSILON
#define OKID_REAL_MIN DBL_MIN
#define OKID_REAL_MAX DBL_MAX
#endif

#define OKID_PI OKID_R(3.14159265358979323846)

/* isfinite without relying on the floating-point environment's flags. */
static inline int okid_is_finite(okid_real x)
{
    return isfinite(x) != 0;
}

/* x in [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX] (identifier.h); false for NaN. */
static inline int okid_in_magnitude_range(okid_real x)
{
    return x >= OKID_MAGNITUDE_MIN && x <= OKID_MAGNITUDE_MAX;
}

/*
 * sqrt(a^2 + b^2) without overflow or underflow, from sqrt alone: sqrt is correctly rounded in
 * every libm, hypot is not (glibc's and newlib's differ in the last bit), so the Givens folds of
 * okid_push give the same bits on the host and on a Cortex-M. Within 2 ulp; hardware VSQRT and
 * VDIV on an FPU beat newlib's integer hypotf.
 */
static inline okid_real okid_hypot(okid_real a, okid_real b)
{
    a = okid_fabs(a);
    b = okid_fabs(b);
    const okid_real big = a > b ? a : b, small = a > b ? b : a;
    if (small == 0 || !okid_is_finite(big)) {
        return big + small; /* 0, Inf and NaN as hypot gives them (but NaN with Inf: NaN) */
    }
    const okid_real ratio = small / big;
    return big * okid_sqrt(1 + ratio * ratio);
}

#endif

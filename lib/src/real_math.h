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
#define okid_hypot hypotf
#define OKID_EPSILON FLT_EPSILON
#define OKID_REAL_MIN FLT_MIN
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
#define okid_hypot hypot
#define OKID_EPSILON DBL_EPSILON
#define OKID_REAL_MIN DBL_MIN
#endif

#define OKID_PI OKID_R(3.14159265358979323846)

/* isfinite without relying on the floating-point environment's flags. */
static inline int okid_is_finite(okid_real x)
{
    return isfinite(x) != 0;
}

#endif

/**
 * \file types.h
 * \brief Scalar, complex and matrix-view types shared by every okid header.
 */
#ifndef OKID_TYPES_H
#define OKID_TYPES_H

#include <stddef.h>

#include "okid/okid_build_config.h"

#ifdef __cplusplus
extern "C" {
#endif

#if OKID_REAL_IS_FLOAT
typedef float okid_real;
#else
/** The floating-point type of every sample and result (double unless built with OKID_REAL=float). */
typedef double okid_real;
#endif

/**
 * The magnitudes the computation keeps finite and accurate (its squares and fourth powers stay
 * normal numbers): dt, K dt, and the RMS of each channel as it enters the regressor (after the
 * scaling of OKID_SCALING_AUTO) must lie in [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX]: 1e-75..1e75
 * in double, 1e-9..1e9 in float. Outside, okid_init() says OKID_E_BAD_PARAMETER (dt) and
 * okid_identify() OKID_E_DATA_RANGE (a channel: rescale it, or use OKID_SCALING_AUTO).
 */
#if OKID_REAL_IS_FLOAT
#define OKID_MAGNITUDE_MIN 1e-9f
#define OKID_MAGNITUDE_MAX 1e9f
#else
#define OKID_MAGNITUDE_MIN 1e-75
#define OKID_MAGNITUDE_MAX 1e75
#endif

/** Alignment, in bytes, that every okid workspace must have (and that each of its regions keeps). */
#define OKID_WORKSPACE_ALIGN 16u

/**
 * Round a byte count up to a multiple of OKID_WORKSPACE_ALIGN (helper of the size macros). The size
 * macros compute in unsigned long long (64 bits at least) whatever size_t is, and OKID__SIZE
 * saturates their result at SIZE_MAX: on a 32-bit target a sum that exceeds 4 GiB gives SIZE_MAX
 * (a static array that large does not compile, and the functions refuse the configuration with
 * OKID_E_BAD_SIZE) instead of wrapping around to a small number.
 */
#define OKID__ALIGN16(bytes) ((((unsigned long long)(bytes)) + 15u) / 16u * 16u)
#define OKID__SIZE(bytes64) ((bytes64) > (unsigned long long)(size_t)-1 ? (size_t)-1 : (size_t)(bytes64))

/** A complex number, stored as LAPACK stores one: real part, then imaginary part. */
typedef struct okid_complex {
    okid_real re;
    okid_real im;
} okid_complex;

/**
 * A read-only view of a column-major matrix: element (i, j) is data[i + j * ld].
 * Views returned by okid point into the caller's workspace and stay valid until the next
 * call that rewrites the same part of it (documented per function).
 */
typedef struct okid_matrix {
    const okid_real *data;
    int rows;
    int cols;
    int ld;
} okid_matrix;

/** Element (i, j) of a matrix view. */
static inline okid_real okid_matrix_at(okid_matrix a, int i, int j)
{
    return a.data[(size_t)i + (size_t)j * (size_t)a.ld];
}

#ifdef __cplusplus
}
#endif

#endif

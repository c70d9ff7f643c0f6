/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file types.h
 * \brief Scalar, complex and matrix-view types shared by every okid header.
 */
#ifndef OKID_TYPES_H
#define OKID_TYPES_H

#include <stddef.h>

#include "okid/limits.h"
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

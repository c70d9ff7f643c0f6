/* SPDX-License-Identifier: Apache-2.0 */
/* Small dense helpers in plain C (sizes here are tens, BLAS would not pay for its call overhead). */
#ifndef OKID_DENSE_H
#define OKID_DENSE_H

#include <stddef.h>

#include "okid/status.h"
#include "okid/types.h"

/* Element (i, j) of a column-major matrix with leading dimension ld. */
#define OKID_AT(a, ld, i, j) ((a)[(size_t)(i) + (size_t)(j) * (size_t)(ld)])

/* b(0:rows, 0:cols) = a(0:rows, 0:cols). */
void okid_copy_matrix(int rows, int cols, const okid_real *a, int lda, okid_real *b, int ldb);

/* a(0:rows, 0:cols) = 0. */
void okid_zero_matrix(int rows, int cols, okid_real *a, int lda);

/* c = alpha * op(a) op(b) + beta * c, op(x) = x or x' (trans 'N' or 'T'); c is m x n, inner dimension k. */
void okid_gemm(char transa, char transb, int m, int n, int k, okid_real alpha, const okid_real *a, int lda,
               const okid_real *b, int ldb, okid_real beta, okid_real *c, int ldc);

/* 1 when every entry of the rows x cols matrix is finite. */
int okid_all_finite(int rows, int cols, const okid_real *a, int lda);

/*
 * Solve a x = b in place by LU with partial pivoting: a (n x n) is overwritten, b (n x nrhs)
 * becomes x (row swaps are applied to b as they happen). OKID_E_DECOMPOSITION_FAILED when a is singular to working precision.
 */
okid_status okid_lu_solve(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb);

/* Complex helpers on okid_complex. */
okid_complex okid_cmul(okid_complex a, okid_complex b);
okid_complex okid_cdiv(okid_complex a, okid_complex b);
okid_complex okid_clog(okid_complex a);
okid_real okid_cabs(okid_complex a);

#endif

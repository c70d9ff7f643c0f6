/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The narrow linear-algebra interface the core is written against. Two backends implement it:
 * linalg_lapacke.c (host and FMUs: LAPACK through column-major LAPACKE_*_work calls) and
 * linalg_eigen.cpp (firmware: heap-free Eigen, the same algorithms; docs/design.md says how the
 * two are kept comparable, test_backend_agreement compares them). Every routine works in
 * caller-provided memory; work sizes are closed formulas (OKID__LWORK_* in the public headers).
 * Matrices are column-major with explicit leading dimensions. Each returns OKID_OK,
 * OKID_E_DECOMPOSITION_FAILED or OKID_E_BACKEND_ARGUMENT.
 */
#ifndef OKID_LINALG_H
#define OKID_LINALG_H

#include "okid/status.h"
#include "okid/types.h"

/*
 * Fold nrows rows (nrows x n, leading dimension ldb) into the n x n upper-triangular factor r:
 * afterwards r' r' = r' r + rows' rows (Householder, so numerically the QR of [r; rows]).
 * rows is overwritten. t and work each hold nbt * n reals, 1 <= nbt <= n (a single row is folded
 * by Givens rotations, whose c and s take n of each: see givens_fold.h).
 */
okid_status okid_la_fold_rows(int n, okid_real *r, int ldr, int nrows, okid_real *rows, int ldb, int nbt,
                              okid_real *t, okid_real *work);

/*
 * Correlation form: c (n x n, upper triangle only) += rows' rows for the nrows x n rows (leading
 * dimension ldb; xSYRK). rows is only read; c's strict lower triangle is not touched.
 */
okid_status okid_la_accumulate_rows(int n, okid_real *c, int ldc, int nrows, const okid_real *rows, int ldb);

/*
 * c (m x n, leading dimension ldc) += a' b for a (k x m, leading dimension lda) and b (k x n,
 * leading dimension ldb): xGEMM ('T', 'N'). LAPACK backend only (the output correlations' batches;
 * the Eigen backend sums them sample by sample).
 */
okid_status okid_la_add_product_tn(int m, int n, int k, const okid_real *a, int lda, const okid_real *b, int ldb,
                                   okid_real *c, int ldc);

/*
 * Cholesky factor of the leading q x q block of the symmetric c (n >= q columns, upper triangle,
 * leading dimension ldc), and the block beside it: on return c(0:q, 0:q) is R11 (upper, R11' R11
 * = C11) and c(0:q, q:n) is R12 = R11^-T C12, so that R11' R12 = C12: the [R11 R12] a QR fold of
 * the same rows gives, up to signs of rows. OKID_E_DECOMPOSITION_FAILED when C11 is not
 * numerically positive definite (c is then partly overwritten).
 */
okid_status okid_la_cholesky_rows(int q, int n, okid_real *c, int ldc);

/*
 * A solve that needs no rank decision: when the n x n lower triangle l (leading dimension ldl) has
 * a reciprocal condition estimate (1-norm, xTRCON) of at least min_rcond, b (n x nrhs, leading
 * dimension ldb; nrhs may be 0) becomes l'^-1 b (xTRTRS) and *solved is 1; otherwise nothing is
 * written and *solved is 0 (the caller then runs the rank-revealing solve). work holds 3 n reals,
 * iwork n ints. LAPACK backend only (the Eigen backend, the firmware's, has no condition estimate).
 */
okid_status okid_la_solve_conditioned(int n, int nrhs, const okid_real *l, int ldl, okid_real *b, int ldb,
                                      okid_real min_rcond, int *solved, okid_real *work, int *iwork);

/*
 * Rank-revealing least squares on an n x n matrix a (overwritten): b (n x nrhs) becomes the
 * minimum-norm solution of min |a x - b| in which columns whose reciprocal condition falls below
 * rcond count as dependent (complete orthogonal factorisation with column pivoting). *rank is
 * the numerical rank. jpvt holds n ints; work holds OKID__LWORK_GELSY(n, nrhs) reals.
 */
okid_status okid_la_lstsq_rank(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb, okid_real rcond,
                               int *rank, int *jpvt, okid_real *work);

/*
 * Thin SVD a = U S V': s gets all min(m, n) singular values in decreasing order; a's first nvec
 * columns the leading nvec left singular vectors, vt's first nvec rows the right ones (nvec in
 * 0..min(m, n)). vt has OKID__SVD_VT_ROWS(m, n, nvec) rows (okid/sizes.h): the LAPACK backend
 * computes and writes every vector (min(m, n) rows); the Eigen backend only the nvec wanted when
 * m >= n (a cheaper route, linalg_eigen.cpp), else all. work holds OKID__LWORK_GESVD(m, n) reals
 * (LAPACK: divide and conquer when OKID__SVD_DC(m, n)).
 */
okid_status okid_la_svd(int m, int n, int nvec, okid_real *a, int lda, okid_real *s, okid_real *vt, int ldvt,
                        okid_real *work);

/*
 * Eigenvalues wr + i wi and right eigenvectors of the n x n matrix a (overwritten), LAPACK
 * layout: for a complex pair (wi[j] > 0), vr(:, j) + i vr(:, j + 1) is the eigenvector of
 * wr[j] + i wi[j]. work holds OKID__LWORK_GEEV(n) reals.
 */
okid_status okid_la_eig(int n, okid_real *a, int lda, okid_real *wr, okid_real *wi, okid_real *vr, int ldvr,
                        okid_real *work);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Rank-revealing least squares on an upper-triangular matrix, in place and without leaving the
 * triangle: the solves of the regressor factor R work in R's unused lower triangle (docs/design.md,
 * fixed memory: no q x q copy beside R). The algorithm is xGELSY's (column pivoting by the largest
 * remaining norm, rank by incremental condition estimation, RZ, minimum-norm solution); only the
 * pivoted QR differs: a triangular matrix is re-triangularised by Givens rotations when a column
 * moves forward, instead of being refactored by Householder reflectors that would fill it.
 */
#ifndef OKID_TRIANGULAR_LSTSQ_H
#define OKID_TRIANGULAR_LSTSQ_H

#include "okid/sizes.h" /* OKID__LWORK_TRIANGULAR_LSTSQ */

/*
 * The n x n upper-triangular a is stored by rows: a(i, j) = a[i lda + j], j >= i; the solve reads
 * and writes only those elements (R + 1 with lda = w is R's strict lower triangle, transposed).
 * b (n x nrhs, column-major, leading dimension ldb) becomes the minimum-norm solution of
 * min |a x - b| in which columns whose reciprocal condition estimate falls below rcond count as
 * dependent. Returns the numerical rank. a is overwritten; perm holds n ints, work
 * OKID__LWORK_TRIANGULAR_LSTSQ(n) reals.
 */
int okid_triangular_lstsq(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb, okid_real rcond, int *perm,
                          okid_real *work);

/*
 * min(rank, limit) of the same a at rcond, by the same pivoted steps stopped after limit columns:
 * enough to tell whether the rank exceeds a bound at O(n^2 limit) instead of O(n^3), and the same
 * decision (the steps before are identical). a is overwritten; perm and work as above.
 */
int okid_triangular_rank(int n, okid_real *a, int lda, okid_real rcond, int limit, int *perm, okid_real *work);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Least squares for the observer Markov parameters (eq. 50) in fixed memory: regressor rows are
 * folded into the upper-triangular factor R of [Phi | Y] (w x w, w = q + m) by blocks, so any
 * number of samples fits in O(w^2) memory. R = [R11 R12; 0 R22]: R11 (q x q) is the factor of
 * the regressor, R12 (q x m) of its correlation with the outputs.
 */
#ifndef OKID_LEAST_SQUARES_H
#define OKID_LEAST_SQUARES_H

#include "numerics/triangular_lstsq.h"
#include "okid/status.h"
#include "okid/types.h"

/* Scratch of the rank-revealing solves on R (OKID__PHASE_SOLVE_BYTES). */
typedef struct okid_lsq_scratch {
    okid_real *scale;  /* q: column norms of R11 */
    okid_real *column; /* q */
    int *perm;         /* q */
    okid_real *work;   /* OKID__LWORK_TRIANGULAR_LSTSQ(q) */
} okid_lsq_scratch;

/* Forgetting: row i of the nrows x ncols rows (0 = oldest) times root^(nrows - 1 - i), root = sqrt(lambda). */
void okid_lsq_weigh_rows(int nrows, int ncols, okid_real *rows, int ld, okid_real lambda);

/* root^nrows: how much the square root of what was accumulated decays while nrows rows arrive. */
okid_real okid_lsq_decay(int nrows, okid_real lambda);

/*
 * Fold nrows rows (nrows x w, leading dimension ldrows, already scaled) into the w x w factor r
 * with the forgetting factor lambda in (0, 1]: r decays by okid_lsq_decay(), the rows are weighed
 * by okid_lsq_weigh_rows() (rows is overwritten). t and work: nbt x w reals each (linalg.h).
 */
okid_status okid_lsq_fold(int w, okid_real *r, int ldr, int nrows, okid_real *rows, int ldrows, okid_real lambda,
                          int nbt, okid_real *t, okid_real *work);

/*
 * Correlation form (OKID_ESTIMATOR_CORRELATION): c (w x w, upper triangle) = lambda^nrows c +
 * the weighted rows' rows, the square of what okid_lsq_fold() folds (rows is overwritten).
 */
okid_status okid_lsq_accumulate(int w, okid_real *c, int ldc, int nrows, okid_real *rows, int ldrows,
                                okid_real lambda);

/*
 * The numerical rank of the equilibrated q x q triangle s (okid_lsq_equilibrated_copy(): stored
 * by rows in R's lower triangle) at the reciprocal condition tol, solving s x = b on the way (nrhs
 * columns of b, leading dimension ldb; 0: the rank only). s is overwritten. The rank-revealing
 * solve (triangular_lstsq.h), after a condition estimate from OKID__FAST_SOLVE_MIN columns.
 */
#if OKID_LINALG_EIGEN /* no condition estimate: the rank-revealing solve, the firmware's code as before */
static inline int okid_lsq_equilibrated_rank(int q, int nrhs, okid_real *s, int ldr, okid_real *b, int ldb,
                                             okid_real tol, const okid_lsq_scratch *scratch)
{
    return okid_triangular_lstsq(q, nrhs, s, ldr, b, ldb, tol, scratch->perm, scratch->work);
}
#else
int okid_lsq_equilibrated_rank(int q, int nrhs, okid_real *s, int ldr, okid_real *b, int ldb, okid_real tol,
                               const okid_lsq_scratch *scratch);
#endif

/*
 * min(rank, limit) of the same s at tol, s overwritten: okid_lsq_equilibrated_rank()'s decision
 * for "is the rank above limit - 1?" without its full O(q^3) pivoted solve where the condition
 * estimate cannot decide (okid_triangular_rank(): the same pivoted steps, stopped at limit). The
 * Eigen backend (the firmware's) keeps the full solve, its code and instruction counts.
 */
#if OKID_LINALG_EIGEN
static inline int okid_lsq_equilibrated_rank_up_to(int q, okid_real *s, int ldr, okid_real tol, int limit,
                                                   const okid_lsq_scratch *scratch)
{
    (void)limit;
    return okid_triangular_lstsq(q, 0, s, ldr, NULL, q, tol, scratch->perm, scratch->work);
}
#else
int okid_lsq_equilibrated_rank_up_to(int q, okid_real *s, int ldr, okid_real tol, int limit,
                                     const okid_lsq_scratch *scratch);
#endif

/*
 * The factor okid_lsq_solve() needs, from the correlation matrix c (q + m columns, upper
 * triangle, overwritten): [R11 R12] by Cholesky (okid_la_cholesky_rows), R22 zero (no solve
 * reads it). The guard, after SLICOT IB01MD's ALG = 'C': OKID_E_DECOMPOSITION_FAILED when C11 is
 * not positive definite or the column-equilibrated R11 has numerical rank below q at the
 * reciprocal condition sqrt(eps): forming C squared the regressor's condition, so columns that
 * independent are lost in C's rounding (and a rank decision at the rank tolerance would rest on
 * noise); the QR fold of the same rows is then needed. scratch: that of okid_lsq_solve().
 */
okid_status okid_lsq_correlation_factor(int q, int m, okid_real *c, int ldc, const okid_lsq_scratch *scratch);

/*
 * Solve R11 X = R12 rank-revealingly: r is the factor (q + m columns, leading dimension ldr > q;
 * its strict lower triangle is the scratch of the solves, the upper triangle is only read); x
 * (q x m, leading dimension ldx, internal column order of sample_buffer.h) gets
 * X' = [D, observer Markov parameters]. nu = r (p + 1) leading columns are the inputs'. Reports
 * the numerical rank of the regressor and of its input part. OKID_E_RANK_DEFICIENT (x untouched)
 * when the input is not persistently exciting (input rank < nu).
 */
okid_status okid_lsq_solve(int q, int m, int nu, okid_real *r, int ldr, okid_real tol, okid_real *x, int ldx,
                           const okid_lsq_scratch *scratch, int *regressor_rank, int *input_rank);

/* Column norms of the leading n columns of the triangular factor r (the regressor's); 1 for a zero column. */
void okid_lsq_column_norms(const okid_real *r, int ldr, int n, okid_real *scale);

/*
 * s = R(0:n, 0:n) diag(1 / scale), equilibrated so that units do not decide rank or condition,
 * written transposed into R's unused strict lower triangle (s(i, j) = s[i ldr + j], the layout of
 * okid_triangular_lstsq with lda = ldr; n < ldr): the solves need no copy beside R and leave R's
 * upper triangle intact. Returns s.
 */
okid_real *okid_lsq_equilibrated_copy(okid_real *r, int ldr, int n, const okid_real *scale);

#endif

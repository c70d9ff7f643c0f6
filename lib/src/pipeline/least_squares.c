/* SPDX-License-Identifier: Apache-2.0 */
/* Block QR accumulation and rank-revealing solve: see least_squares.h. */
#include "pipeline/least_squares.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"
#include "numerics/triangular_lstsq.h"

void okid_lsq_weigh_rows(int nrows, int ncols, okid_real *rows, int ld, okid_real lambda)
{
    const okid_real root = okid_sqrt(lambda);
    okid_real weight = 1;
    for (int i = nrows - 1; i >= 0; --i) {
        for (int j = 0; j < ncols; ++j) {
            OKID_AT(rows, ld, i, j) *= weight;
        }
        weight *= root;
    }
}

okid_real okid_lsq_decay(int nrows, okid_real lambda)
{
    return okid_pow(okid_sqrt(lambda), (okid_real)nrows);
}

okid_status okid_lsq_fold(int w, okid_real *r, int ldr, int nrows, okid_real *rows, int ldrows, okid_real lambda,
                          int nbt, okid_real *t, okid_real *work)
{
    if (nrows == 0) {
        return OKID_OK;
    }
    if (lambda < 1) {
        /* R weighs rows by root^age (its square by lambda^age): row i of the block is nrows-1-i
           samples older than the newest one, what R holds at least nrows. */
        const okid_real rscale = okid_lsq_decay(nrows, lambda);
        for (int j = 0; j < w; ++j) {
            for (int i = 0; i <= j; ++i) {
                OKID_AT(r, ldr, i, j) *= rscale;
            }
        }
        okid_lsq_weigh_rows(nrows, w, rows, ldrows, lambda);
    }
    return okid_la_fold_rows(w, r, ldr, nrows, rows, ldrows, nbt, t, work);
}

okid_status okid_lsq_accumulate(int w, okid_real *c, int ldc, int nrows, okid_real *rows, int ldrows,
                                okid_real lambda)
{
    if (nrows == 0) {
        return OKID_OK;
    }
    if (lambda < 1) {
        const okid_real root = okid_lsq_decay(nrows, lambda), cscale = root * root; /* lambda^nrows */
        for (int j = 0; j < w; ++j) {
            for (int i = 0; i <= j; ++i) {
                OKID_AT(c, ldc, i, j) *= cscale;
            }
        }
        okid_lsq_weigh_rows(nrows, w, rows, ldrows, lambda);
    }
    return okid_la_accumulate_rows(w, c, ldc, nrows, rows, ldrows);
}

/*
 * From OKID__FAST_SOLVE_MIN columns a condition estimate first: the pivoted
 * solve's O(q^3) Givens sweeps were 40 % of a 24-channel identify at q = 501 (docs/design.md,
 * "Conditioned solve"). The rank-revealing solve declares rank q when its estimate of
 * sigma_min / sigma_max, never below the true 1 / cond_2, exceeds tol; cond_2 <= q cond_1 and
 * xTRCON's estimate of 1 / cond_1 is rarely above it by more than a factor 10, so an estimate of
 * at least 10 q tol means rank q, and the triangular solve gives the same unique solution.
 */
#if !OKID_LINALG_EIGEN
/* 1 when the condition estimate shows rank q (b then solved), 0 when the rank-revealing solve must decide. */
static int conditioned_full_rank(int q, int nrhs, okid_real *s, int ldr, okid_real *b, int ldb, okid_real tol,
                                 const okid_lsq_scratch *scratch)
{
    int solved = 0;
    if (q >= OKID__FAST_SOLVE_MIN) {
        const okid_status st = okid_la_solve_conditioned(q, nrhs, s, ldr, b, ldb, (okid_real)10 * (okid_real)q * tol,
                                                         &solved, scratch->work, scratch->perm);
        solved = st == OKID_OK && solved;
    }
    return solved;
}

int okid_lsq_equilibrated_rank(int q, int nrhs, okid_real *s, int ldr, okid_real *b, int ldb, okid_real tol,
                               const okid_lsq_scratch *scratch)
{
    if (conditioned_full_rank(q, nrhs, s, ldr, b, ldb, tol, scratch)) {
        return q;
    }
    return okid_triangular_lstsq(q, nrhs, s, ldr, b, ldb, tol, scratch->perm, scratch->work);
}

int okid_lsq_equilibrated_rank_up_to(int q, okid_real *s, int ldr, okid_real tol, int limit,
                                     const okid_lsq_scratch *scratch)
{
    if (conditioned_full_rank(q, 0, s, ldr, NULL, q, tol, scratch)) {
        return limit < q ? limit : q;
    }
    return okid_triangular_rank(q, s, ldr, tol, limit, scratch->perm, scratch->work);
}
#endif

okid_status okid_lsq_correlation_factor(int q, int m, okid_real *c, int ldc, const okid_lsq_scratch *scratch)
{
    const int w = q + m;
    okid_status st = okid_la_cholesky_rows(q, w, c, ldc);
    if (st != OKID_OK) {
        return OKID_E_DECOMPOSITION_FAILED;
    }
    for (int j = q; j < w; ++j) {
        for (int i = q; i <= j; ++i) {
            OKID_AT(c, ldc, i, j) = 0;
        }
    }
    okid_lsq_column_norms(c, ldc, q, scratch->scale);
    okid_real *s = okid_lsq_equilibrated_copy(c, ldc, q, scratch->scale);
    const int rank = okid_lsq_equilibrated_rank(q, 0, s, ldc, NULL, q, okid_sqrt(OKID_EPSILON), scratch);
    return rank < q ? OKID_E_DECOMPOSITION_FAILED : OKID_OK;
}

void okid_lsq_column_norms(const okid_real *r, int ldr, int n, okid_real *scale)
{
    for (int j = 0; j < n; ++j) {
        okid_real s = 0;
        for (int i = 0; i <= j; ++i) {
            s += OKID_AT(r, ldr, i, j) * OKID_AT(r, ldr, i, j);
        }
        s = okid_sqrt(s);
        scale[j] = (s > 0) ? s : 1; /* a zero column stays zero: it lowers the rank */
    }
}

okid_real *okid_lsq_equilibrated_copy(okid_real *r, int ldr, int n, const okid_real *scale)
{
    okid_real *s = r + 1; /* s(i, j) = s[i ldr + j] is R(j + 1, i): below R's diagonal, as j + 1 <= n < ldr */
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i <= j; ++i) {
            s[(size_t)i * (size_t)ldr + (size_t)j] = OKID_AT(r, ldr, i, j) / scale[j];
        }
    }
    return s;
}

okid_status okid_lsq_solve(int q, int m, int nu, okid_real *r, int ldr, okid_real tol, okid_real *x, int ldx,
                           const okid_lsq_scratch *scratch, int *regressor_rank, int *input_rank)
{
    okid_lsq_column_norms(r, ldr, q, scratch->scale);

    /* Persistence of excitation: rank of the input-only regressor (leading nu columns). */
    okid_real *s = okid_lsq_equilibrated_copy(r, ldr, nu, scratch->scale);
    *input_rank = okid_triangular_lstsq(nu, 0, s, ldr, NULL, q, tol, scratch->perm, scratch->work);
    if (*input_rank < nu) {
        return OKID_E_RANK_DEFICIENT;
    }

    /* Minimum-norm solution of the equilibrated R11 x~ = R12, then x = diag(1/scale) x~. */
    okid_copy_matrix(q, m, r + (size_t)q * (size_t)ldr, ldr, x, ldx);
    s = okid_lsq_equilibrated_copy(r, ldr, q, scratch->scale);
    *regressor_rank = okid_lsq_equilibrated_rank(q, m, s, ldr, x, ldx, tol, scratch);
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < q; ++i) {
            OKID_AT(x, ldx, i, j) /= scratch->scale[i];
        }
    }
    return OKID_OK;
}

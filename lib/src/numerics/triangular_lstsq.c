/* SPDX-License-Identifier: Apache-2.0 */
/* Rank-revealing least squares on a triangular matrix by Givens rotations: see triangular_lstsq.h. */
#include "numerics/triangular_lstsq.h"

#include "numerics/condition_estimate.h"
#include "numerics/real_math.h"

/* a(i, j) of the row-stored triangle */
#define T_AT(a, lda, i, j) ((a)[(size_t)(i) * (size_t)(lda) + (size_t)(j)])

/* ---- pivoting inside the triangle ---- */

/*
 * Swap columns t - 1 and t of the triangle and restore it by the rotation of rows t - 1 and t that
 * zeroes the one element the swap puts below the diagonal; b gets the same rotation (Q' b).
 */
static void swap_adjacent(int n, okid_real *a, int lda, int t, int nrhs, okid_real *b, int ldb)
{
    for (int i = 0; i < t - 1; ++i) {
        const okid_real tmp = T_AT(a, lda, i, t - 1);
        T_AT(a, lda, i, t - 1) = T_AT(a, lda, i, t);
        T_AT(a, lda, i, t) = tmp;
    }
    const okid_real x = T_AT(a, lda, t - 1, t), y = T_AT(a, lda, t, t), left = T_AT(a, lda, t - 1, t - 1);
    const okid_real h = okid_hypot(x, y);
    const okid_real c = h > 0 ? x / h : 1, s = h > 0 ? y / h : 0;
    T_AT(a, lda, t - 1, t - 1) = h;
    T_AT(a, lda, t - 1, t) = c * left;
    T_AT(a, lda, t, t) = -s * left;
    for (int j = t + 1; j < n; ++j) {
        const okid_real u = T_AT(a, lda, t - 1, j), v = T_AT(a, lda, t, j);
        T_AT(a, lda, t - 1, j) = c * u + s * v;
        T_AT(a, lda, t, j) = c * v - s * u;
    }
    for (int k = 0; k < nrhs; ++k) {
        okid_real *col = b + (size_t)k * (size_t)ldb;
        const okid_real u = col[t - 1], v = col[t];
        col[t - 1] = c * u + s * v;
        col[t] = c * v - s * u;
    }
}

/* Squared norm of column j below row i - 1 (rows i..j). */
static okid_real trailing_norm2(const okid_real *a, int lda, int i, int j)
{
    okid_real s = 0;
    for (int l = i; l <= j; ++l) {
        s += T_AT(a, lda, l, j) * T_AT(a, lda, l, j);
    }
    return s;
}

/*
 * Pivoted triangular QR (xLAQP2's order: the column of largest remaining norm next) and its
 * numerical rank by incremental condition estimation (xGELSY), column by column, stopping at the
 * first column the estimate rejects (rows 0..rank-1 of the factor and of Q' b are then final) or
 * after limit columns (returns limit: the rank is at least that; the steps before are the same).
 */
static int pivoted_rank(int n, okid_real *a, int lda, int nrhs, okid_real *b, int ldb, okid_real rcond, int limit,
                        int *perm, okid_real *xmin, okid_real *xmax)
{
    okid_real smin = 0, smax = 0;
    for (int i = 0; i < limit; ++i) {
        int pvt = i;
        okid_real best = trailing_norm2(a, lda, i, i);
        for (int j = i + 1; j < n; ++j) {
            const okid_real norm2 = trailing_norm2(a, lda, i, j);
            if (norm2 > best) {
                best = norm2;
                pvt = j;
            }
        }
        for (int t = pvt; t > i; --t) { /* move column pvt to i, the columns between one back */
            swap_adjacent(n, a, lda, t, nrhs, b, ldb);
            const int moved = perm[t - 1];
            perm[t - 1] = perm[t];
            perm[t] = moved;
        }
        if (i == 0) { /* the estimate starts from |r00| */
            smax = smin = okid_fabs(T_AT(a, lda, 0, 0));
            if (smax == 0) {
                return 0;
            }
            xmin[0] = xmax[0] = 1;
            continue;
        }
        okid_real alpha_min = 0, alpha_max = 0; /* does column i keep the condition below 1 / rcond? */
        for (int l = 0; l < i; ++l) {
            alpha_min += xmin[l] * T_AT(a, lda, l, i);
            alpha_max += xmax[l] * T_AT(a, lda, l, i);
        }
        const okid_ice_step lo = okid_ice_smallest(smin, alpha_min, T_AT(a, lda, i, i));
        const okid_ice_step hi = okid_ice_largest(smax, alpha_max, T_AT(a, lda, i, i));
        if (hi.sest * rcond > lo.sest) {
            return i;
        }
        for (int l = 0; l < i; ++l) {
            xmin[l] *= lo.s;
            xmax[l] *= hi.s;
        }
        xmin[i] = lo.c;
        xmax[i] = hi.c;
        smin = lo.sest;
        smax = hi.sest;
    }
    return limit;
}

/*
 * The elementary reflector of xLARFG on [alpha; x] (x: len contiguous reals): alpha becomes beta,
 * x the vector v of H = I - tau [1; v] [1; v]'. Returns tau (0: H = I).
 */
static okid_real make_reflector(okid_real *alpha, okid_real *x, int len)
{
    okid_real xnorm = 0;
    for (int l = 0; l < len; ++l) {
        xnorm += x[l] * x[l];
    }
    xnorm = okid_sqrt(xnorm);
    if (xnorm == 0) {
        return 0;
    }
    const okid_real beta = -okid_copysign(okid_hypot(*alpha, xnorm), *alpha);
    const okid_real tau = (beta - *alpha) / beta, scale = 1 / (*alpha - beta);
    for (int l = 0; l < len; ++l) {
        x[l] *= scale;
    }
    *alpha = beta;
    return tau;
}

/* [head; tail] -= tau [1; v] ([1; v]' [head; tail]); tail with stride inc. */
static void apply_reflector(okid_real tau, const okid_real *v, int len, okid_real *head, okid_real *tail, int inc)
{
    okid_real w = *head;
    for (int l = 0; l < len; ++l) {
        w += v[l] * tail[(size_t)l * (size_t)inc];
    }
    w *= tau;
    *head -= w;
    for (int l = 0; l < len; ++l) {
        tail[(size_t)l * (size_t)inc] -= w * v[l];
    }
}

int okid_triangular_lstsq(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb, okid_real rcond, int *perm,
                          okid_real *work)
{
    okid_real *xmin = work, *xmax = work + n, *ztau = work + 2 * n, *column = work + 3 * n;
    for (int j = 0; j < n; ++j) {
        perm[j] = j;
    }
    const int rank = pivoted_rank(n, a, lda, nrhs, b, ldb, rcond, n, perm, xmin, xmax);
    const int tail = n - rank;
    /* [T11 T12] = [T 0] Z with Z = Z(0) ... Z(rank-1) (xTZRZF): z vectors into T12's rows. */
    for (int i = rank - 1; i >= 0 && tail > 0; --i) {
        okid_real *z = &T_AT(a, lda, i, rank);
        ztau[i] = make_reflector(&T_AT(a, lda, i, i), z, tail);
        for (int k = 0; k < i; ++k) {
            apply_reflector(ztau[i], z, tail, &T_AT(a, lda, k, i), &T_AT(a, lda, k, rank), 1);
        }
    }
    for (int c = 0; c < nrhs; ++c) {
        okid_real *x = b + (size_t)c * (size_t)ldb;
        for (int i = rank - 1; i >= 0; --i) { /* T y = (Q' b)(0:rank) */
            if (x[i] != 0) {
                x[i] /= T_AT(a, lda, i, i);
                for (int l = 0; l < i; ++l) {
                    x[l] -= x[i] * T_AT(a, lda, l, i);
                }
            }
        }
        for (int i = rank; i < n; ++i) {
            x[i] = 0;
        }
        for (int i = 0; i < rank && tail > 0; ++i) { /* Z' [y; 0] */
            apply_reflector(ztau[i], &T_AT(a, lda, i, rank), tail, &x[i], &x[rank], 1);
        }
        for (int i = 0; i < n; ++i) { /* undo the column permutation */
            column[perm[i]] = x[i];
        }
        for (int i = 0; i < n; ++i) {
            x[i] = column[i];
        }
    }
    return rank;
}

#if !OKID_LINALG_EIGEN /* its one caller is the LAPACK backend's (least_squares.c) */
int okid_triangular_rank(int n, okid_real *a, int lda, okid_real rcond, int limit, int *perm, okid_real *work)
{
    for (int j = 0; j < n; ++j) {
        perm[j] = j;
    }
    return pivoted_rank(n, a, lda, 0, NULL, 1, rcond, limit < n ? limit : n, perm, work, work + n);
}
#endif

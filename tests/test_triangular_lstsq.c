/* SPDX-License-Identifier: Apache-2.0 */
/*
 * okid_triangular_lstsq (the rank-revealing solve of the regressor factor, in R's unused
 * triangle) against the backend's dense xGELSY (LAPACK, or the Eigen backend's Householder port)
 * on the same triangular factors: the same rank, the same minimum-norm solution; the solution
 * orthogonal to the known null space; and nothing written outside the row-stored triangle. The
 * rank stopped at a limit (okid_triangular_rank) against the full one.
 */
#include <math.h>
#include <stdlib.h>

#include "test_support.h"

#include "numerics/linalg.h"
#include "numerics/triangular_lstsq.h"

#define N 12
#define ROWS 30
#define NRHS 2
#define LDA (N + 3)
#define SENTINEL ((okid_real)-777)

static double uniform(uint64_t *state) /* xorshift64*, in [-1, 1) */
{
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    return (double)((*state * 2685821657736338717ull) >> 11) / 9007199254740992.0 * 2 - 1;
}

/* The triangular factor R (column-major, N x N) of a ROWS x N matrix whose column dep[k] is
   2 column base[k] - column 0 for k < ndep, folded row by row as okid_push does. */
static void factor(uint64_t seed, const int *dep, const int *base, int ndep, okid_real *r)
{
    okid_real a[ROWS * N];
    uint64_t state = seed;
    for (int i = 0; i < ROWS; ++i) {
        for (int j = 0; j < N; ++j) {
            a[i * N + j] = (okid_real)uniform(&state);
        }
        for (int k = 0; k < ndep; ++k) {
            a[i * N + dep[k]] = 2 * a[i * N + base[k]] - a[i * N];
        }
    }
    for (int k = 0; k < N * N; ++k) {
        r[k] = 0;
    }
    for (int i = 0; i < ROWS; ++i) {
        okid_real t[N], work[N];
        assert_int_equal(okid_la_fold_rows(N, r, N, 1, a + i * N, 1, 1, t, work), OKID_OK);
    }
}

/* Solve with both and compare; returns the rank. x gets the triangular solve's solution. */
static int solve_both(const okid_real *r, const okid_real *b, okid_real rcond, okid_real *x)
{
    okid_real tri[N * LDA], tri0[N * LDA], dense[N * N], xd[N * NRHS], work[OKID__LWORK_GELSY(N, NRHS)];
    int perm[N], jpvt[N], dense_rank = -1;
    for (int k = 0; k < N * LDA; ++k) {
        tri[k] = SENTINEL;
    }
    for (int j = 0; j < N; ++j) {
        for (int i = 0; i < N; ++i) {
            dense[i + j * N] = r[i + j * N];
            if (i <= j) {
                tri[i * LDA + j] = r[i + j * N];
            }
        }
    }
    for (int k = 0; k < N * NRHS; ++k) {
        x[k] = xd[k] = b[k];
    }
    for (int k = 0; k < N * LDA; ++k) {
        tri0[k] = tri[k];
    }
    okid_real tri_work[OKID__LWORK_TRIANGULAR_LSTSQ(N)];
    const int rank = okid_triangular_lstsq(N, NRHS, tri, LDA, x, N, rcond, perm, tri_work);
    assert_int_equal(okid_la_lstsq_rank(N, NRHS, dense, N, xd, N, rcond, &dense_rank, jpvt, work), OKID_OK);
    assert_int_equal(rank, dense_rank);
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < i; ++j) {
            assert_true(tri[i * LDA + j] == SENTINEL); /* below the row-stored triangle */
        }
        for (int j = N; j < LDA; ++j) {
            assert_true(tri[i * LDA + j] == SENTINEL); /* beyond the rows */
        }
    }
    const double tol = TOL(1e-10, 2e-4);
    for (int k = 0; k < N * NRHS; ++k) {
        assert_within(fabs((double)x[k] - (double)xd[k]), tol * (1 + fabs((double)xd[k])));
    }
    /* without right-hand sides (the rank checks): the same rank; okid_triangular_rank: min(rank,
       limit) for limits below, at and above it (the regressor diagnostics' "rank above k?") */
    okid_real copy[N * LDA];
    for (int k = 0; k < N * LDA; ++k) {
        copy[k] = tri0[k];
    }
    assert_int_equal(okid_triangular_lstsq(N, 0, tri0, LDA, NULL, N, rcond, perm, tri_work), rank);
#if !OKID_LINALG_EIGEN /* okid_triangular_rank is the LAPACK backend's (least_squares.c's diagnostics) */
    const int limits[4] = {1, rank - 1, rank, N};
    for (int k = 0; k < 4; ++k) {
        for (int e = 0; e < N * LDA; ++e) {
            tri0[e] = copy[e];
        }
        const int expected = limits[k] < rank ? limits[k] : rank;
        assert_int_equal(okid_triangular_rank(N, tri0, LDA, rcond, limits[k], perm, tri_work), expected);
    }
#else
    (void)copy;
#endif
    return rank;
}

static void right_hand_sides(uint64_t seed, okid_real *b)
{
    uint64_t state = seed;
    for (int k = 0; k < N * NRHS; ++k) {
        b[k] = (okid_real)uniform(&state);
    }
}

static void test_full_rank(void **state)
{
    (void)state;
    okid_real r[N * N], b[N * NRHS], x[N * NRHS];
    for (uint64_t seed = 1; seed <= 5; ++seed) {
        factor(seed, NULL, NULL, 0, r);
        right_hand_sides(seed + 100, b);
        assert_int_equal(solve_both(r, b, TOL(1e-10, 1e-5), x), N);
        for (int c = 0; c < NRHS; ++c) { /* the residual of a square full-rank system is zero */
            for (int i = 0; i < N; ++i) {
                double s = 0;
                for (int j = i; j < N; ++j) {
                    s += (double)r[i + j * N] * (double)x[j + c * N];
                }
                assert_within(fabs(s - (double)b[i + c * N]), TOL(1e-9, 1e-3));
            }
        }
    }
}

static void test_rank_deficient_minimum_norm(void **state)
{
    (void)state;
    const int dep[2] = {4, 9}, base[2] = {2, 7};
    okid_real r[N * N], b[N * NRHS], x[N * NRHS];
    for (uint64_t seed = 11; seed <= 15; ++seed) {
        factor(seed, dep, base, 2, r);
        right_hand_sides(seed + 100, b);
        assert_int_equal(solve_both(r, b, TOL(1e-10, 1e-5), x), N - 2);
        /* null space: e_dep - 2 e_base + e_0; the minimum-norm solution is orthogonal to it */
        for (int c = 0; c < NRHS; ++c) {
            const okid_real *xc = x + c * N;
            for (int k = 0; k < 2; ++k) {
                const double along = (double)xc[dep[k]] - 2 * (double)xc[base[k]] + (double)xc[0];
                assert_within(fabs(along), TOL(1e-9, 1e-3));
            }
        }
    }
}

static void test_zero_matrix(void **state)
{
    (void)state;
    okid_real tri[N * LDA] = {0}, b[N * NRHS], work[OKID__LWORK_TRIANGULAR_LSTSQ(N)];
    int perm[N];
    right_hand_sides(3, b);
    assert_int_equal(okid_triangular_lstsq(N, NRHS, tri, LDA, b, N, (okid_real)1e-5, perm, work), 0);
    for (int k = 0; k < N * NRHS; ++k) {
        assert_true(b[k] == 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_full_rank),
        cmocka_unit_test(test_rank_deficient_minimum_norm),
        cmocka_unit_test(test_zero_matrix),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The least-squares solve from OKID__FAST_SOLVE_MIN columns (pipeline/least_squares.h), where a
 * condition estimate lets a well-conditioned R11 skip the rank-revealing sweeps: q = 210 columns
 * of white noise (cond below 10) against the normal equations in long double, and the same
 * columns with the last equal to the one before (rank q - 1): the rank-revealing solve must still
 * find the rank and the minimum-norm solution. The correlation form's guard on both.
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "numerics/linalg.h"
#include "pipeline/least_squares.h"

enum { Q = 210, MOUT = 2, W = Q + MOUT, ROWS = 600, NU = 2, NBT = 16 };

/* rows [phi | y] (ROWS x W), y = phi X + noise; the last column of phi repeats the one before when
   deficient. */
static void make_rows(okid_real *rows, int deficient)
{
    okid_real *white = test_white_noise(W, ROWS, 5);
    for (int i = 0; i < ROWS; ++i) {
        for (int j = 0; j < Q; ++j) {
            rows[i + j * ROWS] = white[j + i * W];
        }
        if (deficient) {
            rows[i + (Q - 1) * ROWS] = rows[i + (Q - 2) * ROWS];
        }
        for (int a = 0; a < MOUT; ++a) {
            double s = 0.1 * (double)white[Q + a + i * W];
            for (int j = 0; j < Q; ++j) {
                s += (double)rows[i + j * ROWS] * (0.01 * (j + 1) - 0.5 * a);
            }
            rows[i + (Q + a) * ROWS] = (okid_real)s;
        }
    }
    free(white);
}

/* The least-squares X of the full-rank rows by the normal equations in long double (Gauss-Jordan). */
static void dense_reference(const okid_real *rows, double *x)
{
    static long double g[Q][W];
    for (int j = 0; j < Q; ++j) {
        for (int l = 0; l < W; ++l) {
            long double s = 0;
            for (int i = 0; i < ROWS; ++i) {
                s += (long double)rows[i + j * ROWS] * (long double)rows[i + l * ROWS];
            }
            g[j][l] = s;
        }
    }
    for (int k = 0; k < Q; ++k) {
        const long double pivot = g[k][k];
        for (int l = 0; l < W; ++l) {
            g[k][l] /= pivot;
        }
        for (int i = 0; i < Q; ++i) {
            if (i != k) {
                const long double f = g[i][k];
                for (int l = 0; l < W; ++l) {
                    g[i][l] -= f * g[k][l];
                }
            }
        }
    }
    for (int j = 0; j < Q; ++j) {
        for (int a = 0; a < MOUT; ++a) {
            x[j + a * Q] = (double)g[j][Q + a];
        }
    }
}

static okid_status solve(const okid_real *rows, okid_real *x, int *rank, int *input_rank, okid_status *guard)
{
    static okid_real r[(W + 1) * W], block[ROWS * W], c[(W + 1) * W], t[NBT * W], work[NBT * W];
    static okid_real scale[Q], column[Q], lwork[4 * Q];
    static int perm[Q];
    const okid_lsq_scratch scratch = {scale, column, perm, lwork};
    memset(r, 0, sizeof r);
    memset(c, 0, sizeof c);
    memcpy(block, rows, sizeof block);
    assert_int_equal(okid_lsq_accumulate(W, c, W + 1, ROWS, block, ROWS, 1), OKID_OK);
    *guard = okid_lsq_correlation_factor(Q, MOUT, c, W + 1, &scratch);
    memcpy(block, rows, sizeof block);
    assert_int_equal(okid_lsq_fold(W, r, W + 1, ROWS, block, ROWS, 1, NBT, t, work), OKID_OK);
    return okid_lsq_solve(Q, MOUT, NU, r, W + 1, TOL(1e-10, 1e-5), x, Q, &scratch, rank, input_rank);
}

static void test_well_conditioned(void **state)
{
    (void)state;
    static okid_real rows[ROWS * W], x[Q * MOUT];
    static double ref[Q * MOUT];
    make_rows(rows, 0);
    dense_reference(rows, ref);
    int rank = 0, input_rank = 0;
    okid_status guard = OKID_E_BACKEND_ARGUMENT;
    assert_int_equal(solve(rows, x, &rank, &input_rank, &guard), OKID_OK);
    assert_int_equal(guard, OKID_OK);
    assert_int_equal(rank, Q);
    assert_int_equal(input_rank, NU);
    double worst = 0, norm = 0;
    for (int i = 0; i < Q * MOUT; ++i) {
        worst = fmax(worst, fabs((double)x[i] - ref[i]));
        norm = fmax(norm, fabs(ref[i]));
    }
    /* cond(phi) < 10 (600 x 210 white noise: (sqrt 600 + sqrt 210) / (sqrt 600 - sqrt 210) = 4):
       the solution to cond^2 eps q, with a margin of 10 */
    assert_true(worst <= TOL(1e-11, 5e-3) * norm);
}

static void test_rank_deficient_still_found(void **state)
{
    (void)state;
    static okid_real rows[ROWS * W], x[Q * MOUT];
    make_rows(rows, 1);
    int rank = 0, input_rank = 0;
    okid_status guard = OKID_OK;
    assert_int_equal(solve(rows, x, &rank, &input_rank, &guard), OKID_OK);
    assert_int_equal(guard, OKID_E_DECOMPOSITION_FAILED); /* the correlation form refuses it */
    assert_int_equal(rank, Q - 1);
    for (int a = 0; a < MOUT; ++a) { /* minimum norm: the two equal columns share their weight */
        const double both = 0.01 * (Q - 1) - 0.5 * a + 0.01 * Q - 0.5 * a;
        assert_true(fabs((double)x[Q - 1 + a * Q] - (double)x[Q - 2 + a * Q]) <= TOL(1e-8, 1e-2) * fabs(both));
        assert_true(fabs((double)x[Q - 1 + a * Q] + (double)x[Q - 2 + a * Q] - both) <= 0.05 * fabs(both) + 0.05);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_well_conditioned),
        cmocka_unit_test(test_rank_deficient_still_found),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

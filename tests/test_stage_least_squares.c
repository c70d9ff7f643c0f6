/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The least-squares stage on its own (pipeline/least_squares.h): rows folded into R by blocks, with
 * and without forgetting, then the rank-revealing solve, against a dense reference computed here
 * independently (normal equations of the weighted rows, Gauss-Jordan in long double).
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/least_squares.h"

enum { RIN = 1, MOUT = 2, P = 3, Q = RIN + (RIN + MOUT) * P, NU = RIN * (P + 1), W = Q + MOUT, ROWS = 300, NBT = 8 };

/* Random rows [phi | y] (ROWS x W, leading dimension ROWS), y = phi X_true + noise. */
static void make_rows(okid_real *rows, double noise, uint64_t seed)
{
    okid_real *white = test_white_noise(W, ROWS, seed);
    for (int i = 0; i < ROWS; ++i) {
        for (int j = 0; j < Q; ++j) {
            rows[i + j * ROWS] = white[j + i * W];
        }
        for (int a = 0; a < MOUT; ++a) {
            double s = noise * (double)white[Q + a + i * W];
            for (int j = 0; j < Q; ++j) {
                s += (double)rows[i + j * ROWS] * (0.1 * (j + 1) - 0.3 * a); /* X_true(j, a) */
            }
            rows[i + (Q + a) * ROWS] = (okid_real)s;
        }
    }
    free(white);
}

/* Dense reference: X minimising sum_i lambda^(ROWS-1-i) |phi_i X - y_i|^2 over the columns in use
   (use[j] = 0 drops column j, whose X row is then 0), by the normal equations in long double. */
static void dense_reference(const okid_real *rows, double lambda, const int *use, double *x)
{
    long double g[Q][Q + MOUT];
    memset(g, 0, sizeof g);
    for (int i = 0; i < ROWS; ++i) {
        const long double weight = powl((long double)lambda, (long double)(ROWS - 1 - i));
        for (int j = 0; j < Q; ++j) {
            for (int l = 0; l < Q + MOUT; ++l) {
                g[j][l] += weight * (long double)rows[i + j * ROWS] * (long double)rows[i + l * ROWS];
            }
        }
    }
    for (int j = 0; j < Q; ++j) { /* a dropped column: identity row, zero right-hand side */
        if (!use[j]) {
            for (int l = 0; l < Q + MOUT; ++l) {
                g[j][l] = (l == j) ? 1 : 0;
            }
            for (int i = 0; i < Q; ++i) {
                if (i != j) {
                    g[i][j] = 0;
                }
            }
        }
    }
    for (int k = 0; k < Q; ++k) { /* Gauss-Jordan, the Gram matrix is positive definite */
        const long double pivot = g[k][k];
        for (int l = 0; l < Q + MOUT; ++l) {
            g[k][l] /= pivot;
        }
        for (int i = 0; i < Q; ++i) {
            if (i != k && g[i][k] != 0) {
                const long double f = g[i][k];
                for (int l = 0; l < Q + MOUT; ++l) {
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

/* Fold the rows in blocks of the given sizes (a copy: the fold overwrites them), then solve. */
static okid_status fold_and_solve(const okid_real *rows, double lambda, const int *blocks, okid_real *x, int *rank,
                                  int *input_rank)
{
    static okid_real block[ROWS * W];
    okid_real r[W * W], t[NBT * W], work[NBT * W], scale[Q], column[Q], lwork[4 * Q];
    int perm[Q];
    memset(r, 0, sizeof r);
    int first = 0;
    for (int b = 0; first < ROWS; ++b) {
        const int count = blocks[b] < ROWS - first ? blocks[b] : ROWS - first;
        for (int j = 0; j < W; ++j) {
            for (int i = 0; i < count; ++i) {
                block[i + j * count] = rows[first + i + j * ROWS];
            }
        }
        assert_int_equal(okid_lsq_fold(W, r, W, count, block, count, (okid_real)lambda, count < NBT ? count : NBT, t, work),
                         OKID_OK);
        first += count;
    }
    const okid_lsq_scratch scratch = {scale, column, perm, lwork};
    return okid_lsq_solve(Q, MOUT, NU, r, W, TOL(1e-10, 1e-5), x, Q, &scratch, rank, input_rank);
}

static double max_error(const okid_real *x, const double *ref)
{
    double worst = 0, norm = 0;
    for (int i = 0; i < Q * MOUT; ++i) {
        worst = fmax(worst, fabs((double)x[i] - ref[i]));
        norm = fmax(norm, fabs(ref[i]));
    }
    return worst / norm;
}

static void test_lsq_against_dense(void **state)
{
    (void)state;
    static okid_real rows[ROWS * W];
    make_rows(rows, 0.3, 11);
    const int all[Q] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    const int blocks_a[] = {32, 32, 32, 32, 32, 32, 32, 32, 32, 32}, blocks_b[] = {1, 7, 64, 1, 100, 127};
    double ref[Q * MOUT];
    okid_real x[Q * MOUT];
    int rank = 0, input_rank = 0;
    for (int f = 0; f < 2; ++f) {
        const double lambda = f == 0 ? 1.0 : 0.98;
        dense_reference(rows, lambda, all, ref);
        for (int s = 0; s < 2; ++s) {
            assert_int_equal(fold_and_solve(rows, lambda, s == 0 ? blocks_a : blocks_b, x, &rank, &input_rank), OKID_OK);
            assert_int_equal(rank, Q);
            assert_int_equal(input_rank, NU);
            assert_within(max_error(x, ref), TOL(1e-13, 5e-6)); /* measured 6e-16, 6e-7 */
        }
    }
}

/* An input column that repeats another: not persistently exciting, and x is left alone. */
static void test_lsq_input_rank_deficient(void **state)
{
    (void)state;
    static okid_real rows[ROWS * W];
    make_rows(rows, 0.3, 12);
    for (int i = 0; i < ROWS; ++i) {
        rows[i + 2 * ROWS] = rows[i + 1 * ROWS];
    }
    const int blocks[] = {32, 32, 32, 32, 32, 32, 32, 32, 32, 32};
    okid_real x[Q * MOUT], sentinel[Q * MOUT];
    for (int i = 0; i < Q * MOUT; ++i) {
        x[i] = sentinel[i] = (okid_real)1234.5;
    }
    int rank = 0, input_rank = 0;
    assert_int_equal(fold_and_solve(rows, 1.0, blocks, x, &rank, &input_rank), OKID_E_RANK_DEFICIENT);
    assert_int_equal(input_rank, NU - 1);
    assert_memory_equal(x, sentinel, sizeof x);
}

/* A past-output column that repeats another: rank q - 1, and the fit phi x is the reference's
   (x itself is the minimum-norm one among many). */
static void test_lsq_regressor_rank_deficient(void **state)
{
    (void)state;
    static okid_real rows[ROWS * W];
    make_rows(rows, 0.3, 13);
    for (int i = 0; i < ROWS; ++i) {
        rows[i + (Q - 1) * ROWS] = rows[i + (Q - 2) * ROWS];
    }
    int use[Q] = {1, 1, 1, 1, 1, 1, 1, 1, 1, 1};
    use[Q - 1] = 0;
    double ref[Q * MOUT];
    dense_reference(rows, 1.0, use, ref);
    const int blocks[] = {32, 32, 32, 32, 32, 32, 32, 32, 32, 32};
    okid_real x[Q * MOUT];
    int rank = 0, input_rank = 0;
    assert_int_equal(fold_and_solve(rows, 1.0, blocks, x, &rank, &input_rank), OKID_OK);
    assert_int_equal(rank, Q - 1);
    double worst = 0, norm = 0;
    for (int i = 0; i < ROWS; ++i) {
        for (int a = 0; a < MOUT; ++a) {
            double fit = 0, want = 0;
            for (int j = 0; j < Q; ++j) {
                fit += (double)rows[i + j * ROWS] * (double)x[j + a * Q];
                want += (double)rows[i + j * ROWS] * ref[j + a * Q];
            }
            worst = fmax(worst, fabs(fit - want));
            norm = fmax(norm, fabs(want));
        }
    }
    assert_within(worst, TOL(1e-13, 5e-6) * norm); /* measured 5e-16, 3e-7 */
    /* minimum norm: the two equal columns share their weight */
    for (int a = 0; a < MOUT; ++a) {
        assert_within(fabs((double)x[Q - 1 + a * Q] - (double)x[Q - 2 + a * Q]), TOL(1e-10, 1e-3) * fabs(ref[Q - 2 + a * Q]));
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lsq_against_dense),
        cmocka_unit_test(test_lsq_input_rank_deficient),
        cmocka_unit_test(test_lsq_regressor_rank_deficient),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

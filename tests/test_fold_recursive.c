/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The fold's two tiles on a wide regressor (w = 150 > 128): the recursive panel of 64 columns
 * (block_rows 0, linalg_lapacke.c) and xTPQRT's tile of 16 (explicit block_rows), each against the
 * Gram matrix R0'R0 + B'B summed here in long double, and against each other. Blocks of 200, 37
 * (fewer rows than the tile) and 2 rows; the last panel is partial (150 = 64 + 64 + 22).
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "numerics/linalg.h"
#include "numerics/real_math.h"

enum { W = 150, TILE_MAX = 64, BLOCKS = 3 };
static const int block_rows[BLOCKS] = {200, 37, 2};

/* R starts as a random upper triangle (diagonal 4 + noise: nonsingular), then the blocks are
   folded with tile nbt; gram gets R0'R0 + sum B'B. */
static void fold_all(int nbt, okid_real *r, long double *gram)
{
    static okid_real block[200 * W], t[TILE_MAX * W], work[TILE_MAX * W];
    okid_real *noise = test_white_noise(W, W, 7);
    memset(r, 0, sizeof(okid_real) * W * W);
    for (int j = 0; j < W; ++j) {
        for (int i = 0; i <= j; ++i) {
            r[i + j * W] = noise[i + j * W] + (i == j ? 4 : 0);
        }
    }
    free(noise);
    if (gram != NULL) {
        for (int a = 0; a < W; ++a) {
            for (int b = 0; b < W; ++b) {
                long double s = 0;
                for (int i = 0; i <= (a < b ? a : b); ++i) {
                    s += (long double)r[i + a * W] * (long double)r[i + b * W];
                }
                gram[a + b * W] = s;
            }
        }
    }
    for (int k = 0; k < BLOCKS; ++k) {
        const int n = block_rows[k];
        okid_real *rows = test_white_noise(W, (size_t)n, 100 + (uint64_t)k);
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < W; ++j) {
                block[i + j * n] = rows[j + i * W];
            }
        }
        free(rows);
        if (gram != NULL) {
            for (int a = 0; a < W; ++a) {
                for (int b = 0; b < W; ++b) {
                    long double s = 0;
                    for (int i = 0; i < n; ++i) {
                        s += (long double)block[i + a * n] * (long double)block[i + b * n];
                    }
                    gram[a + b * W] += s;
                }
            }
        }
        assert_int_equal(okid_la_fold_rows(W, r, W, n, block, n, nbt, t, work), OKID_OK);
    }
}

static void test_fold_tiles_agree(void **state)
{
    (void)state;
    static okid_real r64[W * W], r16[W * W];
    static long double gram[W * W];
    fold_all(64, r64, gram);
    fold_all(16, r16, NULL);
    /* R'R = the Gram matrix: Householder is backward stable, |R'R - G| <= c w eps max|G| with a
       modest c (measured below 1 w eps; 10 w eps is the margin) */
    long double gmax = 0;
    for (int i = 0; i < W * W; ++i) {
        gmax = fmaxl(gmax, fabsl(gram[i]));
    }
    double worst_gram = 0;
    for (int a = 0; a < W; ++a) {
        for (int b = 0; b < W; ++b) {
            long double s = 0;
            for (int i = 0; i <= (a < b ? a : b); ++i) {
                s += (long double)r64[i + a * W] * (long double)r64[i + b * W];
            }
            worst_gram = fmax(worst_gram, (double)(fabsl(s - gram[a + b * W]) / gmax));
        }
    }
    assert_true(worst_gram <= 10.0 * W * OKID_EPSILON);
    /* the two tiles give the same R up to round-off: both are xLARFG's reflectors (the same signs),
       R's perturbation is cond(A) eps w at most; A (389 rows of white noise on a diagonally
       dominant triangle) has cond below 10, so 10 w eps relative to max|R| */
    double rmax = 0, worst = 0;
    for (int j = 0; j < W; ++j) {
        for (int i = 0; i <= j; ++i) {
            rmax = fmax(rmax, fabs((double)r16[i + j * W]));
            worst = fmax(worst, fabs((double)r64[i + j * W] - (double)r16[i + j * W]));
        }
    }
    assert_true(worst <= 100.0 * W * OKID_EPSILON * rmax);
    for (int j = 0; j < W; ++j) { /* and an upper triangle */
        for (int i = j + 1; i < W; ++i) {
            assert_true(r64[i + j * W] == 0);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_fold_tiles_agree),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

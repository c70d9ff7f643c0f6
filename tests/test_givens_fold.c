/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The Givens fold of one row (okid_push's kernel, lib/src/givens_fold.c): R'R gains the row's
 * outer product, and its numbers are those of the textbook loop (rotation j sweeps row j of R,
 * the rotation of an exactly zero element skipped), written out here as the reference, for every
 * size the kernel's two-column, four-rotation loop and its remainders can meet.
 */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "numerics/givens_fold.h"
#include "numerics/real_math.h"

enum { MAX_N = 64, LDR = MAX_N + 3 };

/* The textbook loop the kernel reorders. */
static void textbook_fold(int n, okid_real *r, int ldr, okid_real *row, int inc)
{
    for (int j = 0; j < n; ++j) {
        const okid_real x = row[j * inc];
        if (x == 0) {
            continue;
        }
        okid_real *rjj = &r[j + j * ldr];
        const okid_real d = okid_fabs(*rjj), x_abs = okid_fabs(x);
        const okid_real h = d + x_abs * (x_abs / (d + okid_hypot(d, x_abs)));
        const okid_real sign = *rjj < 0 ? -1 : 1;
        const okid_real s = x / (sign * h), t = x / (sign * (d + h)); /* t = s / (1 + c) */
        *rjj = sign * h;
        for (int k = j + 1; k < n; ++k) { /* the rotation as three shears */
#if OKID_FUSED_FOLD /* each rounded once (CMake OKID_FUSED_FOLD) */
            const okid_real x1 = okid_fma(-t, r[j + k * ldr], row[k * inc]);
            r[j + k * ldr] = okid_fma(s, x1, r[j + k * ldr]);
            row[k * inc] = okid_fma(-t, r[j + k * ldr], x1);
#else
            const okid_real x1 = row[k * inc] - t * r[j + k * ldr];
            r[j + k * ldr] += s * x1;
            row[k * inc] = x1 - t * r[j + k * ldr];
#endif
        }
    }
}

/* A triangular factor with a recognisable (never touched) lower part, and a row with zeros where asked. */
static void make_case(okid_rng *rng, int n, int inc, int leading_zeros, okid_real *r, okid_real *row)
{
    static okid_real v[LDR * MAX_N + MAX_N];
    assert_int_equal(okid_rng_normal(rng, 1, LDR * n + n, v, 1), OKID_OK);
    for (int k = 0; k < n; ++k) {
        for (int i = 0; i < LDR; ++i) {
            r[i + k * LDR] = (i <= k) ? v[i + k * LDR] : (okid_real)(1000 + i); /* i >= n: past the matrix */
        }
        row[k * inc] = (k < leading_zeros || k % 7 == 3) ? 0 : v[LDR * n + k];
    }
}

static void check_fold(okid_rng *rng, int n, int inc, int leading_zeros)
{
    static okid_real r[LDR * MAX_N], expected[LDR * MAX_N], before[LDR * MAX_N];
    okid_real row[3 * MAX_N] = {0}, scratch_row[3 * MAX_N], t[MAX_N], s[MAX_N];
    make_case(rng, n, inc, leading_zeros, r, row);
    memcpy(expected, r, sizeof r);
    memcpy(before, r, sizeof r);
    memcpy(scratch_row, row, sizeof row);
    textbook_fold(n, expected, LDR, scratch_row, inc);
    okid_givens_fold_row(n, r, LDR, row, inc, t, s);

    double gram_scale = 0;
    for (int k = 0; k < n; ++k) {
        for (int i = 0; i < LDR; ++i) {
            if (i <= k) { /* the same numbers as the textbook loop (== : a zero may change sign) */
                assert_true(r[i + k * LDR] == expected[i + k * LDR]);
            } else { /* below the diagonal and past n: untouched */
                assert_true(r[i + k * LDR] == before[i + k * LDR]);
            }
        }
        gram_scale = fmax(gram_scale, (double)row[k * inc] * (double)row[k * inc]);
    }
    /* and what the fold means: R'R + row row' = R_new' R_new */
    for (int a = 0; a < n; ++a) {
        for (int b = 0; b <= a; ++b) {
            double old = (double)row[a * inc] * (double)row[b * inc], now = 0;
            for (int i = 0; i <= b; ++i) {
                old += (double)before[i + a * LDR] * (double)before[i + b * LDR];
                now += (double)r[i + a * LDR] * (double)r[i + b * LDR];
            }
            gram_scale = fmax(gram_scale, fabs(old));
            assert_within(fabs(now - old), TOL(1e-13, 1e-5) * (double)n * (gram_scale + 1));
        }
    }
}

static void test_every_size_and_remainder(void **state)
{
    (void)state;
    okid_rng rng;
    assert_int_equal(okid_rng_seed(&rng, 7), OKID_OK);
    for (int n = 0; n <= 20; ++n) {
        check_fold(&rng, n, 1, 0);
    }
    check_fold(&rng, 63, 1, 0); /* the paper configuration's regressor width */
    check_fold(&rng, 64, 1, 0);
}

static void test_strided_row_and_zeros(void **state)
{
    (void)state;
    okid_rng rng;
    assert_int_equal(okid_rng_seed(&rng, 11), OKID_OK);
    check_fold(&rng, 13, 3, 0);   /* a row of a pending block, leading dimension 3 */
    check_fold(&rng, 22, 1, 21);  /* zeros but the last: start-up with zero history */
    check_fold(&rng, 9, 2, 9);    /* an all-zero row changes nothing */
}

/* Folding into a zero factor, as the first row after okid_init: R becomes that row, made positive. */
static void test_first_row_into_zero_factor(void **state)
{
    (void)state;
    enum { N = 6 };
    okid_real r[N * N] = {0}, t[N], s[N];
    const okid_real row[N] = {OKID_R(-3.0), OKID_R(4.0), 0, OKID_R(1.5), OKID_R(-2.0), OKID_R(0.25)};
    okid_givens_fold_row(N, r, N, row, 1, t, s);
    assert_true(r[0] == OKID_R(3.0)); /* hypot(0, -3): rotation 0 carries the whole row into row 0 */
    for (int k = 1; k < N; ++k) {
        assert_true(r[k * N] == -row[k]); /* c = 0, s = -1 */
        for (int i = 1; i <= k; ++i) {
            assert_true(r[i + k * N] == 0);
        }
    }
}

/*
 * A long record: 10^5 rows of 8 correlated columns folded one by one keep R'R equal to their Gram
 * matrix (accumulated in double) to 1e-4 relative in float; measured 1.7e-5, where the textbook
 * rotation c a + s x, whose c = 1 - O(1/k) keeps few bits of 1 - c, drifted to 1.9e-3
 * (docs/accuracy.md). In double 1.1e-14 (textbook 9.3e-14).
 */
static void test_long_record_keeps_the_gram_matrix(void **state)
{
    (void)state;
    enum { N = 8, ROWS = 100000 };
    static double gram[N * N];
    okid_real r[N * N] = {0}, t[N], s[N], z[N], row[N] = {0};
    okid_rng rng;
    assert_int_equal(okid_rng_seed(&rng, 3), OKID_OK);
    for (int k = 0; k < ROWS; ++k) {
        assert_int_equal(okid_rng_normal(&rng, 1, N, z, 1), OKID_OK);
        for (int i = 0; i < N; ++i) { /* each column correlated with the one before, as lagged samples are */
            row[i] = z[i] + (i > 0 ? OKID_R(0.9) * row[i - 1] : 0);
        }
        for (int a = 0; a < N; ++a) {
            for (int b = 0; b < N; ++b) {
                gram[a + b * N] += (double)row[a] * (double)row[b];
            }
        }
        okid_givens_fold_row(N, r, N, row, 1, t, s);
    }
    double error = 0, scale = 0;
    for (int a = 0; a < N; ++a) {
        for (int b = 0; b < N; ++b) {
            double rr = 0;
            for (int i = 0; i < N; ++i) {
                rr += (double)r[i + a * N] * (double)r[i + b * N];
            }
            error = fmax(error, fabs(rr - gram[a + b * N]));
            scale = fmax(scale, fabs(gram[a + b * N]));
        }
    }
    assert_within(error, TOL(1e-12, 1e-4) * scale);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_size_and_remainder),
        cmocka_unit_test(test_strided_row_and_zeros),
        cmocka_unit_test(test_first_row_into_zero_factor),
        cmocka_unit_test(test_long_record_keeps_the_gram_matrix),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

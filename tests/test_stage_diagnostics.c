/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The diagnostics on their own (quality/diagnostics.h): on a factor R built by hand, two 2 x 2
 * blocks [1 1; 0 e] whose equilibrated 1-norm condition numbers are known in closed form
 * (c = sqrt(1 + e^2): |S|_1 = max(1, (1 + e) / c), |S^-1|_1 = max(1, (1 + c) / e)), the rank
 * rules, and the realization's condition and Hankel-span rule on given singular values and modes.
 */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "quality/diagnostics.h"

enum { Q = 4, NU = 2, W = Q + 2 };

static void block_norms(double e, double *norm, double *inverse_norm)
{
    const double c = sqrt(1 + e * e);
    *norm = fmax(*norm, fmax(1, (1 + e) / c));
    *inverse_norm = fmax(*inverse_norm, fmax(1, (1 + c) / e));
}

/* R11 = blockdiag([1 1; 0 e_input], [1 1; 0 e_output]), in a w x w factor. */
static void make_factor(okid_real *r, double e_input, double e_output)
{
    memset(r, 0, sizeof(okid_real) * W * W);
    r[0 + 0 * W] = 1;
    r[0 + 1 * W] = 1;
    r[1 + 1 * W] = (okid_real)e_input;
    r[2 + 2 * W] = 1;
    r[2 + 3 * W] = 1;
    r[3 + 3 * W] = (okid_real)e_output;
}

static unsigned diagnose(double e_input, double e_output, int n, int rank, okid_regressor_diagnostics *out)
{
    okid_real r[W * W], upper[W * W], scale[Q], column[Q], work[4 * Q];
    int perm[Q];
    make_factor(r, e_input, e_output);
    memcpy(upper, r, sizeof r);
    const okid_lsq_scratch scratch = {scale, column, perm, work};
    unsigned warnings = 0;
    assert_int_equal(okid_diagnose_regressor(Q, NU, r, W, TOL(1e-10, 1e-5), n, rank, &scratch, out, &warnings),
                     OKID_OK);
    for (int j = 0; j < W; ++j) { /* the upper triangle, R's accumulation, is only read */
        for (int i = 0; i <= j; ++i) {
            assert_true(r[i + j * W] == upper[i + j * W]);
        }
    }
    return warnings;
}

static void test_condition_numbers(void **state)
{
    (void)state;
    const double e_input = 1e-2, e_output = 1e-1;
    okid_regressor_diagnostics out;
    const unsigned w = diagnose(e_input, e_output, 1, 3, &out);
    double norm = 0, inverse_norm = 0;
    block_norms(e_input, &norm, &inverse_norm);
    assert_relative(out.input_condition, norm * inverse_norm, TOL(1e-14, 1e-6), "input condition", 0);
    block_norms(e_output, &norm, &inverse_norm);
    assert_relative(out.lsq_condition, norm * inverse_norm, TOL(1e-14, 1e-6), "regressor condition", 0);
    assert_int_equal(out.expected_rank, NU + 1);
    assert_false(w & OKID_W_WEAK_EXCITATION);             /* 2e2 * sqrt(tol) < 1 */
    assert_false(w & OKID_W_RANK_BELOW_MODEL);            /* rank 3 = r (p + 1) + n */
    assert_false(w & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM); /* e_output well above sqrt(tol): rank 4 > 3 */
}

static void test_rank_warnings(void **state)
{
    (void)state;
    okid_regressor_diagnostics out;
    /* an input block near singular (condition 2/e * sqrt(tol) > 1): weak excitation */
    assert_true(diagnose(TOL(1e-7, 1e-4), 1e-1, 1, 3, &out) & OKID_W_WEAK_EXCITATION);
    /* a rank below the model's r (p + 1) + n */
    assert_true(diagnose(1e-2, 1e-1, 1, 2, &out) & OKID_W_RANK_BELOW_MODEL);
    /* the last column dependent at sqrt(tol) but not at tol: noise-free data with p above the minimum */
    assert_true(diagnose(1e-2, TOL(1e-7, 1e-4), 1, 4, &out) & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM);
    /* n = 2: the model's rank is q, there is nothing above the minimum to find */
    assert_false(diagnose(1e-2, TOL(1e-7, 1e-4), 2, 4, &out) & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM);
}

static void test_realization(void **state)
{
    (void)state;
    const okid_real sv[3] = {1, (okid_real)0.1, (okid_real)TOL(1e-9, 1e-5)};
    okid_mode modes[2];
    memset(modes, 0, sizeof modes);
    modes[0].is_pair = 1;
    modes[0].eigenvalue.re = (okid_real)0.9;
    modes[0].cmi = (okid_real)0.9;
    modes[0].frequency_hz = 2;    /* period 0.5 s */
    modes[1].is_pair = 1;
    modes[1].eigenvalue.re = (okid_real)0.9;
    modes[1].cmi = (okid_real)0.1; /* inconsistent: not counted */
    modes[1].frequency_hz = (okid_real)0.1;
    okid_real condition = 0;
    unsigned w = 0;
    okid_diagnose_realization(sv, 2, (okid_real)0.5, modes, 2, &condition, &w);
    assert_relative(condition, 10, 1e-6, "sigma_1 / sigma_2", 0);
    assert_int_equal(w, 0u); /* 0.5 s spans the consistent mode's period */
    okid_diagnose_realization(sv, 3, (okid_real)0.4, modes, 2, &condition, &w);
    assert_true(w & OKID_W_REALIZATION_ILL_CONDITIONED); /* sigma_1 / sigma_3 * sqrt(eps) > 1 */
    assert_true(w & OKID_W_HANKEL_SPAN_SHORT);           /* 0.4 s < 0.9 periods of 0.5 s */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_condition_numbers),
        cmocka_unit_test(test_rank_warnings),
        cmocka_unit_test(test_realization),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

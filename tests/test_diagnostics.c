/* SPDX-License-Identifier: Apache-2.0 */
/* Identifiability diagnostics: the warning bits of okid/status.h and the condition numbers of
   okid_result on data whose rank and conditioning are known by construction. */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

enum { PAPER_SAMPLES = 1001 };

static unsigned identify_paper(okid_config *cfg, double noise, okid_result *res, void **ws)
{
    okid_identifier id;
    assert_int_equal(test_identify_noisy(&REF_PAPER, cfg, PAPER_SAMPLES, 2024, noise, &id, ws, res), OKID_OK);
    return res->warnings;
}

/* Noise-free, p = 20: rank exactly r (p + 1) + n = 21 + 4 (docs/design.md: not unique, but the system
   Markov parameters are), flagged as an observer order above the minimum; the realization
   condition is sigma_1 / sigma_4 of the exact Hankel matrix (numpy), 4.44e3: below 1 / sqrt(eps)
   in double, above it (2.9e3) in float, where the fourth state keeps only 3.6 of float's 7.2
   digits (docs/accuracy.md). In float the condition is off by up to 2u sigma_1 / sigma_4
   (Weyl: each sigma moves by about u sigma_1); identify_tol() = 4u sigma_1 / sigma_4 allows twice that. */
static void test_noise_free_above_minimum(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    okid_result res;
    void *ws = NULL;
    const unsigned w = identify_paper(&cfg, 0, &res, &ws);
    assert_int_equal(res.regressor_rank_expected, 25);
    assert_int_equal(res.regressor_rank, 25);
    assert_true(w & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM);
    assert_false(w & (OKID_W_RANK_BELOW_MODEL | OKID_W_WEAK_EXCITATION));
    assert_int_equal((w & OKID_W_REALIZATION_ILL_CONDITIONED) != 0, OKID_REAL_IS_FLOAT);
    const double exact_condition = REF_PAPER.hankel_sv[0] / REF_PAPER.hankel_sv[3];
    assert_relative(res.realization_condition, exact_condition, TOL(1e-8, identify_tol(&REF_PAPER)),
                    "realization condition", 0);
    /* rank deficient: the smallest pivots are round-off (3.6e16 in double, 8.4e7 in float) */
    assert_true(res.lsq_condition > TOL(1e12, 1e6));
    assert_true(res.input_condition >= 1 && res.input_condition < 5); /* white noise: 2.6 */
    /* alpha = beta = 20 at dt = 0.01 s span 0.4 s, the slowest period is 1 / 0.503 Hz. */
    assert_true(w & OKID_W_HANKEL_SPAN_SHORT);
    free(ws);
}

/* p = 2, m p = n: the deadbeat observer is unique, the regressor has full rank q = 7 = r (p + 1) + n. */
static void test_noise_free_minimum_observer(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.observer_order = 2;
    okid_result res;
    void *ws = NULL;
    const unsigned w = identify_paper(&cfg, 0, &res, &ws);
    assert_int_equal(res.regressor_columns, 7);
    assert_int_equal(res.regressor_rank, 7);
    assert_int_equal(res.regressor_rank_expected, 7);
    assert_false(w & (OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM | OKID_W_RANK_BELOW_MODEL | OKID_W_REGRESSOR_RANK_DEFICIENT));
    assert_true(isfinite(res.lsq_condition) && res.lsq_condition < 1e6);
    free(ws);
}

/*
 * Near noise-free with n = 8 on 2-DOF data: the regressor has rank 25 < r (p + 1) + 8 = 29 (the
 * order is overstated), the data is flagged as near noise-free, and sigma_1 / sigma_8 of the
 * Hankel matrix is at the noise floor: ill conditioned. "Near" is relative to the working
 * precision: 1e-9 noise with a tolerance of 1e-6 in double (sigma_1 / sigma_8 about 1e9); float's
 * own round-off is 6e-8, so there it takes 3e-5 noise with a tolerance of 1e-4 (sigma_1 / sigma_8
 * about 2e5).
 */
static void test_overstated_order_near_noise_free(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.order = 8;
    cfg.rank_tolerance = TOL(1e-6, 1e-4);
    okid_result res;
    void *ws = NULL;
    const unsigned w = identify_paper(&cfg, TOL(1e-9, 3e-5), &res, &ws);
    assert_int_equal(res.regressor_rank, 25);
    assert_int_equal(res.regressor_rank_expected, 29);
    assert_true(w & OKID_W_RANK_BELOW_MODEL);
    assert_true(w & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM);
    assert_true(w & OKID_W_REALIZATION_ILL_CONDITIONED);
    assert_relative(res.realization_condition, res.singular_values[0] / res.singular_values[7],
                    TOL(1e-15, FLT_EPSILON), "realization condition", 0);
    assert_true(res.realization_condition > TOL(1e7, 1e4));
    free(ws);
}

/* Float only: 1e-9 noise is below float's round-off, so the data is noise-free to working precision
   and n = 8 is above the Hankel matrix's numerical rank 4 (sigma_8 <= eps k sigma_1): an error
   (as on exactly noise-free data in double), not a warning. */
static void test_float_noise_below_round_off(void **state)
{
    (void)state;
    if (!OKID_REAL_IS_FLOAT) {
        skip();
    }
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.order = 8;
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(test_identify_noisy(&REF_PAPER, &cfg, PAPER_SAMPLES, 2024, 1e-9, &id, &ws, &res),
                     OKID_E_RANK_DEFICIENT);
    okid_progress progress; /* the accumulated data is kept */
    assert_int_equal(okid_get_progress(&id, &progress), OKID_OK);
    assert_int_equal(progress.samples, PAPER_SAMPLES);
    free(ws);
}

/* 2 % noise, the CLI's recommended p = 60 and a 100 x 100 Hankel spanning 2 s: full rank, no
   warning at all; the Hankel span rule sees the 0.503 Hz mode's 1.99 s period. */
static void test_noisy_well_posed(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.observer_order = 60;
    cfg.hankel_rows = cfg.hankel_cols = 100;
    okid_result res;
    void *ws = NULL;
    const unsigned w = identify_paper(&cfg, 0.02, &res, &ws);
    assert_int_equal(res.regressor_rank, res.regressor_columns);
    assert_int_equal(w, 0);
    assert_true(res.lsq_condition > 1 && res.lsq_condition < 1e6);
    free(ws);
}

/* An AR(1) input u(k) = 0.99 u(k-1) + e(k): its equilibrated regressor has a 2-norm condition of
   about (1 + a) / (1 - a) = 199 (the 1-norm figure reported is within a factor 21 of it): above
   1 / sqrt(1e-3), below 1 / 1e-3: weakly exciting, still usable. */
static void test_weak_excitation(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.rank_tolerance = 1e-3;
    const size_t n = 3000;
    okid_real *u = test_white_noise(1, n, 77), *y = malloc(sizeof(okid_real) * 2 * n);
    assert_non_null(y);
    for (size_t k = 1; k < n; ++k) u[k] += 0.99 * u[k - 1];
    test_simulate(&REF_PAPER, n, u, y, NULL);
    size_t bytes = 0;
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    okid_result res;
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&id, n, u, 1, y, 2, NULL), OKID_OK);
    assert_int_equal(okid_identify(&id, &res), OKID_OK);
    assert_true(res.warnings & OKID_W_WEAK_EXCITATION);
    assert_true(res.input_condition > 50 && res.input_condition < 1000);
    free(ws);
    free(u);
    free(y);
}

static void test_warning_strings(void **state)
{
    (void)state;
    const unsigned bits[] = {OKID_W_RANK_BELOW_MODEL, OKID_W_WEAK_EXCITATION, OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM,
                             OKID_W_HANKEL_SPAN_SHORT, OKID_W_REALIZATION_ILL_CONDITIONED};
    for (size_t i = 0; i < sizeof bits / sizeof bits[0]; ++i) {
        assert_string_not_equal(okid_warning_str(bits[i]), "unknown warning");
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_noise_free_above_minimum),
        cmocka_unit_test(test_noise_free_minimum_observer),
        cmocka_unit_test(test_overstated_order_near_noise_free),
        cmocka_unit_test(test_float_noise_below_round_off),
        cmocka_unit_test(test_noisy_well_posed),
        cmocka_unit_test(test_weak_excitation),
        cmocka_unit_test(test_warning_strings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* Identifiability diagnostics: the warning bits of okid/status.h and the condition numbers of
   okid_result on data whose rank and conditioning are known by construction. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>

enum { PAPER_SAMPLES = 1001 };

static unsigned identify_paper(okid_config *cfg, double noise, okid_result *res, void **ws)
{
    okid_identifier id;
    assert_int_equal(test_identify_noisy(&REF_PAPER, cfg, PAPER_SAMPLES, 2024, noise, &id, ws, res), OKID_OK);
    return res->warnings;
}

/* Noise-free, p = 20: rank exactly r (p + 1) + n = 21 + 4 (DESIGN.md: not unique, but the system
   Markov parameters are), flagged as an observer order above the minimum; the realization
   condition is sigma_1 / sigma_4 of the exact Hankel matrix (numpy). */
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
    assert_false(w & (OKID_W_RANK_BELOW_MODEL | OKID_W_WEAK_EXCITATION | OKID_W_REALIZATION_ILL_CONDITIONED));
    assert_relative(res.realization_condition, REF_PAPER.hankel_sv[0] / REF_PAPER.hankel_sv[3], 1e-8,
                    "realization condition", 0);
    assert_true(res.lsq_condition > 1e12);                            /* rank deficient */
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

/* Near noise-free (1e-9) with a tolerance of 1e-6 and n = 8 on 2-DOF data: the regressor has rank
   25 < r (p + 1) + 8 = 29 (the order is overstated), the data is flagged as near noise-free, and
   sigma_1 / sigma_8 of the Hankel matrix is about 1e9: ill conditioned. */
static void test_overstated_order_near_noise_free(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.order = 8;
    cfg.rank_tolerance = 1e-6;
    okid_result res;
    void *ws = NULL;
    const unsigned w = identify_paper(&cfg, 1e-9, &res, &ws);
    assert_int_equal(res.regressor_rank, 25);
    assert_int_equal(res.regressor_rank_expected, 29);
    assert_true(w & OKID_W_RANK_BELOW_MODEL);
    assert_true(w & OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM);
    assert_true(w & OKID_W_REALIZATION_ILL_CONDITIONED);
    assert_relative(res.realization_condition, res.singular_values[0] / res.singular_values[7], 1e-15,
                    "realization condition", 0);
    assert_true(res.realization_condition > 1e7);
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
        cmocka_unit_test(test_noisy_well_posed),
        cmocka_unit_test(test_weak_excitation),
        cmocka_unit_test(test_warning_strings),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

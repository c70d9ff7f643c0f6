/* SPDX-License-Identifier: Apache-2.0 */
/* The instrumental-variable estimator against plain OKID least squares on output-noise data. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>

enum { SAMPLES = 2001 }; /* the benchmark's case: dt 0.05 s, 100 s */

static double frequency_error(okid_estimator estimator, uint64_t seed, double noise, okid_result *res_out)
{
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.05;
    cfg.observer_order = 10;
    cfg.hankel_rows = cfg.hankel_cols = 20;
    cfg.order = 4;
    cfg.zero_initial_state = 1;
    cfg.estimator = estimator;
    return test_paper_record_error(&cfg, SAMPLES, seed, noise, res_out);
}

/* At equal p = 10 (and the same Hankel), 5 % and 20 % output noise, five seeds: the instruments remove
   most of the least squares' bias (mean and worst error over the seeds; a single seed may tie). */
static void test_instruments_beat_least_squares(void **state)
{
    (void)state;
    const double noises[2] = {0.05, 0.20};
    for (int i = 0; i < 2; ++i) {
        double sum_ls = 0, sum_iv = 0, worst_ls = 0, worst_iv = 0;
        for (uint64_t seed = 11; seed <= 15; ++seed) {
            const double ls = frequency_error(OKID_ESTIMATOR_LEAST_SQUARES, seed, noises[i], NULL);
            const double iv = frequency_error(OKID_ESTIMATOR_INSTRUMENTAL, seed, noises[i], NULL);
            print_message("noise %.2f seed %d: frequency error least squares %.4f, instrumental %.4f\n", noises[i],
                          (int)seed, ls, iv);
            sum_ls += ls;
            sum_iv += iv;
            worst_iv = iv > worst_iv ? iv : worst_iv;
            worst_ls = ls > worst_ls ? ls : worst_ls;
        }
        print_message("noise %.2f: mean %.4f -> %.4f, worst %.4f -> %.4f\n", noises[i], sum_ls / 5, sum_iv / 5,
                      worst_ls, worst_iv);
        assert_true(sum_iv < 0.5 * sum_ls);
        assert_true(worst_iv < 0.7 * worst_ls);
    }
}

/* Noise-free data: the instruments give the exact model too (the IV normal matrix is consistent). */
static void test_instruments_exact_without_noise(void **state)
{
    (void)state;
    okid_result res;
    const double err = frequency_error(OKID_ESTIMATOR_INSTRUMENTAL, 3, 0, &res);
    assert_within(err, TOL(1e-8, 1e-3));
    assert_int_equal(res.instrument_lags, 31 + 20); /* automatic: ceil(q / r) + 2 p, q = 31 */
}

static void test_instrument_configuration(void **state)
{
    (void)state;
    okid_config cfg;
    size_t bytes = 0;
    okid_config_default(&cfg, 2, 3);
    cfg.observer_order = 5;
    cfg.estimator = OKID_ESTIMATOR_INSTRUMENTAL;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_OK);
    assert_int_equal(bytes, OKID_WORKSPACE_BYTES_OPTIONS(2, 3, 5, 20, 20, 0, 0, 0, 1, 0, 1, 0));
    cfg.instrument_lags = 13; /* r (L + 1) = 28 >= q = 27 */
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_OK);
    assert_int_equal(bytes, OKID_WORKSPACE_BYTES_OPTIONS(2, 3, 5, 20, 20, 0, 0, 0, 1, 0, 1, 13));
    cfg.instrument_lags = 12; /* 26 instruments for 27 unknowns */
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_SIZE);
    cfg.instrument_lags = OKID_MAX_INSTRUMENT_LAGS + 1;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_SIZE);
    cfg.instrument_lags = -1;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_SIZE);
    cfg.instrument_lags = 0;
    cfg.estimator = (okid_estimator)3; /* 0..2 */
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_PARAMETER);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_instruments_beat_least_squares),
        cmocka_unit_test(test_instruments_exact_without_noise),
        cmocka_unit_test(test_instrument_configuration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

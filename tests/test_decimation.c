/* SPDX-License-Identifier: Apache-2.0 */
/* Built-in decimation and horizons in seconds (okid_config::decimation, okid_config_horizons). */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/decimator.h"

static const double PI = 3.14159265358979323846;

enum { PAPER_SAMPLES = 3001 }; /* 30 s at the paper's dt = 0.01 s */

/* Identify the paper record (dt 0.01 s, 2 % output noise) with p = 30, alpha = beta = 100, n = 4. */
static double paper_error_with_decimation(int decimation, uint64_t seed, okid_result *res_out)
{
    okid_config cfg;
    assert_int_equal(okid_config_default(&cfg, 1, 2), OKID_OK);
    cfg.dt = (okid_real)0.01;
    cfg.decimation = decimation;
    cfg.observer_order = 30;
    cfg.hankel_rows = cfg.hankel_cols = 100;
    cfg.order = 4;
    cfg.zero_initial_state = 1;
    return test_paper_record_error(&cfg, PAPER_SAMPLES, seed, 0.02, res_out);
}

/*
 * The case: the paper's oversampled dt = 0.01 s, 2 % output noise, 30 s. At the same p,
 * alpha, beta (same memory and flops) the decimated record's observer and Hankel span twice the
 * time: every seed's frequency error falls below 1 % where the raw record leaves 1-2.3 %.
 */
static void test_decimation_removes_bias_on_paper_case(void **state)
{
    (void)state;
    double worst_raw = 0, worst_decimated = 0;
    for (uint64_t seed = 1; seed <= 5; ++seed) {
        const double raw = paper_error_with_decimation(1, seed, NULL);
        okid_result res;
        const double decimated = paper_error_with_decimation(2, seed, &res);
        assert_within(fabs((double)res.dt - 0.02), TOL(1e-15, 1e-8)); /* modal frequencies used K dt */
        assert_int_equal(res.decimation, 2);
        assert_int_equal((int)res.samples, PAPER_SAMPLES);
        assert_int_equal((int)res.rows, (PAPER_SAMPLES + 1) / 2); /* from rest: every kept sample gives a row */
        print_message("seed %d: frequency error K = 1 %.4f, K = 2 %.4f\n", (int)seed, raw, decimated);
        assert_true(decimated < raw);
        worst_raw = raw > worst_raw ? raw : worst_raw;
        worst_decimated = decimated > worst_decimated ? decimated : worst_decimated;
    }
    print_message("worst frequency error over 5 seeds: K = 1 %.4f, K = 2 %.4f\n", worst_raw, worst_decimated);
    assert_true(worst_raw > 0.015);
    assert_within(worst_decimated, TOL(0.01, 0.02));
}

/* The biquad's steady-state gain against the Butterworth magnitude |H|^2 = 1 / (1 + (w / wc)^4),
   with the bilinear map w = tan(pi f / fs): computed here from the formula, not from the design. */
static void test_filter_matches_butterworth_magnitude(void **state)
{
    (void)state;
    const int k = 5;
    okid_real coef[OKID_DECIMATOR_COEFS], st[OKID_DECIMATOR_STATE];
    okid_decimator_design(k, coef);
    const double fc = 0.5 / (2.0 * k); /* cycles per sample: half the decimated Nyquist */
    const double freqs[] = {0.0, 0.01, 0.05, 0.1, 0.2, 0.4};
    for (size_t i = 0; i < sizeof freqs / sizeof freqs[0]; ++i) {
        okid_decimator_reset(st, 1);
        double c = 0, s = 0;
        const int settle = 4000, n = 4000; /* n: whole periods of every frequency above */
        for (int t = 0; t < settle + n; ++t) {
            okid_real x = (okid_real)cos(2 * PI * freqs[i] * t);
            okid_decimator_filter(coef, st, 1, &x);
            if (t >= settle) { /* project on the input cosine and sine */
                c += x * cos(2 * PI * freqs[i] * t);
                s += x * sin(2 * PI * freqs[i] * t);
            }
        }
        const double gain = freqs[i] == 0 ? c / n : 2 * hypot(c, s) / n;
        const double ratio = tan(PI * freqs[i]) / tan(PI * fc);
        const double want = 1 / sqrt(1 + pow(ratio, 4));
        assert_relative(gain, want, TOL(1e-6, 1e-4), "gain", (int)i);
    }
}

static void test_horizons_in_seconds(void **state)
{
    (void)state;
    okid_config cfg;
    memset(&cfg, 0, sizeof cfg); /* defined padding: the struct is compared byte by byte below */
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.01;
    cfg.decimation = 5;
    assert_int_equal(okid_config_horizons(&cfg, (okid_real)1.0, (okid_real)0.875, (okid_real)0.02), OKID_OK);
    assert_int_equal(cfg.observer_order, 20);  /* 1 / 0.05 */
    assert_int_equal(cfg.hankel_rows, 18);     /* 17.5 rounds half up */
    assert_int_equal(cfg.hankel_cols, 1);      /* 0.4 rounds to 0: at least 1 */
    const okid_config before = cfg;
    assert_int_equal(okid_config_horizons(&cfg, (okid_real)-1.0, (okid_real)1.0, (okid_real)1.0), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_config_horizons(&cfg, (okid_real)1.0, (okid_real)NAN, (okid_real)1.0), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_config_horizons(&cfg, (okid_real)1.0, (okid_real)1.0, (okid_real)1e4), OKID_E_BAD_SIZE);
    assert_int_equal(okid_config_horizons(NULL, (okid_real)1.0, (okid_real)1.0, (okid_real)1.0), OKID_E_NULL_POINTER);
    assert_memory_equal(&cfg, &before, sizeof cfg); /* untouched on error */
    cfg.decimation = OKID_MAX_DECIMATION + 1;
    assert_int_equal(okid_config_horizons(&cfg, (okid_real)1.0, (okid_real)1.0, (okid_real)1.0), OKID_E_BAD_SIZE);
}

/* Decimation settings: validation, the workspace macro, and what the API does with them. */
static void test_decimation_configuration(void **state)
{
    (void)state;
    okid_config cfg;
    size_t bytes = 0;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.01;
    cfg.observer_order = 10; /* the sizes and row counts below are for p = 10 */
    assert_int_equal(cfg.decimation, 1);
    cfg.decimation = -1;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_SIZE);
    cfg.decimation = OKID_MAX_DECIMATION + 1;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_SIZE);
    cfg.decimation = 4;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_OK);
    assert_int_equal(bytes, OKID_WORKSPACE_BYTES_OPTIONS(1, 2, 10, 20, 20, 0, 0, 0, 4, 0, 0, 0));
    assert_true(bytes > OKID_WORKSPACE_BYTES(1, 2, 10, 20, 20, 0, 0, 0));

    /* pushed samples 0, K, 2K, ... are kept; a model's predictions would be of filtered data: refused */
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    okid_real *u = NULL, *y = NULL;
    test_paper_record(0.01, 4000, 3, 0.01, &u, &y);
    assert_int_equal(okid_push_block(&id, 4000, u, 1, y, 2, NULL), OKID_OK);
    okid_progress pr;
    assert_int_equal(okid_get_progress(&id, &pr), OKID_OK);
    assert_int_equal((int)pr.samples, 4000);
    assert_int_equal((int)pr.rows, 1000 - 10); /* 1000 kept, the first p fill the window */
    okid_result res;
    assert_int_equal(okid_identify(&id, &res), OKID_OK);
    assert_within(fabs((double)res.dt - 0.04), 1e-7);
    okid_real y_hat[2];
    assert_int_equal(okid_predict(&id, u, y_hat), OKID_E_NOT_AVAILABLE);
    free(u);
    free(y);
    free(ws);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_decimation_removes_bias_on_paper_case),
        cmocka_unit_test(test_filter_matches_butterworth_magnitude),
        cmocka_unit_test(test_horizons_in_seconds),
        cmocka_unit_test(test_decimation_configuration),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

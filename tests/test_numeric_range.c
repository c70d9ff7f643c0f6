/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Numbers at the edge of the floating-point range (issue 17, class 5) and the messages' numbers
 * (class 7): dt and K dt outside [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX] are OKID_E_BAD_PARAMETER;
 * channels scaled far outside it identify correctly with OKID_SCALING_AUTO or are refused with
 * OKID_E_DATA_RANGE, never OK with NaN or garbage and never a backend error; a forgetting factor
 * that forgets faster than the unknowns need is OKID_E_NOT_ENOUGH_DATA with the rows it remembers;
 * okid_config_check names the field, its value and its range.
 */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SAMPLES = 1001 };

#if OKID_REAL_IS_FLOAT
static const double HUGE_SCALE = 1e20, TINY_SCALE = 1e-20, WIDE_SCALE = 1e6;
static const okid_real SUBNORMAL_DT = 1e-40f;
#else
static const double HUGE_SCALE = 1e155, TINY_SCALE = 1e-160, WIDE_SCALE = 1e60;
static const okid_real SUBNORMAL_DT = 1e-320;
#endif

static okid_status config_status(const okid_config *cfg)
{
    size_t bytes = 0;
    return okid_workspace_size(cfg, &bytes);
}

static void test_dt_outside_the_range(void **state)
{
    (void)state;
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    okid_config_issue issue;
    cfg.dt = SUBNORMAL_DT; /* a subnormal: its poles ln(lambda) / dt are infinite */
    assert_int_equal(config_status(&cfg), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_PARAMETER);
    assert_string_equal(issue.field, "dt");
    assert_true(issue.min == (double)OKID_MAGNITUDE_MIN && issue.max == (double)OKID_MAGNITUDE_MAX);
    cfg.dt = OKID_MAGNITUDE_MIN / 10;
    assert_int_equal(config_status(&cfg), OKID_E_BAD_PARAMETER);
    cfg.dt = OKID_MAGNITUDE_MIN * 10;
    assert_int_equal(config_status(&cfg), OKID_OK);
    /* K dt above the range, and K dt overflowing to Inf */
    cfg.decimation = 64;
    cfg.dt = OKID_MAGNITUDE_MAX / 10;
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_PARAMETER);
    assert_string_equal(issue.field, "dt");
    assert_true(issue.max == (double)OKID_MAGNITUDE_MAX / 64);
#if OKID_REAL_IS_FLOAT
    cfg.dt = FLT_MAX / 2;
#else
    cfg.dt = DBL_MAX / 2;
#endif
    assert_int_equal(config_status(&cfg), OKID_E_BAD_PARAMETER);
    /* the other entry points that take a dt */
    okid_config_default(&cfg, 1, 2);
    cfg.dt = SUBNORMAL_DT;
    assert_int_equal(okid_config_horizons(&cfg, 1, 1, 1), OKID_E_BAD_PARAMETER);
    const okid_real a[4] = {(okid_real)0.9, 0, 0, (okid_real)0.8}, c[4] = {1, 0, 0, 1};
    static _Alignas(16) unsigned char ws[OKID_MODAL_WORKSPACE_BYTES(2, 2)];
    okid_mode modes[2];
    int num_modes = 0;
    assert_int_equal(okid_modal_analysis(2, 2, a, 2, c, 2, SUBNORMAL_DT, OKID_SENSING_DISPLACEMENT, ws, sizeof ws,
                                         modes, &num_modes, NULL),
                     OKID_E_BAD_PARAMETER);
}

/* The paper's record with the force times input_scale and the responses times output_scale. */
static okid_status identify_scaled(double input_scale, double output_scale, okid_scaling scaling,
                                   okid_identifier *id, void **ws, okid_result *res)
{
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.scaling = scaling;
    size_t bytes = 0;
    *ws = test_workspace(&cfg, &bytes);
    assert_int_equal(okid_init(id, &cfg, *ws, bytes, NULL), OKID_OK);
    okid_real *u = test_white_noise(1, SAMPLES, 2024);
    okid_real *y = malloc(sizeof(okid_real) * 2 * SAMPLES);
    assert_non_null(y);
    test_simulate(&REF_PAPER, SAMPLES, u, y, NULL);
    for (size_t k = 0; k < SAMPLES; ++k) {
        u[k] = (okid_real)((double)u[k] * input_scale);
        y[2 * k] = (okid_real)((double)y[2 * k] * output_scale);
        y[2 * k + 1] = (okid_real)((double)y[2 * k + 1] * output_scale);
    }
    assert_int_equal(okid_push_block(id, SAMPLES, u, 1, y, 2, NULL), OKID_OK);
    free(u);
    free(y);
    return okid_identify(id, res);
}

static void expect_status(double input_scale, double output_scale, okid_scaling scaling, okid_status want)
{
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(identify_scaled(input_scale, output_scale, scaling, &id, &ws, &res), want);
    free(ws);
}

static void expect_paper_modes(double input_scale, double output_scale, okid_scaling scaling)
{
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(identify_scaled(input_scale, output_scale, scaling, &id, &ws, &res), OKID_OK);
    assert_int_equal(res.num_modes, 2);
    assert_modes_match(&REF_PAPER, res.modes, res.num_modes, identify_tol(&REF_PAPER), IDENTIFY_MAC_MIN);
    for (int i = 0; i < res.num_modes; ++i) {
        assert_true(isfinite((double)res.modes[i].msv) && isfinite((double)res.modes[i].emac));
        assert_within(1 - res.modes[i].emac, TOL(1e-3, 1e-2));
    }
    free(ws);
}

/* Too large for the squares of the computation: refused without scaling, identified with it. */
static void test_huge_channels(void **state)
{
    (void)state;
    expect_status(1, HUGE_SCALE, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_status(HUGE_SCALE, 1, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_status(HUGE_SCALE, HUGE_SCALE, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_paper_modes(1, HUGE_SCALE, OKID_SCALING_AUTO);
    expect_paper_modes(HUGE_SCALE, 1, OKID_SCALING_AUTO);
    expect_paper_modes(HUGE_SCALE, HUGE_SCALE, OKID_SCALING_AUTO);
}

/* Too small: refused (without scaling by the channel check, with it by the results' check). */
static void test_tiny_channels(void **state)
{
    (void)state;
    expect_status(1, TINY_SCALE, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_status(TINY_SCALE, 1, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_status(TINY_SCALE, TINY_SCALE, OKID_SCALING_NONE, OKID_E_DATA_RANGE);
    expect_status(1, TINY_SCALE, OKID_SCALING_AUTO, OKID_E_DATA_RANGE);
    expect_status(TINY_SCALE, 1, OKID_SCALING_AUTO, OKID_E_DATA_RANGE);
}

/* Inside the range but far from 1: identified without scaling. */
static void test_wide_but_inside(void **state)
{
    (void)state;
    expect_paper_modes(1, WIDE_SCALE, OKID_SCALING_NONE);
    expect_paper_modes(WIDE_SCALE, 1, OKID_SCALING_NONE);
    expect_paper_modes(1 / WIDE_SCALE, 1, OKID_SCALING_NONE);
}

/* lambda = 1e-12 remembers 1 + floor(2 ln(1e-10) / ln(1e-12)) = 2 rows: too few, and said so. */
static void test_forgetting_shorter_than_the_unknowns(void **state)
{
    (void)state;
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    cfg.forgetting_factor = (okid_real)1e-12;
    cfg.rank_tolerance = (okid_real)1e-6;
    okid_identifier id;
    okid_result res;
    void *ws = NULL;
    assert_int_equal(test_identify_case(&REF_PAPER, &cfg, SAMPLES, 2024, &id, &ws, &res), OKID_E_NOT_ENOUGH_DATA);
    okid_progress progress;
    assert_int_equal(okid_get_progress(&id, &progress), OKID_OK);
    const double ages = 2 * log(1e-6) / log(1e-12); /* 1.0 */
    assert_int_equal(progress.rows_remembered, 1 + (uint64_t)floor(ages + 1e-9));
    assert_true(progress.rows_remembered < (uint64_t)progress.rows_needed);
    free(ws);
    /* lambda = 0.5 remembers 1 + floor(2 ln(1e-6) / ln(0.5)) = 40 rows: still fewer than q = 61 */
    cfg.forgetting_factor = (okid_real)0.5;
    assert_int_equal(test_identify_case(&REF_PAPER, &cfg, SAMPLES, 2024, &id, &ws, &res), OKID_E_NOT_ENOUGH_DATA);
    assert_int_equal(okid_get_progress(&id, &progress), OKID_OK);
    assert_int_equal(progress.rows_remembered, 40);
    free(ws);
    /* lambda = 0.9 remembers 263 >= 61 rows: identified */
    cfg.forgetting_factor = (okid_real)0.9;
    assert_int_equal(test_identify_case(&REF_PAPER, &cfg, SAMPLES, 2024, &id, &ws, &res), OKID_OK);
    assert_int_equal(okid_get_progress(&id, &progress), OKID_OK);
    assert_int_equal(progress.rows_remembered, 1 + (uint64_t)floor(2 * log(1e-6) / log(0.9)));
    free(ws);
}

static void test_config_check_names_the_field(void **state)
{
    (void)state;
    okid_config cfg;
    okid_config_issue issue;
    okid_config_default(&cfg, 1, 2);
    cfg.observer_order = 10;
    cfg.order = 30; /* m p = 20 */
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_ORDER);
    assert_string_equal(issue.field, "order");
    assert_true(issue.value == 30 && issue.min == 0 && issue.max == 20);
    cfg.order = 0;
    cfg.rank_tolerance = (okid_real)1e-30; /* nonzero below epsilon */
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_PARAMETER);
    assert_string_equal(issue.field, "rank_tolerance");
    assert_true(issue.min > 0 && issue.min < 1e-6 && issue.max == 1);
    cfg.rank_tolerance = 0;
    cfg.estimator = OKID_ESTIMATOR_INSTRUMENTAL;
    cfg.instrument_lags = 5; /* below p = 10 */
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_SIZE);
    assert_string_equal(issue.field, "instrument_lags");
    assert_true(issue.value == 5 && issue.min == 30 && issue.max == OKID_MAX_INSTRUMENT_LAGS); /* q = 31: r(L+1) >= q */
    cfg.instrument_lags = 0;
    assert_int_equal(okid_config_check(&cfg, &issue), OKID_OK);
    assert_null(issue.field);
    okid_config_default(&cfg, 15, 44); /* the 32-bit overflow of issue 17: 8.6 GB */
    cfg.observer_order = 554;
    cfg.hankel_rows = cfg.hankel_cols = 1;
    cfg.order = 1;
    cfg.block_rows = 1;
    if (sizeof(size_t) < 8) {
        assert_int_equal(okid_config_check(&cfg, &issue), OKID_E_BAD_SIZE);
        assert_string_equal(issue.field, "workspace bytes");
        assert_true(issue.value > 8e9 && issue.max == (double)SIZE_MAX);
    } else {
        assert_int_equal(okid_config_check(&cfg, &issue), OKID_OK);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_dt_outside_the_range),
        cmocka_unit_test(test_huge_channels),
        cmocka_unit_test(test_tiny_channels),
        cmocka_unit_test(test_wide_but_inside),
        cmocka_unit_test(test_forgetting_shorter_than_the_unknowns),
        cmocka_unit_test(test_config_check_names_the_field),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

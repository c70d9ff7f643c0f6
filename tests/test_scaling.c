/* SPDX-License-Identifier: Apache-2.0 */
/* Per-channel scaling (OKID_SCALING_AUTO): results independent of the units of the data. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { SAMPLES = 3001 };

typedef struct run {
    okid_identifier id;
    okid_result res;
    void *ws;
} run;

/* The paper's dt = 0.01 s, p = 20, alpha = beta = 40, n = 4, from rest, with the given scaling. */
static void paper_config(okid_config *cfg, okid_scaling scaling)
{
    okid_config_default(cfg, 1, 2);
    cfg->dt = (okid_real)0.01;
    cfg->observer_order = 20;
    cfg->hankel_rows = cfg->hankel_cols = 40;
    cfg->order = 4;
    cfg->zero_initial_state = 1;
    cfg->scaling = scaling;
}

/* Identify the paper record (dt 0.01 s, 2 % output noise) with inputs times in_unit and output a
   times out_unit[a], the combined realization (observer gain G too), p = 20, alpha = beta = 40. */
static void identify_in_units(okid_scaling scaling, double in_unit, const double out_unit[2], run *out)
{
    okid_config cfg;
    paper_config(&cfg, scaling);
    cfg.realization = OKID_REALIZATION_COMBINED;
    okid_real *u = NULL, *y = NULL;
    test_paper_record(0.01, SAMPLES, 4, 0.02, &u, &y);
    for (size_t k = 0; k < SAMPLES; ++k) {
        u[k] *= (okid_real)in_unit;
        for (int a = 0; a < 2; ++a) y[2 * k + (size_t)a] *= (okid_real)out_unit[a];
    }
    size_t bytes = 0;
    out->ws = test_workspace(&cfg, &bytes);
    assert_int_equal(okid_init(&out->id, &cfg, out->ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&out->id, SAMPLES, u, 1, y, 2, NULL), OKID_OK);
    assert_int_equal(okid_identify(&out->id, &out->res), OKID_OK);
    free(u);
    free(y);
}

/* Largest relative difference of frequencies and damping ratios (infinite when the mode counts
   differ), and smallest MAC of the sensor shapes. */
static void compare_modes(const okid_result *a, const okid_result *b, const double out_unit[2], double *worst,
                          double *mac_min)
{
    *worst = a->num_modes == b->num_modes ? 0 : INFINITY;
    *mac_min = a->num_modes == b->num_modes ? 1 : 0;
    if (a->num_modes != b->num_modes) {
        return;
    }
    for (int i = 0; i < a->num_modes; ++i) {
        const okid_mode *x = &a->modes[i], *z = &b->modes[i];
        const double df = fabs(x->frequency_hz - z->frequency_hz) / fabs(x->frequency_hz);
        const double dz = fabs(x->damping_ratio - z->damping_ratio) / fabs(x->damping_ratio);
        *worst = fmax(*worst, fmax(df, dz));
        okid_complex unit_shape[2]; /* b's shape in a's units */
        for (int s = 0; s < 2; ++s) {
            unit_shape[s].re = (okid_real)(z->sensor_shape[s].re / out_unit[s]);
            unit_shape[s].im = (okid_real)(z->sensor_shape[s].im / out_unit[s]);
        }
        *mac_min = fmin(*mac_min, (double)okid_mac(x->sensor_shape, unit_shape, 2));
    }
}

/* metres -> millimetres on every output, newtons -> kilonewtons on the input. */
static void test_units_do_not_change_the_modes(void **state)
{
    (void)state;
    const double si[2] = {1, 1}, mm[2] = {1000, 1000};
    run base, other;
    identify_in_units(OKID_SCALING_AUTO, 1, si, &base);
    identify_in_units(OKID_SCALING_AUTO, 1e-3, mm, &other);
    double worst = 0, mac_min = 0;
    compare_modes(&base.res, &other.res, mm, &worst, &mac_min);
    print_message("m, N vs mm, kN: modes differ by %.3g (relative), MAC >= %.15f\n", worst, mac_min);
    /* float: the data differ by a rounding (u = 6e-8) times the identification's conditioning; over
       five BLAS backends the modes moved by up to 7.5e-5 (scripts/blas_kernels.sh): 3x that */
    assert_within(worst, TOL(1e-10, 2.5e-4));
    assert_within(1 - mac_min, TOL(1e-12, 1e-5));

    /* A is the same; B, C, D, G change as the units: B' = 1000 B (per kN), C' = 1000 C, D' = 1e6 D, G' = G / 1000 */
    const int n = base.res.order;
    const double tol = TOL(1e-9, 1e-3);
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            assert_within(fabs(okid_matrix_at(other.res.A, i, j) - okid_matrix_at(base.res.A, i, j)), tol);
        }
        assert_relative(okid_matrix_at(other.res.B, i, 0), 1e3 * okid_matrix_at(base.res.B, i, 0), tol, "B", i);
        for (int a = 0; a < 2; ++a) {
            assert_relative(okid_matrix_at(other.res.C, a, i), 1e3 * okid_matrix_at(base.res.C, a, i), tol, "C", i);
            assert_relative(okid_matrix_at(other.res.G, i, a), 1e-3 * okid_matrix_at(base.res.G, i, a), tol, "G", i);
        }
    }
    for (int a = 0; a < 2; ++a) {
        assert_relative(okid_matrix_at(other.res.D, a, 0), 1e6 * okid_matrix_at(base.res.D, a, 0), tol, "D", a);
        assert_relative(other.res.output_scales[a], 1e3 * base.res.output_scales[a], TOL(1e-12, 1e-6), "scale", a);
    }

    /* The stabilization diagram realizes from the same balanced Hankel: its order-4 modes are the identified ones. */
    size_t stab_bytes = 0;
    assert_int_equal(okid_stabilization_workspace_size(&other.id, 4, 2, &stab_bytes), OKID_OK);
    void *stab_ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (stab_bytes + 15u) / 16u * 16u);
    assert_non_null(stab_ws);
    okid_stabilization table;
    assert_int_equal(okid_stabilization_compute(&other.id, 4, 2, NULL, stab_ws, stab_bytes, &table), OKID_OK);
    const okid_stabilization_order *top = &table.orders[table.num_orders - 1];
    assert_int_equal(top->order, 4);
    assert_int_equal(top->num_modes, other.res.num_modes);
    for (int i = 0; i < top->num_modes; ++i) {
        assert_relative(table.modes[top->first + i].frequency_hz, other.res.modes[i].frequency_hz, TOL(1e-10, 1e-4),
                        "stabilization frequency", i);
    }
    free(stab_ws);
    free(base.ws);
    free(other.ws);
}

/* Mixed units (one sensor in mm, the other in m): with scaling the modes stay; without, the
   Hankel's SVD weighs the millimetre sensor a million times more and the noisy modes move. */
static void test_mixed_units_need_scaling(void **state)
{
    (void)state;
    const double si[2] = {1, 1}, mixed[2] = {1000, 1};
    run a, b;
    double worst = 0, mac_min = 0;
    identify_in_units(OKID_SCALING_AUTO, 1, si, &a);
    identify_in_units(OKID_SCALING_AUTO, 1, mixed, &b);
    compare_modes(&a.res, &b.res, mixed, &worst, &mac_min);
    print_message("mixed units with scaling: modes differ by %.3g\n", worst);
    assert_within(worst, TOL(1e-10, 1e-3)); /* float: the data differ by a rounding, 6e-8, times the conditioning */
    free(a.ws);
    free(b.ws);
    identify_in_units(OKID_SCALING_NONE, 1, si, &a);
    identify_in_units(OKID_SCALING_NONE, 1, mixed, &b);
    compare_modes(&a.res, &b.res, mixed, &worst, &mac_min);
    print_message("mixed units without scaling: modes differ by %.3g (%d and %d modes)\n", worst, a.res.num_modes,
                  b.res.num_modes);
    assert_true(worst > 1e-4);
    free(a.ws);
    free(b.ws);
}

/* The scales are the RMS of each channel over the first block of rows; none without scaling. */
static void test_scales_are_first_block_rms(void **state)
{
    (void)state;
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.01;
    cfg.observer_order = 4;
    cfg.hankel_rows = cfg.hankel_cols = 10;
    cfg.block_rows = 16;
    cfg.scaling = OKID_SCALING_AUTO;
    okid_real *u = NULL, *y = NULL;
    test_paper_record(0.01, 500, 9, 0, &u, &y);
    size_t bytes = 0;
    void *ws = test_workspace(&cfg, &bytes);
    assert_int_equal(bytes, OKID_WORKSPACE_BYTES_OPTIONS(1, 2, 4, 10, 10, 0, 16, 0, 1, 1, 0, 0));
    okid_identifier id;
    okid_result res;
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&id, 500, u, 1, y, 2, NULL), OKID_OK);
    assert_int_equal(okid_identify(&id, &res), OKID_OK);
    /* rows start at sample p = 4 (the window fills first): the first block is samples 4..19 */
    double su = 0, sy[2] = {0, 0};
    for (int k = 4; k < 20; ++k) {
        su += u[k] * u[k];
        for (int a = 0; a < 2; ++a) sy[a] += y[2 * k + a] * y[2 * k + a];
    }
    assert_relative(res.input_scales[0], sqrt(su / 16), TOL(1e-14, 1e-6), "input scale", 0);
    for (int a = 0; a < 2; ++a) assert_relative(res.output_scales[a], sqrt(sy[a] / 16), TOL(1e-14, 1e-6), "output scale", a);
    free(ws);
    cfg.scaling = OKID_SCALING_NONE;
    ws = test_workspace(&cfg, &bytes);
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&id, 500, u, 1, y, 2, NULL), OKID_OK);
    assert_int_equal(okid_identify(&id, &res), OKID_OK);
    assert_null(res.input_scales);
    assert_null(res.output_scales);
    cfg.scaling = (okid_scaling)2;
    assert_int_equal(okid_workspace_size(&cfg, &bytes), OKID_E_BAD_PARAMETER);
    free(ws);
    free(u);
    free(y);
}

/* Scales given by the caller: used as given (data in other units with scales in the same units give
   the same modes), refused once rows are folded, checked, and forgotten by okid_reset(). */
static void test_scales_set_by_the_caller(void **state)
{
    (void)state;
    okid_config cfg;
    paper_config(&cfg, OKID_SCALING_AUTO);
    okid_real *u = NULL, *y = NULL;
    test_paper_record(0.01, SAMPLES, 5, 0.02, &u, &y);
    size_t bytes = 0;
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    okid_result res;
    double freq[2][8];
    const okid_real in_scale[1] = {(okid_real)2.0}, out_scale[2] = {(okid_real)0.5, (okid_real)3.0};
    for (int pass = 0; pass < 2; ++pass) {
        /* pass 1: outputs in mm and scales in mm: the scaled data are the same */
        const okid_real unit = pass ? (okid_real)1000 : (okid_real)1;
        const okid_real outs[2] = {out_scale[0] * unit, out_scale[1] * unit};
        for (size_t k = 0; k < 2 * (size_t)SAMPLES; ++k) y[k] *= pass ? unit : 1;
        assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
        assert_int_equal(okid_set_scales(&id, in_scale, outs), OKID_OK);
        assert_int_equal(okid_push_block(&id, SAMPLES, u, 1, y, 2, NULL), OKID_OK);
        assert_int_equal(okid_identify(&id, &res), OKID_OK);
        assert_true(res.input_scales[0] == in_scale[0] && res.output_scales[1] == outs[1]);
        for (int i = 0; i < res.num_modes; ++i) freq[pass][i] = res.modes[i].frequency_hz;
    }
    /* float: measured up to 5.5e-5 over five BLAS backends (scripts/blas_kernels.sh), 3x that */
    for (int i = 0; i < res.num_modes; ++i) assert_relative(freq[1][i], freq[0][i], TOL(1e-10, 2e-4), "frequency", i);

    const okid_real bad[2] = {(okid_real)1.0, (okid_real)0.0};
    assert_int_equal(okid_set_scales(&id, in_scale, out_scale), OKID_E_NOT_AVAILABLE); /* rows folded */
    assert_int_equal(okid_set_scales(&id, in_scale, bad), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_set_scales(&id, NULL, out_scale), OKID_E_NULL_POINTER);
    assert_int_equal(okid_reset(&id), OKID_OK);
    assert_int_equal(okid_set_scales(&id, in_scale, bad), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_set_scales(&id, in_scale, out_scale), OKID_OK); /* the failed call changed nothing */
    free(ws);
    cfg.scaling = OKID_SCALING_NONE;
    ws = test_workspace(&cfg, &bytes);
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_set_scales(&id, in_scale, out_scale), OKID_E_NOT_AVAILABLE);
    free(ws);
    free(u);
    free(y);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_units_do_not_change_the_modes),
        cmocka_unit_test(test_mixed_units_need_scaling),
        cmocka_unit_test(test_scales_are_first_block_rms),
        cmocka_unit_test(test_scales_set_by_the_caller),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

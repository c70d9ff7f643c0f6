/* SPDX-License-Identifier: Apache-2.0 */
/* The modal parameters of the reference cases, flattened for the backend comparison. */
#include "backend_values.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "reference/reference_data.h"
#include "test_support.h"

static void add(backend_value *values, int max, int *count, const char *what, int mode, int index, double value,
                double scale, double tol)
{
    assert_true(*count < max);
    backend_value *v = &values[(*count)++];
    snprintf(v->name, sizeof v->name, "%s.%d.%d", what, mode, index);
    v->value = value;
    v->scale = scale;
    v->tol = tol;
}

/*
 * The output-only identifier (okid/ambient.h) on the paper's plant under unmeasured white forces on
 * both masses (40 000 samples, 5 % sensor noise, m = 2, L = 20, order 4): the correlation sums are
 * the same C code in both builds, so only the SVD of the 40 x 40 Hankel matrix (the Eigen backend's
 * leading-vector route), the eigenproblem and the indicators' solve differ. Double: 1e-9 as above.
 * Float: each SVD is backward stable, |dH| <= c k u |H| (k = 40 singular values, c a small
 * constant: 4 here), which moves an eigenvalue of A by at most about that times the realization's
 * condition sigma_1 / sigma_n, from each backend; the magnifications to frequency and damping are
 * those of the cases above.
 */
static int ambient_values(backend_value *values, int max)
{
    enum { N = 40000 };
    static const okid_real b2[4] = {1, 0, 0, 1};
    const okid_mechanical_model mm = {2, 2, 2, PAPER_MASS, PAPER_DAMPING, PAPER_STIFFNESS, b2, PAPER_CA, NULL, NULL};
    okid_real ac[16], bc[8], c[8], d[4], work[OKID_STATE_SPACE_WORK_REALS(2, 2)], a[16], b[8];
    okid_real zw[OKID_ZOH_WORK_REALS(4, 2)], x[4] = {0}, tmp[4];
    const okid_real dt = (okid_real)0.05;
    assert_int_equal(okid_model_state_space(&mm, ac, bc, c, d, work, sizeof work / sizeof work[0]), OKID_OK);
    assert_int_equal(okid_discretize_zoh(4, 2, ac, bc, dt, a, b, zw, sizeof zw / sizeof zw[0]), OKID_OK);
    okid_simulator sim;
    assert_int_equal(okid_simulator_init(&sim, 4, 2, 2, a, b, c, d, x, tmp), OKID_OK);
    okid_real *u = test_white_noise(2, N, 11), *e = test_white_noise(2, N, 11 + 7777u);
    okid_real *y = malloc(sizeof(okid_real) * 2u * N);
    assert_non_null(y);
    assert_int_equal(okid_simulate(&sim, N, u, 2, y, 2), OKID_OK);
    for (int i = 0; i < 2; ++i) {
        double power = 0;
        for (int t = 0; t < N; ++t) power += (double)y[2 * t + i] * (double)y[2 * t + i];
        const okid_real level = (okid_real)(0.05 * sqrt(power / N));
        for (int t = 0; t < N; ++t) y[2 * t + i] += level * e[2 * t + i];
    }
    okid_ambient_config cfg;
    assert_int_equal(okid_ambient_config_default(&cfg, 2), OKID_OK);
    cfg.dt = dt;
    cfg.hankel_rows = 20;
    cfg.order = 4;
    size_t bytes = 0;
    assert_int_equal(okid_ambient_workspace_size(&cfg, &bytes), OKID_OK);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15u) / 16u * 16u);
    assert_non_null(ws);
    okid_ambient amb;
    assert_int_equal(okid_ambient_init(&amb, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_ambient_push_block(&amb, N, y, 2, NULL), OKID_OK);
    okid_ambient_result res;
    assert_int_equal(okid_ambient_identify(&amb, &res), OKID_OK);
    int count = 0;
    add(values, max, &count, "ambient", 0, 0, res.num_modes, 1, 0);
    /* float: FLT_EPSILON / 2 is okid_real's rounding unit u */
    const double tol = TOL(1e-9, 2 * 4 * 40 * ((double)FLT_EPSILON / 2) * (double)res.realization_condition);
    for (int i = 0; i < 40; ++i) { /* relative to sigma_1: the backward error's scale */
        add(values, max, &count, "ambient_sv", i, 0, res.singular_values[i], res.singular_values[0], tol);
    }
    for (int i = 0; i < res.num_modes; ++i) {
        const okid_mode *md = &res.modes[i];
        const double lambda = hypot(md->eigenvalue.re, md->eigenvalue.im);
#if OKID_REAL_IS_FLOAT
        const double s_tol = tol / (hypot(md->pole.re, md->pole.im) * (double)dt);
        const double zeta_tol = 2 * s_tol / md->damping_ratio;
#else
        const double s_tol = tol, zeta_tol = tol;
#endif
        add(values, max, &count, "ambient_eigenvalue_re", i, 0, md->eigenvalue.re, lambda, tol);
        add(values, max, &count, "ambient_eigenvalue_im", i, 0, md->eigenvalue.im, lambda, tol);
        add(values, max, &count, "ambient_frequency_hz", i, 0, md->frequency_hz, fabs(md->frequency_hz), s_tol);
        add(values, max, &count, "ambient_damping_ratio", i, 0, md->damping_ratio, fabs(md->damping_ratio), zeta_tol);
        for (int k = 0; k < 2; ++k) {
            add(values, max, &count, "ambient_sensor_shape_re", i, k, md->sensor_shape[k].re, 1, s_tol);
            add(values, max, &count, "ambient_sensor_shape_im", i, k, md->sensor_shape[k].im, 1, s_tol);
        }
    }
    free(ws);
    free(y);
    free(u);
    free(e);
    return count;
}

int backend_case_values(backend_value *values, int max)
{
    /* case, samples and seed as in test_identify_accuracy */
    const struct {
        const ref_case *rc;
        size_t samples;
        uint64_t seed;
    } runs[] = {{&REF_PAPER, 1000, 2024}, {&REF_MIMO, 1500, 11}, {&REF_CHAIN3, 2000, 5}};
    int count = 0;
    for (size_t c = 0; c < sizeof runs / sizeof runs[0]; ++c) {
        const ref_case *rc = runs[c].rc;
        okid_config cfg;
        test_config(rc, &cfg);
        okid_identifier id;
        okid_result res;
        void *ws = NULL;
        assert_int_equal(test_identify_case(rc, &cfg, runs[c].samples, runs[c].seed, &id, &ws, &res), OKID_OK);
        add(values, max, &count, rc->name, 0, 0, res.num_modes, 1, 0);
        for (int i = 0; i < res.num_modes; ++i) {
            const okid_mode *md = &res.modes[i];
            const double lambda = hypot(md->eigenvalue.re, md->eigenvalue.im);
            const double tol = TOL(1e-9, 2 * identify_tol(rc));
#if OKID_REAL_IS_FLOAT /* the magnifications of assert_modes_match: s = ln(lambda) / dt, zeta = -Re s / |s| */
            const double s_tol = tol / (hypot(md->pole.re, md->pole.im) * rc->dt);
            const double zeta_tol = 2 * s_tol / md->damping_ratio;
#else
            const double s_tol = tol, zeta_tol = tol;
#endif
            add(values, max, &count, "eigenvalue_re", i, (int)c, md->eigenvalue.re, lambda, tol);
            add(values, max, &count, "eigenvalue_im", i, (int)c, md->eigenvalue.im, lambda, tol);
            add(values, max, &count, "frequency_hz", i, (int)c, md->frequency_hz, fabs(md->frequency_hz), s_tol);
            add(values, max, &count, "damping_ratio", i, (int)c, md->damping_ratio, fabs(md->damping_ratio), zeta_tol);
            for (int a = 0; a < rc->m; ++a) { /* unit norm, largest component real: relative to 1 */
                add(values, max, &count, "sensor_shape_re", i, a, md->sensor_shape[a].re, 1, s_tol);
                add(values, max, &count, "sensor_shape_im", i, a, md->sensor_shape[a].im, 1, s_tol);
            }
            add(values, max, &count, "emac", i, (int)c, md->emac, 1, s_tol); /* indicators lie in [0, 1] */
            add(values, max, &count, "mpc", i, (int)c, md->mpc, 1, s_tol);
            add(values, max, &count, "msv", i, (int)c, md->msv, fabs(md->msv), s_tol);
        }
        free(ws);
    }
    return count + ambient_values(values + count, max - count);
}

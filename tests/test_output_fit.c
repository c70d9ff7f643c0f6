/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The fit of each output (host_tools/common/output_fit.h) against closed forms: a static gain
 * y = D u explains its output exactly (100 %), an output of pure noise not at all (about 0 %, the
 * warning), and a first-order system fed in several blocks gives the same fit as in one; a
 * 6-state, 2-input, 3-output model's fit against the one computed from the library's simulator; a
 * model with a pole on or outside the unit circle gets none.
 */
#include <float.h>
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "okid/okid.h"
#include "output_fit.h"

enum { N = 400 };

/* A model x(k+1) = a x + b u, y = [c x + d0 u; d1 u] (n = 1, r = 1, m = 2). */
typedef struct small_model {
    okid_real a, b, c[2], d[2];
    okid_result res;
} small_model;

static void small_model_init(small_model *sm, okid_real a, okid_real b, okid_real c0, okid_real d0, okid_real d1)
{
    sm->a = a, sm->b = b, sm->c[0] = c0, sm->c[1] = 0, sm->d[0] = d0, sm->d[1] = d1;
    sm->res = (okid_result){0};
    sm->res.order = 1;
    sm->res.decimation = 1;
    sm->res.A = (okid_matrix){&sm->a, 1, 1, 1};
    sm->res.B = (okid_matrix){&sm->b, 1, 1, 1};
    sm->res.C = (okid_matrix){sm->c, 2, 1, 2};
    sm->res.D = (okid_matrix){sm->d, 2, 1, 2};
}

/* A deterministic, zero-mean, broadband sequence (no generator state shared between tests). */
static okid_real wobble(int k, int seed) { return (okid_real)sin(0.7 * k * k + 1.3 * seed * k + seed); }

static void test_static_gain_explains_everything_and_noise_nothing(void **state)
{
    (void)state;
    small_model sm;
    small_model_init(&sm, 0, 0, 0, 2, 1); /* y0 = 2 u (exact), y1 = u against an output of other noise */
    okid_real u[N], y[2 * N];
    for (int k = 0; k < N; ++k) {
        u[k] = wobble(k, 1);
        y[2 * k] = 2 * u[k];
        y[2 * k + 1] = wobble(k, 2);
    }
    double fit[2];
    unsigned warning = 1234;
    assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), 0);
    /* 100 (1 - 0 / |y0 - mean|): exact to round-off of the sums, N eps relative */
    assert_true(fabs(fit[0] - 100.0) < 1e-9);
    /* y1 and u are unrelated: |y1 - u| ~ sqrt(2) |y1| and the fit 100 (1 - sqrt 2) ~ -41 %; within
       +-15 % of it for N = 400 (the correlation of two such sequences is O(1/sqrt N) = 0.05) */
    assert_true(fit[1] < -26 && fit[1] > -56);
    assert_int_equal(warning, 0u); /* one output explained: no warning */
    small_model_init(&sm, 0, 0, 0, 0, 1);
    for (int k = 0; k < N; ++k) y[2 * k] = wobble(k, 3);
    assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), 0);
    double mean = 0, all = 0, spread = 0; /* yhat = 0: 100 (1 - |y0| / |y0 - mean|), a little below 0 */
    for (int k = 0; k < N; ++k) mean += (double)y[2 * k] / N;
    for (int k = 0; k < N; ++k) all += (double)y[2 * k] * y[2 * k], spread += ((double)y[2 * k] - mean) * (y[2 * k] - mean);
    assert_true(fabs(fit[0] - 100 * (1 - sqrt(all / spread))) < 1e-9 && fit[0] <= 0);
    assert_int_equal(warning, OKID_W_NO_OUTPUT_EXPLAINED);
}

static void test_blocks_give_the_one_push_fit(void **state)
{
    (void)state;
    small_model sm;
    small_model_init(&sm, (okid_real)0.9, 1, (okid_real)0.5, 0, 1);
    okid_real u[N], y[2 * N], x = 0;
    for (int k = 0; k < N; ++k) { /* the model's own response plus a little "noise" */
        u[k] = wobble(k, 4);
        y[2 * k] = (okid_real)0.5 * x + (okid_real)0.01 * wobble(k, 5);
        y[2 * k + 1] = u[k];
        x = (okid_real)0.9 * x + u[k];
    }
    double whole[2], parts[2];
    unsigned warning;
    assert_int_equal(output_fit_record(&sm.res, N, u, y, whole, &warning), 0);
    output_fit *f = output_fit_begin(&sm.res);
    assert_non_null(f);
    output_fit_push(f, 7, u, y);
    output_fit_push(f, N - 7 - 100, u + 7, y + 2 * 7);
    output_fit_push(f, 100, u + N - 100, y + 2 * (N - 100));
    assert_int_equal(output_fit_end(f, parts), 0u);
    assert_true(whole[0] > 90 && whole[0] < 100); /* |e| = 1 % of a response of RMS ~ 1 */
    assert_true(whole[1] == 100.0);
    /* the same samples in the same order: the same sums, bit for bit */
    assert_memory_equal(whole, parts, sizeof whole);
}

static void test_undefined_fits(void **state)
{
    (void)state;
    small_model sm;
    small_model_init(&sm, 0, 0, 0, 1, 1);
    okid_real u[N], y[2 * N];
    for (int k = 0; k < N; ++k) u[k] = wobble(k, 6), y[2 * k] = u[k], y[2 * k + 1] = 5; /* y1 constant */
    double fit[2];
    unsigned warning;
    assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), 0);
    assert_true(fit[0] == 100.0 && isnan(fit[1])); /* a constant output has no spread to explain */
    assert_int_equal(warning, 0u);
    u[10] = (okid_real)NAN; /* a non-finite input: no fit, and no warning made of it */
    assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), 0);
    assert_true(isnan(fit[0]) && isnan(fit[1]));
    assert_int_equal(warning, 0u);
    sm.res.decimation = 2; /* a decimated model's inputs are the identifier's filtered record */
    assert_null(output_fit_begin(&sm.res));
    assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), -1);
    char why[320];
    assert_int_equal(output_fit_missing(2, 0.5, why, sizeof why), 1);
    assert_non_null(strstr(why, "decimation 2"));
    assert_int_equal(output_fit_missing(1, 0.5, why, sizeof why), 0);
    assert_string_equal(why, "");
}

/* A model with a pole outside the unit circle (x(k+1) = 1.05 x + u) gets no fit: its response from
   rest grows as 1.05^k, 1e8 after N samples, and "fit" would then report the growth as a huge
   negative percentage (or NaN after an overflow). A pole on the circle (a = 1: an integrator) is
   refused as OKID_W_UNSTABLE_POLE flags it; a stable one (0.5) is fitted. */
static void test_unstable_model_gets_no_fit(void **state)
{
    (void)state;
    small_model sm;
    okid_mode pole = {0};
    okid_real u[N], y[2 * N];
    for (int k = 0; k < N; ++k) u[k] = wobble(k, 7), y[2 * k] = u[k], y[2 * k + 1] = u[k];
    double fit[2];
    unsigned warning;
    char why[320];
    const okid_real radii[3] = {(okid_real)1.05, 1, (okid_real)0.5};
    for (int i = 0; i < 3; ++i) {
        small_model_init(&sm, radii[i], 1, 1, 0, 1);
        pole.eigenvalue = (okid_complex){radii[i], 0};
        sm.res.num_modes = 1, sm.res.modes = &pole;
        assert_true(output_fit_largest_radius(&sm.res) == (double)radii[i]);
        const int refused = radii[i] >= 1;
        assert_int_equal(output_fit_record(&sm.res, N, u, y, fit, &warning), refused ? -1 : 0);
        assert_int_equal(output_fit_missing(1, output_fit_largest_radius(&sm.res), why, sizeof why), refused);
        if (refused) assert_non_null(strstr(why, "outside the unit circle"));
        if (!refused) assert_true(isfinite(fit[0]) && fit[1] == 100.0);
    }
}

/* output_fit's own simulation loop against okid_simulate() (four xGEMM calls a sample): a stable
   6-state model with 2 inputs and 3 outputs, its outputs the simulator's response plus a known
   disturbance e. The fit from the simulator's response is computed here in full; the two differ by
   the simulations' round-off alone. */
static void test_fit_matches_the_library_simulator(void **state)
{
    (void)state;
    enum { n = 6, r = 2, m = 3, LEN = 3000 };
    static okid_real a[n * n], b[n * r], c[m * n], d[m * r], x[n], tmp[n], u[LEN * r], yhat[LEN * m], y[LEN * m];
    for (int j = 0; j < n; ++j) { /* three damped rotations, radius 0.9-0.96, lightly coupled */
        for (int i = 0; i < n; ++i) a[i + j * n] = (okid_real)(0.01 * wobble(i + n * j, 1));
    }
    for (int q = 0; q < 3; ++q) {
        const double radius = 0.9 + 0.03 * q, angle = 0.3 + 0.5 * q;
        a[2 * q + 2 * q * n] = a[2 * q + 1 + (2 * q + 1) * n] = (okid_real)(radius * cos(angle));
        a[2 * q + (2 * q + 1) * n] = (okid_real)(radius * sin(angle));
        a[2 * q + 1 + 2 * q * n] = (okid_real)(-radius * sin(angle));
    }
    for (int i = 0; i < n * r; ++i) b[i] = wobble(i, 2);
    for (int i = 0; i < m * n; ++i) c[i] = wobble(i, 3);
    for (int i = 0; i < m * r; ++i) d[i] = (okid_real)(0.1 * wobble(i, 4));
    for (int i = 0; i < LEN * r; ++i) u[i] = wobble(i, 5);
    okid_simulator sim;
    assert_int_equal(okid_simulator_init(&sim, n, r, m, a, b, c, d, x, tmp), OKID_OK);
    assert_int_equal(okid_simulate(&sim, LEN, u, r, yhat, m), OKID_OK);
    double error[m] = {0}, mean[m] = {0}, spread[m] = {0}, scale = 0;
    for (int k = 0; k < LEN; ++k) {
        for (int i = 0; i < m; ++i) {
            const double e = 0.1 * (double)wobble(k * m + i, 6 + i);
            y[k * m + i] = (okid_real)((double)yhat[k * m + i] + e);
            mean[i] += (double)y[k * m + i] / LEN;
        }
    }
    for (int k = 0; k < LEN; ++k) {
        for (int i = 0; i < m; ++i) {
            const double v = (double)y[k * m + i], e = v - (double)yhat[k * m + i];
            error[i] += e * e, spread[i] += (v - mean[i]) * (v - mean[i]);
            scale = fmax(scale, fabs(v));
        }
    }
    okid_result res = {0};
    res.order = n;
    res.decimation = 1;
    res.A = (okid_matrix){a, n, n, n}, res.B = (okid_matrix){b, n, r, n};
    res.C = (okid_matrix){c, m, n, m}, res.D = (okid_matrix){d, m, r, m};
    double fit[m];
    unsigned warning;
    assert_int_equal(output_fit_record(&res, LEN, u, y, fit, &warning), 0);
    /* Each simulated output differs by the round-off of two sums of n + r terms, carried through A
       (radius <= 0.96: at most 1 / (1 - 0.96) = 25 steps' worth): |dyhat| <= 2 (n + r) u 25 |y|max
       with u the unit round-off; the fit moves by 100 |dyhat| sqrt(LEN) / |y - mean| at most; the
       check allows 10 times that. */
    const double unit = (sizeof(okid_real) == sizeof(float) ? (double)FLT_EPSILON : DBL_EPSILON) / 2;
    for (int i = 0; i < m; ++i) {
        const double expected = 100.0 * (1.0 - sqrt(error[i]) / sqrt(spread[i]));
        const double bound = 10 * 100.0 * 2 * (n + r) * unit * 25 * scale * sqrt((double)LEN) / sqrt(spread[i]);
        assert_true(expected > 50 && expected < 99); /* the disturbance is a real part of each output */
        assert_true(fabs(fit[i] - expected) <= bound);
    }
    assert_int_equal(warning, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_gain_explains_everything_and_noise_nothing),
        cmocka_unit_test(test_blocks_give_the_one_push_fit),
        cmocka_unit_test(test_undefined_fits),
        cmocka_unit_test(test_unstable_model_gets_no_fit),
        cmocka_unit_test(test_fit_matches_the_library_simulator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The fit of each output (host_tools/common/output_fit.h) against closed forms: a static gain
 * y = D u explains its output exactly (100 %), an output of pure noise not at all (about 0 %, the
 * warning), and a first-order system fed in several blocks gives the same fit as in one.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
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
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_static_gain_explains_everything_and_noise_nothing),
        cmocka_unit_test(test_blocks_give_the_one_push_fit),
        cmocka_unit_test(test_undefined_fits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's residual tests and its covariance under misfit (okid/refine.h): the Ljung-Box
 * statistic, largest autocorrelation and fit of each output against the same figures computed
 * here from the refined model's own residuals; quiet on white noise; the warning names the output
 * under an unmeasured force and under a drift; with an unmeasured force the sandwich covariance
 * replaces the Fisher one and its +-2 sigma intervals hold the exact modes (a small Monte Carlo:
 * the coverage study over many records is scripts/refine_coverage.py). The input-residual
 * cross-correlation test against the same figures computed here: quiet on white noise and under
 * the unmeasured force (coloured but independent of the input), raised where the model misses
 * the input's dynamics (order 2, a wrong D).
 */
#include "refine_paper_case.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { M_OUT = PAPER_OUTPUTS };

/* Entry (i, j) of a column-major matrix. */
#define AT(mat, i, j) ((mat).data[(size_t)(j) * (size_t)(mat).ld + (size_t)(i)])

typedef refine_run run;

/* OKID/ERA (p = h = 20, n = 4) and the output-error refinement over the record. */
static okid_refine_state identify_and_refine(run *rn, double dt, size_t count, const okid_real *u, const okid_real *y)
{
    return paper_identify_and_refine(rn, dt, count, u, y, OKID_REFINE_OUTPUT_ERROR, 0);
}

#define free_run refine_run_free

/* The cross-correlation test of one output recomputed from its residuals e (stride M_OUT) and the
   input, as refine.h defines it: sums over k >= l centred with the record's means, Bartlett's v
   from the centred autocorrelations at lags 1..OKID_REFINE_LAGS-1 (at least 1). */
static double g_xmax[M_OUT], g_xstat[M_OUT];

static void reference_cross(const double *e, int i, size_t count, const okid_real *u)
{
    const int lags = OKID_REFINE_LAGS;
    const double nn = (double)count;
    double em = 0, um = 0;
    for (size_t k = 0; k < count; ++k) {
        em += e[M_OUT * k + i];
        um += (double)u[k];
    }
    em /= nn;
    um /= nn;
    double lag[3][OKID_REFINE_LAGS]; /* e-u, e-e, u-u products at each lag, uncentred */
    for (int l = 0; l < lags; ++l) {
        lag[0][l] = lag[1][l] = lag[2][l] = 0;
        for (size_t k = (size_t)l; k < count; ++k) {
            const double ek = e[M_OUT * k + i], el = e[M_OUT * (k - (size_t)l) + i];
            lag[0][l] += ek * (double)u[k - (size_t)l];
            lag[1][l] += ek * el;
            lag[2][l] += (double)u[k] * (double)u[k - (size_t)l];
        }
    }
    const double see = lag[1][0] - nn * em * em, suu = lag[2][0] - nn * um * um;
    double v = 1, largest = 0;
    for (int l = 1; l < lags; ++l) {
        v += 2 * (lag[1][l] - nn * em * em) / see * (lag[2][l] - nn * um * um) / suu;
    }
    v = v > 1 ? v : 1;
    for (int l = 0; l < lags; ++l) {
        const double rho = fabs(lag[0][l] - nn * em * um) / sqrt(see * suu);
        largest = rho > largest ? rho : largest;
    }
    g_xmax[i] = largest;
    g_xstat[i] = largest * sqrt(nn / v);
}

/*
 * The residual tests recomputed here, in double, from the refined model (A, B, C, D, x0) run over
 * the record: Ljung-Box Q, the largest |r_l| and the fit of each output, as refine.h defines them
 * (and the cross-correlation test into g_xmax, g_xstat).
 */
static void reference_tests(const okid_refine_result *out, size_t count, const okid_real *u, const okid_real *y,
                            double q[M_OUT], double largest[M_OUT], double fit[M_OUT])
{
    const int n = out->order, lags = OKID_REFINE_LAGS;
    double x[8], next[8];
    double *e = malloc(sizeof(double) * M_OUT * count);
    assert_non_null(e);
    for (int i = 0; i < n; ++i) x[i] = (double)out->initial_state[i];
    for (size_t k = 0; k < count; ++k) {
        for (int i = 0; i < M_OUT; ++i) {
            double yhat = (double)AT(out->D, i, 0) * (double)u[k];
            for (int j = 0; j < n; ++j) yhat += (double)AT(out->C, i, j) * x[j];
            e[M_OUT * k + i] = (double)y[M_OUT * k + i] - yhat;
        }
        for (int i = 0; i < n; ++i) {
            next[i] = (double)AT(out->B, i, 0) * (double)u[k];
            for (int j = 0; j < n; ++j) next[i] += (double)AT(out->A, i, j) * x[j];
        }
        memcpy(x, next, sizeof(double) * (size_t)n);
    }
    const double nn = (double)count;
    for (int i = 0; i < M_OUT; ++i) {
        double ss = 0, yy = 0, ys = 0;
        for (size_t k = 0; k < count; ++k) {
            ss += e[M_OUT * k + i] * e[M_OUT * k + i];
            yy += (double)y[M_OUT * k + i] * (double)y[M_OUT * k + i];
            ys += (double)y[M_OUT * k + i];
        }
        q[i] = largest[i] = 0;
        for (int l = 1; l <= lags; ++l) {
            double c = 0;
            for (size_t k = (size_t)l; k < count; ++k) c += e[M_OUT * k + i] * e[M_OUT * (k - (size_t)l) + i];
            const double r = c / ss;
            q[i] += r * r / (nn - l);
            largest[i] = fabs(r) > largest[i] ? fabs(r) : largest[i];
        }
        q[i] *= nn * (nn + 2);
        fit[i] = 100 * (1 - sqrt(ss / (yy - ys * ys / nn)));
        reference_cross(e, i, count, u);
    }
    free(e);
}

/*
 * The refiner's cross-correlation figures against the reference: the same sums in another order
 * (round-off of 2001-term sums, ~1e-13 relative in double). Float: the residuals carry float's
 * 1e-7 relative output error, 2e-6 of a 5 % residual, and the ring's sums of 2001 products add
 * ~1e-4 relative (N eps); |rho| <= 1 so 2e-3 absolute, and the statistic (|rho| sqrt(N / v), sqrt(N)
 * = 45) 0.1 absolute.
 */
static void check_cross(const okid_refine_result *out, int i)
{
    assert_true(fabs((double)out->max_input_correlation[i] - g_xmax[i]) <= TOL(1e-9, 2e-3));
    assert_true(fabs((double)out->input_correlation[i] - g_xstat[i]) <= TOL(1e-7, 1e-1));
    assert_true((out->input_correlation[i] > (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND) ==
                ((out->output_warnings[i] & OKID_W_RESIDUAL_INPUT_CORRELATED) != 0));
}

/* White output noise: the tests agree with the reference, pass, and the stds stay Fisher's. */
static void test_white_noise_is_quiet(void **state)
{
    (void)state;
    const double dt = 0.05;
    const size_t count = 2001;
    okid_real *u, *y;
    paper_record(dt, count, 17, 0, 0.05, &u, &y);
    run rn;
    memset(&rn, 0, sizeof rn);
    assert_int_equal(identify_and_refine(&rn, dt, count, u, y), OKID_REFINE_CONVERGED);
    double q[M_OUT], largest[M_OUT], fit[M_OUT];
    reference_tests(&rn.out, count, u, y, q, largest, fit);
    for (int i = 0; i < M_OUT; ++i) {
        print_message("white: output %d Q %.4f (ref %.4f), max |r| %.4f (band %.4f), fit %.3f %% (ref %.3f)\n", i + 1,
                      (double)rn.out.whiteness[i], q[i], (double)rn.out.max_autocorrelation[i],
                      (double)rn.out.autocorrelation_band, (double)rn.out.fit_percent[i], fit[i]);
        /* the refiner's residuals are those of the same recursion in another order: round-off of a
           2001-sample sum (~1e-13 relative in double) against Q's sensitivity; float: the residuals
           are 5 % of the output, so float's 1e-7 relative output error is 2e-6 of them, squared sums ~1e-4 */
        assert_true(fabs((double)rn.out.whiteness[i] - q[i]) <= TOL(1e-8, 2e-2) * (q[i] + 1));
        assert_true(fabs((double)rn.out.max_autocorrelation[i] - largest[i]) <= TOL(1e-10, 1e-3));
        assert_true(fabs((double)rn.out.fit_percent[i] - fit[i]) <= TOL(1e-9, 1e-2));
        print_message("white: output %d cross-correlation statistic %.4f (ref %.4f), max |rho| %.4f (ref %.4f), band %.4f\n",
                      i + 1, (double)rn.out.input_correlation[i], g_xstat[i], (double)rn.out.max_input_correlation[i],
                      g_xmax[i], (double)rn.out.input_correlation_band[i]);
        check_cross(&rn.out, i);
        assert_true(rn.out.whiteness[i] < OKID_REFINE_WHITENESS_BOUND);
        assert_true(rn.out.input_correlation[i] < (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND);
        assert_int_equal(rn.out.output_warnings[i], 0);
        assert_true(fit[i] > 90); /* 5 % noise: fit 95 % */
    }
    assert_true(fabs((double)rn.out.autocorrelation_band - 1.96 / sqrt((double)count)) < 1e-6);
    assert_int_equal(rn.out.warnings & (OKID_W_RESIDUAL_NOT_WHITE | OKID_W_OUTPUT_NOT_EXPLAINED |
                                        OKID_W_RESIDUAL_INPUT_CORRELATED), 0);
    assert_int_equal(rn.out.covariance, OKID_REFINE_COVARIANCE_FISHER);
    free_run(&rn);
    free(u);
    free(y);
}

/* Noise-free data: the residuals are round-off (correlated, but no noise to test): no warning. */
static void test_noise_free_fails_no_test(void **state)
{
    (void)state;
    const double dt = 0.05;
    const size_t count = 1001;
    okid_real *u, *y;
    paper_record(dt, count, 5, 0, 0, &u, &y);
    run rn;
    memset(&rn, 0, sizeof rn);
    assert_int_equal(identify_and_refine(&rn, dt, count, u, y), OKID_REFINE_CONVERGED);
    for (int i = 0; i < M_OUT; ++i) {
        assert_int_equal(rn.out.output_warnings[i], 0);
        assert_true(rn.out.fit_percent[i] > 99.99);
    }
    assert_int_equal(rn.out.warnings & (OKID_W_RESIDUAL_NOT_WHITE | OKID_W_OUTPUT_NOT_EXPLAINED |
                                        OKID_W_RESIDUAL_INPUT_CORRELATED), 0);
    assert_int_equal(rn.out.covariance, OKID_REFINE_COVARIANCE_FISHER);
    free_run(&rn);
    free(u);
    free(y);
}

/* A drift (offset and slow ramp) on output 2: that output, and only the residual tests, say so. */
static void test_drift_names_the_output(void **state)
{
    (void)state;
    const double dt = 0.05;
    const size_t count = 2001;
    okid_real *u, *y;
    paper_record(dt, count, 23, 0, 0.02, &u, &y);
    double rms2 = 0;
    for (size_t k = 0; k < count; ++k) rms2 += (double)y[2 * k + 1] * (double)y[2 * k + 1];
    rms2 = sqrt(rms2 / (double)count);
    for (size_t k = 0; k < count; ++k) y[2 * k + 1] += (okid_real)(rms2 * (0.5 + 1.5 * (double)k / (double)count));
    run rn;
    memset(&rn, 0, sizeof rn);
    (void)identify_and_refine(&rn, dt, count, u, y);
    double q[M_OUT], largest[M_OUT], fit[M_OUT];
    reference_tests(&rn.out, count, u, y, q, largest, fit);
    for (int i = 0; i < M_OUT; ++i) {
        print_message("drift on output 2: output %d Q %.1f (ref %.1f), max |r| %.3f, fit %.1f %%, bits %u\n", i + 1,
                      (double)rn.out.whiteness[i], q[i], (double)rn.out.max_autocorrelation[i],
                      (double)rn.out.fit_percent[i], rn.out.output_warnings[i]);
        assert_true(fabs((double)rn.out.whiteness[i] - q[i]) <= TOL(1e-7, 2e-2) * (q[i] + 1));
        print_message("drift on output 2: output %d cross-correlation statistic %.3f (ref %.3f)\n", i + 1,
                      (double)rn.out.input_correlation[i], g_xstat[i]);
        check_cross(&rn.out, i);
    }
    assert_true(rn.out.output_warnings[1] & OKID_W_RESIDUAL_NOT_WHITE);
    assert_true(rn.out.warnings & OKID_W_RESIDUAL_NOT_WHITE);
    free_run(&rn);
    free(u);
    free(y);
}

/*
 * The model misses some of the input's dynamics: refined at order 2 (one of the two modes) on
 * white-noise records, or its start's D set to 0 with max_passes 2 (the result is then the start
 * model, the wrong D unrefined: acceleration outputs feed the force through). The cross-correlation
 * test agrees with the reference and names the output.
 */
static void test_missed_dynamics_correlated(void **state)
{
    (void)state;
    const double dt = 0.05;
    const size_t count = 2001;
    enum { RECORDS = 6 };
    int flagged = 0;
    for (int s = 0; s < RECORDS; ++s) {
        okid_real *u, *y;
        paper_record(dt, count, 400u + (uint64_t)s, 0, 0.05, &u, &y);
        run rn;
        memset(&rn, 0, sizeof rn);
        (void)paper_identify_and_refine_with(&rn, dt, count, u, y, OKID_REFINE_OUTPUT_ERROR, 0, 2, 0, 1);
        double q[M_OUT], largest[M_OUT], fit[M_OUT];
        reference_tests(&rn.out, count, u, y, q, largest, fit);
        for (int i = 0; i < M_OUT; ++i) {
            print_message("order 2, record %d: output %d statistic %.3f (ref %.3f), max |rho| %.3f, bits %u\n", s,
                          i + 1, (double)rn.out.input_correlation[i], g_xstat[i],
                          (double)rn.out.max_input_correlation[i], rn.out.output_warnings[i]);
            check_cross(&rn.out, i);
        }
        flagged += (rn.out.warnings & OKID_W_RESIDUAL_INPUT_CORRELATED) != 0;
        free_run(&rn);
        memset(&rn, 0, sizeof rn);
        assert_int_equal(paper_identify_and_refine_with(&rn, dt, count, u, y, OKID_REFINE_OUTPUT_ERROR, 0, 4, 2, 0),
                         OKID_REFINE_ITERATION_LIMIT);
        reference_tests(&rn.out, count, u, y, q, largest, fit);
        for (int i = 0; i < M_OUT; ++i) {
            print_message("D = 0, record %d: output %d statistic %.3f (ref %.3f), max |rho| %.3f, bits %u\n", s, i + 1,
                          (double)rn.out.input_correlation[i], g_xstat[i], (double)rn.out.max_input_correlation[i],
                          rn.out.output_warnings[i]);
            check_cross(&rn.out, i);
        }
        assert_true(rn.out.output_warnings[0] & OKID_W_RESIDUAL_INPUT_CORRELATED);
        free_run(&rn);
        free(u);
        free(y);
    }
    print_message("order 2: %d of %d records flagged correlated with the input\n", flagged, RECORDS);
    assert_int_equal(flagged, RECORDS);
}

/*
 * An unmeasured white force of 30 % on mass 2 and 2 % output noise: the residuals are coloured,
 * both outputs are flagged, the stds are the sandwich ones, and over a few records their +-2 sigma
 * intervals hold the exact frequencies and damping ratios (the Fisher ones held 36-70 %).
 */
static void test_unmeasured_force_sandwich(void **state)
{
    (void)state;
    const double dt = 0.05;
    const size_t count = 2001;
    enum { RECORDS = 8 };
    const double truth[4] = {REF_PAPER.freq_hz[0], REF_PAPER.freq_hz[1], REF_PAPER.damping_ratio[0],
                             REF_PAPER.damping_ratio[1]};
    int inside = 0, checks = 0, flagged = 0, correlated = 0;
    for (int s = 0; s < RECORDS; ++s) {
        okid_real *u, *y;
        paper_record(dt, count, 300u + (uint64_t)s, 0.3, 0.02, &u, &y);
        run rn;
        memset(&rn, 0, sizeof rn);
        (void)identify_and_refine(&rn, dt, count, u, y);
        flagged += (rn.out.warnings & OKID_W_RESIDUAL_NOT_WHITE) != 0;
        if (s == 0) {
            double q[M_OUT], largest[M_OUT], fit[M_OUT];
            reference_tests(&rn.out, count, u, y, q, largest, fit);
            for (int i = 0; i < M_OUT; ++i) {
                print_message("unmeasured force: output %d Q %.1f (ref %.1f), max |r| %.3f, fit %.1f %%\n", i + 1,
                              (double)rn.out.whiteness[i], q[i], (double)rn.out.max_autocorrelation[i],
                              (double)rn.out.fit_percent[i]);
                assert_true(fabs((double)rn.out.whiteness[i] - q[i]) <= TOL(1e-7, 2e-2) * (q[i] + 1));
                assert_true(rn.out.output_warnings[i] & OKID_W_RESIDUAL_NOT_WHITE);
                print_message("unmeasured force: output %d cross-correlation statistic %.3f (ref %.3f), band %.4f\n",
                              i + 1, (double)rn.out.input_correlation[i], g_xstat[i],
                              (double)rn.out.input_correlation_band[i]);
                check_cross(&rn.out, i);
            }
        }
        for (int i = 0; i < M_OUT; ++i) {
            correlated += (rn.out.output_warnings[i] & OKID_W_RESIDUAL_INPUT_CORRELATED) != 0;
        }
        int pairs = 0;
        for (int i = 0; i < rn.out.num_modes && pairs < 2; ++i) {
            if (!rn.out.modes[i].is_pair) continue;
            const double got[2] = {(double)rn.out.modes[i].frequency_hz, (double)rn.out.modes[i].damping_ratio};
            const double sd[2] = {(double)rn.out.mode_std[i].frequency_hz, (double)rn.out.mode_std[i].damping_ratio};
            for (int k = 0; k < 2; ++k) {
                assert_true(sd[k] > 0);
                inside += fabs(got[k] - truth[2 * k + pairs]) <= 2 * sd[k];
                ++checks;
            }
            ++pairs;
        }
        assert_int_equal(pairs, 2);
        if (rn.out.warnings & OKID_W_RESIDUAL_NOT_WHITE) {
            assert_int_equal(rn.out.covariance, OKID_REFINE_COVARIANCE_SANDWICH);
        }
        free_run(&rn);
        free(u);
        free(y);
    }
    print_message("unmeasured force: %d of %d records flagged, +-2 sigma coverage %d of %d\n", flagged, RECORDS,
                  inside, checks);
    assert_int_equal(flagged, RECORDS);
    /* the force nobody measured is independent of the measured one: the residual is coloured but
       not correlated with the input; at <= 0.1 % per (output, input) pair, 2 or more of these 16
       pairs flagged has probability ~1e-4 */
    print_message("unmeasured force: %d of %d outputs correlated with the input\n", correlated, 2 * RECORDS);
    assert_true(correlated <= 1);
    /* 32 checks at a true 95 % give >= 26 with probability 0.999 (binomial, if independent); the
       Fisher stds (coverage 36-70 %) give >= 26 with probability below 0.01 */
    assert_true(inside >= 26);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_white_noise_is_quiet),
        cmocka_unit_test(test_noise_free_fails_no_test),
        cmocka_unit_test(test_drift_names_the_output),
        cmocka_unit_test(test_unmeasured_force_sandwich),
        cmocka_unit_test(test_missed_dynamics_correlated),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

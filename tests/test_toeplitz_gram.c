/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The correlation form's Toeplitz block Gram (pipeline/toeplitz_gram.c) against the explicit Gram
 * of the same regressor rows summed here in long double, for several (r, m, p, rows): rows built by
 * the sample buffer from random samples, from rest or not, channel-scaled, with a gap (the window
 * restarted) inside the block, and a block of one row. Then the identifier: the correlation form
 * (Toeplitz Gram without forgetting, xSYRK with it) against the QR fold with decimation, automatic
 * scaling, a non-finite sample inside a block and a partial block at identify.
 */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "pipeline/channel_scaling.h"
#include "pipeline/sample_buffer.h"
#include "pipeline/toeplitz_gram.h"

enum { MAX_W = 64, MAX_ROWS = 80, MAX_N = 8 };

static const double EPS = sizeof(okid_real) == sizeof(float) ? (double)FLT_EPSILON : DBL_EPSILON;

typedef struct gram_case {
    int r, m, p, rows, gap;  /* gap: the window restarts before this sample (0: none) */
    int zero_initial, scaled;
} gram_case;

/* The (channel, lag) of every row column, read from a row whose window holds channel s at lag l as
   100 l + s + 1: the layout as the sample buffer writes it, not as the code under test assumes. */
static void probe_layout(int r, int m, int p, int *channel, int *lag)
{
    const int n = r + m, w = n * (p + 1);
    okid_real ring_data[MAX_N * 16], z[MAX_N], row[MAX_W];
    okid_ring_ ring = {ring_data, n, p, 0, 0};
    okid_ring_restart(&ring, 0);
    for (int l = p; l >= 1; --l) {
        for (int s = 0; s < n; ++s) {
            z[s] = (okid_real)(100 * l + s + 1);
        }
        okid_ring_append(&ring, z, r, z + r, m);
    }
    for (int s = 0; s < n; ++s) {
        z[s] = (okid_real)(s + 1);
    }
    okid_buffer_write_row(&ring, r, z, z + r, row, 1);
    for (int c = 0; c < w; ++c) {
        const int code = (int)row[c];
        channel[c] = code % 100 - 1;
        lag[c] = code / 100;
    }
}

/* The rows of one case (rows x w, leading dimension MAX_ROWS), as the identifier builds them. */
static int build_rows(const gram_case *gc, uint64_t seed, okid_real *block)
{
    const int n = gc->r + gc->m, samples = gc->rows + 2 * gc->p + 2;
    okid_real ring_data[MAX_N * 16];
    okid_ring_ ring = {ring_data, n, gc->p, 0, 0};
    okid_ring_restart(&ring, gc->zero_initial);
    okid_real *z = test_white_noise(n, (size_t)samples, seed);
    int rows = 0;
    for (int k = 0; k < samples && rows < gc->rows; ++k) {
        if (gc->gap > 0 && k == gc->gap) {
            okid_ring_restart(&ring, 0);
        }
        const okid_real *zk = z + (size_t)k * (size_t)n;
        if (okid_ring_full(&ring)) {
            okid_buffer_write_row(&ring, gc->r, zk, zk + gc->r, block + rows, MAX_ROWS);
            ++rows;
        }
        okid_ring_append(&ring, zk, gc->r, zk + gc->r, gc->m);
    }
    free(z);
    if (gc->scaled) {
        okid_real scales[MAX_N];
        for (int s = 0; s < n; ++s) {
            scales[s] = (okid_real)(0.25 + 0.5 * s);
        }
        okid_scaling_apply(gc->r, gc->m, gc->p, scales, rows, block, MAX_ROWS, NULL, 0, MAX_ROWS);
    }
    return rows;
}

static void check_case(const gram_case *gc)
{
    const int n = gc->r + gc->m, w = n * (gc->p + 1);
    static okid_real block[MAX_ROWS * MAX_W], c[MAX_W * MAX_W], work[(MAX_N + 2) * MAX_W + 1];
    static long double exact[MAX_W * MAX_W], size[MAX_W * MAX_W];
    int channel[MAX_W], lag[MAX_W];
    probe_layout(gc->r, gc->m, gc->p, channel, lag);
    const int rows = build_rows(gc, 11 + (uint64_t)w, block);
    assert_int_equal(rows, gc->rows);
    /* an accumulated matrix to add to: upper triangle 1 + i + j, strict lower triangle a sentinel */
    for (int j = 0; j < w; ++j) {
        for (int i = 0; i < w; ++i) {
            c[i + j * w] = i <= j ? (okid_real)(1 + i + j) : (okid_real)-7;
        }
    }
    for (int a = 0; a < w; ++a) {
        for (int b = 0; b < w; ++b) {
            long double s = 0, abs_s = 0;
            for (int t = 0; t < rows; ++t) {
                const long double x = (long double)block[t + a * MAX_ROWS] * (long double)block[t + b * MAX_ROWS];
                s += x;
                abs_s += fabsl(x);
            }
            exact[a + b * w] = s;
            size[a + b * w] = abs_s;
        }
    }
    assert_int_equal(okid_toeplitz_gram(gc->r, gc->m, gc->p, rows, block, MAX_ROWS, c, w, work), OKID_OK);
    double worst = 0;
    for (int b = 0; b < w; ++b) {
        for (int a = 0; a < w; ++a) {
            if (a > b) {
                assert_true(c[a + b * w] == (okid_real)-7); /* the lower triangle is not touched */
                continue;
            }
            /*
             * Entry (a, b) comes from G_0(d) by min(lag) recursion steps along its block diagonal,
             * each adding one first-row and one last-row product: its error is at most
             * gamma_(rows + 3 p + 2) times the sum of |products| over the entries of that chain
             * (the first-row product's GEMM error, the steps' roundings, the addition to c).
             */
            const int steps = lag[a] < lag[b] ? lag[a] : lag[b];
            long double chain = (long double)(1 + a + b);
            for (int t = 0; t <= steps; ++t) {
                for (int a2 = 0; a2 < w; ++a2) {
                    for (int b2 = 0; b2 < w; ++b2) {
                        if (channel[a2] == channel[a] && channel[b2] == channel[b] && lag[a2] == lag[a] - t
                            && lag[b2] == lag[b] - t) {
                            chain += size[a2 + b2 * w];
                        }
                    }
                }
            }
            const double tol = (gc->rows + 3 * gc->p + 2) * EPS * (double)chain;
            const double err = fabs((double)((long double)c[a + b * w] - (1 + a + b) - exact[a + b * w]));
            assert_true(err <= tol);
            worst = fmax(worst, err / tol);
        }
    }
    print_message("r %d, m %d, p %d, %d rows, gap %d, zero_initial %d, scaled %d: largest error %.3g of its bound\n",
                  gc->r, gc->m, gc->p, rows, gc->gap, gc->zero_initial, gc->scaled, worst);
}

static void test_gram_against_explicit_sum(void **state)
{
    (void)state;
    const gram_case cases[] = {
        {1, 2, 3, 40, 0, 0, 0},  {2, 3, 5, 64, 0, 1, 0}, {1, 1, 0, 9, 0, 0, 1},  {3, 2, 4, 77, 0, 0, 1},
        {1, 2, 6, 50, 30, 0, 0}, {2, 1, 3, 60, 20, 1, 1}, {1, 2, 4, 1, 0, 0, 0}, {1, 2, 4, 12, 9, 0, 0},
    };
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; ++i) {
        check_case(&cases[i]);
    }
}

static void test_bad_arguments(void **state)
{
    (void)state;
    okid_real rows[4] = {0}, c[4] = {0}, work[9] = {0};
    assert_int_equal(okid_toeplitz_gram(1, 1, 0, 2, rows, 1, c, 2, work), OKID_E_BACKEND_ARGUMENT); /* ld < rows */
    assert_int_equal(okid_toeplitz_gram(1, 1, 0, 1, rows, 1, c, 1, work), OKID_E_BACKEND_ARGUMENT); /* ldc < w */
    assert_int_equal(okid_toeplitz_gram(1, 1, 0, 0, rows, 1, c, 2, work), OKID_OK);
}

/* The paper plant (r = 1, m = 2), 2 % noise, 2501 samples (not a multiple of any block size). */
typedef struct id_run {
    okid_status status;
    okid_real markov[2 * 21];
    double condition;
} id_run;

static id_run identify(okid_estimator estimator, int decimation, int scaling, int gap, double forgetting)
{
    enum { N = 2501 };
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.05;
    cfg.observer_order = 6;
    cfg.order = 4;
    cfg.hankel_rows = cfg.hankel_cols = 10;
    cfg.decimation = decimation;
    cfg.scaling = scaling ? OKID_SCALING_AUTO : OKID_SCALING_NONE;
    cfg.forgetting_factor = (okid_real)forgetting;
    cfg.estimator = estimator;
    okid_real *u, *y;
    test_paper_record(0.05, N, 5, 0.02, &u, &y);
    if (gap > 0) {
        y[2 * gap] = (okid_real)NAN;
    }
    size_t bytes;
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    for (int k = 0; k < N; ++k) {
        const okid_status st = okid_push(&id, u + k, y + 2 * k);
        assert_int_equal(st, k == gap && gap > 0 ? OKID_E_NONFINITE_SAMPLE : OKID_OK);
    }
    okid_result res;
    id_run out;
    memset(&out, 0, sizeof out);
    out.status = okid_identify(&id, &res);
    if (out.status == OKID_OK) {
        for (int j = 0; j < 21 && j < res.markov.cols; ++j) {
            for (int i = 0; i < 2; ++i) {
                out.markov[j * 2 + i] = res.markov.data[j * res.markov.ld + i];
            }
        }
        out.condition = (double)res.lsq_condition;
    }
    free(ws);
    free(u);
    free(y);
    return out;
}

static void test_identification_agrees_with_the_qr_fold(void **state)
{
    (void)state;
    const int settings[][3] = {{1, 0, 0}, {2, 0, 0}, {1, 1, 0}, {1, 0, 1000}, {2, 1, 777}};
    const double forgetting[2] = {1, 0.999};
    for (size_t s = 0; s < sizeof settings / sizeof settings[0]; ++s) {
        for (int f = 0; f < 2; ++f) {
            const int dec = settings[s][0], scaled = settings[s][1], gap = settings[s][2];
            const id_run qr = identify(OKID_ESTIMATOR_LEAST_SQUARES, dec, scaled, gap, forgetting[f]);
            const id_run co = identify(OKID_ESTIMATOR_CORRELATION, dec, scaled, gap, forgetting[f]);
            assert_int_equal(qr.status, OKID_OK);
            assert_int_equal(co.status, OKID_OK);
            /* as test_correlation_form's solution_tol: 2 w (q cond)^2 eps, q = 19, w = 21 */
            const double kappa = 19 * qr.condition, tol = 2 * 21 * kappa * kappa * EPS;
            const double diff = max_relative_difference(co.markov, qr.markov, 2 * 21);
            print_message("decimation %d, scaling %d, gap %d, lambda %g: differ by %.3g (tolerance %.3g)\n", dec, scaled,
                          gap, forgetting[f], diff, tol);
            if (tol < 1e-2) { /* float: kappa^2 eps leaves nothing to compare above that */
                assert_within(diff, tol);
            }
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_gram_against_explicit_sum),
        cmocka_unit_test(test_bad_arguments),
        cmocka_unit_test(test_identification_agrees_with_the_qr_fold),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

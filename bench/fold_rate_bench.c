/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The fold's rate against the same run's DGEMM (issue 29): okid_push_block of N samples of white
 * noise (r = 1 input, m outputs, p = 20: q = 61, 221, 501) with block_rows 0 (the QR fold, 2 w^2 N
 * flops: for w > 128 the recursive panel of 64 columns), with block_rows 256 (the same rows per
 * fold with xTPQRT's tile of 16: the rate the recursive panel replaced) and with the correlation
 * estimator twice: as it runs (the Toeplitz block Gram, 2 (r + m) w N flops) and with a forgetting
 * factor of 1 - 1e-9 (the xSYRK path, w^2 N flops, with the rows' weights and C's decay on top),
 * CPU time, next to DGEMM of w x 512 by 512 x w. The correlation columns' rates are in xSYRK's
 * w^2 N flops (what the Gram is worth), so they compare directly with DGEMM's.
 * One BLAS thread: run with OPENBLAS_NUM_THREADS=1.
 *   build/bench/okid_fold_rate_bench [samples]      (default 50 000)
 * Prints figures; nothing is asserted.
 */
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "okid/okid.h"

void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
            const int *ldc, size_t la, size_t lb);

static double cpu_seconds(void)
{
    return (double)clock() / CLOCKS_PER_SEC; /* the process's CPU time */
}

/* GFlop/s of C += A' B with A, B 512 x w (the shape of a fold's update), over 0.3 s at least. */
static double dgemm_rate(int w)
{
    const int k = 512;
    double *a = malloc(sizeof(double) * (size_t)k * (size_t)w), *c = calloc((size_t)w * (size_t)w, sizeof(double));
    for (size_t i = 0; i < (size_t)k * (size_t)w; ++i) {
        a[i] = (double)rand() / RAND_MAX - 0.5;
    }
    const double one = 1;
    int reps = 0;
    const double t0 = cpu_seconds();
    while (cpu_seconds() - t0 < 0.3) {
        dgemm_("T", "N", &w, &w, &k, &one, a, &k, a, &k, &one, c, &w, 1, 1);
        ++reps;
    }
    const double rate = 2.0 * w * w * k * reps / (cpu_seconds() - t0) / 1e9;
    free(a);
    free(c);
    return rate;
}

/* CPU seconds of pushing the samples (the folds, and the regressor rows they are made of). */
static double push_seconds(int m, okid_estimator estimator, int block_rows, double forgetting, size_t samples,
                           const double *u, const double *y)
{
    okid_config cfg;
    okid_config_default(&cfg, 1, m);
    cfg.dt = 0.01;
    cfg.order = 2;
    cfg.estimator = estimator;
    cfg.block_rows = block_rows;
    cfg.forgetting_factor = forgetting;
    size_t bytes = 0;
    if (okid_workspace_size(&cfg, &bytes) != OKID_OK) {
        return -1;
    }
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    okid_identifier id;
    double best = -1;
    for (int rep = 0; rep < 3 && ws != NULL; ++rep) {
        if (okid_init(&id, &cfg, ws, bytes, NULL) != OKID_OK) {
            break;
        }
        const double t0 = cpu_seconds();
        if (okid_push_block(&id, samples, u, 1, y, (size_t)m, NULL) != OKID_OK) {
            break;
        }
        const double t = cpu_seconds() - t0;
        best = (best < 0 || t < best) ? t : best;
    }
    free(ws);
    return best;
}

int main(int argc, char **argv)
{
    const size_t samples = argc > 1 ? (size_t)strtoul(argv[1], NULL, 10) : 50000;
    const int outputs[3] = {2, 10, 24};
    printf("| q | w | DGEMM [GFlop/s] | QR fold [s] | QR fold [GFlop/s] | of DGEMM | block_rows 256 [GFlop/s] | "
           "of DGEMM | correlation, SYRK path [s] | [GFlop/s] | of DGEMM | correlation, Toeplitz Gram [s] | "
           "[GFlop/s of SYRK's flops] | SYRK path / Toeplitz |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for (int c = 0; c < 3; ++c) {
        const int m = outputs[c], q = 1 + (1 + m) * 20, w = q + m;
        double *u = malloc(sizeof(double) * samples), *y = malloc(sizeof(double) * samples * (size_t)m);
        if (u == NULL || y == NULL) {
            fprintf(stderr, "out of memory\n");
            return 1;
        }
        for (size_t i = 0; i < samples; ++i) {
            u[i] = (double)rand() / RAND_MAX - 0.5;
        }
        for (size_t i = 0; i < samples * (size_t)m; ++i) {
            y[i] = (double)rand() / RAND_MAX - 0.5;
        }
        const double gemm = dgemm_rate(w);
        const double rows = (double)(samples - 20);
        const double qr = push_seconds(m, OKID_ESTIMATOR_LEAST_SQUARES, 0, 1, samples, u, y);
        const double tp = push_seconds(m, OKID_ESTIMATOR_LEAST_SQUARES, 256, 1, samples, u, y);
        const double co = push_seconds(m, OKID_ESTIMATOR_CORRELATION, 0, 1 - 1e-9, samples, u, y);
        const double tg = push_seconds(m, OKID_ESTIMATOR_CORRELATION, 0, 1, samples, u, y);
        if (qr <= 0 || tp <= 0 || co <= 0 || tg <= 0) {
            fprintf(stderr, "q = %d: the identifier refused the configuration\n", q);
            return 1;
        }
        const double qr_rate = 2.0 * w * w * rows / qr / 1e9, co_rate = 1.0 * w * w * rows / co / 1e9;
        const double tp_rate = 2.0 * w * w * rows / tp / 1e9, tg_rate = 1.0 * w * w * rows / tg / 1e9;
        printf("| %d | %d | %.1f | %.3f | %.1f | %.0f %% | %.1f | %.0f %% | %.3f | %.1f | %.0f %% | %.3f | %.1f | %.1fx |\n",
               q, w, gemm, qr, qr_rate, 100 * qr_rate / gemm, tp_rate, 100 * tp_rate / gemm, co, co_rate,
               100 * co_rate / gemm, tg, tg_rate, co / tg);
        free(u);
        free(y);
    }
    return 0;
}

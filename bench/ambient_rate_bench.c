/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The output-only path's host cost (okid/ambient.h, docs/ambient.md "Against the peers"): on a
 * record of N samples of m outputs (raw little-endian doubles, sample after sample, as
 * numpy's y.astype('<f8').tofile() writes an (N, m) array), the fastest of REPS runs of
 * init + okid_ambient_push_block() of the whole record, of init + okid_ambient_push() sample by
 * sample, and of okid_ambient_identify(), wall time; the modes of both and their largest relative
 * difference (batched sums against sample by sample, docs/ambient.md "Batched sums"). One BLAS thread: run with
 * OPENBLAS_NUM_THREADS=1.
 *
 *   okid_ambient_rate_bench FILE M DT L ORDER [REPS [BATCH]]
 *   e.g. OPENBLAS_NUM_THREADS=1 build/bench/okid_ambient_rate_bench /tmp/paper.bin 2 0.05 20 4
 */
#define _POSIX_C_SOURCE 200809L /* clock_gettime */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "okid/okid.h"

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: %s FILE M DT L ORDER [REPS [BATCH]]\n", argv[0]);
        return 2;
    }
    const int m = atoi(argv[2]), reps = argc > 6 ? atoi(argv[6]) : 20;
    FILE *f = fopen(argv[1], "rb");
    if (f == NULL) {
        fprintf(stderr, "cannot open %s\n", argv[1]);
        return 1;
    }
    fseek(f, 0, SEEK_END);
    const size_t n = (size_t)ftell(f) / sizeof(double) / (size_t)m;
    fseek(f, 0, SEEK_SET);
    double *raw = malloc(sizeof(double) * n * (size_t)m);
    okid_real *y = malloc(sizeof(okid_real) * n * (size_t)m);
    if (raw == NULL || y == NULL || fread(raw, sizeof(double), n * (size_t)m, f) != n * (size_t)m) {
        fprintf(stderr, "cannot read %s\n", argv[1]);
        return 1;
    }
    fclose(f);
    for (int a = 0; a < m; ++a) { /* the mean removed, as the CLI and Python do */
        double mean = 0;
        for (size_t t = 0; t < n; ++t) mean += raw[t * (size_t)m + (size_t)a];
        mean /= (double)n;
        for (size_t t = 0; t < n; ++t) y[t * (size_t)m + (size_t)a] = (okid_real)(raw[t * (size_t)m + (size_t)a] - mean);
    }
    okid_ambient_config cfg;
    okid_ambient_config_default(&cfg, m);
    cfg.dt = (okid_real)atof(argv[3]);
    cfg.hankel_rows = atoi(argv[4]);
    cfg.order = atoi(argv[5]);
    size_t bytes = 0;
    if (okid_ambient_workspace_size(&cfg, &bytes) != OKID_OK) {
        fprintf(stderr, "configuration refused\n");
        return 1;
    }
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN);
    okid_ambient amb, by_sample;
    okid_ambient_result res, res_sample;
    void *ws_sample = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN);
    double best_block = 1e30, best_sample = 1e30, best_identify = 1e30;
    for (int r = 0; r < reps; ++r) {
        double t0 = now();
        okid_ambient_init(&by_sample, &cfg, ws_sample, bytes, NULL);
        for (size_t t = 0; t < n; ++t) okid_ambient_push(&by_sample, y + t * (size_t)m);
        double t1 = now();
        best_sample = t1 - t0 < best_sample ? t1 - t0 : best_sample;
        t0 = now();
        okid_ambient_init(&amb, &cfg, ws, bytes, NULL);
        okid_ambient_push_block(&amb, n, y, (size_t)m, NULL);
        t1 = now();
        best_block = t1 - t0 < best_block ? t1 - t0 : best_block;
        t0 = now();
        const okid_status st = okid_ambient_identify(&amb, &res);
        t1 = now();
        if (st != OKID_OK) {
            fprintf(stderr, "identify failed: %d\n", (int)st);
            return 1;
        }
        best_identify = t1 - t0 < best_identify ? t1 - t0 : best_identify;
    }
    const double flops = 2.0 * m * m * (2.0 * cfg.hankel_rows + 1) * (double)n; /* every output a reference */
    printf("N %zu m %d L %d order %d workspace %zu B\n", n, m, cfg.hankel_rows, cfg.order, bytes);
    printf("push per sample %.3f ms (%.2f GFlop/s)\n", best_sample * 1e3, flops / best_sample * 1e-9);
    printf("push_block      %.3f ms (%.2f GFlop/s)\n", best_block * 1e3, flops / best_block * 1e-9);
    printf("identify        %.3f ms\n", best_identify * 1e3);
    /* push_block's batched sums against push's sample by sample: the modes' relative differences */
    const int same = okid_ambient_identify(&by_sample, &res_sample) == OKID_OK && res_sample.num_modes == res.num_modes;
    double df = 0, dz = 0;
    for (int i = 0; i < res.num_modes; ++i) {
        printf("mode %d %.6f Hz damping %.6f\n", i + 1, (double)res.modes[i].frequency_hz, (double)res.modes[i].damping_ratio);
        if (same) {
            const double rf = fabs((double)(res.modes[i].frequency_hz - res_sample.modes[i].frequency_hz)) / (double)res.modes[i].frequency_hz;
            const double rz = fabs((double)(res.modes[i].damping_ratio - res_sample.modes[i].damping_ratio)) / fabs((double)res.modes[i].damping_ratio);
            df = rf > df ? rf : df;
            dz = rz > dz ? rz : dz;
        }
    }
    if (same) {
        printf("batched against sample by sample: frequencies %.2g, damping ratios %.2g relative (largest)\n", df, dz);
    } else {
        printf("batched against sample by sample: the mode counts differ\n");
    }
    free(ws_sample);
    free(ws);
    free(y);
    free(raw);
    return 0;
}

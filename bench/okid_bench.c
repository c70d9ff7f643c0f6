/* SPDX-License-Identifier: Apache-2.0 */
/*
 * okid's speed and memory benchmark (a program that prints figures; no test times anything):
 *   - the machine's limit: single-core DGEMM rate of the BLAS in use;
 *   - the push path (samples/s, ns/sample, fraction of the DGEMM rate at 2 q^2 flops per sample)
 *     for configurations from the paper's (r = 1, m = 2, p = 20) to larger ones, per block size;
 *   - one identify (Markov recovery + ERA + modal analysis) for Hankel sizes 20 .. 200;
 *   - end to end: the paper's experiment (1001 samples) and a long record (100 000 samples);
 *   - the workspace bytes of each configuration.
 * Medians of repeated runs. Usage: okid_bench [--quick] [--json FILE]
 * Select the BLAS at run time, e.g. LD_LIBRARY_PATH=/usr/lib/x86_64-linux-gnu/openblas-pthread.
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "okid/okid.h"

/* The Fortran BLAS entry point (every BLAS provides it). */
void dgemm_(const char *ta, const char *tb, const int *m, const int *n, const int *k, const double *alpha,
            const double *a, const int *lda, const double *b, const int *ldb, const double *beta, double *c,
            const int *ldc, size_t la, size_t lb);

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static double median(double *v, int n)
{
    qsort(v, (size_t)n, sizeof *v, compare);
    return v[n / 2];
}

enum { MAX_REPEATS = 64 };

static double dgemm_gflops(int n, int repeats)
{
    double *a = malloc(sizeof(double) * (size_t)n * (size_t)n), *b = malloc(sizeof(double) * (size_t)n * (size_t)n);
    double *c = calloc((size_t)n * (size_t)n, sizeof(double)), t[MAX_REPEATS];
    for (int i = 0; i < n * n; ++i) a[i] = b[i] = 1.0 / (1 + i % 97);
    const double one = 1, zero = 0;
    for (int rep = 0; rep < repeats; ++rep) {
        const double t0 = now();
        dgemm_("N", "N", &n, &n, &n, &one, a, &n, b, &n, &zero, c, &n, 1, 1);
        t[rep] = now() - t0;
    }
    free(a), free(b), free(c);
    return 2.0 * n * (double)n * n / median(t, repeats) / 1e9;
}

typedef struct paper_data {
    okid_real *u, *y;
    size_t count;
} paper_data;

/* The paper's 2-DOF case (r = 1, m = 2) from the library's own simulator; m > 2 and r > 1 reuse
   the channels with different gains so the regressor stays well conditioned. */
static paper_data make_data(size_t count, int r, int m)
{
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    const okid_real b2[4] = {1, 0, 0, 1}, ca[8] = {1, 0, 0, 1, 0.5, 1, 1, -0.5};
    okid_real mm[4], rr[4], kk[4], ac[16], bc[8], a[16], b[8], c[16], d[8], x[4], tmp[4];
    static okid_real work[OKID_ZOH_WORK_REALS(4, 2)];
    okid_chain_model(2, masses, dampers, springs, mm, rr, kk);
    const okid_mechanical_model model = {2, r, m, mm, rr, kk, b2, NULL, NULL, NULL};
    okid_real cam[8];
    for (int i = 0; i < m; ++i) {
        cam[i] = ca[2 * i], cam[m + i] = ca[2 * i + 1];
    }
    okid_mechanical_model mod = model;
    mod.out_acc = cam;
    okid_model_state_space(&mod, ac, bc, c, d, work, OKID_ZOH_WORK_REALS(4, 2));
    okid_discretize_zoh(4, r, ac, bc, 0.01, a, b, work, OKID_ZOH_WORK_REALS(4, 2));
    paper_data pd = {malloc(sizeof(okid_real) * count * (size_t)r), malloc(sizeof(okid_real) * count * (size_t)m), count};
    okid_rng rng;
    okid_rng_seed(&rng, 2024);
    okid_rng_normal(&rng, 1, count * (size_t)r, pd.u, 1);
    okid_simulator sim;
    okid_simulator_init(&sim, 4, r, m, a, b, c, d, x, tmp);
    okid_simulate(&sim, count, pd.u, (size_t)r, pd.y, (size_t)m);
    return pd;
}

static void configure(okid_config *cfg, int r, int m, int p, int hankel, int block_rows)
{
    okid_config_default(cfg, r, m);
    cfg->dt = 0.01;
    cfg->observer_order = p;
    cfg->order = 4;
    cfg->hankel_rows = cfg->hankel_cols = hankel;
    cfg->block_rows = block_rows;
    cfg->zero_initial_state = 1;
}

static void *workspace_for(const okid_config *cfg, size_t *bytes)
{
    if (okid_workspace_size(cfg, bytes) != OKID_OK) {
        fprintf(stderr, "okid_bench: invalid configuration\n");
        exit(1);
    }
    return aligned_alloc(OKID_WORKSPACE_ALIGN, (*bytes + 15) / 16 * 16);
}

/* Seconds per sample of okid_push_block over the whole record (median), or of single pushes. */
static double push_seconds(const okid_config *cfg, const paper_data *pd, int single, int repeats)
{
    size_t bytes;
    void *ws = workspace_for(cfg, &bytes);
    okid_identifier id;
    double t[MAX_REPEATS];
    for (int rep = 0; rep < repeats; ++rep) {
        okid_init(&id, cfg, ws, bytes, NULL);
        const double t0 = now();
        if (single) {
            for (size_t k = 0; k < pd->count; ++k) {
                okid_push(&id, pd->u + k * (size_t)cfg->num_inputs, pd->y + k * (size_t)cfg->num_outputs);
            }
        } else {
            okid_push_block(&id, pd->count, pd->u, (size_t)cfg->num_inputs, pd->y, (size_t)cfg->num_outputs, NULL);
        }
        t[rep] = (now() - t0) / (double)pd->count;
    }
    free(ws);
    return median(t, repeats);
}

static double identify_seconds(const okid_config *cfg, const paper_data *pd, int repeats)
{
    size_t bytes;
    void *ws = workspace_for(cfg, &bytes);
    okid_identifier id;
    okid_result res;
    double t[MAX_REPEATS];
    okid_init(&id, cfg, ws, bytes, NULL);
    okid_push_block(&id, pd->count, pd->u, (size_t)cfg->num_inputs, pd->y, (size_t)cfg->num_outputs, NULL);
    for (int rep = 0; rep < repeats; ++rep) {
        const double t0 = now();
        const okid_status st = okid_identify(&id, &res);
        t[rep] = now() - t0;
        if (st != OKID_OK) {
            fprintf(stderr, "okid_bench: identify: %s\n", okid_status_str(st));
            exit(1);
        }
    }
    free(ws);
    return median(t, repeats);
}

static double end_to_end_seconds(const okid_config *cfg, const paper_data *pd, int repeats)
{
    size_t bytes;
    void *ws = workspace_for(cfg, &bytes);
    okid_identifier id;
    okid_result res;
    double t[MAX_REPEATS];
    for (int rep = 0; rep < repeats; ++rep) {
        const double t0 = now();
        okid_init(&id, cfg, ws, bytes, NULL);
        okid_push_block(&id, pd->count, pd->u, 1, pd->y, 2, NULL);
        okid_identify(&id, &res);
        t[rep] = now() - t0;
    }
    free(ws);
    return median(t, repeats);
}

int main(int argc, char **argv)
{
    int quick = 0;
    const char *json_path = NULL;
    for (int i = 1; i < argc; ++i) {
        if (strcmp(argv[i], "--quick") == 0) {
            quick = 1;
        } else if (strcmp(argv[i], "--json") == 0 && i + 1 < argc) {
            json_path = argv[++i];
        } else {
            fprintf(stderr, "usage: %s [--quick] [--json FILE]\n", argv[0]);
            return 2;
        }
    }
    const int repeats = quick ? 3 : 9;
    FILE *json = json_path ? fopen(json_path, "w") : NULL;
    if (json_path && json == NULL) {
        fprintf(stderr, "okid_bench: cannot write %s\n", json_path);
        return 1;
    }
    const double gflops = dgemm_gflops(quick ? 256 : 1000, repeats);
    printf("single-core DGEMM (n = %d): %.2f GFlop/s\n\n", quick ? 256 : 1000, gflops);
    if (json) fprintf(json, "{\n  \"dgemm_gflops\": %.6g,\n  \"push\": [", gflops);

    printf("push path (median of %d runs)\n", repeats);
    printf("  %-18s %6s %12s %14s %10s %12s %10s\n", "config", "block", "samples/s", "ns/sample", "q", "workspace B",
           "of DGEMM");
    const int configs[4][3] = {{1, 2, 20}, {1, 2, 50}, {2, 4, 20}, {2, 4, 50}};
    const int blocks[5] = {1, 32, 64, 128, 256};
    double best_paper = 0;
    int first = 1;
    for (int c = 0; c < (quick ? 2 : 4); ++c) {
        const int r = configs[c][0], m = configs[c][1], p = configs[c][2];
        paper_data pd = make_data(quick ? 3000 : 40000, r, m);
        for (int b = 0; b < 5; ++b) {
            okid_config cfg;
            configure(&cfg, r, m, p, 20, blocks[b]);
            size_t bytes;
            okid_workspace_size(&cfg, &bytes);
            /* Row-by-row folding is slow: a shorter record says enough about it. */
            paper_data part = pd;
            if (blocks[b] == 1) part.count = quick ? 300 : 2000;
            const double s = push_seconds(&cfg, &part, 0, blocks[b] == 1 ? 3 : repeats);
            const double q = r + (double)(r + m) * p, fraction = 2 * q * q / s / (gflops * 1e9);
            printf("  r=%d m=%d p=%-2d %6s %6d %12.0f %14.1f %10.0f %12zu %9.1f%%\n", r, m, p, "", blocks[b], 1 / s,
                   1e9 * s, q, bytes, 100 * fraction);
            if (c == 0 && 1 / s > best_paper) best_paper = 1 / s;
            if (json) {
                fprintf(json, "%s\n    {\"r\": %d, \"m\": %d, \"p\": %d, \"block_rows\": %d, \"samples_per_s\": %.6g, "
                              "\"dgemm_fraction\": %.6g, \"workspace_bytes\": %zu}",
                        first ? "" : ",", r, m, p, blocks[b], 1 / s, fraction, bytes);
                first = 0;
            }
        }
        free(pd.u), free(pd.y);
    }
    paper_data pd = make_data(1001, 1, 2);
    okid_config cfg;
    configure(&cfg, 1, 2, 20, 20, 0);
    const double single = push_seconds(&cfg, &pd, 1, repeats);
    printf("  r=1 m=2 p=20, one okid_push() per sample (default block 32): %.0f samples/s, %.1f ns/sample\n\n",
           1 / single, 1e9 * single);

    printf("one identify (r=1 m=2 p=20, n=4, after 1001 samples)\n");
    if (json) fprintf(json, "\n  ],\n  \"identify\": [");
    const int hankels[4] = {20, 50, 100, 200};
    paper_data longer = make_data(4000, 1, 2);
    for (int h = 0; h < (quick ? 2 : 4); ++h) {
        configure(&cfg, 1, 2, 20, hankels[h], 0);
        size_t bytes;
        okid_workspace_size(&cfg, &bytes);
        const double s = identify_seconds(&cfg, hankels[h] > 40 ? &longer : &pd, repeats);
        printf("  Hankel %3d x %3d blocks: %10.1f us   workspace %zu B\n", hankels[h], hankels[h], 1e6 * s, bytes);
        if (json) fprintf(json, "%s\n    {\"hankel\": %d, \"seconds\": %.6g, \"workspace_bytes\": %zu}", h ? "," : "",
                          hankels[h], s, bytes);
    }
    configure(&cfg, 1, 2, 20, 20, 0);
    const double paper_e2e = end_to_end_seconds(&cfg, &pd, repeats);
    paper_data record = make_data(quick ? 10000 : 100000, 1, 2);
    cfg.block_rows = 128;
    const double long_e2e = end_to_end_seconds(&cfg, &record, quick ? 1 : 3);
    printf("\nend to end (init + push_block + identify)\n  paper, 1001 samples:     %10.1f us\n"
           "  long record, %6zu samples: %8.1f ms (block 128)\n",
           1e6 * paper_e2e, record.count, 1e3 * long_e2e);
    if (json) {
        fprintf(json, "\n  ],\n  \"push_samples_per_s_paper_best\": %.6g,\n  \"paper_e2e_seconds\": %.6g,\n"
                      "  \"long_record_samples\": %zu,\n  \"long_record_seconds\": %.6g\n}\n",
                best_paper, paper_e2e, record.count, long_e2e);
        fclose(json);
    }
    free(pd.u), free(pd.y), free(longer.u), free(longer.y), free(record.u), free(record.y);
    return 0;
}

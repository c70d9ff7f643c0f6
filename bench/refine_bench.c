/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's cost on the host (a program that prints figures; docs/refinement.md): the
 * paper's system with a white force, OKID/ERA then the prediction-error refinement, for the
 * issue's two configurations; seconds of each, passes, and the workspace. Medians over seeds.
 * Usage: okid_refine_bench [SEEDS]
 */
#define _POSIX_C_SOURCE 199309L
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

static int compare(const void *a, const void *b)
{
    const double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* The paper's record: masses 2, 3; dampers 2, 4, 3; springs 20, 40, 30; accelerations; noise x RMS. */
static void record(double dt, size_t count, uint64_t seed, double noise, okid_real *u, okid_real *y)
{
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30}, b2[2] = {1, 0};
    const okid_real eye[4] = {1, 0, 0, 1};
    okid_real mm[4], rr[4], kk[4], ac[16], bc[4], a[16], b[4], c[8], d[2], state[4] = {0}, scratch[4];
    okid_real work[OKID_ZOH_WORK_REALS(4, 1)];
    okid_chain_model(2, masses, dampers, springs, mm, rr, kk);
    const okid_mechanical_model model = {2, 1, 2, mm, rr, kk, b2, eye, NULL, NULL};
    okid_model_state_space(&model, ac, bc, c, d, work, sizeof work / sizeof work[0]);
    okid_discretize_zoh(4, 1, ac, bc, (okid_real)dt, a, b, work, sizeof work / sizeof work[0]);
    okid_simulator sim;
    okid_simulator_init(&sim, 4, 1, 2, a, b, c, d, state, scratch);
    okid_rng rng;
    okid_rng_seed(&rng, seed);
    okid_rng_normal(&rng, 1, count, u, 1);
    okid_simulate(&sim, count, u, 1, y, 2);
    okid_real *e = malloc(sizeof(okid_real) * count);
    for (int i = 0; i < 2; ++i) {
        double power = 0;
        for (size_t k = 0; k < count; ++k) power += (double)y[2 * k + (size_t)i] * (double)y[2 * k + (size_t)i];
        okid_rng_normal(&rng, (okid_real)(noise * sqrt(power / (double)count)), count, e, 1);
        for (size_t k = 0; k < count; ++k) y[2 * k + (size_t)i] += e[k];
    }
    free(e);
}

static void run(double dt, size_t count, double noise, int p, int h, int seeds)
{
    okid_real *u = malloc(sizeof(okid_real) * count), *y = malloc(sizeof(okid_real) * 2 * count);
    double t_id[64], t_rf[64], passes[64];
    size_t rf_bytes = 0;
    okid_refine_workspace_size(4, 1, 2, &rf_bytes);
    void *rf_ws = aligned_alloc(OKID_WORKSPACE_ALIGN, rf_bytes);
    int converged = 0;
    for (int s = 0; s < seeds; ++s) {
        record(dt, count, 100u + (uint64_t)s, noise, u, y);
        okid_config cfg;
        okid_config_default(&cfg, 1, 2);
        cfg.dt = (okid_real)dt;
        cfg.observer_order = p;
        cfg.order = 4;
        cfg.hankel_rows = cfg.hankel_cols = h;
        size_t bytes = 0;
        okid_workspace_size(&cfg, &bytes);
        void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
        okid_identifier id;
        okid_result res;
        double t0 = now();
        okid_init(&id, &cfg, ws, bytes, NULL);
        okid_push_block(&id, count, u, 1, y, 2, NULL);
        const okid_status st = okid_identify(&id, &res);
        t_id[s] = now() - t0;
        okid_refine_config rc;
        okid_refine_config_default(&rc);
        okid_refiner rf;
        okid_refine_state state = OKID_REFINE_NEED_PASS;
        t0 = now();
        if (st != OKID_OK || okid_refine_init(&rf, &rc, &res, OKID_SENSING_ACCELERATION, rf_ws, rf_bytes, NULL) != OKID_OK) {
            state = OKID_REFINE_DIVERGED;
        }
        int n_passes = 0;
        while (state == OKID_REFINE_NEED_PASS) {
            okid_refine_begin_pass(&rf);
            for (size_t k = 0; k < count; k += 4096) {
                const size_t len = count - k < 4096 ? count - k : 4096;
                okid_refine_push_block(&rf, len, u + k, 1, y + 2 * k, 2);
            }
            okid_refine_end_pass(&rf, &state);
            ++n_passes;
        }
        t_rf[s] = now() - t0;
        passes[s] = n_passes;
        converged += state == OKID_REFINE_CONVERGED;
        free(ws);
    }
    qsort(t_id, (size_t)seeds, sizeof(double), compare);
    qsort(t_rf, (size_t)seeds, sizeof(double), compare);
    qsort(passes, (size_t)seeds, sizeof(double), compare);
    printf("dt %.2f s, %zu samples, %.0f %% noise, p = %d, Hankel %d x %d: OKID/ERA %.2f ms, refinement %.2f ms "
           "(%.0f passes, median of %d; %d converged), refine workspace %zu bytes\n",
           dt, count, noise * 100, p, h, h, 1e3 * t_id[seeds / 2], 1e3 * t_rf[seeds / 2], passes[seeds / 2], seeds,
           converged, rf_bytes);
    free(rf_ws);
    free(u);
    free(y);
}

int main(int argc, char **argv)
{
    int seeds = argc > 1 ? atoi(argv[1]) : 21;
    seeds = seeds < 1 ? 1 : seeds > 64 ? 64 : seeds;
    run(0.05, 2001, 0.05, 20, 20, seeds);
    run(0.01, 10001, 0.02, 40, 100, seeds);
    return 0;
}

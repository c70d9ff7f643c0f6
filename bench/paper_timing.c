/*
 * Times the paper case (r = 1, m = 2, p = 20, n = 4, Hankel 20 x 20, 1001 samples): the push path
 * per sample (single pushes and one block push) and one okid_identify(), median of repeated runs.
 *   build/bench/okid_bench_paper [repeats]
 */
#define _POSIX_C_SOURCE 199309L
#include <stdio.h>
#include <stdlib.h>
#include <time.h>

#include "okid/okid.h"

enum { SAMPLES = 1001, STATES = 4 };
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char workspace[OKID_WORKSPACE_BYTES(1, 2, 20, 20, 20, STATES, 0, 0)];
static double force[SAMPLES], acc[2 * SAMPLES];

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

static void make_data(void)
{
    const double masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    const double b2[2] = {1, 0}, ca[4] = {1, 0, 0, 1};
    double mm[4], rr[4], kk[4], ac[16], bc[4], a[16], b[4], c[8], d[2], x[4], tmp[4];
    static double work[OKID_ZOH_WORK_REALS(4, 1)];
    okid_chain_model(2, masses, dampers, springs, mm, rr, kk);
    const okid_mechanical_model model = {2, 1, 2, mm, rr, kk, b2, ca, NULL, NULL};
    okid_model_state_space(&model, ac, bc, c, d, work, OKID_STATE_SPACE_WORK_REALS(2, 1));
    okid_discretize_zoh(4, 1, ac, bc, 0.01, a, b, work, OKID_ZOH_WORK_REALS(4, 1));
    okid_rng rng;
    okid_rng_seed(&rng, 2024);
    okid_rng_normal(&rng, 1, SAMPLES, force, 1);
    okid_simulator sim;
    okid_simulator_init(&sim, 4, 1, 2, a, b, c, d, x, tmp);
    okid_simulate(&sim, SAMPLES, force, 1, acc, 2);
}

int main(int argc, char **argv)
{
    const int repeats = (argc > 1) ? atoi(argv[1]) : 200;
    if (repeats < 1) {
        fprintf(stderr, "usage: %s [repeats >= 1]\n", argv[0]);
        return 2;
    }
    double *push_single = malloc(sizeof(double) * (size_t)repeats);
    double *push_block = malloc(sizeof(double) * (size_t)repeats);
    double *identify = malloc(sizeof(double) * (size_t)repeats);
    if (!push_single || !push_block || !identify) {
        return 2;
    }
    make_data();
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = 0.01;
    cfg.observer_order = 20;
    cfg.order = STATES;
    cfg.zero_initial_state = 1;
    okid_identifier id;
    okid_result res;
    for (int rep = 0; rep < repeats; ++rep) {
        if (okid_init(&id, &cfg, workspace, sizeof workspace, NULL) != OKID_OK) {
            return 1;
        }
        double t0 = now();
        for (int k = 0; k < SAMPLES; ++k) {
            okid_push(&id, &force[k], &acc[2 * k]);
        }
        push_single[rep] = (now() - t0) / SAMPLES;
        t0 = now();
        const okid_status st = okid_identify(&id, &res);
        identify[rep] = now() - t0;
        if (st != OKID_OK) {
            fprintf(stderr, "identify: %s\n", okid_status_str(st));
            return 1;
        }
        okid_reset(&id);
        t0 = now();
        okid_push_block(&id, SAMPLES, force, 1, acc, 2, NULL);
        push_block[rep] = (now() - t0) / SAMPLES;
    }
    printf("paper case r=1 m=2 p=20 n=4 Hankel 20x20, %d samples, workspace %zu bytes, %d repeats (median)\n",
           SAMPLES, sizeof workspace, repeats);
    printf("push, one sample per call : %8.1f ns/sample  (%.0f samples/s)\n", 1e9 * median(push_single, repeats),
           1 / median(push_single, repeats));
    printf("push, one block of %d    : %8.1f ns/sample  (%.0f samples/s)\n", SAMPLES, 1e9 * median(push_block, repeats),
           1 / median(push_block, repeats));
    printf("identify (fold rest + LSQ + Markov + ERA + modal): %.1f us\n", 1e6 * median(identify, repeats));
    printf("first push to modes: %.1f us\n",
           1e6 * (median(push_single, repeats) * SAMPLES + median(identify, repeats)));
    free(push_single);
    free(push_block);
    free(identify);
    return 0;
}

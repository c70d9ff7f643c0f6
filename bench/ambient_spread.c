/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The statistical spread of output-only identification (okid/ambient.h) on the paper's 2-DOF
 * system driven by unmeasured unit white forces on both masses: rms relative errors of the two
 * frequencies and damping ratios over seeds, against the figures sqrt(zeta / (omega T)) and
 * 1 / sqrt(zeta omega T) that tests/test_ambient.c scales its tolerances by. Prints; times nothing.
 *
 * With SEGMENTS > 1 it also prints the segments' standard deviations (okid_ambient_config::segments):
 * their mean against the measured rms error, and how often the exact value lies within 2 of them.
 *
 *   okid_ambient_spread SAMPLES L NOISE SEEDS DT [REFERENCE [SEGMENTS]]   (REFERENCE -1: every output)
 *   e.g. build/bench/okid_ambient_spread 40000 20 0.05 30 0.05          (every output a reference)
 *        build/bench/okid_ambient_spread 40000 20 0.05 30 0.05 1        (the second mass only)
 *        build/bench/okid_ambient_spread 40000 20 0.05 100 0.05 -1 16   (16 segments)
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "okid/okid.h"

static const okid_real MASS[4] = {2, 0, 0, 3}, DAMPING[4] = {6, -4, -4, 7}, STIFFNESS[4] = {60, -40, -40, 70};
static const okid_real B2[4] = {1, 0, 0, 1}, CA[4] = {1, 0, 0, 1};
/* the exact modes (tests/reference/reference_data.h, from make_reference.py) */
static const double FREQ[2] = {0.5032921210448703, 1.0476860961782999};
static const double ZETA[2] = {0.15811388300841872, 0.3291402943021918};

int main(int argc, char **argv)
{
    if (argc < 6) {
        fprintf(stderr, "usage: %s SAMPLES L NOISE SEEDS DT [REFERENCE]\n", argv[0]);
        return 2;
    }
    const size_t count = (size_t)atof(argv[1]);
    const int lags = atoi(argv[2]), seeds = atoi(argv[4]);
    const double noise = atof(argv[3]), dt = atof(argv[5]);
    const okid_mechanical_model model = {2, 2, 2, MASS, DAMPING, STIFFNESS, B2, CA, NULL, NULL};
    okid_real ac[16], bc[8], c[8], d[4], work[OKID_STATE_SPACE_WORK_REALS(2, 2)], a[16], b[8];
    okid_real zoh[OKID_ZOH_WORK_REALS(4, 2)];
    if (okid_model_state_space(&model, ac, bc, c, d, work, sizeof work / sizeof work[0]) != OKID_OK ||
        okid_discretize_zoh(4, 2, ac, bc, (okid_real)dt, a, b, zoh, sizeof zoh / sizeof zoh[0]) != OKID_OK) {
        fprintf(stderr, "model failed\n");
        return 1;
    }
    okid_ambient_config cfg;
    okid_ambient_config_default(&cfg, 2);
    cfg.dt = (okid_real)dt;
    cfg.hankel_rows = lags;
    cfg.order = 4;
    if (argc > 6 && atoi(argv[6]) >= 0) {
        cfg.num_references = 1;
        cfg.reference_channels[0] = atoi(argv[6]);
    }
    cfg.segments = argc > 7 ? atoi(argv[7]) : 0;
    size_t bytes = 0;
    if (okid_ambient_workspace_size(&cfg, &bytes) != OKID_OK) {
        fprintf(stderr, "configuration refused\n");
        return 1;
    }
    okid_real *u = malloc(sizeof(okid_real) * 2u * count), *y = malloc(sizeof(okid_real) * 2u * count);
    okid_real *e = malloc(sizeof(okid_real) * 2u * count);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15u) / 16u * 16u);
    if (u == NULL || y == NULL || e == NULL || ws == NULL) {
        return 1;
    }
    double sf[2] = {0, 0}, sz[2] = {0, 0}, mf[2] = {0, 0}, mz[2] = {0, 0};
    double stdf[2] = {0, 0}, stdz[2] = {0, 0};
    int ok = 0, inside_f[2] = {0, 0}, inside_z[2] = {0, 0}, with_std = 0;
    for (int s = 0; s < seeds; ++s) {
        okid_rng rng;
        okid_rng_seed(&rng, 1000u + (uint64_t)s);
        okid_rng_normal(&rng, 1, 2u * count, u, 1);
        okid_rng_normal(&rng, 1, 2u * count, e, 1);
        okid_real x[4] = {0, 0, 0, 0}, tmp[4];
        okid_simulator sim;
        okid_simulator_init(&sim, 4, 2, 2, a, b, c, d, x, tmp);
        okid_simulate(&sim, count, u, 2, y, 2);
        double rms[2] = {0, 0};
        for (size_t t = 0; t < count; ++t) {
            for (int i = 0; i < 2; ++i) rms[i] += (double)y[2 * t + i] * (double)y[2 * t + i] / (double)count;
        }
        for (size_t t = 0; t < count; ++t) {
            for (int i = 0; i < 2; ++i) y[2 * t + i] += (okid_real)(noise * sqrt(rms[i])) * e[2 * t + i];
        }
        okid_ambient amb;
        okid_ambient_result res;
        if (okid_ambient_init(&amb, &cfg, ws, bytes, NULL) != OKID_OK ||
            okid_ambient_push_block(&amb, count, y, 2, NULL) != OKID_OK || okid_ambient_identify(&amb, &res) != OKID_OK ||
            res.num_modes != 2) {
            continue;
        }
        ++ok;
        with_std += res.frequency_std != NULL;
        for (int i = 0; i < 2 && res.frequency_std != NULL; ++i) {
            const double df = (double)res.frequency_std[i], dz = (double)res.damping_std[i];
            stdf[i] += df / FREQ[i];
            stdz[i] += dz / ZETA[i];
            inside_f[i] += fabs((double)res.modes[i].frequency_hz - FREQ[i]) <= 2 * df;
            inside_z[i] += fabs((double)res.modes[i].damping_ratio - ZETA[i]) <= 2 * dz;
        }
        for (int i = 0; i < 2; ++i) {
            const double ef = ((double)res.modes[i].frequency_hz - FREQ[i]) / FREQ[i];
            const double ez = ((double)res.modes[i].damping_ratio - ZETA[i]) / ZETA[i];
            sf[i] += ef * ef;
            sz[i] += ez * ez;
            mf[i] += ef;
            mz[i] += ez;
        }
    }
    const double T = (double)count * dt;
    printf("%d of %d seeds identified two pairs; T = %g s\n", ok, seeds, T);
    for (int i = 0; i < 2 && ok > 0; ++i) {
        const double omega = 2 * 3.141592653589793 * FREQ[i];
        const double ff = sqrt(ZETA[i] / (omega * T)), fz = 1 / sqrt(ZETA[i] * omega * T);
        printf("mode %d: frequency rms %.3g (mean %+.2g) = %.2f x sqrt(zeta/(omega T)); "
               "damping rms %.3g (mean %+.2g) = %.2f x 1/sqrt(zeta omega T)\n",
               i + 1, sqrt(sf[i] / ok), mf[i] / ok, sqrt(sf[i] / ok) / ff, sqrt(sz[i] / ok), mz[i] / ok,
               sqrt(sz[i] / ok) / fz);
        if (with_std > 0) {
            printf("        segments: mean frequency std %.3g (rms error %.3g), exact within 2 std %d of %d; "
                   "mean damping std %.3g (rms error %.3g), within 2 std %d of %d\n",
                   stdf[i] / with_std, sqrt(sf[i] / ok), inside_f[i], with_std, stdz[i] / with_std, sqrt(sz[i] / ok),
                   inside_z[i], with_std);
        }
    }
    free(ws);
    free(e);
    free(y);
    free(u);
    return ok > 0 ? 0 : 1;
}

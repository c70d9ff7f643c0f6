/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Float that converges: the paper's 2-DOF structure (m = 2, 3 kg, k = 20, 40, 30 N/m, c = k / 10)
 * driven by unit white noise at 100 Hz, simulated in double, both accelerations with 2 % white
 * output noise, fed sample by sample to the identifier (p = 40, alpha = beta = 40, n = 4, from
 * rest, block_rows 1 as in the firmware example); identify at every checkpoint and print the
 * relative errors of both modes' frequency and damping ratio against the exact ones:
 *   error <samples> <mode> <frequency error> <damping error>
 * Every input is made in double by integer arithmetic (its own generator, no libm), so a float
 * build and a double build, on the host or the target, see the same record to the last bit:
 * compare_convergence.cmake holds a float run against a double run of this program.
 */
#include <stdint.h>
#include <stdio.h>

#include "okid/okid.h"

#ifndef CONVERGENCE_BLOCK_ROWS
#define CONVERGENCE_BLOCK_ROWS 1
#endif
#ifndef CONVERGENCE_CHECKPOINTS /* record lengths at which to identify, increasing */
#define CONVERGENCE_CHECKPOINTS 10000, 100000, 1000000
#endif

/* At 2 % noise the paper's p = 20 with a 20 x 20 Hankel matrix finds one complex mode and a real
   pair instead of the slow mode, in double too: with the noise in the outputs only, the observer
   that the least squares fit approximates is slow and needs a longer memory p. */
#ifndef CONVERGENCE_OBSERVER_ORDER
#define CONVERGENCE_OBSERVER_ORDER 40
#endif
#ifndef CONVERGENCE_HANKEL
#define CONVERGENCE_HANKEL 40
#endif

enum { STATES = 4, INPUTS = 1, OUTPUTS = 2, OBSERVER_ORDER = CONVERGENCE_OBSERVER_ORDER, HANKEL = CONVERGENCE_HANKEL };
#define DT 0.01
#define NOISE_FRACTION 0.02 /* output noise: 2 % of each channel's noise-free RMS */

static const unsigned long checkpoints[] = {CONVERGENCE_CHECKPOINTS};
enum { CHECKPOINT_COUNT = sizeof checkpoints / sizeof checkpoints[0] };

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    workspace[OKID_WORKSPACE_BYTES(INPUTS, OUTPUTS, OBSERVER_ORDER, HANKEL, HANKEL, STATES, CONVERGENCE_BLOCK_ROWS, 0)];
static okid_identifier identifier;

/* splitmix64: uniform on [-sqrt 3, sqrt 3) (unit variance) from the top 53 bits. */
static double uniform_unit_variance(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    z ^= z >> 31;
    return ((double)(z >> 11) * 0x1.0p-53 * 2 - 1) * 1.7320508075688772;
}

/* The structure in double: state (q1, q2, q1', q2'), force on mass 1, accelerations of both. */
typedef struct plant {
    double a[STATES][STATES], b[STATES], c[OUTPUTS][STATES], d[OUTPUTS];
    double x[STATES];
} plant;

/* Zero-order hold: exp of [[Ac, Bc], [0, 0]] dt by its Taylor series (norm 0.7: 30 terms are exact). */
static void plant_build(plant *p)
{
    enum { N = STATES + 1 };
    /* M^-1 K and M^-1 C = M^-1 K / 10 with M = diag(2, 3), K = [60 -40; -40 70] */
    const double mk[2][2] = {{30, -20}, {-40.0 / 3, 70.0 / 3}};
    double z[N][N] = {{0}}, term[N][N] = {{0}}, sum[N][N] = {{0}}, next[N][N];
    for (int i = 0; i < 2; ++i) {
        z[i][2 + i] = DT;
        for (int j = 0; j < 2; ++j) {
            z[2 + i][j] = -mk[i][j] * DT;
            z[2 + i][2 + j] = -mk[i][j] / 10 * DT;
            p->c[i][j] = -mk[i][j];
            p->c[i][2 + j] = -mk[i][j] / 10;
        }
    }
    z[2][4] = 0.5 * DT; /* M^-1 (1, 0)' */
    p->d[0] = 0.5;
    p->d[1] = 0;
    for (int i = 0; i < N; ++i) {
        term[i][i] = sum[i][i] = 1;
    }
    for (int k = 1; k <= 30; ++k) {
        for (int i = 0; i < N; ++i) {
            for (int j = 0; j < N; ++j) {
                double s = 0;
                for (int l = 0; l < N; ++l) s += term[i][l] * z[l][j];
                next[i][j] = s / k;
            }
        }
        for (int i = 0; i < N; ++i) {
            for (int j = 0; j < N; ++j) {
                term[i][j] = next[i][j];
                sum[i][j] += next[i][j];
            }
        }
    }
    for (int i = 0; i < STATES; ++i) {
        for (int j = 0; j < STATES; ++j) p->a[i][j] = sum[i][j];
        p->b[i] = sum[i][STATES];
        p->x[i] = 0;
    }
}

static void plant_step(plant *p, double u, double y[OUTPUTS])
{
    double next[STATES];
    for (int i = 0; i < OUTPUTS; ++i) {
        double s = p->d[i] * u;
        for (int j = 0; j < STATES; ++j) s += p->c[i][j] * p->x[j];
        y[i] = s;
    }
    for (int i = 0; i < STATES; ++i) {
        double s = p->b[i] * u;
        for (int j = 0; j < STATES; ++j) s += p->a[i][j] * p->x[j];
        next[i] = s;
    }
    for (int i = 0; i < STATES; ++i) p->x[i] = next[i];
}

/* Exact modes: C = K / 10, so the undamped modes of (K, M), omega^2 = 10 and 130 / 3, and
   zeta = omega / 20. frequency_hz is omega / (2 pi), as okid reports it. */
static const double OMEGA_SQUARED[2] = {10, 130.0 / 3};

static double sqrt_newton(double v) /* no libm: the same bits everywhere */
{
    double r = v > 1 ? v : 1;
    for (int i = 0; i < 60; ++i) r = 0.5 * (r + v / r);
    return r;
}

/* The identified mode nearest in frequency to the exact one (complex pairs only: with noise, an
   order-4 model may spend two states on a real pair instead of the slow mode). */
static const okid_mode *nearest_pair(const okid_result *res, double f)
{
    const okid_mode *best = NULL;
    double best_distance = 0;
    for (int i = 0; i < res->num_modes; ++i) {
        const double distance = (double)res->modes[i].frequency_hz - f;
        const double d = distance < 0 ? -distance : distance;
        if (res->modes[i].is_pair && (best == NULL || d < best_distance)) {
            best = &res->modes[i];
            best_distance = d;
        }
    }
    return best;
}

static int report(unsigned long samples, const okid_result *res)
{
    int ok = 1;
    for (int i = 0; i < 2; ++i) {
        const double omega = sqrt_newton(OMEGA_SQUARED[i]);
        const double f = omega / (2 * 3.14159265358979323846), zeta = omega / 20;
        const okid_mode *mode = nearest_pair(res, f);
        if (mode == NULL) {
            printf("after %lu samples: no complex mode\n", samples);
            return 0;
        }
        const double df = ((double)mode->frequency_hz - f) / f;
        const double dz = ((double)mode->damping_ratio - zeta) / zeta;
        printf("error %lu %d %.4e %.4e (%d modes: %.6f Hz, zeta %.6f)\n", samples, i + 1, df < 0 ? -df : df,
               dz < 0 ? -dz : dz, res->num_modes, (double)mode->frequency_hz, (double)mode->damping_ratio);
        ok = ok && mode != nearest_pair(res, sqrt_newton(OMEGA_SQUARED[1 - i]) / (2 * 3.14159265358979323846));
    }
    return ok;
}

int main(void)
{
    static plant p;
    plant_build(&p);
    uint64_t input_rng = 2024, noise_rng = 7;

    /* The noise level: 2 % of each channel's RMS over the first 10 000 noise-free samples. */
    double rms[OUTPUTS] = {0, 0}, y[OUTPUTS];
    for (int k = 0; k < 10000; ++k) {
        plant_step(&p, uniform_unit_variance(&input_rng), y);
        for (int i = 0; i < OUTPUTS; ++i) rms[i] += y[i] * y[i] / 10000;
    }
    for (int i = 0; i < OUTPUTS; ++i) rms[i] = NOISE_FRACTION * sqrt_newton(rms[i]);
    plant_build(&p); /* from rest again, the same input sequence */
    input_rng = 2024;

    okid_config cfg;
    okid_config_default(&cfg, INPUTS, OUTPUTS);
    cfg.dt = (okid_real)DT;
    cfg.observer_order = OBSERVER_ORDER;
    cfg.hankel_rows = cfg.hankel_cols = HANKEL;
    cfg.order = STATES;
    cfg.block_rows = CONVERGENCE_BLOCK_ROWS;
    cfg.sensing = OKID_SENSING_ACCELERATION;
    cfg.zero_initial_state = 1;
    okid_status st = okid_init(&identifier, &cfg, workspace, sizeof workspace, NULL);
    printf("%s build, block_rows %d, 2 %% output noise\n", OKID_REAL_IS_FLOAT ? "float" : "double",
           CONVERGENCE_BLOCK_ROWS);

    int ok = st == OKID_OK;
    unsigned long k = 0;
    for (int c = 0; ok && c < CHECKPOINT_COUNT; ++c) {
        for (; ok && k < checkpoints[c]; ++k) {
            const double u = uniform_unit_variance(&input_rng);
            plant_step(&p, u, y);
            const okid_real force = (okid_real)u;
            okid_real measured[OUTPUTS];
            for (int i = 0; i < OUTPUTS; ++i) {
                measured[i] = (okid_real)(y[i] + rms[i] * uniform_unit_variance(&noise_rng));
            }
            st = okid_push(&identifier, &force, measured);
            ok = st == OKID_OK;
        }
        okid_result res;
        if (ok) {
            st = okid_identify(&identifier, &res);
            ok = st == OKID_OK && report(k, &res);
        }
    }
    if (st != OKID_OK) {
        printf("okid: %s after %lu samples\n", okid_status_str(st), k);
    }
    return ok ? 0 : 1;
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * okid in the style of controller firmware (bare metal, runs under QEMU on the MPS2 boards):
 * - one static workspace, sized at compile time by OKID_WORKSPACE_BYTES: no heap, no init-time sizing;
 * - control_tick() is what a sampling interrupt would run: excite the structure, read the
 *   sensors, push the sample (here the plant model of plant_2dof.c stands in for the sensors);
 * - the background loop identifies every IDENTIFY_EVERY samples and prints the modes over
 *   semihosting (a real controller would hand them to its application instead).
 * Exit status 0 when the last identification found both modes of the structure within the
 * tolerance docs/accuracy.md states for this build's okid_real (the qemu run's verdict).
 */
#include <stdio.h>

#include "okid/okid.h"
#include "plant_2dof.h"

#define SAMPLE_INTERVAL ((okid_real)0.01) /* s: the paper's 100 Hz */

/* BLOCK_ROWS 1 folds each sample at once by Givens rotations, so every tick costs the same (no
   burst every 32nd sample) and the workspace keeps one pending row only. */
enum { BLOCK_ROWS = 1 };
enum { IDENTIFY_EVERY = 500, RUN_SAMPLES = 1500 };

#ifndef OKID_WORKSPACE_BYTES_FOR_EXAMPLE
#define OKID_WORKSPACE_BYTES_FOR_EXAMPLE                                                                  \
    OKID_WORKSPACE_BYTES(PLANT_INPUTS, PLANT_OUTPUTS, PLANT_OBSERVER_ORDER, PLANT_HANKEL_ROWS, PLANT_HANKEL_COLS, \
                         PLANT_STATES, BLOCK_ROWS, 0)
#endif

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char workspace[OKID_WORKSPACE_BYTES_FOR_EXAMPLE];
static okid_identifier identifier;

#if OKID_REAL_IS_FLOAT
/* docs/accuracy.md: after 1500 noise-free samples the slow mode is off by up to 5e-4 in frequency
   and 1.5e-3 (M4F, M33) to 1.8e-2 (M55) in damping: the oversampled, rank-deficient regressor in
   float magnifies the last bits in which the targets' records differ (newlib's and picolibc's
   float libm make the excitation), no longer rounding piled up in the fold */
static const double FREQUENCY_TOL = 1e-3, DAMPING_TOL = 3e-2;
#else
static const double FREQUENCY_TOL = 1e-9, DAMPING_TOL = 1e-8;
#endif

/* The structure and its state: the plant model stands in for the real one. */
typedef struct plant_io {
    plant_2dof model;
    okid_simulator sim;
    okid_real state[PLANT_STATES], scratch[PLANT_STATES];
    okid_rng excitation;
} plant_io;

/* One sample period: drive the shaker with white noise, read both accelerometers, push. */
static okid_status control_tick(plant_io *io)
{
    okid_real force, accelerations[PLANT_OUTPUTS];
    okid_status st = okid_rng_normal(&io->excitation, 1, 1, &force, 1);
    if (st == OKID_OK) {
        st = okid_simulate(&io->sim, 1, &force, PLANT_INPUTS, accelerations, PLANT_OUTPUTS);
    }
    return st == OKID_OK ? okid_push(&identifier, &force, accelerations) : st;
}

static void print_modes(unsigned long sample, const okid_result *result)
{
    printf("after %lu samples: %d modes, regressor rank %d of %d\n", sample, result->num_modes,
           result->regressor_rank, result->regressor_columns);
    for (int i = 0; i < result->num_modes; ++i) {
        const okid_mode *mode = &result->modes[i];
        printf("  mode %d: %.6f Hz, damping %.5f, lambda %.7f %+.7fi\n", i + 1, (double)mode->frequency_hz,
               (double)mode->damping_ratio, (double)mode->eigenvalue.re, (double)mode->eigenvalue.im);
    }
}

/* The last identification against the modes of the plant model itself. */
static int modes_match_plant(const plant_io *io, const okid_result *result)
{
    static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char modal_ws[OKID_MODAL_WORKSPACE_BYTES(PLANT_STATES, PLANT_OUTPUTS)];
    okid_mode exact[PLANT_STATES];
    int count = 0;
    if (okid_modal_analysis(PLANT_STATES, PLANT_OUTPUTS, io->model.a, PLANT_STATES, io->model.c, PLANT_OUTPUTS,
                            SAMPLE_INTERVAL, OKID_SENSING_ACCELERATION, modal_ws, sizeof modal_ws, exact, &count,
                            NULL) != OKID_OK ||
        count != result->num_modes) {
        return 0;
    }
    int ok = 1;
    for (int i = 0; i < count; ++i) {
        const double df = (double)(result->modes[i].frequency_hz - exact[i].frequency_hz) / (double)exact[i].frequency_hz;
        const double dz = (double)(result->modes[i].damping_ratio - exact[i].damping_ratio) / (double)exact[i].damping_ratio;
        printf("  mode %d vs the plant: frequency error %.1e (tolerance %.0e), damping error %.1e (tolerance %.0e)\n",
               i + 1, df, FREQUENCY_TOL, dz, DAMPING_TOL);
        ok = ok && df <= FREQUENCY_TOL && -df <= FREQUENCY_TOL && dz <= DAMPING_TOL && -dz <= DAMPING_TOL;
    }
    return ok;
}

int main(void)
{
    static plant_io io;
    okid_config cfg;
    plant_2dof_identifier_config(&cfg, SAMPLE_INTERVAL, BLOCK_ROWS);

    okid_status st = plant_2dof_build(&io.model, SAMPLE_INTERVAL);
    if (st == OKID_OK) {
        st = okid_simulator_init(&io.sim, PLANT_STATES, PLANT_INPUTS, PLANT_OUTPUTS, io.model.a, io.model.b,
                                 io.model.c, io.model.d, io.state, io.scratch);
    }
    okid_rng_seed(&io.excitation, 2024);
    if (st == OKID_OK) {
        st = okid_init(&identifier, &cfg, workspace, sizeof workspace, NULL);
    }
    printf("okid firmware example: %s, workspace %lu bytes (static), identify every %d samples\n",
           OKID_REAL_IS_FLOAT ? "float" : "double", (unsigned long)sizeof workspace, IDENTIFY_EVERY);

    okid_result result;
    int identified = 0;
    for (unsigned long k = 1; st == OKID_OK && k <= RUN_SAMPLES; ++k) {
        st = control_tick(&io);
        if (st == OKID_OK && k % IDENTIFY_EVERY == 0) {
            st = okid_identify(&identifier, &result);
            if (st == OKID_OK) {
                print_modes(k, &result);
                identified = 1;
            }
        }
    }
    if (st != OKID_OK) {
        printf("okid: %s\n", okid_status_str(st));
        return 2;
    }
    const int ok = identified && modes_match_plant(&io, &result);
    printf("%s\n", ok ? "PASS" : "FAIL");
    return ok ? 0 : 1;
}

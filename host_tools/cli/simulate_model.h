/* SPDX-License-Identifier: Apache-2.0 */
/* The chain experiment of okid simulate, shared with okid crlb: options, model, record. */
#ifndef OKID_CLI_SIMULATE_MODEL_H
#define OKID_CLI_SIMULATE_MODEL_H

#include <stddef.h>

#include "okid/okid.h"

enum { MAX_DOFS = 16 };

typedef struct simulate_options {
    double masses[MAX_DOFS], dampers[MAX_DOFS + 1], springs[MAX_DOFS + 1];
    int dofs, num_dampers, num_springs, force_dof, samples, seed;
    double dt, noise;
    int sensing; /* okid_sensing */
    const char *output;
} simulate_options;

/* Discrete model of the chain: a (n x n), b (n), c (m x n), d (m), n = 2 dofs, m = dofs. */
typedef struct discrete_model {
    okid_real a[4 * MAX_DOFS * MAX_DOFS], b[2 * MAX_DOFS], c[2 * MAX_DOFS * MAX_DOFS], d[MAX_DOFS];
} discrete_model;

/* The options of a command on the chain experiment (name, synopsis for --help); 0 or EXIT_USAGE. */
int simulate_parse_options(const char *name, const char *synopsis, int argc, char **argv, simulate_options *o);

/* The exact ZOH model of the chain at o->dt. */
okid_status simulate_build_model(const simulate_options *o, discrete_model *dm);

/*
 * The chain's continuous-time mode with the largest damped frequency |Im s| / 2 pi: that frequency
 * and the mode's undamped natural frequency [Hz] (both 0 without an oscillating mode). Sampled at
 * o->dt, a damped frequency at or above the Nyquist frequency 1 / (2 dt) aliases.
 */
okid_status simulate_fastest_mode(const simulate_options *o, double *damped_hz, double *natural_hz);

/* The noise-free record: the white-noise force (seed) u (samples) and the outputs y (dofs x samples). */
okid_status simulate_record(const simulate_options *o, const discrete_model *dm, okid_real *u, okid_real *y);

#endif

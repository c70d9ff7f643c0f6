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

/* What the chain's continuous-time modes say about sampling it at o->dt and bounding its modes. */
typedef struct chain_modes {
    /* the mode with the largest damped frequency |Im s| / 2 pi: that frequency and its undamped
       natural frequency [Hz] (both 0 without an oscillating mode); a damped frequency at or above
       the Nyquist frequency 1 / (2 dt) aliases */
    double fastest_damped_hz, fastest_natural_hz;
    /* the oscillating mode whose half-power band 2 zeta f is the widest against the gap to the
       nearest other mode's natural frequency: band / gap (0 with fewer than two), f [Hz], zeta */
    double overlap, overlap_hz, overlap_damping;
    /* the largest modulus exp(Re s dt) of a discrete eigenvalue at o->dt, and that mode's f [Hz], zeta */
    double max_modulus, max_modulus_hz, max_modulus_damping;
} chain_modes;

okid_status simulate_chain_modes(const simulate_options *o, chain_modes *out);

/* The noise-free record: the white-noise force (seed) u (samples) and the outputs y (dofs x samples). */
okid_status simulate_record(const simulate_options *o, const discrete_model *dm, okid_real *u, okid_real *y);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The plant the firmware example identifies: the paper's 2-DOF structure (m1 = 2, m2 = 3 kg,
 * r = 2, 4, 3 N s/m, k = 20, 40, 30 N/m, force on mass 1, accelerations of both masses),
 * discretised with a zero-order hold. On a real controller the sensors replace it.
 */
#ifndef OKID_PLANT_2DOF_H
#define OKID_PLANT_2DOF_H

#include "okid/okid.h"

enum { PLANT_DOFS = 2, PLANT_STATES = 4, PLANT_INPUTS = 1, PLANT_OUTPUTS = 2 };

/* The paper's identifier configuration for it: p = 20, alpha = beta = 20, n = 4. */
enum { PLANT_OBSERVER_ORDER = 20, PLANT_HANKEL_ROWS = 20, PLANT_HANKEL_COLS = 20 };

typedef struct plant_2dof {
    okid_real a[PLANT_STATES * PLANT_STATES], b[PLANT_STATES * PLANT_INPUTS];
    okid_real c[PLANT_OUTPUTS * PLANT_STATES], d[PLANT_OUTPUTS * PLANT_INPUTS];
} plant_2dof;

/* Discrete model {A, B, C, D} of the structure for the sample interval dt (eq. 65-82, 13-14). */
okid_status plant_2dof_build(plant_2dof *plant, okid_real dt);

/*
 * The paper's configuration of the identifier for this plant (the enum above, acceleration
 * sensing, from rest) with the sample interval dt and block_rows (1: fold every sample at once).
 */
void plant_2dof_identifier_config(okid_config *cfg, okid_real dt, int block_rows);

/*
 * A record of the plant from rest: count samples of white force of unit variance drawn from rng
 * (force[k]) and the exact accelerations they cause (accelerations[PLANT_OUTPUTS k + i]). The
 * benchmark programs' data; rng goes on from where the force left it.
 */
okid_status plant_2dof_record(okid_real dt, okid_rng *rng, int count, okid_real *force, okid_real *accelerations);

/*
 * plant_2dof_record() seeded with seed, then white sensor noise of noise x the output's RMS added
 * to each output (noise_scratch: count reals). The cost programs' noisy records.
 */
okid_status plant_2dof_noisy_record(okid_real dt, uint64_t seed, okid_real noise, int count, okid_real *force,
                                    okid_real *accelerations, okid_real *noise_scratch);

#endif

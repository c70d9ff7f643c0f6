/* SPDX-License-Identifier: Apache-2.0 */
/* See plant_2dof.h. Every buffer is on the stack and small (about 1 KiB in double). */
#include "plant_2dof.h"

okid_status plant_2dof_build(plant_2dof *plant, okid_real dt)
{
    const okid_real masses[PLANT_DOFS] = {2, 3}, dampers[PLANT_DOFS + 1] = {2, 4, 3};
    const okid_real springs[PLANT_DOFS + 1] = {20, 40, 30};
    const okid_real force_on_mass1[PLANT_DOFS] = {1, 0}, accelerometers[PLANT_OUTPUTS * PLANT_DOFS] = {1, 0, 0, 1};
    okid_real mass[PLANT_DOFS * PLANT_DOFS], damping[PLANT_DOFS * PLANT_DOFS], stiffness[PLANT_DOFS * PLANT_DOFS];
    okid_real ac[PLANT_STATES * PLANT_STATES], bc[PLANT_STATES * PLANT_INPUTS];
    okid_real work[OKID_STATE_SPACE_WORK_REALS(PLANT_DOFS, PLANT_INPUTS)];
    okid_real zoh_work[OKID_ZOH_WORK_REALS(PLANT_STATES, PLANT_INPUTS)];
    okid_status st = okid_chain_model(PLANT_DOFS, masses, dampers, springs, mass, damping, stiffness);
    if (st != OKID_OK) {
        return st;
    }
    const okid_mechanical_model mech = {PLANT_DOFS, PLANT_INPUTS, PLANT_OUTPUTS, mass, damping, stiffness,
                                        force_on_mass1, accelerometers, NULL, NULL};
    st = okid_model_state_space(&mech, ac, bc, plant->c, plant->d, work, sizeof work / sizeof work[0]);
    if (st != OKID_OK) {
        return st;
    }
    return okid_discretize_zoh(PLANT_STATES, PLANT_INPUTS, ac, bc, dt, plant->a, plant->b, zoh_work,
                               sizeof zoh_work / sizeof zoh_work[0]);
}

void plant_2dof_identifier_config(okid_config *cfg, okid_real dt, int block_rows)
{
    okid_config_default(cfg, PLANT_INPUTS, PLANT_OUTPUTS);
    cfg->dt = dt;
    cfg->observer_order = PLANT_OBSERVER_ORDER;
    cfg->hankel_rows = PLANT_HANKEL_ROWS;
    cfg->hankel_cols = PLANT_HANKEL_COLS;
    cfg->order = PLANT_STATES;
    cfg->block_rows = block_rows;
    cfg->sensing = OKID_SENSING_ACCELERATION;
    cfg->zero_initial_state = 1; /* the structure is at rest when the controller starts */
}

okid_status plant_2dof_record(okid_real dt, okid_rng *rng, int count, okid_real *force, okid_real *accelerations)
{
    plant_2dof plant;
    okid_simulator sim;
    okid_real state[PLANT_STATES], scratch[PLANT_STATES];
    okid_status st = plant_2dof_build(&plant, dt);
    if (st == OKID_OK) st = okid_rng_normal(rng, 1, (size_t)count, force, 1);
    if (st == OKID_OK) {
        st = okid_simulator_init(&sim, PLANT_STATES, PLANT_INPUTS, PLANT_OUTPUTS, plant.a, plant.b, plant.c, plant.d,
                                 state, scratch);
    }
    if (st == OKID_OK) st = okid_simulate(&sim, (size_t)count, force, PLANT_INPUTS, accelerations, PLANT_OUTPUTS);
    return st;
}

okid_status plant_2dof_noisy_record(okid_real dt, uint64_t seed, okid_real noise, int count, okid_real *force,
                                    okid_real *accelerations, okid_real *noise_scratch)
{
    okid_rng rng;
    okid_rng_seed(&rng, seed);
    okid_status st = plant_2dof_record(dt, &rng, count, force, accelerations);
    for (int i = 0; i < PLANT_OUTPUTS && st == OKID_OK; ++i) {
        okid_real power = 0;
        for (int k = 0; k < count; ++k) power += accelerations[PLANT_OUTPUTS * k + i] * accelerations[PLANT_OUTPUTS * k + i];
        const okid_real rms = (okid_real)__builtin_sqrt((double)(power / (okid_real)count));
        st = okid_rng_normal(&rng, noise * rms, (size_t)count, noise_scratch, 1);
        for (int k = 0; k < count && st == OKID_OK; ++k) accelerations[PLANT_OUTPUTS * k + i] += noise_scratch[k];
    }
    return st;
}

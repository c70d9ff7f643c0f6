/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The plant FMU: the paper's 2-DOF system (eq. 65-82), force on mass 1, stepped exactly with a
 * zero-order hold over each communication step (eq. 13-14, the core's model module). Outputs are
 * the accelerations of both masses (acc1 with direct feedthrough of the force), displacements, velocities.
 */
#include <math.h>
#include <stddef.h>
#include <stdio.h>
#include <string.h>

#include "fmu_config.h"
#include "fmu_model.h"
#include "okid/okid.h"

enum { DOFS = 2, STATES = 4 };

typedef struct plant_data {
    double masses[DOFS], dampers[DOFS + 1], springs[DOFS + 1]; /* parameters */
    double force;                                             /* input */
    double acc[DOFS], disp[DOFS], vel[DOFS];                  /* outputs */
    /* internal: the continuous model, its ZOH for the step h_cached, and the state [x; v] */
    okid_real ac[STATES * STATES], bc[STATES], c[DOFS * STATES], d[DOFS];
    okid_real a[STATES * STATES], b[STATES], x[STATES];
    double h_cached;
    okid_real work[OKID_ZOH_WORK_REALS(STATES, 1)];
} plant_data;

#define OFF(field) offsetof(plant_data, field)
#define PARAM(name, field, index, start, min, unit, text) \
    {name, NULL, FMU_REAL, FMU_PARAMETER, FMU_FIXED, OFF(field) + (index) * sizeof(double), {0, 0, 0}, start, min, \
     (double)INFINITY, NULL, unit, text, NULL}
#define OUT(name, field, index, depends_on, unit, text) \
    {name, NULL, FMU_REAL, FMU_OUTPUT, FMU_CONTINUOUS, OFF(field) + (index) * sizeof(double), {0, 0, 0}, 0, (double)NAN, (double)NAN, \
     NULL, unit, text, depends_on}
#define POSITIVE 2.2250738585072014e-308

static const fmu_variable_group GROUPS[] = {
    PARAM("m1", masses, 0, 2.0, POSITIVE, "kg", "mass 1 (> 0)"),
    PARAM("m2", masses, 1, 3.0, POSITIVE, "kg", "mass 2 (> 0)"),
    PARAM("r1", dampers, 0, 2.0, 0, "N.s/m", "damper between the left wall and mass 1"),
    PARAM("r2", dampers, 1, 4.0, 0, "N.s/m", "damper between mass 1 and mass 2"),
    PARAM("r3", dampers, 2, 3.0, 0, "N.s/m", "damper between mass 2 and the right wall"),
    PARAM("k1", springs, 0, 20.0, 0, "N/m", "spring between the left wall and mass 1"),
    PARAM("k2", springs, 1, 40.0, 0, "N/m", "spring between mass 1 and mass 2"),
    PARAM("k3", springs, 2, 30.0, 0, "N/m", "spring between mass 2 and the right wall"),
    {"force", NULL, FMU_REAL, FMU_INPUT, FMU_CONTINUOUS, OFF(force), {0, 0, 0}, 0.0, (double)NAN, (double)NAN, NULL, "N", "force on mass 1", NULL},
    /* acc = C x + D force, D = M^-1 b = (1/m1, 0): the force acts on mass 1 directly, on mass 2 only
       through the state (M is diagonal for every parameter value); x and v change in DoStep only */
    OUT("acc1", acc, 0, "force", "m/s2", "acceleration of mass 1"),
    OUT("acc2", acc, 1, NULL, "m/s2", "acceleration of mass 2"),
    OUT("x1", disp, 0, NULL, "m", "displacement of mass 1"),
    OUT("x2", disp, 1, NULL, "m", "displacement of mass 2"),
    OUT("v1", vel, 0, NULL, "m/s", "velocity of mass 1"),
    OUT("v2", vel, 1, NULL, "m/s", "velocity of mass 2"),
};

static void set_defaults(void *data)
{
    plant_data *p = data;
    const double masses[DOFS] = {2, 3}, dampers[DOFS + 1] = {2, 4, 3}, springs[DOFS + 1] = {20, 40, 30};
    memcpy(p->masses, masses, sizeof masses);
    memcpy(p->dampers, dampers, sizeof dampers);
    memcpy(p->springs, springs, sizeof springs);
}

static void token(const void *data, int fmi_version, unsigned long config_hash, char *out, size_t size)
{
    (void)data, (void)fmi_version, (void)config_hash;
    snprintf(out, size, "%s", OKID_FMU_TOKEN);
}

static void update_outputs(void *data)
{
    plant_data *p = data;
    for (int i = 0; i < DOFS; ++i) {
        double s = (double)p->d[i] * p->force;
        for (int j = 0; j < STATES; ++j) s += (double)p->c[i + j * DOFS] * (double)p->x[j];
        p->acc[i] = s;
        p->disp[i] = (double)p->x[i];
        p->vel[i] = (double)p->x[DOFS + i];
    }
}

static fmu_status exit_initialization(void *data, const fmu_allocator *memory, fmu_logger *logger)
{
    plant_data *p = data;
    (void)memory;
    okid_real masses[DOFS], dampers[DOFS + 1], springs[DOFS + 1], mm[DOFS * DOFS], rr[DOFS * DOFS], kk[DOFS * DOFS];
    for (int i = 0; i <= DOFS; ++i) {
        if (i < DOFS) masses[i] = (okid_real)p->masses[i];
        dampers[i] = (okid_real)p->dampers[i];
        springs[i] = (okid_real)p->springs[i];
    }
    const okid_real b2[DOFS] = {1, 0}, ca[DOFS * DOFS] = {1, 0, 0, 1};
    okid_status st = okid_chain_model(DOFS, masses, dampers, springs, mm, rr, kk);
    const okid_mechanical_model model = {DOFS, 1, DOFS, mm, rr, kk, b2, ca, NULL, NULL};
    if (st == OKID_OK) {
        st = okid_model_state_space(&model, p->ac, p->bc, p->c, p->d, p->work, sizeof p->work / sizeof p->work[0]);
    }
    if (st != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError",
                "plant parameters refused: masses must be > 0, dampers and springs >= 0, all finite (%s)",
                okid_status_str(st));
        return FMU_ERROR;
    }
    memset(p->x, 0, sizeof p->x);
    p->h_cached = 0;
    update_outputs(p);
    return FMU_OK;
}

static fmu_status do_step(void *data, double t, double h, fmu_logger *logger)
{
    plant_data *p = data;
    (void)t;
    if (!isfinite(p->force)) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "the force input is not finite: step refused, state kept");
        return FMU_ERROR;
    }
    if (h != p->h_cached) { /* exact discretisation for this step size, computed once per size */
        const okid_status st = okid_discretize_zoh(STATES, 1, p->ac, p->bc, (okid_real)h, p->a, p->b, p->work,
                                                   sizeof p->work / sizeof p->work[0]);
        if (st != OKID_OK) {
            fmu_log(logger, FMU_ERROR, "logStatusError", "discretisation failed: %s", okid_status_str(st));
            return FMU_ERROR;
        }
        p->h_cached = h;
    }
    okid_real next[STATES];
    for (int i = 0; i < STATES; ++i) {
        okid_real s = p->b[i] * (okid_real)p->force;
        for (int j = 0; j < STATES; ++j) s += p->a[i + j * STATES] * p->x[j];
        next[i] = s;
    }
    memcpy(p->x, next, sizeof next);
    update_outputs(p);
    return FMU_OK;
}

const fmu_model FMU_MODEL = {
    "okid_plant_2dof",
    "The 2-DOF mass-spring-damper system of Guida, Nilvetti, Pappalardo, stepped exactly (ZOH)",
    0.01,
    1, /* exact ZOH for any step size */
    GROUPS,
    (int)(sizeof GROUPS / sizeof GROUPS[0]),
    sizeof(plant_data),
    set_defaults,
    token,
    NULL,
    exit_initialization,
    do_step,
    update_outputs,
    NULL,
    NULL, /* the plant's data has no pointers: its state serializes */
};

/* SPDX-License-Identifier: Apache-2.0 */
/* okid simulate: a chain of masses excited by white noise, sampled exactly (ZOH), written as CSV. */
#include <errno.h>
#include <float.h>
#include <limits.h>
#include <stddef.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_common.h"
#include "option_table.h"
#include "simulate_model.h"

static const char synopsis[] =
    "usage: okid simulate [options]\n"
    "\n"
    "Simulates masses in a chain between two walls (spring k_i and damper r_i join mass i-1 and\n"
    "mass i), excited by a white-noise force of unit variance on one mass, sampled exactly with a\n"
    "zero-order hold, from rest. The default is the paper's 2-DOF experiment. Writes CSV columns\n"
    "t, force, then acc1..accN (or vel1.., disp1..), one per mass.\n"
    "\n";

static const char epilogue[] = "\nExit status: 0 success, 1 write error, 2 usage error (a bad option or model).\n";

#define AT(member) offsetof(simulate_options, member), sizeof(((simulate_options *)0)->member), 0
#define LIST(member, count) offsetof(simulate_options, member), sizeof(double), offsetof(simulate_options, count)

static const cli_option simulate_table[] = {
    /* name, alias, kind, offset/size/count, min, max, range, names, field, metavar, note, default, help */
    {"masses", NULL, CLI_REAL_LIST, LIST(masses, dofs), 0, MAX_DOFS, CLI_MIN_OPEN | CLI_NO_MAX, NULL, NULL,
     "M1,M2,...", NULL, NULL, "masses [kg]"},
    {"dampers", NULL, CLI_REAL_LIST, LIST(dampers, num_dampers), 0, MAX_DOFS + 1, CLI_NO_MAX, NULL, NULL, "R1,...",
     "one more than the masses", NULL, "damping coefficients [N s/m]"},
    {"springs", NULL, CLI_REAL_LIST, LIST(springs, num_springs), 0, MAX_DOFS + 1, CLI_NO_MAX, NULL, NULL, "K1,...",
     "one more than the masses", NULL, "stiffnesses [N/m]"},
    {"force-dof", NULL, CLI_INT, AT(force_dof), 1, MAX_DOFS, 0, NULL, NULL, "K", "at most the number of masses", NULL,
     "the mass the force acts on, 1-based"},
    {"sensing", NULL, CLI_ENUM, AT(sensing), 0, 0, 0, cli_sensing_names, NULL, "KIND", NULL, NULL,
     "what the output columns measure"},
    {"samples", NULL, CLI_INT, AT(samples), 1, INT_MAX, 0, NULL, NULL, "N", NULL, NULL, "number of samples"},
    {"dt", NULL, CLI_REAL, AT(dt), DBL_MIN, 0, CLI_NO_MAX, NULL, NULL, "S", NULL, NULL, "sample interval [s]"},
    {"seed", NULL, CLI_INT, AT(seed), INT_MIN, INT_MAX, 0, NULL, NULL, "S", NULL, NULL, "random seed"},
    {"noise", NULL, CLI_REAL, AT(noise), 0, 0, CLI_NO_MAX, NULL, NULL, "F", NULL, NULL,
     "output noise: normal, std F times each output's RMS"},
    {"output", NULL, CLI_TEXT, AT(output), 0, 0, 0, NULL, NULL, "FILE", NULL, "standard output", "where to write"},
    {NULL, NULL, CLI_FLAG, 0, 0, 0, 0, 0, 0, NULL, NULL, NULL, NULL, NULL, NULL},
};

static void simulate_defaults(simulate_options *o)
{
    const double masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    memset(o, 0, sizeof *o);
    memcpy(o->masses, masses, sizeof masses);
    memcpy(o->dampers, dampers, sizeof dampers);
    memcpy(o->springs, springs, sizeof springs);
    o->dofs = 2, o->num_dampers = 3, o->num_springs = 3, o->force_dof = 1;
    o->samples = 1001, o->seed = 1, o->dt = 0.01, o->sensing = OKID_SENSING_ACCELERATION;
}

int simulate_parse_options(const char *name, const char *text, int argc, char **argv, simulate_options *o)
{
    simulate_options defaults;
    simulate_defaults(&defaults);
    const cli_command command = {name, text, epilogue, simulate_table, &defaults, 0, NULL};
    int operands = 0;
    *o = defaults;
    const int rc = cli_parse_options(&command, argc, argv, o, NULL, &operands);
    if (rc != 0) {
        return rc;
    }
    if (o->num_dampers != o->dofs + 1 || o->num_springs != o->dofs + 1) {
        return cli_error(EXIT_USAGE, "%d masses need %d dampers and %d springs (got %d and %d)", o->dofs, o->dofs + 1,
                         o->dofs + 1, o->num_dampers, o->num_springs);
    }
    if (o->force_dof > o->dofs) {
        return cli_error(EXIT_USAGE, "--force-dof %d: there are %d masses", o->force_dof, o->dofs);
    }
    return 0;
}

/* The chain's continuous model into ac (n x n), bc (n), c (m x n), d (m); work: OKID_ZOH_WORK_REALS(2 MAX_DOFS, 1). */
static okid_status continuous_model(const simulate_options *o, okid_real *ac, okid_real *bc, okid_real *c, okid_real *d,
                                    okid_real *work)
{
    const int n2 = o->dofs;
    okid_real masses[MAX_DOFS], dampers[MAX_DOFS + 1], springs[MAX_DOFS + 1];
    for (int i = 0; i <= n2; ++i) {
        if (i < n2) masses[i] = (okid_real)o->masses[i];
        dampers[i] = (okid_real)o->dampers[i];
        springs[i] = (okid_real)o->springs[i];
    }
    okid_real *mm = calloc((size_t)(3 * n2 * n2 + 2 * n2 + n2 * n2), sizeof(okid_real));
    if (mm == NULL) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    okid_real *rr = mm + n2 * n2, *kk = rr + n2 * n2, *b2 = kk + n2 * n2, *eye = b2 + 2 * n2;
    b2[o->force_dof - 1] = 1;
    for (int i = 0; i < n2; ++i) eye[i + i * n2] = 1;
    okid_status st = okid_chain_model(n2, masses, dampers, springs, mm, rr, kk);
    okid_mechanical_model model = {n2, 1, n2, mm, rr, kk, b2, NULL, NULL, NULL};
    if (o->sensing == (int)OKID_SENSING_ACCELERATION) model.out_acc = eye;
    if (o->sensing == (int)OKID_SENSING_VELOCITY) model.out_vel = eye;
    if (o->sensing == (int)OKID_SENSING_DISPLACEMENT) model.out_disp = eye;
    if (st == OKID_OK) st = okid_model_state_space(&model, ac, bc, c, d, work, OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1));
    free(mm);
    return st;
}

okid_status simulate_build_model(const simulate_options *o, discrete_model *dm)
{
    const int n = 2 * o->dofs;
    okid_real *ac = calloc((size_t)(2 * n * n), sizeof(okid_real));
    okid_real *work = calloc(OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1), sizeof(okid_real));
    if (ac == NULL || work == NULL) {
        free(ac), free(work);
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    okid_real *bc = ac + n * n;
    okid_status st = continuous_model(o, ac, bc, dm->c, dm->d, work);
    if (st == OKID_OK) st = okid_discretize_zoh(n, 1, ac, bc, (okid_real)o->dt, dm->a, dm->b, work,
                                                OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1));
    free(ac);
    free(work);
    return st;
}

okid_status simulate_chain_modes(const simulate_options *o, chain_modes *out)
{
    const int n = 2 * o->dofs, m = o->dofs;
    memset(out, 0, sizeof *out);
    discrete_model *fine = calloc(1, sizeof *fine);
    okid_real *ac = calloc((size_t)(2 * n * n), sizeof(okid_real));
    okid_real *work = calloc(OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1), sizeof(okid_real));
    okid_mode *modes = calloc((size_t)n, sizeof *modes);
    const size_t bytes = (OKID_MODAL_WORKSPACE_BYTES(2 * MAX_DOFS, MAX_DOFS) + 15) / 16 * 16;
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, bytes);
    okid_status st = fine && ac && work && modes && ws ? OKID_OK : OKID_E_WORKSPACE_TOO_SMALL;
    okid_real *bc = ac ? ac + n * n : NULL;
    if (st == OKID_OK) st = continuous_model(o, ac, bc, fine->c, fine->d, work);
    /* sampled at h <= 1 / ||ac||_inf every pole has |s| h <= 1 < pi: none aliases */
    double norm = 0;
    for (int i = 0; st == OKID_OK && i < n; ++i) {
        double row = 0;
        for (int j = 0; j < n; ++j) row += fabs((double)ac[i + j * n]);
        norm = row > norm ? row : norm;
    }
    const okid_real h = (okid_real)(norm > 1 ? 1 / norm : 1);
    if (st == OKID_OK) st = okid_discretize_zoh(n, 1, ac, bc, h, fine->a, fine->b, work, OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1));
    int count = 0;
    if (st == OKID_OK) {
        st = okid_modal_analysis(n, m, fine->a, n, fine->c, m, h, (okid_sensing)o->sensing, ws, bytes, modes, &count,
                                 NULL);
    }
    for (int k = 0; st == OKID_OK && k < count; ++k) {
        const double f = (double)modes[k].frequency_hz, zeta = (double)modes[k].damping_ratio;
        const double modulus = exp(-zeta * 2 * 3.14159265358979323846 * f * o->dt);
        if (modulus > out->max_modulus) {
            out->max_modulus = modulus, out->max_modulus_hz = f, out->max_modulus_damping = zeta;
        }
        if (!modes[k].is_pair) continue;
        const double damped = fabs((double)modes[k].pole.im) / (2 * 3.14159265358979323846);
        if (damped > out->fastest_damped_hz) out->fastest_damped_hz = damped, out->fastest_natural_hz = f;
        double gap = HUGE_VAL;
        for (int j = 0; j < count; ++j) {
            if (j != k && modes[j].is_pair) gap = fmin(gap, fabs((double)modes[j].frequency_hz - f));
        }
        if (gap < HUGE_VAL && 2 * zeta * f > out->overlap * gap) {
            out->overlap = gap > 0 ? 2 * zeta * f / gap : HUGE_VAL, out->overlap_hz = f, out->overlap_damping = zeta;
        }
    }
    free(fine), free(ac), free(work), free(modes), free(ws);
    return st;
}

okid_status simulate_record(const simulate_options *o, const discrete_model *dm, okid_real *u, okid_real *y)
{
    okid_real state[2 * MAX_DOFS], scratch[2 * MAX_DOFS];
    okid_rng rng;
    okid_simulator sim;
    okid_rng_seed(&rng, (uint64_t)o->seed);
    okid_status st = okid_rng_normal(&rng, 1, (size_t)o->samples, u, 1);
    if (st == OKID_OK) st = okid_simulator_init(&sim, 2 * o->dofs, 1, o->dofs, dm->a, dm->b, dm->c, dm->d, state, scratch);
    if (st == OKID_OK) st = okid_simulate(&sim, (size_t)o->samples, u, 1, y, (size_t)o->dofs);
    return st;
}

static void add_output_noise(const simulate_options *o, okid_real *y, size_t count, int m)
{
    okid_rng rng;
    okid_rng_seed(&rng, (uint64_t)o->seed ^ UINT64_C(0x6f6b6964)); /* apart from the force's stream */
    for (int i = 0; i < m; ++i) {
        double power = 0;
        for (size_t k = 0; k < count; ++k) power += (double)y[k * (size_t)m + (size_t)i] * (double)y[k * (size_t)m + (size_t)i];
        const double rms = sqrt(power / (double)count);
        for (size_t k = 0; k < count; ++k) {
            okid_real e = 0;
            okid_rng_normal(&rng, (okid_real)(o->noise * rms), 1, &e, 1);
            y[k * (size_t)m + (size_t)i] += e;
        }
    }
}

static int write_csv(const simulate_options *o, const okid_real *u, const okid_real *y, FILE *out)
{
    static const char *const prefix[3] = {"disp", "vel", "acc"};
    fputs("t,force", out);
    for (int i = 0; i < o->dofs; ++i) fprintf(out, ",%s%d", prefix[o->sensing], i + 1);
    fputc('\n', out);
    for (int k = 0; k < o->samples; ++k) {
        fprintf(out, "%.17g,%.17g", k * o->dt, (double)u[k]);
        for (int i = 0; i < o->dofs; ++i) fprintf(out, ",%.17g", (double)y[(size_t)k * (size_t)o->dofs + (size_t)i]);
        fputc('\n', out);
    }
    return (fflush(out) != 0 || ferror(out)) ? -1 : 0;
}

int simulate_command(int argc, char **argv)
{
    simulate_options o;
    int rc = simulate_parse_options("simulate", synopsis, argc, argv, &o);
    if (rc != 0) {
        return rc;
    }
    discrete_model *dm = calloc(1, sizeof *dm);
    okid_real *u = malloc(sizeof(okid_real) * (size_t)o.samples);
    okid_real *y = malloc(sizeof(okid_real) * (size_t)o.samples * (size_t)o.dofs);
    if (dm == NULL || u == NULL || y == NULL) {
        free(dm), free(u), free(y);
        return cli_error(EXIT_DATA, "out of memory");
    }
    okid_status st = simulate_build_model(&o, dm);
    if (st == OKID_OK) st = simulate_record(&o, dm, u, y);
    if (st != OKID_OK) {
        rc = cli_error(EXIT_USAGE, "cannot simulate this model: %s", okid_status_str(st));
    } else {
        if (o.noise > 0) add_output_noise(&o, y, (size_t)o.samples, o.dofs);
        FILE *out = o.output ? fopen(o.output, "w") : stdout;
        if (out == NULL) {
            rc = cli_error(EXIT_DATA, "cannot write '%s': %s", o.output, strerror(errno));
        } else {
            int failed = write_csv(&o, u, y, out) != 0;
            failed |= o.output != NULL && fclose(out) != 0;
            if (failed) rc = cli_error(EXIT_DATA, "cannot write '%s'", o.output ? o.output : "standard output");
        }
    }
    free(dm);
    free(u);
    free(y);
    return rc;
}

/* okid simulate: a chain of masses excited by white noise, sampled exactly (ZOH), written as CSV. */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_common.h"

enum { MAX_DOFS = 16 };

static const char simulate_usage[] =
    "usage: okid simulate [options]\n"
    "\n"
    "Simulates masses in a chain between two walls (spring k_i and damper r_i join mass i-1 and\n"
    "mass i), excited by a white-noise force of unit variance on one mass, sampled exactly with a\n"
    "zero-order hold, from rest. The default is the paper's 2-DOF experiment. Writes CSV columns\n"
    "t, force, then acc1..accN (or vel1.., disp1..), one per mass.\n"
    "\n"
    "  --masses M1,M2,...       masses [kg] (default 2,3)\n"
    "  --dampers R1,...         N+1 damping coefficients [N s/m] (default 2,4,3)\n"
    "  --springs K1,...         N+1 stiffnesses [N/m] (default 20,40,30)\n"
    "  --force-dof K            the mass the force acts on, 1-based (default 1)\n"
    "  --sensing KIND           acceleration|velocity|displacement (default acceleration)\n"
    "  --samples N              number of samples (default 1001: 10 s at 0.01 s)\n"
    "  --dt S                   sample interval [s] (default 0.01)\n"
    "  --seed S                 random seed (default 1)\n"
    "  --noise F                output noise: normal, std F times each output's RMS (default 0)\n"
    "  --output FILE            write to FILE instead of standard output\n"
    "\n"
    "Exit status: 0 success, 1 write error, 2 usage error (a bad option or model).\n";

typedef struct simulate_options {
    double masses[MAX_DOFS], dampers[MAX_DOFS + 1], springs[MAX_DOFS + 1];
    int dofs, num_dampers, num_springs, force_dof, samples, seed;
    double dt, noise;
    okid_sensing sensing;
    const char *output;
} simulate_options;

/* Every simulate option takes a value; an unknown one is reported as such, not as lacking a value. */
static int is_option(const char *opt)
{
    static const char *const names[] = {"--masses", "--dampers", "--springs", "--force-dof", "--sensing",
                                         "--samples", "--dt", "--seed", "--noise", "--output"};
    for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i) {
        if (strcmp(opt, names[i]) == 0) {
            return 1;
        }
    }
    return 0;
}

static int parse_options(int argc, char **argv, simulate_options *o)
{
    const double masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    memset(o, 0, sizeof *o);
    memcpy(o->masses, masses, sizeof masses);
    memcpy(o->dampers, dampers, sizeof dampers);
    memcpy(o->springs, springs, sizeof springs);
    o->dofs = 2, o->num_dampers = 3, o->num_springs = 3, o->force_dof = 1;
    o->samples = 1001, o->seed = 1, o->dt = 0.01, o->sensing = OKID_SENSING_ACCELERATION;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) {
            fputs(simulate_usage, stdout);
            exit(0);
        }
        if (strncmp(opt, "--", 2) != 0) {
            return cli_error(EXIT_USAGE, "unexpected argument '%s' (see 'okid simulate --help')", opt);
        }
        if (!is_option(opt)) {
            return cli_error(EXIT_USAGE, "unknown option '%s' (see 'okid simulate --help')", opt);
        }
        if (i + 1 >= argc) {
            return cli_error(EXIT_USAGE, "option %s needs a value (see 'okid simulate --help')", opt);
        }
        const char *val = argv[++i];
        int bad = 0;
        if (strcmp(opt, "--masses") == 0) {
            bad = cli_parse_real_list(val, o->masses, MAX_DOFS, &o->dofs);
        } else if (strcmp(opt, "--dampers") == 0) {
            bad = cli_parse_real_list(val, o->dampers, MAX_DOFS + 1, &o->num_dampers);
        } else if (strcmp(opt, "--springs") == 0) {
            bad = cli_parse_real_list(val, o->springs, MAX_DOFS + 1, &o->num_springs);
        } else if (strcmp(opt, "--force-dof") == 0) {
            bad = cli_parse_int(val, &o->force_dof);
        } else if (strcmp(opt, "--sensing") == 0) {
            bad = cli_parse_sensing(val, &o->sensing);
        } else if (strcmp(opt, "--samples") == 0) {
            bad = cli_parse_int(val, &o->samples) != 0 || o->samples < 1;
        } else if (strcmp(opt, "--dt") == 0) {
            bad = cli_parse_real(val, &o->dt) != 0 || !(o->dt > 0);
        } else if (strcmp(opt, "--seed") == 0) {
            bad = cli_parse_int(val, &o->seed);
        } else if (strcmp(opt, "--noise") == 0) {
            bad = cli_parse_real(val, &o->noise) != 0 || o->noise < 0;
        } else if (strcmp(opt, "--output") == 0) {
            o->output = val;
        } else {
            return cli_error(EXIT_USAGE, "unknown option '%s' (see 'okid simulate --help')", opt);
        }
        if (bad && (strcmp(opt, "--masses") == 0 || strcmp(opt, "--dampers") == 0 || strcmp(opt, "--springs") == 0)) {
            return cli_error(EXIT_USAGE, "bad value '%s' for %s: comma-separated finite numbers, at most %d masses",
                             val, opt, MAX_DOFS);
        }
        if (bad) {
            return cli_error(EXIT_USAGE, "bad value '%s' for %s", val, opt);
        }
    }
    if (o->num_dampers != o->dofs + 1 || o->num_springs != o->dofs + 1) {
        return cli_error(EXIT_USAGE, "%d masses need %d dampers and %d springs (got %d and %d)", o->dofs, o->dofs + 1,
                         o->dofs + 1, o->num_dampers, o->num_springs);
    }
    if (o->force_dof < 1 || o->force_dof > o->dofs) {
        return cli_error(EXIT_USAGE, "--force-dof %d: there are %d masses", o->force_dof, o->dofs);
    }
    return 0;
}

/* Discrete model of the chain: a (n x n), b (n), c (m x n), d (m), n = 2 dofs, m = dofs. */
typedef struct discrete_model {
    okid_real a[4 * MAX_DOFS * MAX_DOFS], b[2 * MAX_DOFS], c[2 * MAX_DOFS * MAX_DOFS], d[MAX_DOFS];
} discrete_model;

static okid_status build_model(const simulate_options *o, discrete_model *dm)
{
    const int n2 = o->dofs, n = 2 * n2;
    okid_real masses[MAX_DOFS], dampers[MAX_DOFS + 1], springs[MAX_DOFS + 1];
    for (int i = 0; i <= n2; ++i) {
        if (i < n2) masses[i] = (okid_real)o->masses[i];
        dampers[i] = (okid_real)o->dampers[i];
        springs[i] = (okid_real)o->springs[i];
    }
    okid_real *mm = calloc((size_t)(3 * n2 * n2 + 2 * n2 + n2 * n2 + 2 * n * n), sizeof(okid_real));
    okid_real *work = calloc(OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1), sizeof(okid_real));
    if (mm == NULL || work == NULL) {
        free(mm), free(work);
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    okid_real *rr = mm + n2 * n2, *kk = rr + n2 * n2, *b2 = kk + n2 * n2, *eye = b2 + 2 * n2, *ac = eye + n2 * n2,
              *bc = ac + n * n;
    b2[o->force_dof - 1] = 1;
    for (int i = 0; i < n2; ++i) eye[i + i * n2] = 1;
    okid_status st = okid_chain_model(n2, masses, dampers, springs, mm, rr, kk);
    okid_mechanical_model model = {n2, 1, n2, mm, rr, kk, b2, NULL, NULL, NULL};
    if (o->sensing == OKID_SENSING_ACCELERATION) model.out_acc = eye;
    if (o->sensing == OKID_SENSING_VELOCITY) model.out_vel = eye;
    if (o->sensing == OKID_SENSING_DISPLACEMENT) model.out_disp = eye;
    if (st == OKID_OK) st = okid_model_state_space(&model, ac, bc, dm->c, dm->d, work, OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1));
    if (st == OKID_OK) st = okid_discretize_zoh(n, 1, ac, bc, (okid_real)o->dt, dm->a, dm->b, work,
                                                OKID_ZOH_WORK_REALS(2 * MAX_DOFS, 1));
    free(mm);
    free(work);
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
    int rc = parse_options(argc, argv, &o);
    if (rc != 0) {
        return rc;
    }
    discrete_model *dm = calloc(1, sizeof *dm);
    okid_real *u = malloc(sizeof(okid_real) * (size_t)o.samples);
    okid_real *y = malloc(sizeof(okid_real) * (size_t)o.samples * (size_t)o.dofs);
    okid_real state[2 * MAX_DOFS], scratch[2 * MAX_DOFS];
    if (dm == NULL || u == NULL || y == NULL) {
        free(dm), free(u), free(y);
        return cli_error(EXIT_DATA, "out of memory");
    }
    okid_status st = build_model(&o, dm);
    okid_rng rng;
    okid_simulator sim;
    okid_rng_seed(&rng, (uint64_t)o.seed);
    if (st == OKID_OK) st = okid_rng_normal(&rng, 1, (size_t)o.samples, u, 1);
    if (st == OKID_OK) st = okid_simulator_init(&sim, 2 * o.dofs, 1, o.dofs, dm->a, dm->b, dm->c, dm->d, state, scratch);
    if (st == OKID_OK) st = okid_simulate(&sim, (size_t)o.samples, u, 1, y, (size_t)o.dofs);
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

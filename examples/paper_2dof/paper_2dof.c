/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The paper's section III end to end (Guida, Nilvetti, Pappalardo): build the 2-DOF model, simulate
 * 10 s of white-noise force at dt = 0.01 s, identify with OKID/ERA, and print identified against
 * exact eigenvalues, frequencies, damping ratios and eq. 98-99 mode shapes with relative errors.
 * Exit status 0 when every relative error is below the tolerance (1e-9, or the first argument).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>

#include "okid/okid.h"

enum { DOFS = 2, STATES = 4, INPUTS = 1, OUTPUTS = 2, SAMPLES = 1001 };
enum { OBSERVER_ORDER = 20, HANKEL_ROWS = 20, HANKEL_COLS = 20 };
static const okid_real DT = 0.01;

/* Every buffer is static and sized at compile time, as firmware would do it. */
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    workspace[OKID_WORKSPACE_BYTES(INPUTS, OUTPUTS, OBSERVER_ORDER, HANKEL_ROWS, HANKEL_COLS, STATES, 0, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char exact_workspace[OKID_MODAL_WORKSPACE_BYTES(STATES, OUTPUTS)];
static okid_real force[SAMPLES], accelerations[OUTPUTS * SAMPLES];
static okid_real zoh_work[OKID_ZOH_WORK_REALS(STATES, INPUTS)];

typedef struct exact_model {
    okid_real a[STATES * STATES], b[STATES * INPUTS], c[OUTPUTS * STATES], d[OUTPUTS * INPUTS];
} exact_model;

static int check(okid_status status, const char *what)
{
    if (status != OKID_OK) {
        fprintf(stderr, "paper_2dof: %s failed: %s\n", what, okid_status_str(status));
        return 0;
    }
    return 1;
}

/* Eq. 65-82 and the exact zero-order hold of eq. 13-14. */
static int build_model(exact_model *model)
{
    const okid_real masses[DOFS] = {2, 3}, dampers[DOFS + 1] = {2, 4, 3}, springs[DOFS + 1] = {20, 40, 30};
    const okid_real b2[DOFS] = {1, 0}, ca[OUTPUTS * DOFS] = {1, 0, 0, 1};
    okid_real mass[DOFS * DOFS], damping[DOFS * DOFS], stiffness[DOFS * DOFS];
    okid_real ac[STATES * STATES], bc[STATES * INPUTS], work[OKID_STATE_SPACE_WORK_REALS(DOFS, INPUTS)];
    if (!check(okid_chain_model(DOFS, masses, dampers, springs, mass, damping, stiffness), "chain model")) {
        return 0;
    }
    const okid_mechanical_model mech = {DOFS, INPUTS, OUTPUTS, mass, damping, stiffness, b2, ca, NULL, NULL};
    return check(okid_model_state_space(&mech, ac, bc, model->c, model->d, work, sizeof work / sizeof work[0]),
                 "state space") &&
           check(okid_discretize_zoh(STATES, INPUTS, ac, bc, DT, model->a, model->b, zoh_work,
                                     sizeof zoh_work / sizeof zoh_work[0]),
                 "zero-order hold");
}

/* White-noise force of unit variance on mass 1, accelerations of both masses, from rest. */
static int simulate(const exact_model *model)
{
    okid_rng rng;
    okid_simulator sim;
    okid_real state[STATES], scratch[STATES];
    okid_rng_seed(&rng, 2024);
    return check(okid_rng_normal(&rng, 1, SAMPLES, force, 1), "white noise") &&
           check(okid_simulator_init(&sim, STATES, INPUTS, OUTPUTS, model->a, model->b, model->c, model->d,
                                     state, scratch),
                 "simulator") &&
           check(okid_simulate(&sim, SAMPLES, force, INPUTS, accelerations, OUTPUTS), "simulation");
}

static int identify(okid_identifier *id, okid_result *result)
{
    okid_config cfg;
    okid_config_default(&cfg, INPUTS, OUTPUTS);
    cfg.dt = DT;
    cfg.observer_order = OBSERVER_ORDER;
    cfg.order = STATES;
    cfg.hankel_rows = HANKEL_ROWS;
    cfg.hankel_cols = HANKEL_COLS;
    cfg.sensing = OKID_SENSING_ACCELERATION;
    cfg.zero_initial_state = 1; /* the simulation starts from rest */
    size_t needed = 0;
    if (!check(okid_init(id, &cfg, workspace, sizeof workspace, &needed), "okid_init")) {
        return 0;
    }
    for (int k = 0; k < SAMPLES; ++k) { /* sample by sample, as from a control interrupt */
        if (!check(okid_push(id, &force[k], &accelerations[OUTPUTS * k]), "okid_push")) {
            return 0;
        }
    }
    printf("OKID/ERA: r = %d, m = %d, p = %d, n = %d, Hankel %d x %d blocks, %d samples, dt = %g s\n",
           INPUTS, OUTPUTS, OBSERVER_ORDER, STATES, HANKEL_ROWS, HANKEL_COLS, SAMPLES, (double)DT);
    printf("workspace: %zu bytes (static, sized by OKID_WORKSPACE_BYTES)\n\n", needed);
    return check(okid_identify(id, result), "okid_identify");
}

static double cabs_of(okid_complex z)
{
    return hypot((double)z.re, (double)z.im);
}

static double relative_error(okid_complex got, okid_complex want)
{
    const okid_complex diff = {got.re - want.re, got.im - want.im};
    return cabs_of(diff) / cabs_of(want);
}

static double scalar_error(okid_real got, okid_real want)
{
    return fabs((double)(got - want)) / fabs((double)want);
}

/* Largest |phi_hat - phi| / |phi| over the components, shapes already unit-normalised alike. */
static double shape_error(const okid_complex *got, const okid_complex *want, int len)
{
    double diff = 0, norm = 0;
    for (int i = 0; i < len; ++i) {
        const okid_complex d = {got[i].re - want[i].re, got[i].im - want[i].im};
        diff = fmax(diff, cabs_of(d));
        norm = fmax(norm, cabs_of(want[i]));
    }
    return diff / norm;
}

/* Ten decimals; a part that rounds to zero prints as +0 so signs of round-off do not distract. */
static void print_complex(const char *label, okid_complex z)
{
    const double re = fabs((double)z.re) < 5e-11 ? 0.0 : (double)z.re;
    const double im = fabs((double)z.im) < 5e-11 ? 0.0 : (double)z.im;
    printf("%s%+.10f %c %.10fi", label, re, im < 0 ? '-' : '+', fabs(im));
}

static double report_mode(int index, const okid_mode *got, const okid_mode *want)
{
    const double lambda_err = relative_error(got->eigenvalue, want->eigenvalue);
    const double freq_err = scalar_error(got->frequency_hz, want->frequency_hz);
    const double zeta_err = scalar_error(got->damping_ratio, want->damping_ratio);
    const double shape_err = shape_error(got->shape, want->shape, STATES);
    printf("mode %d\n", index + 1);
    print_complex("  eigenvalue   exact ", want->eigenvalue);
    print_complex("   identified ", got->eigenvalue);
    printf("   rel. error %.2e\n", lambda_err);
    printf("  frequency    exact %.10f Hz         identified %.10f Hz         rel. error %.2e\n",
           (double)want->frequency_hz, (double)got->frequency_hz, freq_err);
    printf("  damping      exact %.10f            identified %.10f            rel. error %.2e\n",
           (double)want->damping_ratio, (double)got->damping_ratio, zeta_err);
    printf("  shape (eq. 98-99, [x1 x2 v1 v2], unit norm, largest component real > 0)\n");
    for (int i = 0; i < STATES; ++i) {
        print_complex("    exact ", want->shape[i]);
        print_complex("   identified ", got->shape[i]);
        printf("\n");
    }
    printf("  shape rel. error %.2e, MAC %.12f\n", shape_err,
           (double)okid_mac(got->shape, want->shape, STATES));
    return fmax(fmax(lambda_err, freq_err), fmax(zeta_err, shape_err));
}

int main(int argc, char **argv)
{
    const double tolerance = argc > 1 ? atof(argv[1]) : 1e-9;
    static exact_model model;
    static okid_identifier id;
    okid_result result;
    okid_mode exact[STATES];
    int exact_count = 0;
    if (!build_model(&model) || !simulate(&model) || !identify(&id, &result)) {
        return 2;
    }
    /* Exact modes: eigen-analysis of the exact discrete model with the same eq. 64 basis. */
    if (!check(okid_modal_analysis(STATES, OUTPUTS, model.a, STATES, model.c, OUTPUTS, DT,
                                   OKID_SENSING_ACCELERATION, exact_workspace, sizeof exact_workspace, exact,
                                   &exact_count, NULL),
               "exact modal analysis")) {
        return 2;
    }
    printf("Hankel singular values:");
    for (int i = 0; i < result.num_singular_values && i < 8; ++i) {
        printf(" %.3e", (double)result.singular_values[i]);
    }
    printf("%s\nregressor rank %d of %d columns, %llu rows\n\n", result.num_singular_values > 8 ? " ..." : "",
           result.regressor_rank, result.regressor_columns, (unsigned long long)result.rows);
    if (result.num_modes != exact_count) {
        fprintf(stderr, "paper_2dof: identified %d modes, exact model has %d\n", result.num_modes, exact_count);
        return 1;
    }
    printf("identified eigenvalues (paper eq. 94: 0.9767 +- 0.0608i, 0.9945 +- 0.0311i):");
    for (int i = 0; i < result.num_modes; ++i) {
        printf(" %.4f +- %.4fi", (double)result.modes[i].eigenvalue.re, (double)result.modes[i].eigenvalue.im);
    }
    printf("\n\n");
    double worst = 0;
    for (int i = 0; i < exact_count; ++i) {
        worst = fmax(worst, report_mode(i, &result.modes[i], &exact[i]));
    }
    printf("\nlargest relative error: %.2e (tolerance %.0e): %s\n", worst, tolerance,
           worst < tolerance ? "PASS" : "FAIL");
    return worst < tolerance ? 0 : 1;
}

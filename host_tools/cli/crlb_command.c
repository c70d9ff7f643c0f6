/* SPDX-License-Identifier: Apache-2.0 */
/*
 * okid crlb: the Cramer-Rao lower bound of the modes of a planned chain experiment (the record
 * okid simulate writes with the same options): the standard deviation below which no unbiased
 * estimate of a frequency or damping ratio can go, for the exact model of order 2 dofs, that
 * force record and output noise of F times each output's RMS. The library computes it as the
 * refinement of the true model with the noise fixed (okid_refine_set_noise, docs/refinement.md).
 */
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "cli_common.h"
#include "simulate_model.h"

static const char synopsis[] =
    "usage: okid crlb [options]\n"
    "\n"
    "The Cramer-Rao lower bound (one standard deviation) of the natural frequencies and damping\n"
    "ratios of the chain experiment that 'okid simulate' writes with the same options (model,\n"
    "--samples, --dt, --seed of the force), with output noise --noise F (> 0) times each output's\n"
    "RMS, for a model of order 2 x masses with feedthrough and unknown initial state. Compare it\n"
    "with the frequency_std and damping_std of 'okid identify --refine' (docs/refinement.md).\n"
    "\n";

/* Why okid_refine_result::std_status is not OKID_OK, in words. */
static const char *crlb_std_reason(const okid_refine_result *rr)
{
    switch (rr->std_status) {
    case OKID_E_RANK_DEFICIENT:
        return "the Fisher information is singular: the record does not determine the model's parameters "
               "(a constant or too short force, a mode the force does not excite or the outputs do not see)";
    case OKID_E_DATA_RANGE:
        return "a mode has no continuous-time pole (a real non-positive eigenvalue) or its standard deviation "
               "is not a finite number";
    default:
        return okid_status_str(rr->std_status);
    }
}

/* A record shorter than one period of the fastest mode determines no mode: that is the cause to
   name when the outputs vanish or the Fisher information is singular, not the force. */
static int short_record_error(const simulate_options *o, double fastest_hz)
{
    const double span = o->samples * o->dt;
    return cli_error(EXIT_USAGE, "cannot compute the bound: the record spans %g s (%d samples of dt %g s), less than "
                     "one period of the chain's fastest mode (%g s at %.6g Hz): no mode is determined; give a larger "
                     "--dt or more --samples", span, o->samples, o->dt, 1 / fastest_hz, fastest_hz);
}

/*
 * The one Jacobian pass at the exact model is the bound whatever the refinement's state: its Fisher
 * information, inverted, is the bound in closed form, and max_passes 2 takes no step. The state
 * only says whether the Gauss-Newton decrement test passed, which a singular information always
 * fails (std_status then names that cause). What must hold is that the pass was the exact model's:
 * accepted (a residual RMS > 0: the refiner's floor) and reproducing the record to round-off
 * (measured: 3e-11 of the RMS for a 16-mass chain; 1e-6 leaves five orders of margin while a model
 * that is not the record's misses by O(1)).
 */
static int bound_pass_is_the_models(const okid_refine_result *rr, okid_refine_state state, const okid_real *sigma,
                                    double noise, int m)
{
    if (state == OKID_REFINE_CONVERGED) return 1;
    if (state != OKID_REFINE_ITERATION_LIMIT) return 0;
    for (int i = 0; i < m; ++i) {
        const double rms_y = (double)sigma[i] / noise, rms_e = (double)rr->residual_rms[i];
        if (!(rms_e > 0 && rms_e <= 1e-6 * rms_y)) return 0;
    }
    return 1;
}

/*
 * A singular Fisher information of a chain whose modes overlap: a resonance much wider than the gap
 * to the next mode, whatever the record's length (its conditioning is the spectrum's, not the
 * length's). Measured with numpy's own Fisher information (tests/python/test_hostile_round3.py):
 * 16 unit masses, dampers and springs (the 0.317 Hz mode, damping 0.996, a band 155 times the gap)
 * are singular at working precision (condition 2e18 at 10, 100 and 200 s of record), with dampers
 * 0.5 (factor 78) too; dampers 0.1 (factor 16) are not (5e12), nor 6 unit masses (26: 5e14). The
 * factor names the cause only when the information is singular; 10 keeps it from naming a mild
 * overlap (the paper chain's 1.3) as the cause of another singularity.
 */
#define CRLB_OVERLAP_CAUSE 10

/* The refinement's start model keeps |lambda| <= 0.9999 (OKID_REFINE_MAX_MODULUS of
   lib/src/analysis/refine_modal_form.c, docs/refinement.md): a mode beyond is not the chain's. */
#define CRLB_MAX_MODULUS 0.9999

/* The bound: start from the exact model, noise fixed, one pass over the noise-free record. */
static int compute_bound(const simulate_options *o, const discrete_model *dm, const okid_real *u, const okid_real *y,
                         double fastest_hz, const chain_modes *cm, okid_refiner *rf, void **ws, okid_refine_result *out,
                         okid_real *sigma)
{
    const int n = 2 * o->dofs, m = o->dofs;
    const int short_record = fastest_hz > 0 && o->samples * o->dt * fastest_hz < 1;
    okid_result truth;
    memset(&truth, 0, sizeof truth);
    truth.order = n;
    truth.dt = (okid_real)o->dt;
    truth.A = (okid_matrix){dm->a, n, n, n};
    truth.B = (okid_matrix){dm->b, n, 1, n};
    truth.C = (okid_matrix){dm->c, m, n, m};
    truth.D = (okid_matrix){dm->d, m, 1, m};
    for (int i = 0; i < m; ++i) {
        double power = 0;
        for (int k = 0; k < o->samples; ++k) power += (double)y[(size_t)k * (size_t)m + (size_t)i] * (double)y[(size_t)k * (size_t)m + (size_t)i];
        sigma[i] = (okid_real)(o->noise * sqrt(power / o->samples));
        if (!(sigma[i] > 0)) { /* a noise std of 0 is no bound: say which output is silent, and why */
            if (short_record) return short_record_error(o, fastest_hz);
            return cli_error(EXIT_USAGE, "output %d (mass %d) is zero over the record's %d sample(s): the noise, F times its "
                             "RMS, is 0 and bounds nothing; give more --samples", i + 1, i + 1, o->samples);
        }
    }
    okid_refine_config rc;
    okid_refine_config_default(&rc);
    rc.max_passes = 2;
    size_t bytes = 0;
    okid_status st = okid_refine_workspace_size(n, 1, m, &bytes);
    *ws = st == OKID_OK ? aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16) : NULL;
    if (*ws == NULL) return cli_error(EXIT_DATA, "out of memory");
    st = okid_refine_init(rf, &rc, &truth, (okid_sensing)o->sensing, *ws, bytes, NULL);
    if (st == OKID_OK) st = okid_refine_set_noise(rf, sigma);
    if (st == OKID_OK) st = okid_refine_begin_pass(rf);
    if (st == OKID_OK) st = okid_refine_push_block(rf, (size_t)o->samples, u, 1, y, (size_t)m);
    okid_refine_state state = OKID_REFINE_NEED_PASS;
    if (st == OKID_OK) st = okid_refine_end_pass(rf, &state);
    if (st == OKID_OK) st = okid_refine_get_result(rf, out);
    if (short_record && st == OKID_E_RANK_DEFICIENT) {
        return short_record_error(o, fastest_hz);
    }
    if (st != OKID_OK) return cli_error(EXIT_DATA, "cannot compute the bound: %s", okid_status_str(st));
    if (!bound_pass_is_the_models(out, state, sigma, o->noise, m)) {
        if (short_record) return short_record_error(o, fastest_hz);
        if (cm->max_modulus >= CRLB_MAX_MODULUS) {
            return cli_error(EXIT_DATA, "cannot compute the bound: the %.6g Hz mode (damping ratio %.4g) has a discrete "
                             "eigenvalue of modulus %.6f at dt %g s, beyond the refinement's %g (its start model pulls "
                             "it inside: not this chain's); give a larger --dt or heavier --dampers",
                             cm->max_modulus_hz, cm->max_modulus_damping, cm->max_modulus, o->dt, CRLB_MAX_MODULUS);
        }
        return cli_error(EXIT_DATA, "cannot compute the bound: the exact model does not reproduce its own noise-free "
                         "record (%s)", okid_refine_state_str(state));
    }
    if (out->std_status != OKID_OK && short_record && out->std_status == OKID_E_RANK_DEFICIENT) {
        return cli_error(EXIT_DATA, "cannot compute the bound: %s; the record spans %g s, less than one period of "
                         "the chain's fastest mode (%g s at %.6g Hz)", crlb_std_reason(out), o->samples * o->dt,
                         1 / fastest_hz, fastest_hz);
    }
    if (out->std_status == OKID_E_RANK_DEFICIENT && cm->overlap >= CRLB_OVERLAP_CAUSE) {
        return cli_error(EXIT_DATA, "cannot compute the bound: the Fisher information is singular at working "
                         "precision: the chain's modes overlap (the %.6g Hz mode, damping ratio %.4g, has a half-power "
                         "band 2 zeta f %.3g times the gap to its nearest mode): no record length tells them apart; "
                         "give lighter --dampers or fewer --masses", cm->overlap_hz, cm->overlap_damping, cm->overlap);
    }
    if (out->std_status != OKID_OK) {
        return cli_error(EXIT_DATA, "cannot compute the bound: %s", crlb_std_reason(out));
    }
    return 0;
}

static int print_bound(const simulate_options *o, const okid_refine_result *rr, const okid_real *sigma, FILE *out)
{
    fprintf(out, "# okid crlb: %d masses, %d samples, dt = %g s, force seed %d, noise %g x RMS (std", o->dofs,
            o->samples, o->dt, o->seed, o->noise);
    for (int i = 0; i < o->dofs; ++i) fprintf(out, " %.6g", (double)sigma[i]);
    fprintf(out, "), %d parameters\n", rr->num_parameters);
    fputs("mode,frequency_hz,frequency_std,damping_ratio,damping_std\n", out);
    for (int i = 0; i < rr->num_modes; ++i) {
        fprintf(out, "%d,%.10g,%.6g,%.10g,%.6g\n", i + 1, (double)rr->modes[i].frequency_hz,
                (double)rr->mode_std[i].frequency_hz, (double)rr->modes[i].damping_ratio,
                (double)rr->mode_std[i].damping_ratio);
    }
    return (fflush(out) != 0 || ferror(out)) ? -1 : 0;
}

int crlb_command(int argc, char **argv)
{
    simulate_options o;
    int rc = simulate_parse_options("crlb", synopsis, argc, argv, &o);
    if (rc != 0) return rc;
    if (!(o.noise > 0)) return cli_error(EXIT_USAGE, "--noise %g: the bound needs output noise, F > 0", o.noise);
    discrete_model *dm = calloc(1, sizeof *dm);
    okid_real *u = malloc(sizeof(okid_real) * (size_t)o.samples);
    okid_real *y = malloc(sizeof(okid_real) * (size_t)o.samples * (size_t)o.dofs);
    okid_real sigma[MAX_DOFS];
    void *ws = NULL;
    if (dm == NULL || u == NULL || y == NULL) {
        free(dm), free(u), free(y);
        return cli_error(EXIT_DATA, "out of memory");
    }
    chain_modes cm;
    okid_status st = simulate_chain_modes(&o, &cm);
    if (st == OKID_OK && cm.fastest_damped_hz >= 0.5 / o.dt) {
        free(dm), free(u), free(y);
        return cli_error(EXIT_USAGE,
                         "--dt %g: the chain's mode of natural frequency %.6g Hz (damped %.6g Hz) is at or above the "
                         "Nyquist frequency 1/(2 dt) = %.6g Hz and aliases at this dt: its bound would be another "
                         "mode's; give --dt below %.6g s",
                         o.dt, cm.fastest_natural_hz, cm.fastest_damped_hz, 0.5 / o.dt, 0.5 / cm.fastest_damped_hz);
    }
    if (st == OKID_OK) st = simulate_build_model(&o, dm);
    if (st == OKID_OK) st = simulate_record(&o, dm, u, y);
    okid_refiner rf;
    okid_refine_result rr;
    if (st != OKID_OK) {
        rc = cli_error(EXIT_USAGE, "cannot simulate this model: %s", okid_status_str(st));
    } else {
        rc = compute_bound(&o, dm, u, y, cm.fastest_natural_hz, &cm, &rf, &ws, &rr, sigma);
    }
    if (rc == 0) {
        FILE *out = o.output ? fopen(o.output, "w") : stdout;
        if (out == NULL) {
            rc = cli_error(EXIT_DATA, "cannot write '%s': %s", o.output, strerror(errno));
        } else {
            int failed = print_bound(&o, &rr, sigma, out) != 0;
            failed |= o.output != NULL && fclose(out) != 0;
            if (failed) rc = cli_error(EXIT_DATA, "cannot write '%s'", o.output ? o.output : "standard output");
        }
    }
    free(ws);
    free(dm);
    free(u);
    free(y);
    return rc;
}

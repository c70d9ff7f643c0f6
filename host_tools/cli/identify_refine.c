/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify --refine: the refinement over the record, the choice of its start, their output. */
#include "identify_refine.h"

#include <math.h>
#include <stdlib.h>

#include "cli_common.h"
#include "json_writer.h"

/* The iteration limit, with what to do about it: how far the last step was from converging. */
static void warn_iteration_limit(const okid_refine_result *out, okid_real step_tolerance)
{
    const double tol = step_tolerance > 0 ? (double)step_tolerance : (double)OKID_REFINE_STEP_TOLERANCE;
    const double dec = (double)out->decrement;
    fprintf(stderr, "okid: warning: the refinement did not converge (%s after %d passes): the modes are the best "
            "found; ", okid_refine_state_str(out->state), out->passes);
    if (dec < 0 && out->iterations == 0) {
        fprintf(stderr, "no step was accepted: check the start (order, horizons)\n");
    } else if (dec < 0) {
        fprintf(stderr, "the Gauss-Newton matrix is singular at the best model: the record does not determine "
                "every parameter (fewer states, or fewer inputs than the lifted record's)\n");
    } else if (dec < 100 * tol) {
        fprintf(stderr, "the last step's decrement %.3g is within 100x the tolerance %.3g: raise --max-passes "
                "(the modes move by about %.2g standard deviations)\n", dec, tol, sqrt(dec));
    } else {
        fprintf(stderr, "the last step's decrement %.3g is %.3g times the tolerance %.3g (steps of about %.2g "
                "standard deviations): more passes may not help; if a residual is not white the model does not "
                "describe the record (order, drift, a force nobody measured: --refine-model innovation)\n",
                dec, dec / tol, tol, sqrt(dec));
    }
}

int identify_refine(const identify_options *o, const okid_result *res, size_t n, const okid_real *u,
                    const okid_real *y, int quiet, okid_refiner *rf, void **ws, okid_refine_result *out)
{
    enum { BLOCK = 4096 };
    const int r = res->B.cols, m = res->C.rows;
    if (res->decimation > 1) {
        return cli_error(EXIT_USAGE, "--refine with --decimation %d: the refinement needs the record at the model's "
                         "sample interval; identify without decimation", res->decimation);
    }
    size_t bytes = 0;
    okid_status st = okid_refine_model_workspace_size(o->refine_cfg.refine_model, res->order, r, m, &bytes);
    *ws = st == OKID_OK ? aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16) : NULL;
    if (*ws == NULL) {
        return cli_error(EXIT_DATA, "refinement: %s", st == OKID_OK ? "out of memory" : okid_status_str(st));
    }
    st = okid_refine_init(rf, &o->refine_cfg, res, o->cfg.sensing, *ws, bytes, NULL);
    okid_refine_state state = OKID_REFINE_NEED_PASS;
    while (st == OKID_OK && state == OKID_REFINE_NEED_PASS) {
        st = okid_refine_begin_pass(rf);
        for (size_t k = 0; st == OKID_OK && k < n; k += BLOCK) {
            const size_t len = n - k < BLOCK ? n - k : BLOCK;
            st = okid_refine_push_block(rf, len, u + k * (size_t)r, (size_t)r, y + k * (size_t)m, (size_t)m);
        }
        if (st == OKID_OK) st = okid_refine_end_pass(rf, &state);
    }
    if (st == OKID_OK) st = okid_refine_get_result(rf, out);
    if (st != OKID_OK) {
        return quiet ? EXIT_DATA : cli_error(EXIT_DATA, "refinement failed: %s", okid_status_str(st));
    }
    if (state == OKID_REFINE_ITERATION_LIMIT && !quiet) {
        warn_iteration_limit(out, o->refine_cfg.step_tolerance);
    } else if (state != OKID_REFINE_CONVERGED && !quiet) {
        fprintf(stderr, "okid: warning: the refinement did not converge (%s after %d passes)%s\n",
                okid_refine_state_str(state), out->passes,
                state == OKID_REFINE_DIVERGED ? ": the modes are OKID/ERA's" : ": the modes are the best found");
    }
    return 0;
}

/* start_search_run()'s refinement of a start: identify_refine(), quietly. */
typedef struct start_record {
    const identify_options *o;
    size_t n;
    const okid_real *u, *y;
} start_record;

static int refine_start(void *context, const okid_result *start, int *state, double *cost, unsigned *warnings)
{
    const start_record *rec = context;
    identify_options capped = *rec->o;
    capped.refine_cfg.max_passes = start_search_passes(capped.refine_cfg.max_passes);
    okid_refiner rf;
    okid_refine_result out;
    void *rf_ws = NULL;
    const int rc = identify_refine(&capped, start, rec->n, rec->u, rec->y, 1, &rf, &rf_ws, &out);
    if (rc == 0) {
        *state = (int)out.state;
        *cost = (double)out.cost;
        *warnings = out.warnings;
    }
    free(rf_ws);
    return rc;
}

void identify_choose_start(const identify_options *o, okid_config *cfg, size_t n, const okid_real *u,
                           const okid_real *y, start_search *search)
{
    start_record rec = {o, n, u, y};
    start_search_run(cfg, n, u, y, refine_start, &rec, search);
}

void print_start_search(const start_search *search)
{
    printf("\nstart of the refinement chosen from the data (lowest cost after refining each, a start whose "
           "model splits a mode last):\n");
    printf("    p  Hankel  state            cost\n");
    for (int i = 0; i < search->count; ++i) {
        const start_candidate *c = &search->candidates[i];
        printf("%5d  %6d  %-15s  %.8g%s%s\n", c->observer_order, c->hankel_blocks,
               c->state >= 0 ? json_refine_state_name((okid_refine_state)c->state) : c->identified ? "refine failed" : "identify failed",
               c->cost, c->split ? "  (splits a mode)" : "", i == search->best ? "  <- chosen" : "");
    }
}

void warn_mode_split(const okid_refine_result *rr, int m)
{
    if (!(rr->warnings & OKID_W_MODE_SPLIT)) return;
    const okid_mode *a = &rr->modes[rr->split_modes[0]], *b = &rr->modes[rr->split_modes[1]];
    fprintf(stderr, "okid: warning: the refined pairs %.4g Hz (damping %.3g) and %.4g Hz (damping %.3g) are one mode "
            "split in two (MAC %.3f of their sensor shapes; docs/refinement.md, \"One mode split in two\"): order %d "
            "is higher than the record supports there; give a lower --order (2 per mode) or leave the order to the "
            "mode selection\n", (double)a->frequency_hz, (double)a->damping_ratio, (double)b->frequency_hz,
            (double)b->damping_ratio, (double)okid_mac(a->sensor_shape, b->sensor_shape, m), rr->order);
}

/*
 * Output i's cross-correlation test on one line however many inputs failed it (a lifted record has
 * K r inputs): the input with the largest statistic in full, then how many others and their names.
 */
static void warn_input_correlated(const okid_refine_result *rr, int m, int i, const char *label,
                                  const char *const *input_names)
{
    const int r = rr->B.cols;
    const okid_real bound = (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND;
    int worst = -1, others = 0;
    for (int j = 0; j < r; ++j) {
        const okid_real s = rr->input_correlation[(size_t)i + (size_t)m * (size_t)j];
        if (!(s > bound)) continue;
        if (worst >= 0) ++others;
        if (worst < 0 || s > rr->input_correlation[(size_t)i + (size_t)m * (size_t)worst]) worst = j;
    }
    if (worst < 0) return;
    char iname[64];
    snprintf(iname, sizeof iname, "%d", worst + 1);
    const size_t at = (size_t)i + (size_t)m * (size_t)worst;
    fprintf(stderr, "okid: warning: output %s: the refined residual is correlated with input %s (cross-correlation "
            "up to %.3g against the band %.3g over lags 0..%d, statistic %.3g above %.4g)",
            label, input_names != NULL ? input_names[worst] : iname, (double)rr->max_input_correlation[at],
            (double)rr->input_correlation_band[at], OKID_REFINE_LAGS - 1, (double)rr->input_correlation[at],
            OKID_REFINE_INPUT_CORRELATION_BOUND);
    if (others > 0) {
        fprintf(stderr, " and with %d more input%s (", others, others > 1 ? "s" : "");
        int listed = 0;
        for (int j = 0; j < r; ++j) {
            if (j == worst || !(rr->input_correlation[(size_t)i + (size_t)m * (size_t)j] > bound)) continue;
            if (listed == 6) {
                fputs(", ...", stderr);
                break;
            }
            snprintf(iname, sizeof iname, "%d", j + 1);
            fprintf(stderr, "%s%s", listed++ ? ", " : "", input_names != NULL ? input_names[j] : iname);
        }
        fputc(')', stderr);
    }
    fputs(": the model misses some of the input's dynamics (too low an order, a wrong D)\n", stderr);
}

void warn_residual_tests(const okid_refine_result *rr, int m, const char *const *output_names,
                         const char *const *input_names)
{
    for (int i = 0; i < m; ++i) {
        const unsigned w = rr->output_warnings[i];
        char name[64];
        snprintf(name, sizeof name, "%d", i + 1);
        const char *label = output_names != NULL ? output_names[i] : name;
        if (w & OKID_W_RESIDUAL_NOT_WHITE) {
            fprintf(stderr, "okid: warning: output %s: the refined residual is not white (Ljung-Box Q %.4g above %.4g, "
                    "autocorrelation up to %.3g against the band %.3g): a force nobody measured, a drift or too low "
                    "an order; the stds are the sandwich ones\n", label, (double)rr->whiteness[i],
                    OKID_REFINE_WHITENESS_BOUND, (double)rr->max_autocorrelation[i], (double)rr->autocorrelation_band);
        }
        if (w & OKID_W_RESIDUAL_INPUT_CORRELATED) warn_input_correlated(rr, m, i, label, input_names);
        if (w & OKID_W_OUTPUT_NOT_EXPLAINED) {
            fprintf(stderr, "okid: warning: output %s: the refined model explains %.3g %% of it (below %.3g %%): a drift, "
                    "an offset, a force nobody measured or a sensor the model does not describe\n", label,
                    (double)rr->fit_percent[i], OKID_REFINE_FIT_LOW);
        }
    }
}

void print_refinement(const okid_refine_result *rr, int m, const char *const *output_names,
                      const char *const *input_names)
{
    const int r = rr->B.cols;
    printf("\nrefinement (prediction error, %s, %d parameters): %s after %d passes, %d steps\n",
           rr->refine_model == OKID_REFINE_INNOVATION ? "innovation form" : "output error", rr->num_parameters,
           okid_refine_state_str(rr->state), rr->passes, rr->iterations);
    printf("residual RMS per output, start -> end:");
    for (int i = 0; i < m; ++i) {
        printf(" %.4g -> %.4g", (double)rr->residual_rms_start[i], (double)rr->residual_rms[i]);
    }
    for (unsigned bit = 1; bit != 0 && bit <= rr->warnings; bit <<= 1) {
        if (rr->warnings & bit) printf("\nwarning: %s", okid_warning_str(bit));
    }
    printf("\nresidual tests (Ljung-Box Q over %d lags, white below %.4g; largest |autocorrelation|, band %.3g):\n",
           OKID_REFINE_LAGS, OKID_REFINE_WHITENESS_BOUND, (double)rr->autocorrelation_band);
    for (int i = 0; i < m; ++i) {
        printf("  output %-12s  Q %-10.4g  max |r| %-8.3g  fit %6.2f %%  %s\n",
               output_names != NULL ? output_names[i] : "", (double)rr->whiteness[i],
               (double)rr->max_autocorrelation[i], (double)rr->fit_percent[i],
               rr->output_warnings[i] & OKID_W_RESIDUAL_NOT_WHITE ? "NOT white" : "white");
    }
    printf("input-residual cross-correlation (lags 0..%d; statistic max |rho| sqrt(N/v), uncorrelated below %.4g):\n",
           OKID_REFINE_LAGS - 1, OKID_REFINE_INPUT_CORRELATION_BOUND);
    for (int i = 0; i < m; ++i) {
        for (int j = 0; j < r; ++j) {
            const size_t at = (size_t)i + (size_t)m * (size_t)j;
            printf("  output %-12s  input %-12s  statistic %-8.3g  max |rho| %-8.3g  band %-8.3g  %s\n",
                   output_names != NULL ? output_names[i] : "", input_names != NULL ? input_names[j] : "",
                   (double)rr->input_correlation[at], (double)rr->max_input_correlation[at],
                   (double)rr->input_correlation_band[at],
                   rr->input_correlation[at] > (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND ? "CORRELATED" : "uncorrelated");
        }
    }
    printf("standard deviations from the %s covariance\n",
           rr->covariance == OKID_REFINE_COVARIANCE_SANDWICH ? "sandwich (residual not white)" : "Fisher");
    printf(" mode  frequency [Hz]  +/- 1 std       damping ratio  +/- 1 std\n");
    for (int i = 0; i < rr->num_modes; ++i) {
        printf("%5d  %14.8f  %-14.3g  %13.8f  %.3g%s\n", i + 1, (double)rr->modes[i].frequency_hz,
               (double)rr->mode_std[i].frequency_hz, (double)rr->modes[i].damping_ratio,
               (double)rr->mode_std[i].damping_ratio, rr->modes[i].is_pair ? "" : "  (real)");
    }
}

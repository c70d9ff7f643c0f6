/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify: read a CSV recording, choose the input and output columns, identify, print. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "auto_identify.h"
#include "auto_modes.h"
#include "auto_report.h"
#include "auto_settings.h"
#include "identify_ambient.h"
#include "cli_common.h"
#include "config_explain.h"
#include "csv_reader.h"
#include "identify_options.h"
#include "identify_refine.h"
#include "json_writer.h"
#include "output_fit.h"
#include "record_channels.h"
#include "record_reader.h"
#include "refine_choice.h"
#include "refine_selection.h"
#include "warning_poles.h"
#include "identify_lift.h"

/* Names of the chosen columns, for the table and the JSON. */
typedef struct column_choice {
    int inputs[OKID_MAX_DIMENSION], outputs[OKID_MAX_DIMENSION];
    const char *input_names[OKID_MAX_DIMENSION], *output_names[OKID_MAX_DIMENSION];
    int r, m;
    int lift_factor;      /* --decimation-method lift: K (the inputs are the lifted ones), else 0 */
    lifted_names lifted;  /* their names */
} column_choice;

/* The settings, the diagnostics and the warnings of a result. */
static void print_header(const okid_config *cfg, const okid_result *res, const column_choice *cc, const char *file)
{
    printf("okid %s: %s, %llu samples, dt = %g s\n", OKID_VERSION_STRING, file, (unsigned long long)res->samples,
           (double)res->dt);
    printf("inputs:");
    for (int i = 0; i < cc->r; ++i) printf(" %s", cc->input_names[i]);
    printf("; outputs:");
    for (int i = 0; i < cc->m; ++i) printf(" %s", cc->output_names[i]);
    printf("\n");
    printf("r = %d inputs, m = %d outputs, p = %d, Hankel %d x %d, %s realization, %s sensing\n", cfg->num_inputs,
           cfg->num_outputs, cfg->observer_order, cfg->hankel_rows, cfg->hankel_cols,
           cfg->realization == OKID_REALIZATION_COMBINED ? "combined" : "system", cli_name_of(cli_sensing_names, (int)cfg->sensing));
    if (cc->lift_factor > 0) {
        printf("decimation %d by lifting: %d samples are one sample of %d inputs (--decimation-method lift)\n",
               cc->lift_factor, cc->lift_factor, cc->r);
    }
    printf("decimation %d (model dt = %g s), scaling %s, %s estimator\n", res->decimation, (double)res->dt,
           cfg->scaling == OKID_SCALING_AUTO ? "auto" : "none",
           cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL   ? "instrumental-variable"
           : cfg->estimator == OKID_ESTIMATOR_CORRELATION ? "correlation-form least-squares"
                                                          : "least-squares");
    printf("order n = %d, regressor rank %d of %d (an n-state system gives %d), input rank %d\n", res->order,
           res->regressor_rank, res->regressor_columns, res->regressor_rank_expected, res->input_rank);
    printf("condition numbers: least squares %.3g, input %.3g, realization %.3g\n", (double)res->lsq_condition,
           (double)res->input_condition, (double)res->realization_condition);
    printf("singular values:");
    for (int i = 0; i < res->num_singular_values && i < 12; ++i) {
        printf(" %.4g", (double)res->singular_values[i]);
    }
    printf("%s\n", res->num_singular_values > 12 ? " ..." : "");
    for (unsigned bit = 1; bit != 0 && bit <= res->warnings; bit <<= 1) {
        /* no physical mode: said with its reason where the modes are listed (auto_print_modes) */
        if ((res->warnings & bit) && bit != OKID_W_NO_PHYSICAL_MODE) {
            char poles[512]; /* the poles it is about, by frequency */
            warning_poles_text(res->modes, res->num_modes, bit, poles, sizeof poles);
            printf("warning: %s%s\n", okid_warning_str(bit), poles);
        }
    }
}

/* How much of each output the model explains (output_fit.h). */
static void print_fit(const double *fit, const column_choice *cc)
{
    printf("fit of each output (%% explained by the model's response from rest, as MATLAB's compare):");
    for (int i = 0; i < cc->m; ++i) printf(" %s %.2f %%", cc->output_names[i], fit[i]);
    printf("\n");
}

/* The fit of each output over the record, the temporary file of samples read once more; its
   warning into res. 0, or -1 when there is no fit (output_fit_begin). */
static int record_fit(record_reader *reader, const record_columns *cols, okid_result *res, double *fit)
{
    enum { BLOCK = 4096 };
    output_fit *f = output_fit_begin(res);
    okid_real *u = malloc(sizeof(okid_real) * BLOCK * (size_t)cols->r);
    okid_real *y = malloc(sizeof(okid_real) * BLOCK * (size_t)cols->m);
    char error[512];
    int rc = f != NULL && u != NULL && y != NULL && fseek(reader->samples, 0, SEEK_SET) == 0 ? 0 : -1;
    for (long got = 1; rc == 0 && got > 0;) {
        got = record_read_block(reader, cols, BLOCK, u, y, error, sizeof error);
        if (got < 0) rc = -1;
        if (got > 0) output_fit_push(f, (size_t)got, u, y);
    }
    if (f != NULL) {
        const unsigned warning = output_fit_end(f, fit);
        if (rc == 0) res->warnings |= warning;
    }
    free(u);
    free(y);
    return rc;
}

/* The model's modes and their shapes (eq. 64). */
static void print_model_modes(const okid_config *cfg, const okid_result *res, const column_choice *cc)
{
    printf("\n mode  frequency [Hz]  damping ratio   EMAC    MPC    CMI          MSV   eigenvalue (discrete)\n");
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_mode *md = &res->modes[i];
        printf("%5d  %14.8f  %13.8f  %5.3f  %5.3f  %5.3f  %11.4g  %+.10f", i + 1, (double)md->frequency_hz,
               (double)md->damping_ratio, (double)md->emac, (double)md->mpc, (double)md->cmi, (double)md->msv,
               (double)md->eigenvalue.re);
        if (md->is_pair) {
            printf(" +/- %.10fi", fabs((double)md->eigenvalue.im));
        } else {
            printf("  (real)");
        }
        printf("\n");
    }
    /* what the sensors see first, by output name (for acceleration sensing eq. 64's displacement and
       velocity are derived from it) */
    printf("\nsensor shapes C psi (largest component 1); columns:");
    for (int i = 0; i < cc->m; ++i) printf(" %s", cc->output_names[i]);
    printf("\n");
    for (int i = 0; i < res->num_modes; ++i) {
        printf("%5d", i + 1);
        auto_print_sensor_shape(&res->modes[i], cfg->num_outputs);
    }
    /* eq. 64: the displacement, then the velocity, at each sensor location */
    printf("\nmode shapes (eq. 64, unit norm; displacement and velocity whatever the sensing); columns:");
    for (int a = 0; a < 2 * cc->m; ++a) {
        printf(" %s(%s)", a < cc->m ? "disp" : "vel", cc->output_names[a % cc->m]);
    }
    printf("\n");
    for (int i = 0; i < res->num_modes; ++i) {
        printf("%5d ", i + 1);
        for (int a = 0; a < 2 * cfg->num_outputs; ++a) {
            printf(" %+.5f%+.5fi", (double)res->modes[i].shape[a].re, (double)res->modes[i].shape[a].im);
        }
        printf("\n");
    }
}

/* okid_workspace_size() said no: the setting, its value, its valid range (config_explain.h). */
static int settings_error(const okid_config *cfg, okid_status st)
{
    char message[640];
    (void)config_explain(cfg, st, CONFIG_EXPLAIN_CLI, message, sizeof message);
    return cli_error(EXIT_USAGE, "%s", message);
}

/* The stability marks of the table: 's' all three criteria, 'f' frequency only or with one more, 'o' new. */
static char stability_mark(unsigned flags)
{
    return flags == OKID_STABLE_ALL ? 's' : (flags & OKID_STABLE_FREQUENCY) ? 'f' : 'o';
}

static void print_stabilization(const okid_stabilization *st)
{
    printf("\nstabilization (s: stable in frequency 1 %%, damping 5 %%, MAC 0.98; f: frequency only; o: new)\n");
    for (int i = 0; i < st->num_orders; ++i) {
        const okid_stabilization_order *o = &st->orders[i];
        printf("%4d:", o->order);
        for (int k = 0; k < o->num_modes; ++k) {
            const okid_mode *md = &st->modes[o->first + k];
            if (md->is_pair) printf(" %.4f%c", (double)md->frequency_hz, stability_mark(st->stability[o->first + k]));
        }
        printf("\n");
    }
    if (st->rank_limit < st->orders[st->num_orders - 1].order + 2) {
        printf("(the Hankel matrix has numerical rank %d: no higher orders)\n", st->rank_limit);
    }
}

/* Print the result (and the stabilization diagram and refinement when asked) as a table or JSON. */
static int report(const identify_options *o, const okid_config *cfg, okid_identifier *id, const okid_result *res,
                  const column_choice *cc, double elapsed, const okid_refine_result *refined,
                  const start_search *search, const auto_choice *choice, const auto_modes *am, const double *fit)
{
    okid_stabilization st;
    void *stab_ws = NULL;
    if (o->stabilization > 0) {
        size_t bytes = 0;
        okid_status s = okid_stabilization_workspace_size(id, o->stabilization, 2, &bytes);
        if (s == OKID_E_BAD_ORDER) {
            return cli_error(EXIT_USAGE, "--stabilization %d: at most the Hankel size min(alpha m, beta r) = %d",
                             o->stabilization, res->num_singular_values);
        }
        stab_ws = s == OKID_OK ? aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16) : NULL;
        if (stab_ws == NULL) {
            return cli_error(EXIT_DATA, "stabilization: %s", s == OKID_OK ? "out of memory" : okid_status_str(s));
        }
        s = okid_stabilization_compute(id, o->stabilization, 2, NULL, stab_ws, bytes, &st);
        if (s != OKID_OK) {
            free(stab_ws);
            return cli_error(EXIT_DATA, "stabilization failed: %s", okid_status_str(s));
        }
    }
    if (refined != NULL) {
        warn_residual_tests(refined, cfg->num_outputs, cc->output_names, cc->input_names);
        warn_mode_split(refined, cfg->num_outputs);
    }
    if (o->json) {
        if (refined != NULL) { /* the refined model is the result; OKID/ERA's is its "start" */
            json_result_header(stdout, cfg, res, cc->input_names, cc->output_names, o->timing ? elapsed : -1);
            json_start(stdout, cfg, res);
            json_refined_result(stdout, &o->refine_cfg, refined, cfg->num_outputs);
            /* no order given: the settings and the refinement's order chosen from the data */
            if (choice != NULL) auto_json_chosen(stdout, choice, (double)cfg->dt, refined->order, o->refine_order_reason);
            if (o->refine_choice != NULL) {
                const refine_choice *rc = o->refine_choice;
                fprintf(stdout, ",\n  \"refine_model_choice\": {\"requested\": \"auto\", \"chosen\": \"%s\", \"reason\": \"%s\", "
                        "\"detail\": ", okid_refine_model_str(rc->chosen), refine_choice_reason_name(rc->reason));
                json_string(stdout, rc->detail);
                fputc('}', stdout);
            }
        } else if (choice != NULL) { /* the fit before "chosen": after the model's members, as okid.Result.to_dict() */
            json_result_fields(stdout, cfg, res, cc->input_names, cc->output_names, o->timing ? elapsed : -1);
            if (fit != NULL) json_output_fit(stdout, fit, cfg->num_outputs);
            auto_json(stdout, choice, (double)cfg->dt, am, res, cfg->num_outputs);
        } else {
            json_result(stdout, cfg, res, cc->input_names, cc->output_names, o->timing ? elapsed : -1);
            if (fit != NULL) json_output_fit(stdout, fit, cfg->num_outputs);
        }
        if (stab_ws != NULL) json_stabilization(stdout, &st, o->stabilization, 2, cfg->num_outputs);
        if (refined != NULL && search->count > 0) json_start_search(stdout, search);
        /* only when lifting: the filter's runs keep their JSON (scripts/json_hash.sh) */
        if (cc->lift_factor > 0) {
            fprintf(stdout, ",\n  \"decimation_method\": \"lift\", \"lift_factor\": %d", cc->lift_factor);
        }
        fputs("\n}\n", stdout);
    } else {
        print_header(cfg, res, cc, o->file);
        char missing[320];
        if (refined == NULL && fit != NULL) print_fit(fit, cc);
        if (refined == NULL && fit == NULL &&
            output_fit_missing(res->decimation, output_fit_largest_radius(res), missing, sizeof missing)) {
            printf("fit of each output: %s\n", missing);
        }
        if (choice != NULL) auto_print_choice(choice, (double)cfg->dt);
        if (refined != NULL && choice != NULL) printf("order %d (chosen): %s\n", refined->order, o->refine_order_reason);
        if (am != NULL) {
            auto_print_modes(am, res, cc->output_names, cfg->num_outputs, o->all_poles);
        } else {
            print_model_modes(cfg, res, cc);
        }
        if (stab_ws != NULL && st.num_orders > 0) print_stabilization(&st);
        if (refined != NULL && search->count > 0) print_start_search(search);
        if (refined != NULL) print_refinement(refined, cfg->num_outputs, cc->output_names, cc->input_names);
        if (o->refine_choice != NULL) {
            printf("refine_model auto: %s (%s)\n", okid_refine_model_str(o->refine_choice->chosen),
                   o->refine_choice->detail);
        }
        if (o->timing) {
            printf("\nelapsed from okid_init to the %s: %.6f s\n",
                   refined != NULL ? "refined modes (start search, OKID/ERA, refinement)" : "modes", elapsed);
        }
    }
    free(stab_ws);
    return 0;
}

/* okid_identify() failed: say why with the data's own numbers where the data is the cause. */
static int identify_failure(const okid_config *cfg, okid_identifier *id, okid_status st, const column_choice *cc,
                            const record_scan *scan)
{
    okid_progress progress;
    if (st == OKID_E_NOT_ENOUGH_DATA && okid_get_progress(id, &progress) == OKID_OK) {
        if (progress.rows >= (uint64_t)progress.rows_needed) {
            /* the forgetting factor's memory: weights lambda^(age/2) below the rank tolerance do not count;
               lambda >= tol^(2/(q-1)) remembers q rows (0 in the configuration: the library's default) */
            const double tol = cfg->rank_tolerance > 0 ? (double)cfg->rank_tolerance : OKID_REAL_IS_FLOAT ? 1e-5 : 1e-10;
            return cli_error(EXIT_DATA,
                             "not enough data for the forgetting factor %g: it remembers %llu regressor rows (weights "
                             "above the rank tolerance %g), %d needed (q = r + (r+m)p); use at least %.6g",
                             (double)cfg->forgetting_factor, (unsigned long long)progress.rows_remembered, tol,
                             progress.rows_needed, pow(tol, 2.0 / (progress.rows_needed - 1)));
        }
        return cli_error(EXIT_DATA, "not enough data: %llu regressor rows from %zu samples, %d needed (q = r + (r+m)p)",
                         (unsigned long long)progress.rows, scan->samples, progress.rows_needed);
    }
    if (st == OKID_E_DATA_RANGE) {
        for (int c = 0; c < cc->r + cc->m; ++c) {
            const double rms = scan->rms[c];
            if (rms > 0 && (rms < (double)OKID_MAGNITUDE_MIN || rms > (double)OKID_MAGNITUDE_MAX)) {
                return cli_error(EXIT_DATA,
                                 "column '%s' has an RMS of %g, outside %g..%g where the identification's squares stay "
                                 "finite: rescale it (a unit change)%s",
                                 c < cc->r ? cc->input_names[c] : cc->output_names[c - cc->r], rms,
                                 (double)OKID_MAGNITUDE_MIN, (double)OKID_MAGNITUDE_MAX,
                                 cfg->scaling == OKID_SCALING_AUTO ? "" : " or use --scale auto");
            }
        }
        return cli_error(EXIT_DATA, "identification failed: %s", okid_status_str(st));
    }
    return cli_error(EXIT_DATA, "identification failed: %s", okid_status_str(st));
}

/* All the samples the scan kept, into memory (*u: r per sample, *y: m per sample; the caller frees
   them). 0, or an exit code after one line on stderr. */
static int load_samples(record_reader *reader, const record_columns *cols, size_t samples, okid_real **u,
                        okid_real **y)
{
    char error[512];
    *u = malloc(sizeof(okid_real) * samples * (size_t)cols->r);
    *y = malloc(sizeof(okid_real) * samples * (size_t)cols->m);
    if (*u == NULL || *y == NULL || record_read_block(reader, cols, samples, *u, *y, error, sizeof error) < 0) {
        const int rc = cli_error(EXIT_DATA, "%s", *u == NULL || *y == NULL ? "out of memory" : error);
        free(*u), free(*y);
        return rc;
    }
    return 0;
}

/* With --timing: the chosen samples in memory, so that the fastest of --repeat runs times the library alone. */
static okid_status identify_timed(const identify_options *o, const okid_config *cfg, record_reader *reader,
                                  const record_columns *cols, size_t samples, void *ws, size_t bytes,
                                  okid_identifier *id, okid_result *res, double *elapsed, int *rc)
{
    okid_real *u, *y;
    *rc = load_samples(reader, cols, samples, &u, &y);
    if (*rc != 0) {
        return OKID_OK;
    }
    okid_status st = OKID_OK;
    for (int rep = 0; rep < (o->repeat > 1 ? o->repeat : 1); ++rep) { /* the fastest of K: warm caches */
        struct timespec t0, t1;
        timespec_get(&t0, TIME_UTC);
        st = okid_init(id, cfg, ws, bytes, NULL);
        if (st == OKID_OK) st = okid_push_block(id, samples, u, (size_t)cols->r, y, (size_t)cols->m, NULL);
        if (st == OKID_OK) st = okid_identify(id, res);
        timespec_get(&t1, TIME_UTC);
        const double seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        *elapsed = (*elapsed < 0 || seconds < *elapsed) ? seconds : *elapsed;
    }
    free(u);
    free(y);
    return st;
}

/* The samples the scan kept, in blocks into the identifier, then identify. */
static okid_status identify_streamed(const okid_config *cfg, record_reader *reader, const record_columns *cols,
                                     void *ws, size_t bytes, okid_identifier *id, okid_result *res, int *rc)
{
    enum { BLOCK = 4096 }; /* samples per okid_push_block: 4 MB at most with 64 inputs and 64 outputs */
    char error[512];
    okid_real *u = malloc(sizeof(okid_real) * BLOCK * (size_t)cols->r);
    okid_real *y = malloc(sizeof(okid_real) * BLOCK * (size_t)cols->m);
    okid_status st = okid_init(id, cfg, ws, bytes, NULL);
    if (u == NULL || y == NULL) {
        *rc = cli_error(EXIT_DATA, "out of memory");
    }
    while (*rc == 0 && st == OKID_OK) {
        const long got = record_read_block(reader, cols, BLOCK, u, y, error, sizeof error);
        if (got < 0) {
            *rc = cli_error(EXIT_DATA, "%s", error);
        } else if (got == 0) {
            break;
        } else {
            st = okid_push_block(id, (size_t)got, u, (size_t)cols->r, y, (size_t)cols->m, NULL);
        }
    }
    if (*rc == 0 && st == OKID_OK) st = okid_identify(id, res);
    free(u);
    free(y);
    return st;
}

/* One refine model's run: its start (searched or given), OKID/ERA, the refinement. */
typedef struct model_run {
    okid_config cfg;
    start_search search;
    void *grown, *rf_ws;
    okid_identifier id;
    okid_result res;
    okid_refiner rf;
    okid_refine_result refined;
    okid_status st; /* okid_identify()'s */
    int rc;         /* identify_refine()'s */
    okid_identifier *start_id; /* the given start's identifier (the mode selection's), else &id */
} model_run;

static void model_run_free(model_run *run)
{
    free(run->rf_ws);
    free(run->grown);
}

/* start non-NULL (the mode selection's, refine_selection.h): refined as it is, without a search. */
static void run_model(const identify_options *o, const okid_config *cfg, size_t n, const okid_real *u,
                      const okid_real *y, const record_columns *cols, void *ws, size_t bytes,
                      const okid_result *start, okid_identifier *start_id, model_run *run)
{
    run->cfg = *cfg;
    run->search = (start_search){.count = 0, .best = -1};
    run->grown = run->rf_ws = NULL;
    run->rc = 0;
    run->start_id = &run->id;
    if (start != NULL) {
        run->res = *start;
        run->start_id = start_id;
        run->st = OKID_OK;
        run->rc = identify_refine(o, &run->res, n, u, y, 0, &run->rf, &run->rf_ws, &run->refined);
        return;
    }
    if (!o->horizons_given && cfg->decimation <= 1) {
        identify_choose_start(o, &run->cfg, n, u, y, &run->search);
        if (okid_workspace_size(&run->cfg, &bytes) != OKID_OK ||
            (run->grown = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16)) == NULL) {
            run->st = OKID_OK;
            run->rc = cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", bytes);
            return;
        }
        ws = run->grown;
    }
    run->st = okid_init(&run->id, &run->cfg, ws, bytes, NULL);
    if (run->st == OKID_OK) run->st = okid_push_block(&run->id, n, u, (size_t)cols->r, y, (size_t)cols->m, NULL);
    if (run->st == OKID_OK) run->st = okid_identify(&run->id, &run->res);
    if (run->st == OKID_OK) run->rc = identify_refine(o, &run->res, n, u, y, 0, &run->rf, &run->rf_ws, &run->refined);
}

/* okid_config_horizons refused --observer-seconds/--hankel-seconds: the line and the exit code. */
static int horizons_error(okid_status st, const okid_config *cfg)
{
    const double step = (double)cfg->dt * (cfg->decimation > 1 ? cfg->decimation : 1);
    return cli_error(EXIT_USAGE, "--observer-seconds/--hankel-seconds: %s (at most %d blocks of K dt = %g s)",
                     okid_status_str(st), OKID_MAX_HORIZON, step);
}

/* auto_identify() failed (ai->failure, status st): the line on stderr and the exit code. */
static int auto_failure_exit(auto_identification *ai, okid_status st, const column_choice *cc, const record_scan *scan)
{
    switch (ai->failure) {
    case AUTO_OK: return 0;
    case AUTO_FAILED_HORIZONS: return horizons_error(st, &ai->cfg);
    case AUTO_FAILED_SETTINGS: return settings_error(&ai->cfg, st);
    case AUTO_FAILED_DATA: return cli_error(EXIT_DATA, "%s", ai->shortfall);
    case AUTO_FAILED_MEMORY: return cli_error(EXIT_DATA, "out of memory");
    case AUTO_FAILED_MODES:
    case AUTO_FAILED_MODEL: return identify_failure(&ai->cfg, auto_failed_identifier(ai), st, cc, scan);
    }
    return cli_error(EXIT_DATA, "identification failed: %s", okid_status_str(st));
}

/*
 * okid identify --refine: the record into memory (the refinement feeds it once per pass), then the
 * start search identifies and refines from several starts; then OKID/ERA, the refinement, the report.
 * --refine-model auto: output error, then the innovation form when output error's residual is not
 * white (with its own start search and OKID/ERA run, in its own workspace), and the choice of
 * refine_choice.h; the report is the chosen model's, with the choice and its reason.
 */
static int identify_and_refine(const identify_options *o, okid_config *cfg, record_reader *reader,
                               const record_columns *cols, const record_scan *scan, void *ws, size_t bytes,
                               const column_choice *cc)
{
    const size_t n = scan->samples;
    okid_real *u, *y;
    const int loaded = load_samples(reader, cols, n, &u, &y);
    if (loaded != 0) {
        return loaded;
    }
    struct timespec t0, t1; /* --timing: the mode selection, the start search, OKID/ERA and the refinement */
    timespec_get(&t0, TIME_UTC);
    /* no order given: the order and the start from the physical modes (refine_selection.h), selected on
       the record the refinement sees (its decimation kept: 1, or the lifted record's) */
    auto_identification ai = {0};
    refine_selection sel = {0};
    const okid_result *start = NULL;
    if (cfg->order == 0) {
        const auto_request rq = {.cfg = *cfg, .given = o->given | AUTO_GIVEN_DECIMATION,
                                 .observer_seconds = o->observer_seconds, .hankel_seconds = o->hankel_seconds,
                                 .n = n, .u = u, .y = y};
        const okid_status st = auto_identify(&rq, &ai);
        int rc = st == OKID_OK ? 0 : auto_failure_exit(&ai, st, cc, scan);
        if (rc == 0 && refine_selection_start(&ai, &sel) != 0) rc = cli_error(EXIT_DATA, "out of memory");
        if (rc != 0) {
            auto_identification_free(&ai);
            free(u), free(y);
            return rc;
        }
        if (sel.order == 0) {
            /* nothing physical to start from: the library's order on a real record is a model of the
               noise (Hayward at its own dt: order 408, hours of passes), and from it the refinement
               splits modes (docs/refinement.md); refuse at once and say what to do */
            const int k = ai.cfg.decimation > 1 ? ai.cfg.decimation : 1;
            rc = cli_error(EXIT_DATA, "--refine without --order: the mode selection keeps no physical mode on the "
                           "record the refinement fits (dt = %g s, decimation %d): %s, so there is no start to refine; "
                           "without --refine the decimation is chosen from the data and may find them; to refine anyway "
                           "give --order N (2 per mode) and --observer-seconds/--hankel-seconds",
                           (double)ai.cfg.dt * k, k, sel.reason);
            refine_selection_free(&sel);
            auto_identification_free(&ai);
            free(u), free(y);
            return rc;
        }
        start = &sel.start;
        *cfg = ai.cfg;
        cfg->order = 0; /* "config": the order as given; "chosen" says how */
    }
    const int automatic = o->refine_cfg.refine_model == (okid_refine_model)REFINE_MODEL_AUTO;
    identify_options oe = *o, inn = *o;
    oe.refine_cfg.refine_model = OKID_REFINE_OUTPUT_ERROR;
    inn.refine_cfg.refine_model = OKID_REFINE_INNOVATION;
    model_run runs[2];
    model_run *chosen = &runs[0];
    run_model(automatic ? &oe : o, cfg, n, u, y, cols, ws, bytes, start, &ai.id, &runs[0]);
    refine_choice choice = {.chosen = OKID_REFINE_OUTPUT_ERROR};
    int ran_innovation = 0;
    if (automatic && runs[0].st == OKID_OK && runs[0].rc == 0) {
        if (refine_choice_needs_innovation(&runs[0].refined)) {
            /* a workspace of its own: runs[0]'s result views point into the first one */
            size_t inn_bytes = 0;
            void *inn_ws = okid_workspace_size(cfg, &inn_bytes) == OKID_OK
                               ? aligned_alloc(OKID_WORKSPACE_ALIGN, (inn_bytes + 15) / 16 * 16) : NULL;
            if (inn_ws == NULL) {
                model_run_free(&runs[0]);
                refine_selection_free(&sel);
                auto_identification_free(&ai);
                free(u), free(y);
                return cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", inn_bytes);
            }
            run_model(&inn, cfg, n, u, y, cols, inn_ws, inn_bytes, start, &ai.id, &runs[1]);
            ran_innovation = 1;
            const int inn_ok = runs[1].st == OKID_OK && runs[1].rc == 0;
            refine_choose(&runs[0].refined, inn_ok ? &runs[1].refined : NULL, cols->m, &choice);
            if (choice.chosen == OKID_REFINE_INNOVATION) chosen = &runs[1];
            /* the chosen run's workspace lives until the report: the grown one or inn_ws */
            if (runs[1].grown == NULL) runs[1].grown = inn_ws;
            else free(inn_ws);
        } else {
            refine_choose(&runs[0].refined, NULL, cols->m, &choice);
        }
    }
    int rc = chosen->rc;
    if (chosen->st != OKID_OK) {
        rc = identify_failure(&chosen->cfg, &chosen->id, chosen->st, cc, scan);
    } else if (rc == 0) {
        timespec_get(&t1, TIME_UTC);
        const double elapsed = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        identify_options shown = chosen == &runs[1] ? inn : automatic ? oe : *o;
        if (automatic) shown.refine_choice = &choice;
        shown.refine_order_reason = sel.reason;
        *cfg = chosen->cfg;
        rc = report(&shown, cfg, chosen->start_id, &chosen->res, cc, elapsed, &chosen->refined, &chosen->search,
                    ai.modes != NULL ? &ai.choice : NULL, NULL, NULL);
    }
    model_run_free(&runs[0]);
    if (ran_innovation) model_run_free(&runs[1]);
    refine_selection_free(&sel);
    auto_identification_free(&ai);
    free(u);
    free(y);
    return rc;
}

/*
 * okid identify with a setting or the order left to the data (auto_identify.h): the record into
 * memory, then the host library's automatic identification, then the report.
 */
static int identify_auto(const identify_options *o, const okid_config *cfg, record_reader *reader,
                         const record_columns *cols, const record_scan *scan, const column_choice *cc)
{
    auto_request rq = {.cfg = *cfg, .given = o->given, .observer_seconds = o->observer_seconds,
                       .hankel_seconds = o->hankel_seconds, .n = scan->samples};
    okid_real *u, *y;
    int rc = load_samples(reader, cols, rq.n, &u, &y);
    if (rc != 0) {
        return rc;
    }
    rq.u = u, rq.y = y;
    struct timespec t0, t1;
    timespec_get(&t0, TIME_UTC);
    auto_identification ai;
    const okid_status st = auto_identify(&rq, &ai);
    timespec_get(&t1, TIME_UTC);
    const double elapsed = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    switch (ai.failure) {
    case AUTO_OK: {
        okid_config shown = ai.cfg; /* "config": the order as given (0: chosen, "chosen" says how) */
        shown.order = o->cfg.order;
        double fit[OKID_MAX_DIMENSION];
        unsigned warning = 0;
        const int have_fit = output_fit_record(&ai.result, rq.n, u, y, fit, &warning) == 0;
        ai.result.warnings |= warning;
        rc = report(o, &shown, &ai.id, &ai.result, cc, elapsed, NULL, NULL, &ai.choice, ai.modes, have_fit ? fit : NULL);
        break;
    }
    default: rc = auto_failure_exit(&ai, st, cc, scan); break;
    }
    auto_identification_free(&ai);
    free(u);
    free(y);
    return rc;
}

static int run(identify_options *o, record_reader *reader, const char *label)
{
    const csv_table *header = &reader->stream.header;
    char error[512];
    int time_col = -1;
    record_columns cols;
    int rc = record_find_time_column(header, &time_col, error, sizeof error);
    if (rc == 0) rc = record_choose_columns(header, time_col, o->inputs, o->outputs, &cols, error, sizeof error);
    if (rc != 0) {
        return cli_error(rc, "%s", error);
    }
    column_choice *cc = calloc(1, sizeof *cc);
    if (cc == NULL) {
        return cli_error(EXIT_DATA, "out of memory");
    }
    cc->r = cols.r, cc->m = cols.m;
    memcpy(cc->inputs, cols.inputs, sizeof cc->inputs);
    memcpy(cc->outputs, cols.outputs, sizeof cc->outputs);
    for (int i = 0; i < cc->r; ++i) cc->input_names[i] = header->names[cc->inputs[i]];
    for (int i = 0; i < cc->m; ++i) cc->output_names[i] = header->names[cc->outputs[i]];
    record_scan scan;
    if (record_scan_all(reader, &cols, &scan, error, sizeof error) != 0) {
        rc = cli_error(EXIT_DATA, "%s: %s", label, error);
    }
    double dt = 0;
    if (rc == 0) {
        rc = record_dt(&scan, header, time_col, o->have_dt, o->dt, o->ignore_time_column, &dt, error, sizeof error);
        if (rc != 0) cli_error(rc, "%s", error);
    }
    /* --decimation-method lift: the identification sees the lifted record at K dt, undecimated */
    if (rc == 0 && o->decimation_method == DECIMATION_LIFT && o->cfg.decimation > 1) {
        rc = identify_lift_record(o->cfg.decimation, reader, &cols, &scan, cc->input_names, &cc->lifted);
        if (rc == 0) {
            cc->lift_factor = o->cfg.decimation;
            cc->r = cols.r;
            memcpy(cc->inputs, cols.inputs, sizeof cc->inputs);
            dt *= o->cfg.decimation;
        }
    }
    if (rc != 0) {
        free(cc);
        return rc;
    }
    if (cc->r == 0) { /* --inputs 0: no measured force, the outputs alone (docs/ambient.md) */
        rc = identify_ambient(o, reader, &cols, &scan, cc->output_names, dt);
        free(cc);
        return rc;
    }
    if (o->references != NULL || o->segments > 0 || o->segment_samples > 0) {
        free(cc);
        return cli_error(EXIT_USAGE, "--%s applies to output-only identification only (--inputs 0)",
                         o->references != NULL ? "references" : o->segments > 0 ? "segments" : "segment-samples");
    }
    const int r = cc->r, m = cc->m;
    okid_config cfg = o->cfg;
    cfg.num_inputs = r;
    cfg.num_outputs = m;
    cfg.dt = (okid_real)dt;
    if (cc->lift_factor > 0) cfg.decimation = 1;
    okid_status st = OKID_OK;
    if ((st = auto_horizon_seconds(&cfg, o->observer_seconds, o->hankel_seconds)) != OKID_OK) {
        free(cc);
        return horizons_error(st, &cfg);
    }
    /* settings not given, or the order: chosen from the data, the physical modes selected */
    const unsigned all = AUTO_GIVEN_DECIMATION | AUTO_GIVEN_OBSERVER | AUTO_GIVEN_HANKEL;
    if (!o->refine && (o->given != all || cfg.order == 0)) {
        rc = identify_auto(o, &cfg, reader, &cols, &scan, cc);
        free(cc);
        return rc;
    }
    size_t bytes = 0;
    st = okid_workspace_size(&cfg, &bytes);
    if (st != OKID_OK) {
        free(cc);
        return settings_error(&cfg, st);
    }
    /* the data's sufficiency before the large allocation */
    if (config_data_shortfall(&cfg, scan.samples, error, sizeof error)) {
        free(cc);
        return cli_error(EXIT_DATA, "%s", error);
    }
    /* aligned_alloc wants a size that is a multiple of the alignment */
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    if (ws == NULL) {
        free(cc);
        return cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", bytes);
    }
    if (o->refine) { /* the refinement's passes and its start search read the record from memory */
        const int code = identify_and_refine(o, &cfg, reader, &cols, &scan, ws, bytes, cc);
        free(ws);
        free(cc);
        return code;
    }
    okid_identifier id;
    okid_result res;
    double elapsed = -1;
    st = o->timing ? identify_timed(o, &cfg, reader, &cols, scan.samples, ws, bytes, &id, &res, &elapsed, &rc)
                   : identify_streamed(&cfg, reader, &cols, ws, bytes, &id, &res, &rc);
    if (rc == 0 && st == OKID_E_DECOMPOSITION_FAILED && cfg.estimator == OKID_ESTIMATOR_CORRELATION) {
        /* the correlation form's guard refused (okid/identifier.h): the whole record is at hand, so
           identify it again with the QR fold, which needs no more memory, and say so (SLICOT IWARN = 2) */
        cfg.estimator = OKID_ESTIMATOR_LEAST_SQUARES; /* and the JSON's config says what gave the result */
        if (fseek(reader->samples, 0, SEEK_SET) != 0) {
            rc = cli_error(EXIT_DATA, "cannot read the temporary file of samples again: %s", strerror(errno));
        } else {
            elapsed = -1;
            st = o->timing ? identify_timed(o, &cfg, reader, &cols, scan.samples, ws, bytes, &id, &res, &elapsed, &rc)
                           : identify_streamed(&cfg, reader, &cols, ws, bytes, &id, &res, &rc);
            res.warnings |= OKID_W_CORRELATION_FALLBACK;
        }
    }
    double fit[OKID_MAX_DIMENSION];
    const int have_fit = rc == 0 && st == OKID_OK && record_fit(reader, &cols, &res, fit) == 0;
    if (rc == 0) {
        rc = st == OKID_OK ? report(o, &cfg, &id, &res, cc, elapsed, NULL, NULL, NULL, NULL, have_fit ? fit : NULL)
                           : identify_failure(&cfg, &id, st, cc, &scan);
    }
    free(ws);
    free(cc);
    return rc;
}

int identify_command(int argc, char **argv)
{
    identify_options o;
    int rc = identify_parse_options(argc, argv, &o);
    if (rc != 0) {
        return rc;
    }
    const char *label = strcmp(o.file, "-") == 0 ? "standard input" : o.file;
    record_reader reader;
    char error[512];
    if (record_open(&reader, o.file, error, sizeof error) != 0) {
        return cli_error(EXIT_DATA, "%s: %s", label, error);
    }
    rc = run(&o, &reader, label);
    record_close(&reader);
    /* a full disk or a closed pipe must not look like success */
    if (fflush(stdout) != 0 || ferror(stdout)) {
        return rc ? rc : cli_error(EXIT_DATA, "cannot write the result to standard output");
    }
    return rc;
}

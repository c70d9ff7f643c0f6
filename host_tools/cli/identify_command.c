/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify: read a CSV recording, choose the input and output columns, identify, print. */
#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_common.h"
#include "csv_reader.h"
#include "identify_options.h"
#include "identify_refine.h"
#include "json_writer.h"
#include "record_reader.h"
#include "time_column.h"

/*
 * Fills columns[] (room for OKID_MAX_DIMENSION) from NAMES or COUNT (a count starts at column
 * *next). used[] marks the columns already taken (the time column, the inputs): a column is an
 * input or an output, never both, and never twice. A value that names a column is a name; one
 * that could be a count too is refused (docs/cli.md). is_default: the built-in count, never a name.
 */
static int select_columns(const csv_table *t, const char *spec, int *next, char *used, int *columns, int *count,
                          const char *what, int is_default)
{
    int n = 0;
    *count = 0;
    int left = 0;
    for (int j = *next; j < t->num_columns; ++j) left += !used[j];
    int named = is_default ? -1 : csv_find_column(t, spec);
    int first_free = *next;
    while (first_free < t->num_columns && used[first_free]) ++first_free;
    if (cli_parse_int(spec, &n) == 0 && n == 1 && named == first_free) {
        named = -1; /* the count and the name take the same column */
    }
    if (cli_parse_int(spec, &n) == 0 && named >= 0 && !used[named] && n >= 1 && n <= left &&
        n <= OKID_MAX_DIMENSION) {
        return cli_error(EXIT_USAGE,
                         "--%s %s: ambiguous, both a count (the next %d column(s)) and the name of column %d ('%s'): "
                         "write --%s %s, (a trailing comma: a list of names) for that column, or name the columns "
                         "you mean (--%s A,B)",
                         what, spec, n, named + 1, t->names[named], what, spec, what);
    }
    if (cli_parse_int(spec, &n) == 0 && named < 0) {
        /* a count takes the next columns not yet taken (the time column, named inputs): never one twice */
        if (n < 1 || n > left) {
            return cli_error(EXIT_USAGE, "--%s %d: the file has %d column(s) after the ones already taken", what, n,
                             left);
        }
        if (n > OKID_MAX_DIMENSION) {
            return cli_error(EXIT_USAGE, "--%s %d: at most %d %s", what, n, OKID_MAX_DIMENSION, what);
        }
        for (int j = 0; j < n; ++j) {
            while (used[*next]) ++*next;
            used[*next] = 1;
            columns[j] = (*next)++;
        }
        *count = n;
        return 0;
    }
    char *copy = malloc(strlen(spec) + 1);
    if (copy == NULL) {
        return cli_error(EXIT_DATA, "out of memory");
    }
    strcpy(copy, spec);
    int rc = 0;
    for (char *name = strtok(copy, ","); name != NULL && rc == 0; name = strtok(NULL, ",")) {
        const int col = csv_find_column(t, name);
        if (col < 0) {
            rc = cli_error(EXIT_USAGE, "--%s: no column named '%s' in the file", what, name);
        } else if (used[col]) {
            rc = cli_error(EXIT_USAGE, "--%s: column '%s' is already %s", what, name,
                           time_column_unit(name) > 0 ? "the time column (see docs/robustness.md)" : "an input or an output");
        } else if (*count >= OKID_MAX_DIMENSION) {
            rc = cli_error(EXIT_USAGE, "--%s: at most %d %s", what, OKID_MAX_DIMENSION, what);
        } else {
            used[col] = 1;
            columns[(*count)++] = col;
        }
    }
    free(copy);
    if (rc == 0 && *count == 0) {
        rc = cli_error(EXIT_USAGE, "--%s: no column given", what);
    }
    return rc;
}

/* Names of the chosen columns, for the table and the JSON. */
typedef struct column_choice {
    int inputs[OKID_MAX_DIMENSION], outputs[OKID_MAX_DIMENSION];
    const char *input_names[OKID_MAX_DIMENSION], *output_names[OKID_MAX_DIMENSION];
    int r, m;
} column_choice;

static void print_table(const okid_config *cfg, const okid_result *res, const column_choice *cc, const char *file)
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
        if (res->warnings & bit) {
            printf("warning: %s\n", okid_warning_str(bit));
        }
    }
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
    /* eq. 64: the displacement, then the velocity, at each sensor location */
    printf("\nmode shapes (eq. 64, unit norm); columns:");
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

/* The time column (time_column.h), -1 without one; two of them are refused (-2, message printed). */
static int find_time_column(const csv_table *t)
{
    int found = -1;
    for (int j = 0; j < t->num_columns; ++j) {
        if (time_column_unit(t->names[j]) > 0) {
            if (found >= 0) {
                cli_error(EXIT_DATA, "two time columns ('%s' and '%s'): keep one (docs/robustness.md)", t->names[found],
                          t->names[j]);
                return -2;
            }
            found = j;
        }
    }
    return found;
}

/* Inputs and outputs from --inputs / --outputs (defaults: one input, every other column an output);
   the time column is never one of them. */
static int choose_columns(const identify_options *o, const csv_table *t, int time_col, column_choice *cc)
{
    char *used = calloc((size_t)t->num_columns, 1);
    if (used == NULL) {
        return cli_error(EXIT_DATA, "out of memory");
    }
    if (time_col >= 0) used[time_col] = 1;
    int next = 0;
    int rc = select_columns(t, o->inputs ? o->inputs : "1", &next, used, cc->inputs, &cc->r, "inputs", o->inputs == NULL);
    if (rc == 0 && o->outputs != NULL) {
        rc = select_columns(t, o->outputs, &next, used, cc->outputs, &cc->m, "outputs", 0);
    } else if (rc == 0) {
        cc->m = 0;
        for (int j = 0; j < t->num_columns && rc == 0; ++j) {
            if (used[j]) continue;
            if (cc->m == OKID_MAX_DIMENSION) {
                rc = cli_error(EXIT_USAGE, "more than %d output columns: choose them with --outputs", OKID_MAX_DIMENSION);
            } else {
                cc->outputs[cc->m++] = j;
            }
        }
        if (rc == 0 && cc->m == 0) {
            rc = cli_error(EXIT_USAGE, "no output columns left after the inputs");
        }
    }
    free(used);
    for (int i = 0; rc == 0 && i < cc->r; ++i) cc->input_names[i] = t->names[cc->inputs[i]];
    for (int i = 0; rc == 0 && i < cc->m; ++i) cc->output_names[i] = t->names[cc->outputs[i]];
    return rc;
}

/*
 * okid_workspace_size() said no: the setting, its value and its valid range (okid_config_check),
 * and where the range comes from other settings, the combination with its numbers.
 */
static long long min3(long long a, long long b, long long c)
{
    const long long ab = a < b ? a : b;
    return ab < c ? ab : c;
}

static int settings_error(const okid_config *cfg, okid_status st)
{
    okid_config_issue issue;
    (void)okid_config_check(cfg, &issue);
    char range[160] = "";
    if (issue.field != NULL && strcmp(issue.field, "rank_tolerance") == 0) {
        snprintf(range, sizeof range, "; rank_tolerance = %g must be 0 (the default) or in [%g, %g)", issue.value,
                 issue.min, issue.max);
    } else if (issue.field != NULL && strcmp(issue.field, "workspace bytes") == 0) {
        snprintf(range, sizeof range, "; the workspace would be %.4g bytes, more than this machine can address (%g)",
                 issue.value, issue.max);
    } else if (issue.field != NULL) {
        snprintf(range, sizeof range, "; %s = %.6g is outside %.6g..%.6g", issue.field, issue.value, issue.min,
                 issue.max);
    }
    const long long r = cfg->num_inputs, m = cfg->num_outputs, p = cfg->observer_order;
    const long long columns = r + (cfg->realization == OKID_REALIZATION_COMBINED ? m : 0);
    const long long hankel = cfg->hankel_rows * m, window = cfg->hankel_cols * columns;
    const long long largest = min3(hankel, window, m * p);
    char hint[256] = "";
    if (st == OKID_E_BAD_ORDER && cfg->order == 0) {
        snprintf(hint, sizeof hint, "; the automatic order would search up to min(alpha m, beta columns, m p) = "
                 "%lld, more than %d: give --order", largest, OKID_MAX_ORDER);
    } else if (st == OKID_E_BAD_ORDER) {
        snprintf(hint, sizeof hint, "; --order %d must be at most min(alpha m, beta columns, m p) = "
                 "min(%lld, %lld, %lld) = %lld", cfg->order, hankel, window, m * p, largest);
    } else if (cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL && st == OKID_E_BAD_SIZE) {
        snprintf(hint, sizeof hint, "; --instrument-lags %d: instrumental variables need r (L + 1) >= q = %lld, "
                 "L >= p = %lld and L <= %d", cfg->instrument_lags, r + (r + m) * p, p, OKID_MAX_INSTRUMENT_LAGS);
    }
    return cli_error(EXIT_USAGE, "invalid settings (r = %d, m = %d, p = %d, n = %d, Hankel %d x %d): %s%s%s",
                     cfg->num_inputs, cfg->num_outputs, cfg->observer_order, cfg->order, cfg->hankel_rows,
                     cfg->hankel_cols, okid_status_str(st), range, hint);
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
                  const start_search *search)
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
    if (o->json) {
        json_result(stdout, cfg, res, cc->input_names, cc->output_names, o->timing ? elapsed : -1);
        if (stab_ws != NULL) json_stabilization(stdout, &st, o->stabilization, 2, cfg->num_outputs);
        if (refined != NULL) {
            json_refinement(stdout, &o->refine_cfg, refined, cfg->num_outputs);
            if (search->count > 0) json_start_search(stdout, search);
        }
        fputs("\n}\n", stdout);
    } else {
        print_table(cfg, res, cc, o->file);
        if (stab_ws != NULL && st.num_orders > 0) print_stabilization(&st);
        if (refined != NULL && search->count > 0) print_start_search(search);
        if (refined != NULL) print_refinement(refined, cfg->num_outputs);
        if (o->timing) printf("\nelapsed from okid_init to the modes: %.6f s\n", elapsed);
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

/* dt: --dt, or the time column's uniform step (time_column.h). */
static int record_dt(const identify_options *o, const csv_table *header, int time_col, const record_scan *scan,
                     double *dt)
{
    char error[512];
    if (o->have_dt) {
        *dt = o->dt;
        /* --dt with a time column: they must agree (a wrong --dt scales every frequency) */
        if (time_col >= 0 && !o->ignore_time_column &&
            time_stamps_check_dt(&scan->stamps, header->names[time_col], o->dt, error, sizeof error) != 0) {
            return cli_error(EXIT_USAGE, "%s", error);
        }
        return 0;
    }
    if (time_col < 0) {
        return cli_error(EXIT_USAGE, "no time column (t, time or timestamp, with an optional unit: docs/robustness.md) "
                                     "in the file: give --dt");
    }
    return time_stamps_step(&scan->stamps, header->names[time_col], dt, error, sizeof error) == 0
               ? 0
               : cli_error(EXIT_DATA, "%s", error);
}

/* Regressor rows the record can give at most: every K-th sample kept, the first p only fill the window. */
static unsigned long long rows_at_most(const okid_config *cfg, size_t samples)
{
    const unsigned long long k = cfg->decimation > 1 ? (unsigned long long)cfg->decimation : 1u;
    const unsigned long long kept = (samples + k - 1) / k;
    const unsigned long long window = cfg->zero_initial_state ? 0u : (unsigned long long)cfg->observer_order;
    return kept > window ? kept - window : 0u;
}

/*
 * okid identify --refine: the chosen channels come back from the scan into memory ((r + m) 8 bytes
 * per sample), since the refinement makes several passes over them and, without horizons, the
 * start search identifies and refines from several starts; then OKID/ERA, the refinement, the report.
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
    start_search search = {.count = 0, .best = -1};
    void *grown = NULL;
    if (!o->horizons_given && cfg->decimation <= 1) {
        identify_choose_start(o, cfg, n, u, y, &search);
        if (okid_workspace_size(cfg, &bytes) != OKID_OK ||
            (grown = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16)) == NULL) {
            free(u), free(y);
            return cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", bytes);
        }
        ws = grown;
    }
    okid_identifier id;
    okid_result res;
    okid_status st = okid_init(&id, cfg, ws, bytes, NULL);
    if (st == OKID_OK) st = okid_push_block(&id, n, u, (size_t)cols->r, y, (size_t)cols->m, NULL);
    if (st == OKID_OK) st = okid_identify(&id, &res);
    int rc;
    if (st != OKID_OK) {
        rc = identify_failure(cfg, &id, st, cc, scan);
    } else {
        okid_refiner rf;
        okid_refine_result refined;
        void *rf_ws = NULL;
        rc = identify_refine(o, &res, n, u, y, 0, &rf, &rf_ws, &refined);
        if (rc == 0) rc = report(o, cfg, &id, &res, cc, -1, &refined, &search);
        free(rf_ws);
    }
    free(grown);
    free(u);
    free(y);
    return rc;
}

static int run(identify_options *o, record_reader *reader, const char *label)
{
    const csv_table *header = &reader->stream.header;
    const int time_col = find_time_column(header);
    if (time_col == -2) {
        return EXIT_DATA;
    }
    column_choice *cc = calloc(1, sizeof *cc);
    if (cc == NULL) {
        return cli_error(EXIT_DATA, "out of memory");
    }
    int rc = choose_columns(o, header, time_col, cc);
    record_columns cols = {time_col, time_col >= 0 ? time_column_unit(header->names[time_col]) : 1, {0}, {0}, cc->r,
                           cc->m};
    memcpy(cols.inputs, cc->inputs, sizeof cols.inputs);
    memcpy(cols.outputs, cc->outputs, sizeof cols.outputs);
    record_scan scan;
    char error[512];
    if (rc == 0 && record_scan_all(reader, &cols, &scan, error, sizeof error) != 0) {
        rc = cli_error(EXIT_DATA, "%s: %s", label, error);
    }
    double dt = 0;
    if (rc == 0) rc = record_dt(o, header, time_col, &scan, &dt);
    if (rc != 0) {
        free(cc);
        return rc;
    }
    const int r = cc->r, m = cc->m;
    okid_config cfg = o->cfg;
    cfg.num_inputs = r;
    cfg.num_outputs = m;
    cfg.dt = (okid_real)dt;
    okid_status st = OKID_OK;
    if (o->observer_seconds > 0 || o->hankel_seconds > 0) {
        /* horizons in seconds: the ones not given keep their counts (count * K dt round-trips) */
        const double step = dt * cfg.decimation;
        st = okid_config_horizons(&cfg, (okid_real)(o->observer_seconds > 0 ? o->observer_seconds : cfg.observer_order * step),
                                  (okid_real)(o->hankel_seconds > 0 ? o->hankel_seconds : cfg.hankel_rows * step),
                                  (okid_real)(o->hankel_seconds > 0 ? o->hankel_seconds : cfg.hankel_cols * step));
        if (st != OKID_OK) {
            free(cc);
            return cli_error(EXIT_USAGE, "--observer-seconds/--hankel-seconds: %s (at most %d blocks of K dt = %g s)",
                             okid_status_str(st), OKID_MAX_HORIZON, step);
        }
    }
    size_t bytes = 0;
    st = okid_workspace_size(&cfg, &bytes);
    if (st != OKID_OK) {
        free(cc);
        return settings_error(&cfg, st);
    }
    /* the data's sufficiency before the large allocation */
    const int q = r + (r + m) * cfg.observer_order;
    if (rows_at_most(&cfg, scan.samples) < (unsigned long long)q) {
        free(cc);
        return cli_error(EXIT_DATA, "not enough data: %zu samples give at most %llu regressor rows, %d needed "
                                    "(q = r + (r+m)p with p = %d)",
                         scan.samples, rows_at_most(&cfg, scan.samples), q, cfg.observer_order);
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
    if (rc == 0) {
        rc = st == OKID_OK ? report(o, &cfg, &id, &res, cc, elapsed, NULL, NULL)
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

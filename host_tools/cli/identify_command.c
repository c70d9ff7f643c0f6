/* okid identify: read a CSV recording, choose the input and output columns, identify, print. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "cli_common.h"
#include "csv_reader.h"
#include "json_writer.h"

static const char identify_usage[] =
    "usage: okid identify [options] FILE.csv\n"
    "\n"
    "FILE.csv has a header row of column names; an optional first column named t or time holds the\n"
    "sample times. Every other cell is a finite number.\n"
    "\n"
    "  --inputs NAMES|COUNT     input (force) columns: comma-separated names, or how many columns\n"
    "                           follow the time column (default 1)\n"
    "  --outputs NAMES|COUNT    output (sensor) columns: names, or how many follow the inputs\n"
    "                           (default: every remaining column)\n"
    "  --dt S                   sample interval [s] (default: from the time column, which must be uniform)\n"
    "  --observer-order P       observer order p (default 20)\n"
    "  --order N                model order n; 0 = largest singular-value gap (default 0)\n"
    "  --hankel-rows A          Hankel block rows alpha (default 20)\n"
    "  --hankel-cols B          Hankel block columns beta (default 20)\n"
    "  --sensing KIND           acceleration|velocity|displacement (default acceleration)\n"
    "  --realization KIND       system|combined (default system; combined also gives the observer gain G)\n"
    "  --forgetting L           exponential forgetting factor in (0, 1] (default 1)\n"
    "  --rank-tolerance T       relative tolerance of the rank-revealing least squares (default 1e-10)\n"
    "  --zero-initial-state     the record starts at rest (use its first samples with zero history)\n"
    "  --json                   print one JSON object instead of a table\n"
    "  --timing                 report the seconds from okid_init to the modes (\"elapsed_seconds\" in JSON)\n"
    "  --repeat K               with --timing: identify K times from scratch, report the fastest (default 1)\n";

typedef struct identify_options {
    const char *file, *inputs, *outputs;
    double dt;
    int have_dt, json, timing, repeat;
    okid_config cfg;
} identify_options;

static int parse_options(int argc, char **argv, identify_options *o)
{
    memset(o, 0, sizeof *o);
    o->repeat = 1;
    okid_config_default(&o->cfg, 1, 1);
    o->cfg.observer_order = 20;
    o->cfg.order = 0;
    for (int i = 1; i < argc; ++i) {
        const char *opt = argv[i];
        if (strcmp(opt, "--help") == 0 || strcmp(opt, "-h") == 0) {
            fputs(identify_usage, stdout);
            exit(0);
        }
        if (strcmp(opt, "--json") == 0) {
            o->json = 1;
            continue;
        }
        if (strcmp(opt, "--timing") == 0) {
            o->timing = 1;
            continue;
        }
        if (strcmp(opt, "--zero-initial-state") == 0) {
            o->cfg.zero_initial_state = 1;
            continue;
        }
        if (strncmp(opt, "--", 2) != 0) {
            if (o->file != NULL) {
                return cli_error(EXIT_USAGE, "more than one input file ('%s' and '%s')", o->file, opt);
            }
            o->file = opt;
            continue;
        }
        if (i + 1 >= argc) {
            return cli_error(EXIT_USAGE, "option %s needs a value (see 'okid identify --help')", opt);
        }
        const char *val = argv[++i];
        double real = 0;
        int bad = 0;
        if (strcmp(opt, "--inputs") == 0) {
            o->inputs = val;
        } else if (strcmp(opt, "--outputs") == 0) {
            o->outputs = val;
        } else if (strcmp(opt, "--repeat") == 0) {
            bad = cli_parse_int(val, &o->repeat) != 0 || o->repeat < 1 || o->repeat > 100000;
        } else if (strcmp(opt, "--dt") == 0) {
            bad = cli_parse_real(val, &o->dt) != 0 || !(o->dt > 0);
            o->have_dt = 1;
        } else if (strcmp(opt, "--observer-order") == 0) {
            bad = cli_parse_int(val, &o->cfg.observer_order);
        } else if (strcmp(opt, "--order") == 0) {
            bad = cli_parse_int(val, &o->cfg.order);
        } else if (strcmp(opt, "--hankel-rows") == 0) {
            bad = cli_parse_int(val, &o->cfg.hankel_rows);
        } else if (strcmp(opt, "--hankel-cols") == 0) {
            bad = cli_parse_int(val, &o->cfg.hankel_cols);
        } else if (strcmp(opt, "--sensing") == 0) {
            bad = cli_parse_sensing(val, &o->cfg.sensing);
        } else if (strcmp(opt, "--realization") == 0) {
            bad = strcmp(val, "system") != 0 && strcmp(val, "combined") != 0;
            o->cfg.realization = strcmp(val, "combined") == 0 ? OKID_REALIZATION_COMBINED : OKID_REALIZATION_SYSTEM;
        } else if (strcmp(opt, "--forgetting") == 0) {
            bad = cli_parse_real(val, &real) != 0;
            o->cfg.forgetting_factor = real;
        } else if (strcmp(opt, "--rank-tolerance") == 0) {
            bad = cli_parse_real(val, &real) != 0;
            o->cfg.rank_tolerance = real;
        } else {
            return cli_error(EXIT_USAGE, "unknown option '%s' (see 'okid identify --help')", opt);
        }
        if (bad) {
            return cli_error(EXIT_USAGE, "bad value '%s' for %s", val, opt);
        }
    }
    if (o->file == NULL) {
        return cli_error(EXIT_USAGE, "no input file (usage: okid identify [options] FILE.csv)");
    }
    return 0;
}

static int is_time_name(const char *name)
{
    return strcmp(name, "t") == 0 || strcmp(name, "time") == 0;
}

/* Fills columns[] from NAMES or COUNT (starting at *next for a count). */
static int select_columns(const csv_table *t, const char *spec, int *next, int *columns, int *count,
                          const char *what)
{
    int n = 0;
    if (cli_parse_int(spec, &n) == 0) {
        if (n < 1 || *next + n > t->num_columns) {
            return cli_error(EXIT_USAGE, "--%s %d: the file has %d columns after the ones already taken", what, n,
                             t->num_columns - *next);
        }
        for (int j = 0; j < n; ++j) {
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
    *count = 0;
    for (char *name = strtok(copy, ","); name != NULL; name = strtok(NULL, ",")) {
        const int col = csv_find_column(t, name);
        if (col < 0) {
            cli_error(EXIT_USAGE, "--%s: no column named '%s' in the file", what, name);
            free(copy);
            return EXIT_USAGE;
        }
        if (*count >= OKID_MAX_DIMENSION) {
            free(copy);
            return cli_error(EXIT_USAGE, "--%s: more than %d columns", what, OKID_MAX_DIMENSION);
        }
        columns[(*count)++] = col;
    }
    free(copy);
    return (*count > 0) ? 0 : cli_error(EXIT_USAGE, "--%s: no column given", what);
}

/* dt from a uniform time column. */
static int time_step(const csv_table *t, int col, double *dt)
{
    if (t->num_rows < 2) {
        return cli_error(EXIT_DATA, "one row is not enough to find dt from the time column");
    }
    const size_t n = t->num_rows, nc = (size_t)t->num_columns;
    *dt = (t->values[(n - 1) * nc + (size_t)col] - t->values[(size_t)col]) / (double)(n - 1);
    if (!(*dt > 0)) {
        return cli_error(EXIT_DATA, "the time column does not increase");
    }
    for (size_t k = 1; k < n; ++k) {
        const double step = t->values[k * nc + (size_t)col] - t->values[(k - 1) * nc + (size_t)col];
        if (fabs(step - *dt) > 1e-6 * *dt) {
            return cli_error(EXIT_DATA, "the time column is not uniform (data row %zu steps by %g, mean step %g): "
                                        "resample it or give --dt", k + 1, step, *dt);
        }
    }
    return 0;
}

static void print_table(const okid_config *cfg, const okid_result *res, const char *file)
{
    printf("okid %s: %s, %llu samples, dt = %g s\n", OKID_VERSION_STRING, file, (unsigned long long)res->samples,
           (double)res->dt);
    printf("r = %d inputs, m = %d outputs, p = %d, Hankel %d x %d, %s realization, %s sensing\n", cfg->num_inputs,
           cfg->num_outputs, cfg->observer_order, cfg->hankel_rows, cfg->hankel_cols,
           cfg->realization == OKID_REALIZATION_COMBINED ? "combined" : "system", cli_sensing_name(cfg->sensing));
    printf("order n = %d, regressor rank %d of %d, input rank %d\n", res->order, res->regressor_rank,
           res->regressor_columns, res->input_rank);
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
    printf("\n mode  frequency [Hz]  damping ratio        eigenvalue (discrete)\n");
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_mode *md = &res->modes[i];
        printf("%5d  %14.8f  %13.8f  %+.10f %c %.10fi\n", i + 1, (double)md->frequency_hz,
               (double)md->damping_ratio, (double)md->eigenvalue.re, md->is_pair ? '+' : ' ',
               md->is_pair ? (double)md->eigenvalue.im : 0.0);
    }
    printf("\nmode shapes (eq. 64: displacements, then velocities at the sensors; unit norm)\n");
    for (int i = 0; i < res->num_modes; ++i) {
        printf("%5d ", i + 1);
        for (int a = 0; a < 2 * cfg->num_outputs; ++a) {
            printf(" %+.5f%+.5fi", (double)res->modes[i].shape[a].re, (double)res->modes[i].shape[a].im);
        }
        printf("\n");
    }
}

static int run(identify_options *o, const csv_table *t)
{
    int inputs[OKID_MAX_DIMENSION], outputs[OKID_MAX_DIMENSION], r = 0, m = 0;
    const int time_col = is_time_name(t->names[0]) ? 0 : -1;
    int next = time_col + 1, rc = 0;
    if ((rc = select_columns(t, o->inputs ? o->inputs : "1", &next, inputs, &r, "inputs")) != 0) {
        return rc;
    }
    if (o->outputs != NULL) {
        if ((rc = select_columns(t, o->outputs, &next, outputs, &m, "outputs")) != 0) {
            return rc;
        }
    } else {
        for (int j = 0; j < t->num_columns && m < OKID_MAX_DIMENSION; ++j) {
            int used = (j == time_col);
            for (int i = 0; i < r; ++i) used |= (inputs[i] == j);
            if (!used) outputs[m++] = j;
        }
        if (m == 0) {
            return cli_error(EXIT_USAGE, "no output columns left after the inputs");
        }
    }
    double dt = o->dt;
    if (!o->have_dt) {
        if (time_col < 0) {
            return cli_error(EXIT_USAGE, "no time column (t or time) in the file: give --dt");
        }
        if ((rc = time_step(t, time_col, &dt)) != 0) {
            return rc;
        }
    }
    okid_config cfg = o->cfg;
    cfg.num_inputs = r;
    cfg.num_outputs = m;
    cfg.dt = dt;
    size_t bytes = 0;
    okid_status st = okid_workspace_size(&cfg, &bytes);
    if (st != OKID_OK) {
        return cli_error(EXIT_USAGE, "invalid settings: %s", okid_status_str(st));
    }
    const size_t n = t->num_rows, nc = (size_t)t->num_columns;
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    okid_real *u = malloc(sizeof(okid_real) * n * (size_t)r), *y = malloc(sizeof(okid_real) * n * (size_t)m);
    if (ws == NULL || u == NULL || y == NULL) {
        free(ws), free(u), free(y);
        return cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", bytes);
    }
    for (size_t k = 0; k < n; ++k) {
        for (int i = 0; i < r; ++i) u[k * (size_t)r + (size_t)i] = (okid_real)t->values[k * nc + (size_t)inputs[i]];
        for (int i = 0; i < m; ++i) y[k * (size_t)m + (size_t)i] = (okid_real)t->values[k * nc + (size_t)outputs[i]];
    }
    okid_identifier id;
    okid_result res;
    okid_progress progress;
    double elapsed = -1;
    for (int rep = 0; rep < (o->repeat > 1 ? o->repeat : 1); ++rep) { /* the fastest of K: warm caches */
        struct timespec t0, t1;
        timespec_get(&t0, TIME_UTC);
        st = okid_init(&id, &cfg, ws, bytes, NULL);
        if (st == OKID_OK) st = okid_push_block(&id, n, u, (size_t)r, y, (size_t)m, NULL);
        if (st == OKID_OK) st = okid_identify(&id, &res);
        timespec_get(&t1, TIME_UTC);
        const double seconds = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
        elapsed = (elapsed < 0 || seconds < elapsed) ? seconds : elapsed;
    }
    if (st == OKID_E_NOT_ENOUGH_DATA && okid_get_progress(&id, &progress) == OKID_OK) {
        rc = cli_error(EXIT_DATA, "not enough data: %llu regressor rows from %zu samples, %d needed (q = r + (r+m)p)",
                       (unsigned long long)progress.rows, n, progress.rows_needed);
    } else if (st != OKID_OK) {
        rc = cli_error(EXIT_DATA, "identification failed: %s", okid_status_str(st));
    } else if (o->json) {
        json_result(stdout, &cfg, &res, o->timing ? elapsed : -1);
    } else {
        print_table(&cfg, &res, o->file);
        if (o->timing) printf("\nelapsed from okid_init to the modes: %.6f s\n", elapsed);
    }
    free(ws);
    free(u);
    free(y);
    return rc;
}

int identify_command(int argc, char **argv)
{
    identify_options o;
    int rc = parse_options(argc, argv, &o);
    if (rc != 0) {
        return rc;
    }
    csv_table table;
    char error[512];
    if (csv_read_file(o.file, &table, error, sizeof error) != 0) {
        return cli_error(EXIT_DATA, "%s: %s", o.file, error);
    }
    rc = run(&o, &table);
    csv_free(&table);
    return rc;
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * okid identify --inputs 0: output-only (ambient) identification of a record without a measured
 * force (okid/ambient.h, docs/ambient.md). The same command and flags as the input-output case,
 * since the record, the columns, dt, --order, --hankel-rows, --sensing and the JSON's "modes" mean
 * the same; the settings that belong to the observer (OKID) are refused in one line.
 */
#include "identify_ambient.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "ambient_modes.h"
#include "ambient_settings.h"
#include "auto_settings.h"
#include "cli_common.h"
#include "json_writer.h"

/* The first okid_config setting given that output-only identification has no use for, or NULL. */
static const char *inapplicable_option(const identify_options *o)
{
    okid_config d;
    okid_config_default(&d, 1, 1);
    const okid_config *c = &o->cfg;
    const struct {
        int given;
        const char *flag;
    } checks[] = {
        {(o->given & AUTO_GIVEN_OBSERVER) != 0, "--observer-order/--observer-seconds"},
        {(o->given & AUTO_GIVEN_DECIMATION) != 0, "--decimation"},
        {c->hankel_cols != d.hankel_cols && c->hankel_cols != c->hankel_rows, "--hankel-cols (L is both rows and columns: give --hankel-rows)"},
        {c->block_rows != d.block_rows, "--block-rows"},
        {c->forgetting_factor != d.forgetting_factor, "--forgetting-factor"},
        {c->rank_tolerance != d.rank_tolerance, "--rank-tolerance"},
        {c->realization != d.realization, "--realization"},
        {c->zero_initial_state != d.zero_initial_state, "--zero-initial-state"},
        {c->scaling != d.scaling, "--scaling (the correlations are always scaled by the channels' RMS)"},
        {c->estimator != d.estimator, "--estimator"},
        {c->instrument_lags != d.instrument_lags, "--instrument-lags"},
        {o->refine, "--refine"},
        {o->stabilization > 0, "--stabilization"},
        {o->all_poles, "--all-poles (the JSON's \"poles\" hold the verdicts)"},
    };
    for (size_t i = 0; i < sizeof checks / sizeof checks[0]; ++i) {
        if (checks[i].given) return checks[i].flag;
    }
    return NULL;
}

/* --references COUNT (the first outputs) or NAMES (of outputs) into cfg; 0, or EXIT_USAGE after one line. */
static int choose_references(const char *spec, const char *const *names, int m, okid_ambient_config *cfg)
{
    cfg->num_references = 0;
    if (spec == NULL) {
        return 0;
    }
    int count = 0;
    if (cli_parse_int(spec, &count) == 0) {
        int named = 0; /* a count that is also an output's name is refused, as --outputs does */
        for (int a = 0; a < m; ++a) named |= strcmp(names[a], spec) == 0;
        if (!named) {
            if (count < 1 || count > m) {
                return cli_error(EXIT_USAGE, "--references %d: 1..%d (the outputs)", count, m);
            }
            cfg->num_references = count;
            for (int l = 0; l < count; ++l) cfg->reference_channels[l] = l;
            return 0;
        }
        return cli_error(EXIT_USAGE, "--references %s: ambiguous, a count and the name of an output: write '%s,'",
                         spec, spec);
    }
    int chosen[OKID_MAX_DIMENSION] = {0};
    const char *p = spec;
    while (*p != '\0') {
        const char *end = strchr(p, ',');
        const size_t len = end != NULL ? (size_t)(end - p) : strlen(p);
        int found = -1;
        for (int a = 0; a < m && found < 0; ++a) {
            if (strlen(names[a]) == len && strncmp(names[a], p, len) == 0) found = a;
        }
        if (found < 0 && len > 0) {
            return cli_error(EXIT_USAGE, "--references: '%.*s' is not one of the output columns", (int)len, p);
        }
        if (found >= 0) chosen[found] = 1;
        p += len + (end != NULL);
    }
    for (int a = 0; a < m; ++a) {
        if (chosen[a]) cfg->reference_channels[cfg->num_references++] = a;
    }
    return cfg->num_references > 0 ? 0 : cli_error(EXIT_USAGE, "--references: no output column given");
}

static int clamp_count(double value, int lo, int hi)
{
    const double v = floor(value + 0.5);
    return v < lo ? lo : v > hi ? hi : (int)v;
}

/* okid_ambient_config_check() refused: the flag, its value and the range, in one line. */
static int settings_refused(const okid_ambient_config *cfg)
{
    okid_config_issue issue;
    (void)okid_ambient_config_check(cfg, &issue);
    static const struct {
        const char *field, *flag;
    } flags[] = {{"num_outputs", "--outputs"}, {"num_references", "--references"},
                 {"reference_channels", "--references"}, {"hankel_rows", "--hankel-rows"},
                 {"order", "--order"}, {"dt", "--dt"}, {"sensing", "--sensing"}, {"segments", "--segments"},
                 {"segment_samples", "--segment-samples"}};
    const char *flag = issue.field != NULL ? issue.field : "?";
    for (size_t i = 0; i < sizeof flags / sizeof flags[0]; ++i) {
        if (issue.field != NULL && strcmp(issue.field, flags[i].field) == 0) flag = flags[i].flag;
    }
    const int is_order = issue.field != NULL && strcmp(issue.field, "order") == 0;
    return cli_error(EXIT_USAGE, "%s %g: valid %g..%g for output-only identification%s", flag, issue.value, issue.min,
                     issue.max, is_order ? " (at most L min(m, references), and 512)" : "");
}

static void print_table(const okid_ambient_config *cfg, const okid_ambient_result *res, const char *file,
                        const char *const *names, const char *const *refs, double band_hz, double elapsed)
{
    printf("okid %s: %s, %llu samples, dt = %g s, output-only (no input columns)\n", OKID_VERSION_STRING, file,
           (unsigned long long)res->samples, (double)res->dt);
    printf("outputs:");
    for (int a = 0; a < cfg->num_outputs; ++a) printf(" %s", names[a]);
    printf("; references:");
    for (int l = 0; l < res->G.cols; ++l) printf(" %s", refs[l]);
    printf("\nHankel of the correlations R(1..%d): %d x %d blocks (hankel_rows L = %d", 2 * cfg->hankel_rows,
           cfg->hankel_rows, cfg->hankel_rows, cfg->hankel_rows);
    if (band_hz > 0) printf(", chosen: one period of %.4g Hz, below which 5 %% of the energy lies", band_hz);
    printf("), %s sensing\n", cli_name_of(cli_sensing_names, (int)cfg->sensing));
    printf("order n = %d, realization condition %.3g\nsingular values:", res->order, (double)res->realization_condition);
    for (int i = 0; i < res->num_singular_values && i < 12; ++i) printf(" %.4g", (double)res->singular_values[i]);
    printf("%s\n", res->num_singular_values > 12 ? " ..." : "");
    for (unsigned bit = 1; bit != 0 && bit <= res->warnings; bit <<= 1) {
        /* no physical mode: said with its reason where the modes are listed (ambient_print_modes) */
        if ((res->warnings & bit) && bit != OKID_W_NO_PHYSICAL_MODE) printf("warning: %s\n", okid_warning_str(bit));
    }
    const int stds = res->frequency_std != NULL;
    if (stds) printf("standard deviations from %d segments (docs/ambient.md)\n", res->segments_used);
    printf("\n mode  frequency [Hz]  damping ratio   EMAC    MPC    CMI%s\n", stds ? "   std f [Hz]  std damping" : "");
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_mode *md = &res->modes[i];
        printf("%5d  %14.8f  %13.8f  %5.3f  %5.3f  %5.3f", i + 1, (double)md->frequency_hz, (double)md->damping_ratio,
               (double)md->emac, (double)md->mpc, (double)md->cmi);
        if (stds) printf("  %11.3g  %11.3g", (double)res->frequency_std[i], (double)res->damping_std[i]);
        printf("%s\n", md->is_pair ? "" : "  (real)");
    }
    if (elapsed >= 0) printf("\nelapsed from okid_ambient_init to the modes: %.6f s\n", elapsed);
}

int identify_ambient(const identify_options *o, record_reader *reader, const record_columns *cols,
                     const record_scan *scan, const char *const *output_names, double dt)
{
    const char *flag = inapplicable_option(o);
    if (flag != NULL) {
        return cli_error(EXIT_USAGE, "%s does not apply to output-only identification (--inputs 0)", flag);
    }
    const int m = cols->m;
    const size_t n = scan->samples;
    okid_ambient_config cfg;
    okid_ambient_config_default(&cfg, m);
    cfg.dt = (okid_real)dt;
    cfg.order = o->cfg.order;
    cfg.sensing = o->cfg.sensing;
    cfg.segments = o->segments;
    cfg.segment_samples = o->segment_samples;
    int rc = choose_references(o->references, output_names, m, &cfg);
    if (rc != 0) {
        return rc;
    }
    okid_real unused_input = 0; /* no input column: the reader writes none */
    okid_real *y = malloc(sizeof(okid_real) * (n > 0 ? n : 1u) * (size_t)m);
    char error[512];
    if (y == NULL || record_read_block(reader, cols, n, &unused_input, y, error, sizeof error) < 0) {
        free(y);
        return cli_error(EXIT_DATA, "%s", y == NULL ? "out of memory" : error);
    }
    ambient_remove_mean(y, n, m); /* a mean is a constant, not a mode: the library expects none */
    double band_hz = 0;
    const int nref = cfg.num_references > 0 ? cfg.num_references : m;
    auto_band band; /* estimated once: for L here and for the physical modes' choice below */
    const auto_band *have_band = NULL;
    if (o->hankel_seconds > 0) {
        cfg.hankel_rows = clamp_count(o->hankel_seconds / dt, 1, OKID_MAX_HORIZON);
    } else if (o->given & AUTO_GIVEN_HANKEL) {
        cfg.hankel_rows = o->cfg.hankel_rows;
    } else {
        (void)ambient_record_band(y, n, m, dt, &band);
        have_band = &band;
        band_hz = band.low_hz;
        cfg.hankel_rows = ambient_band_hankel_rows(&band, n, m, dt, cfg.order, nref);
    }
    size_t bytes = 0;
    if (okid_ambient_workspace_size(&cfg, &bytes) != OKID_OK) {
        free(y);
        return settings_refused(&cfg);
    }
    if (n < 2u * (size_t)cfg.hankel_rows + 1u) {
        free(y);
        return cli_error(EXIT_DATA, "not enough data: %zu samples, at least 2 L + 1 = %d for L = %d", n,
                         2 * cfg.hankel_rows + 1, cfg.hankel_rows);
    }
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    if (ws == NULL) {
        free(y);
        return cli_error(EXIT_DATA, "out of memory (workspace of %zu bytes)", bytes);
    }
    struct timespec t0, t1;
    timespec_get(&t0, TIME_UTC);
    /* without --order, the physical modes across orders and Hankel sizes, and the order that holds them */
    ambient_modes *am = cfg.order == 0 ? calloc(1, sizeof *am) : NULL;
    if (cfg.order == 0 && am == NULL) {
        free(ws);
        free(y);
        return cli_error(EXIT_DATA, "out of memory");
    }
    okid_status st = OKID_OK;
    if (am != NULL) {
        const int given = o->hankel_seconds > 0 || (o->given & AUTO_GIVEN_HANKEL);
        st = ambient_modes_find(&cfg, given, have_band, n, y, NULL, am);
        if (st == OKID_OK && (am->order != 0 || am->choice.windows[0] != cfg.hankel_rows)) {
            cfg.order = am->order;
            cfg.hankel_rows = am->choice.windows[0];
            free(ws);
            ws = okid_ambient_workspace_size(&cfg, &bytes) == OKID_OK
                     ? aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16)
                     : NULL;
            if (ws == NULL) st = OKID_E_WORKSPACE_TOO_SMALL;
        }
    }
    okid_ambient amb;
    okid_ambient_result res;
    if (st == OKID_OK) st = okid_ambient_init(&amb, &cfg, ws, bytes, NULL);
    if (st == OKID_OK) st = okid_ambient_push_block(&amb, n, y, (size_t)m, NULL);
    if (st == OKID_OK) st = okid_ambient_identify(&amb, &res);
    timespec_get(&t1, TIME_UTC);
    const double elapsed = (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec);
    if (st != OKID_OK) {
        rc = cli_error(EXIT_DATA, "output-only identification failed: %s", okid_status_str(st));
    } else {
        if (am != NULL && am->num_modes == 0) res.warnings |= OKID_W_NO_PHYSICAL_MODE; /* as okid.identify_ambient */
        const char *refs[OKID_MAX_DIMENSION];
        for (int l = 0; l < nref; ++l) refs[l] = output_names[cfg.num_references > 0 ? cfg.reference_channels[l] : l];
        if (o->json && am != NULL) {
            okid_ambient_config as_given = cfg; /* "config" has the order as given (0), as the input-output path's */
            as_given.order = 0;
            json_ambient_fields(stdout, &as_given, &res, output_names, refs, o->timing ? elapsed : -1);
            ambient_modes_json(stdout, am, &res, m);
            fputs("\n}\n", stdout);
        } else if (o->json) {
            json_ambient_result(stdout, &cfg, &res, output_names, refs, o->timing ? elapsed : -1);
        } else {
            print_table(&cfg, &res, o->file, output_names, refs, band_hz, o->timing ? elapsed : -1);
            if (am != NULL) ambient_print_modes(am, &res, output_names, m);
        }
    }
    if (am != NULL) ambient_modes_free(am);
    free(am);
    free(ws);
    free(y);
    return rc;
}

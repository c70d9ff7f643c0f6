/* SPDX-License-Identifier: Apache-2.0 */
/*
 * mode_selection_run: identify a CSV record (header row; t, the inputs, then the outputs), build
 * the stabilization table and print the automatic mode selection (okid/mode_selection.h) as JSON.
 * A test driver (tests/python/test_mode_selection_real.py and scripts/real_consensus.py), not a
 * surface: the CLI takes the selection in a later step.
 *
 *   mode_selection_run --inputs R --outputs M [--observer-order P] [--hankel A] [--decimation K]
 *                      [--max-order N] [--step S] [--scaling none|auto] [--table]
 *                      [--damping-max Z] [--mpc-min X] [--emac-min X] [--min-fraction X]
 *                      [--frequency-distance X] [--mac-min X] [--frequency-max F] FILE.csv
 */
#define _POSIX_C_SOURCE 200809L
#include <errno.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#include "okid/okid.h"

static int fail(const char *what, okid_status st)
{
    fprintf(stderr, "mode_selection_run: %s: %s\n", what, okid_status_str(st));
    return 1;
}

/* Reads the numeric rows of a CSV with `cols` columns after its header; returns rows, or -1. */
static long read_csv(const char *path, int cols, double **data)
{
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        fprintf(stderr, "mode_selection_run: %s: %s\n", path, strerror(errno));
        return -1;
    }
    char line[8192];
    if (fgets(line, sizeof line, f) == NULL) {
        fclose(f);
        return -1;
    }
    size_t cap = 1024, rows = 0;
    double *d = malloc(sizeof(double) * cap * (size_t)cols);
    while (d != NULL && fgets(line, sizeof line, f) != NULL) {
        if (rows == cap) {
            cap *= 2;
            double *nd = realloc(d, sizeof(double) * cap * (size_t)cols);
            if (nd == NULL) {
                free(d);
                d = NULL;
                break;
            }
            d = nd;
        }
        char *p = line;
        for (int c = 0; c < cols; ++c) {
            char *end = NULL;
            d[rows * (size_t)cols + (size_t)c] = strtod(p, &end);
            if (end == p) {
                fprintf(stderr, "mode_selection_run: %s: row %zu has fewer than %d numbers\n", path, rows + 2, cols);
                free(d);
                fclose(f);
                return -1;
            }
            p = (*end == ',') ? end + 1 : end;
        }
        ++rows;
    }
    fclose(f);
    *data = d;
    return d == NULL ? -1 : (long)rows;
}

static void json_mode(const okid_mode *md, int m)
{
    printf("\"frequency_hz\": %.10g, \"damping_ratio\": %.10g, \"mpc\": %.6g, \"emac\": %.6g, \"cmi\": %.6g, \"msv\": %.6g, "
           "\"eigenvalue_abs2\": %.12g, \"is_pair\": %d, \"sensor_shape_abs\": [",
           (double)md->frequency_hz, (double)md->damping_ratio, (double)md->mpc, (double)md->emac,
           (double)md->cmi, (double)md->msv, (double)(md->eigenvalue.re * md->eigenvalue.re + md->eigenvalue.im * md->eigenvalue.im),
           md->is_pair);
    for (int a = 0; a < m; ++a) {
        const double re = md->sensor_shape[a].re, im = md->sensor_shape[a].im;
        printf("%s%.6g", a ? ", " : "", re * re + im * im > 0 ? __builtin_sqrt(re * re + im * im) : 0.0);
    }
    printf("]");
}

int main(int argc, char **argv)
{
    int r = 0, m = 0, p = 20, alpha = 50, decim = 1, nmax = 40, step = 2, table = 0;
    okid_scaling scaling = OKID_SCALING_AUTO;
    okid_mode_selection_criteria crit;
    (void)okid_mode_selection_criteria_default(&crit);
    const char *path = NULL;
    for (int i = 1; i < argc; ++i) {
        const char *a = argv[i];
        const char *v = (i + 1 < argc) ? argv[i + 1] : NULL;
#define INT_OPT(name, var) if (strcmp(a, name) == 0 && v) { var = atoi(v); ++i; continue; }
#define REAL_OPT(name, var) if (strcmp(a, name) == 0 && v) { var = (okid_real)atof(v); ++i; continue; }
        INT_OPT("--inputs", r)
        INT_OPT("--outputs", m)
        INT_OPT("--observer-order", p)
        INT_OPT("--hankel", alpha)
        INT_OPT("--decimation", decim)
        INT_OPT("--max-order", nmax)
        INT_OPT("--step", step)
        REAL_OPT("--damping-max", crit.damping_max)
        REAL_OPT("--mpc-min", crit.mpc_min)
        REAL_OPT("--emac-min", crit.emac_min)
        REAL_OPT("--min-fraction", crit.min_fraction)
        REAL_OPT("--frequency-distance", crit.frequency_distance)
        REAL_OPT("--damping-distance", crit.damping_distance)
        REAL_OPT("--mac-min", crit.mac_min)
        REAL_OPT("--frequency-max", crit.frequency_max_hz)
        REAL_OPT("--frequency-min", crit.frequency_min_hz)
        if (strcmp(a, "--scaling") == 0 && v) {
            scaling = strcmp(v, "none") == 0 ? OKID_SCALING_NONE : OKID_SCALING_AUTO;
            ++i;
            continue;
        }
        if (strcmp(a, "--table") == 0) {
            table = 1;
            continue;
        }
        if (a[0] == '-') {
            fprintf(stderr, "mode_selection_run: unknown option %s\n", a);
            return 2;
        }
        path = a;
    }
    if (path == NULL || r < 1 || m < 1) {
        fprintf(stderr, "usage: mode_selection_run --inputs R --outputs M [options] FILE.csv\n");
        return 2;
    }
    double *data = NULL;
    const int cols = 1 + r + m;
    const long rows = read_csv(path, cols, &data);
    if (rows < 2) {
        return 1;
    }
    okid_config cfg;
    (void)okid_config_default(&cfg, r, m);
    cfg.dt = (okid_real)((data[(size_t)(rows - 1) * (size_t)cols] - data[0]) / (double)(rows - 1));
    cfg.observer_order = p;
    cfg.hankel_rows = cfg.hankel_cols = alpha;
    cfg.decimation = decim;
    cfg.scaling = scaling;
    cfg.sensing = OKID_SENSING_ACCELERATION;
    cfg.order = 2;
    okid_config_issue ci;
    okid_status st = okid_config_check(&cfg, &ci);
    if (st != OKID_OK) {
        fprintf(stderr, "mode_selection_run: %s = %g outside [%g, %g]\n", ci.field ? ci.field : "?", ci.value, ci.min,
                ci.max);
        return 2;
    }
    size_t bytes = 0;
    (void)okid_workspace_size(&cfg, &bytes);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15u) / 16u * 16u);
    okid_identifier id;
    if (ws == NULL || (st = okid_init(&id, &cfg, ws, bytes, NULL)) != OKID_OK) {
        return fail("init", st);
    }
    okid_real u[64], y[64];
    for (long k = 0; k < rows; ++k) {
        for (int c = 0; c < r; ++c) u[c] = (okid_real)data[(size_t)k * (size_t)cols + 1u + (size_t)c];
        for (int c = 0; c < m; ++c) y[c] = (okid_real)data[(size_t)k * (size_t)cols + 1u + (size_t)r + (size_t)c];
        if ((st = okid_push(&id, u, y)) != OKID_OK) {
            return fail("push", st);
        }
    }
    okid_result res;
    if ((st = okid_identify(&id, &res)) != OKID_OK) {
        return fail("identify", st);
    }
    const int hank = res.num_singular_values;
    if (nmax > hank) nmax = hank;
    size_t sbytes = 0, mbytes = 0;
    if ((st = okid_stabilization_workspace_size(&id, nmax, step, &sbytes)) != OKID_OK) {
        return fail("stabilization size", st);
    }
    void *sws = aligned_alloc(OKID_WORKSPACE_ALIGN, (sbytes + 15u) / 16u * 16u);
    okid_stabilization stab;
    if ((st = okid_stabilization_compute(&id, nmax, step, NULL, sws, sbytes, &stab)) != OKID_OK) {
        return fail("stabilization", st);
    }
    if ((st = okid_mode_selection_workspace_size(nmax, step, &mbytes)) != OKID_OK) {
        return fail("selection size", st);
    }
    void *mws = aligned_alloc(OKID_WORKSPACE_ALIGN, (mbytes + 15u) / 16u * 16u);
    okid_mode_selection sel;
    struct timespec t0, t1;
    clock_gettime(CLOCK_MONOTONIC, &t0);
    st = okid_select_modes(&stab, m, &crit, mws, mbytes, &sel, &ci);
    clock_gettime(CLOCK_MONOTONIC, &t1);
    if (st != OKID_OK) {
        if (st == OKID_E_BAD_PARAMETER) {
            fprintf(stderr, "mode_selection_run: %s = %g outside [%g, %g]\n", ci.field, ci.value, ci.min, ci.max);
            return 2;
        }
        return fail("select", st);
    }
    printf("{\"file\": \"%s\", \"dt\": %.10g, \"samples\": %ld, \"observer_order\": %d, \"hankel\": %d, "
           "\"decimation\": %d, \"max_order\": %d, \"step\": %d, \"rank_limit\": %d, \"num_orders\": %d, "
           "\"min_orders\": %d, \"num_candidates\": %d, \"num_clusters\": %d, \"num_dropped\": %d, "
           "\"selection_seconds\": %.6g, \"modes\": [",
           path, (double)res.dt, rows, p, alpha, decim, nmax, step, stab.rank_limit, sel.num_orders, sel.min_orders,
           sel.num_candidates, sel.num_clusters, sel.num_dropped,
           (double)(t1.tv_sec - t0.tv_sec) + 1e-9 * (double)(t1.tv_nsec - t0.tv_nsec));
    for (int i = 0; i < sel.num_modes; ++i) {
        const okid_selected_mode *s = &sel.modes[i];
        printf("%s\n  {", i ? "," : "");
        json_mode(&s->mode, m);
        printf(", \"order\": %d, \"num_orders\": %d, \"lowest_order\": %d, \"highest_order\": %d, "
               "\"frequency_mean\": %.10g, \"frequency_std\": %.6g, \"frequency_min\": %.10g, \"frequency_max\": %.10g, "
               "\"damping_mean\": %.6g, \"damping_std\": %.6g, \"damping_min\": %.6g, \"damping_max\": %.6g, \"cmi_min\": %.6g}",
               s->order, s->num_orders, s->lowest_order, s->highest_order, (double)s->frequency_mean,
               (double)s->frequency_std, (double)s->frequency_min, (double)s->frequency_max, (double)s->damping_mean,
               (double)s->damping_std, (double)s->damping_min, (double)s->damping_max, (double)s->cmi_min);
    }
    printf("]");
    if (table) {
        printf(",\n\"table\": [");
        for (int o = 0; o < stab.num_orders; ++o) {
            const okid_stabilization_order *ord = &stab.orders[o];
            for (int i = 0; i < ord->num_modes; ++i) {
                printf("%s\n  {\"order\": %d, ", (o || i) ? "," : "", ord->order);
                json_mode(&stab.modes[ord->first + i], m);
                printf("}");
            }
        }
        printf("]");
    }
    printf("}\n");
    free(mws);
    free(sws);
    free(ws);
    free(data);
    return 0;
}

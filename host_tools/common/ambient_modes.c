/* SPDX-License-Identifier: Apache-2.0 */
/* The physical modes of an output-only record over three Hankel sizes: the sums once, then per size a table and
   a selection; combine. */
#include "ambient_modes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "ambient_settings.h"
#include "auto_modes.h" /* AUTO_DAMPING_MAX */
#include "auto_report.h" /* auto_print_sensor_shape */
#include "auto_settings.h"
#include "json_writer.h"

/* The tables' largest order: the input-output path's (docs/quality.md section 8). */
enum { AMBIENT_TABLE_ORDERS = MODE_WINDOWS_MAX_ORDER };
/* The verdict of a pole that passes every hard criterion but no two sizes hold. */
#define AMBIENT_UNSTABLE_ACROSS "not stable across orders and Hankel sizes"

static int references_of(const okid_ambient_config *cfg)
{
    return cfg->num_references > 0 ? cfg->num_references : cfg->num_outputs;
}

/*
 * L, when not given: one slowest period (ambient_band_hankel_rows()), confirmed at two thirds
 * and four thirds of it, as the input-output path confirms its three periods at two and four; the
 * selection's band from f5 / 3 (less than a cycle in the Hankel span below) to 0.8 Nyquist.
 */
static void choose(const okid_ambient_config *cfg, int hankel_given, const auto_band *band, size_t n, ambient_choice *c)
{
    const int m = cfg->num_outputs, nref = references_of(cfg);
    const double dt = (double)cfg->dt;
    c->hankel_given = hankel_given;
    c->no_band = !(band->low_hz > 0);
    c->band_low_hz = band->low_hz;
    c->band_high_hz = band->high_hz;
    if (hankel_given) {
        c->windows[0] = cfg->hankel_rows;
        c->num_windows = 1;
    } else {
        const int main = ambient_band_hankel_rows(band, n, m, dt, 0, nref);
        int most = ambient_hankel_rows_most(n, m);
        most = most > main ? most : main;
        c->windows[0] = main;
        c->windows[1] = (int)floor(2.0 * main / 3.0 + 0.5);
        c->windows[2] = (int)floor(4.0 * main / 3.0 + 0.5);
        for (int w = 1; w < 3; ++w) c->windows[w] = c->windows[w] < 2 ? 2 : c->windows[w] > most ? most : c->windows[w];
        c->num_windows = 3;
    }
    c->max_order = AMBIENT_TABLE_ORDERS;
    c->frequency_min_hz = c->band_low_hz / 3;
    c->frequency_max_hz = 0.8 * 0.5 / dt;
}

/* The table's largest order at L: even, at most max_order and L min(m, r_ref); below 2: none. */
static int table_top(const okid_ambient_config *cfg, int L, int max_order)
{
    const int m = cfg->num_outputs, nref = references_of(cfg), side = m < nref ? m : nref;
    const int top = max_order < L * side ? max_order : L * side;
    return top - top % 2;
}

/* The record's sums at L block rows (the largest size), once (docs/ambient.md, "Physical modes"). */
static okid_status sum_record(ambient_sums *sums, const okid_ambient_config *cfg, int L, int max_order, size_t n,
                              const okid_real *y)
{
    sums->cfg = *cfg;
    sums->cfg.hankel_rows = L;
    sums->cfg.order = table_top(cfg, L, max_order); /* the workspace only holds the sums and the ERA scratch here */
    if (sums->cfg.order < 2) return OKID_E_BAD_ORDER;
    sums->cfg.segments = 0; /* the segments serve the reported model only */
    sums->cfg.segment_samples = 0;
    size_t bytes = 0;
    okid_status st = okid_ambient_workspace_size(&sums->cfg, &bytes);
    if (st != OKID_OK) return st;
    if ((sums->workspace = mode_windows_workspace(bytes)) == NULL) return OKID_E_WORKSPACE_TOO_SMALL;
    st = okid_ambient_init(&sums->amb, &sums->cfg, sums->workspace, bytes, NULL);
    if (st == OKID_OK) {
        st = okid_ambient_push_block(&sums->amb, n, y, (size_t)sums->cfg.num_outputs, NULL);
        if (st == OKID_E_NONFINITE_SAMPLE) st = OKID_OK; /* gaps: no product spans them */
    }
    return st;
}

/* One Hankel size: the table of the even orders 2..min(max_order, L min(m, r_ref)) from amb's sums
   (configured as cfg), the selection. */
static okid_status run_size(ambient_run *run, okid_ambient *amb, const okid_ambient_config *cfg, int L, int max_order,
                            const okid_mode_selection_criteria *criteria)
{
    const int top = table_top(cfg, L, max_order);
    if (top < 2) return OKID_E_BAD_ORDER;
    size_t bytes = 0;
    okid_status st = okid_ambient_stabilization_workspace_size_at(amb, L, top, 2, &bytes);
    if (st == OKID_OK && (run->table_workspace = mode_windows_workspace(bytes)) == NULL) st = OKID_E_WORKSPACE_TOO_SMALL;
    if (st == OKID_OK) {
        st = okid_ambient_stabilization_compute_at(amb, L, top, 2, NULL, run->table_workspace, bytes, &run->table);
    }
    if (st == OKID_OK) st = okid_mode_selection_workspace_size(top, 2, &bytes);
    if (st == OKID_OK && (run->selection_workspace = mode_windows_workspace(bytes)) == NULL) st = OKID_E_WORKSPACE_TOO_SMALL;
    if (st == OKID_OK) {
        st = okid_select_modes(&run->table, cfg->num_outputs, criteria, run->selection_workspace, bytes,
                               &run->selection, NULL);
    }
    return st;
}

/* The sizes' selections grouped into the reported modes and the reported model's order (the rule of
   mode_windows.h), once the runs are done: OKID_OK, or the main run's failure. */
static okid_status combine(ambient_modes *out, int m)
{
    if (out->runs[0].status == OKID_E_BAD_ORDER) {
        return OKID_OK; /* a Hankel matrix too small for one pair (L min(m, r_ref) < 2): no mode, the gap order */
    }
    if (out->runs[0].status != OKID_OK) {
        return out->runs[0].status;
    }
    /* group the sizes' modes: a mode of size w joins the first reported mode it matches */
    int support[OKID_MAX_ORDER] = {0};
    for (int w = 0; w < out->num_runs; ++w) {
        if (out->runs[w].status == OKID_OK) {
            mode_windows_add(&out->criteria, &out->runs[w].selection, w, m, out->modes, &out->num_modes, support);
        }
    }
    mode_windows_keep(out->modes, &out->num_modes, out->num_runs > 1 ? 2 : 1); /* two of three sizes; one size alone */
    mode_windows_order(&out->runs[0].table, &out->criteria, out->modes, out->num_modes, m, &out->order,
                       &out->order_holds_all);
    if (out->num_modes == 0) out->order = 0; /* no mode: the gap order */
    return OKID_OK;
}

/* The library's selection criteria with the input-output path's damping limit and the choice's band. */
static void default_criteria(const ambient_choice *c, okid_mode_selection_criteria *criteria)
{
    okid_mode_selection_criteria_default(criteria);
    criteria->damping_max = (okid_real)AUTO_DAMPING_MAX; /* the input-output path's limit */
    criteria->frequency_min_hz = (okid_real)c->frequency_min_hz;
    criteria->frequency_max_hz = (okid_real)c->frequency_max_hz;
}

okid_status ambient_modes_find(const okid_ambient_config *cfg, int hankel_given, const auto_band *band, size_t n,
                               const okid_real *y, const okid_mode_selection_criteria *criteria, ambient_modes *out)
{
    memset(out, 0, sizeof *out);
    auto_band estimated;
    if (band == NULL) {
        (void)ambient_record_band(y, n, cfg->num_outputs, (double)cfg->dt, &estimated);
        band = &estimated;
    }
    choose(cfg, hankel_given, band, n, &out->choice);
    if (criteria != NULL) {
        out->criteria = *criteria;
    } else {
        default_criteria(&out->choice, &out->criteria);
    }
    out->num_runs = out->choice.num_windows;
    int largest = 0;
    for (int w = 0; w < out->num_runs; ++w) largest = out->choice.windows[w] > largest ? out->choice.windows[w] : largest;
    const okid_status summed = sum_record(&out->sums, cfg, largest, out->choice.max_order, n, y);
    for (int w = 0; w < out->num_runs; ++w) {
        out->runs[w].status = summed != OKID_OK && table_top(cfg, out->choice.windows[w], out->choice.max_order) >= 2
                                  ? summed
                                  : run_size(&out->runs[w], &out->sums.amb, &out->sums.cfg, out->choice.windows[w],
                                             out->choice.max_order, &out->criteria);
    }
    return combine(out, cfg->num_outputs);
}

okid_status ambient_modes_of(okid_ambient *amb, const okid_ambient_config *cfg, ambient_modes *out)
{
    memset(out, 0, sizeof *out);
    ambient_choice *c = &out->choice;
    c->hankel_given = 1;
    c->no_band = 1; /* a stream has no record to take the band from */
    c->windows[0] = cfg->hankel_rows;
    c->num_windows = 1;
    c->max_order = AMBIENT_TABLE_ORDERS;
    c->frequency_min_hz = 0;
    c->frequency_max_hz = 0.8 * 0.5 / (double)cfg->dt;
    default_criteria(c, &out->criteria);
    out->num_runs = 1;
    out->runs[0].status = run_size(&out->runs[0], amb, cfg, cfg->hankel_rows, c->max_order, &out->criteria);
    return combine(out, cfg->num_outputs);
}

const char *ambient_pole_verdict(const ambient_modes *am, const okid_mode *pole, int m)
{
    return mode_windows_verdict(&am->criteria, am->modes, am->num_modes, pole, m, AMBIENT_UNSTABLE_ACROSS);
}

void ambient_print_modes(const ambient_modes *am, const okid_ambient_result *res, const char *const *output_names,
                         int m)
{
    const ambient_choice *c = &am->choice;
    const okid_stabilization *t = &am->runs[0].table;
    if (!c->no_band) {
        printf("band of the outputs' energy: 5 %% below %.3g Hz, 95 %% below %.3g Hz\n", c->band_low_hz, c->band_high_hz);
    }
    if (c->num_windows > 1) {
        printf("Hankel sizes L = %d (one period of the 5 %% frequency), checked at %d and %d\n", c->windows[0],
               c->windows[1], c->windows[2]);
    }
    printf("physical modes: %d (stable in at least %d of the %d orders 2..%d of a table, in %s; band %.3g..%.3g Hz)\n",
           am->num_modes, am->runs[0].selection.min_orders, t->num_orders,
           t->num_orders > 0 ? t->orders[t->num_orders - 1].order : 0,
           am->num_runs > 1 ? "two of the three Hankel sizes" : "the one Hankel size", (double)am->criteria.frequency_min_hz,
           (double)am->criteria.frequency_max_hz);
    if (am->runs[0].selection.exact_last_order) {
        printf("(noise-free data: the correlations' Hankel matrix has numerical rank %d, so its order-%d model is exact "
               "and its modes need no higher order to confirm them)\n", t->rank_limit, t->orders[t->num_orders - 1].order);
    }
    if (am->num_modes == 0) {
        printf("warning: no physical mode found: no pole stays put across the orders%s; the model below has the "
               "largest-gap order\n", am->num_runs > 1 ? " and the Hankel sizes" : "");
        return;
    }
    printf(" mode  frequency [Hz]  damping ratio  f std over orders  damping range    orders  sizes  EMAC   MPC\n");
    for (int k = 0; k < am->num_modes; ++k) {
        const okid_selected_mode *s = am->modes[k].selected;
        printf("%5d  %14.6f  %13.6f  %17.3g  %6.4f..%6.4f  %4d/%-3d  %2d/%-2d  %5.3f  %5.3f\n", k + 1,
               (double)s->mode.frequency_hz, (double)s->mode.damping_ratio, (double)s->frequency_std,
               (double)s->damping_min, (double)s->damping_max, s->num_orders,
               am->runs[am->modes[k].window].table.num_orders, am->modes[k].windows, am->num_runs,
               (double)s->mode.emac, (double)s->mode.mpc);
    }
    printf("\nsensor shapes C psi (largest component 1); columns:");
    for (int i = 0; i < m; ++i) printf(" %s", output_names[i]);
    printf("\n");
    for (int k = 0; k < am->num_modes; ++k) {
        printf("%5d", k + 1);
        auto_print_sensor_shape(&am->modes[k].selected->mode, m);
    }
    printf("\nmodel: order %d at L = %d, %s\n", res->order, c->windows[0],
           mode_windows_order_reason(am->num_modes, am->order_holds_all));
}

static void json_setting(FILE *out, const char *name, int value, int chosen, const char *reason)
{
    fprintf(out, "\"%s\": {\"value\": %d, \"chosen\": %s, \"reason\": ", name, value, chosen ? "true" : "false");
    json_string(out, reason);
    fputc('}', out);
}

void ambient_modes_json(FILE *out, const ambient_modes *am, const okid_ambient_result *res, int m)
{
    const ambient_choice *c = &am->choice;
    fputs(",\n  \"chosen\": {\"band_hz\": [", out);
    json_number(out, c->band_low_hz);
    fputs(", ", out);
    json_number(out, c->band_high_hz);
    fputs("], \"slowest_period_seconds\": ", out);
    json_number(out, c->band_low_hz > 0 ? 1 / c->band_low_hz : 0);
    fputs(",\n    ", out);
    char reason[256];
    snprintf(reason, sizeof reason, "%.6g s, one period of the 5 %% energy frequency; checked at 2/3 and 4/3 of it",
             c->windows[0] * (double)res->dt);
    const int chosen = !c->hankel_given && !c->no_band;
    json_setting(out, "hankel_rows", c->windows[0], chosen,
                 chosen ? reason : c->hankel_given ? "given" : "default (the record has no band)");
    fprintf(out, ",\n    \"hankel_windows\": [%d", c->windows[0]);
    for (int i = 1; i < c->num_windows; ++i) fprintf(out, ", %d", c->windows[i]);
    fprintf(out, "], \"max_order\": %d, \"selection_band_hz\": [", c->max_order);
    json_number(out, (double)am->criteria.frequency_min_hz);
    fputs(", ", out);
    json_number(out, (double)am->criteria.frequency_max_hz);
    fputs("],\n    ", out);
    json_setting(out, "order", res->order, am->num_modes > 0,
                 mode_windows_order_reason(am->num_modes, am->order_holds_all));
    fputs("}", out);
    int orders[3] = {0, 0, 0};
    for (int w = 0; w < am->num_runs; ++w) orders[w] = am->runs[w].table.num_orders;
    mode_windows_json(out, am->modes, am->num_modes, orders, am->num_runs, 0, NULL, res->modes, res->num_modes, &am->criteria, m,
                      AMBIENT_UNSTABLE_ACROSS);
}

void ambient_modes_free(ambient_modes *am)
{
    free(am->sums.workspace);
    for (int w = 0; w < am->num_runs; ++w) {
        free(am->runs[w].table_workspace);
        free(am->runs[w].selection_workspace);
    }
    memset(am, 0, sizeof *am);
}

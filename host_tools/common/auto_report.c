/* SPDX-License-Identifier: Apache-2.0 */
/* The report of the settings chosen from the data and of the physical modes. */
#include "auto_report.h"

#include <math.h>

#include "json_writer.h"

/* 1 when the setting was chosen from the data (not given, and the record had a band). */
static int chosen(const auto_choice *c, unsigned bit)
{
    return !c->no_band && !(c->given & bit);
}

/* What a setting's line says about where it came from. */
static const char *origin(const auto_choice *c, unsigned bit)
{
    return (c->given & bit) ? "given" : chosen(c, bit) ? "chosen" : "default";
}

/* Why the observer order is the one chosen (one sentence, no trailing period). */
static void observer_reason(const auto_choice *c, double step, char *buf, size_t size)
{
    const char *capped = c->observer_order == c->observer_orders[0] && c->observer_order == c->observer_limit
                             ? ", capped by the record's length (ten rows per unknown)" : "";
    if (c->num_observers <= 1) {
        snprintf(buf, size, "%.6g s, half the slowest period%s", c->observer_order * step, capped);
        return;
    }
    int used = snprintf(buf, size, "%.6g s (%.2f slowest periods), the model's: the shortest of the observer orders",
                        c->observer_order * step, c->observer_order * step / c->slowest_period_s);
    for (int j = 0; j < c->num_observers && used > 0 && (size_t)used < size; ++j) {
        used += snprintf(buf + used, size - (size_t)used, "%s %d", j ? "," : "", c->observer_orders[j]);
    }
    if (used > 0 && (size_t)used < size) {
        snprintf(buf + used, size - (size_t)used, " (%.1f to %.1f slowest periods, whose modes are combined) whose "
                 "model holds every physical mode%s", AUTO_OBSERVER_FIRST,
                 AUTO_OBSERVER_FIRST + (AUTO_OBSERVERS - 1) * AUTO_OBSERVER_STEP, capped);
    }
}

/*
 * Why the decimation is the one chosen (no trailing period; json: the JSON's words, more digits):
 * the filter's -3 dB point 1/(4 K dt) at or above the 95 % frequency, or K = 1 when even K = 2
 * would put it below (then 1/(4 dt) itself may lie below it: no filter runs at K = 1).
 */
static void decimation_reason(const auto_choice *c, double dt, int json, char *buf, size_t size)
{
    const double edge = 1.0 / (4.0 * c->decimation * dt), f95 = c->band.high_hz;
    if (edge < f95) {
        snprintf(buf, size, "none: at K = 2 the anti-alias filter's -3 dB point 1/(8 dt) = %.*g Hz would lie below the "
                 "95 %% energy frequency %.*g Hz", json ? 6 : 3, edge / 2, json ? 6 : 3, f95);
    } else if (json) {
        snprintf(buf, size, "the anti-alias filter's -3 dB point 1/(4 K dt) = %.6g Hz at or above the 95 %% energy "
                 "frequency %.6g Hz", edge, f95);
    } else {
        snprintf(buf, size, "the anti-alias filter's -3 dB point 1/(4 K dt) = %.3g Hz stays above the 95 %% frequency", edge);
    }
}

void auto_print_choice(const auto_choice *c, double dt)
{
    const double step = c->decimation * dt;
    if (c->no_band) {
        printf("the outputs are too short or flat to choose settings from: the library's defaults\n");
    } else if (c->given != (AUTO_GIVEN_DECIMATION | AUTO_GIVEN_OBSERVER | AUTO_GIVEN_HANKEL)) {
        printf("band of the outputs' energy: 5 %% below %.3g Hz, 95 %% below %.3g Hz (Welch, %d-sample segments)\n",
               c->band.low_hz, c->band.high_hz, c->band.segment);
    }
    printf("decimation %d (%s)", c->decimation, origin(c, AUTO_GIVEN_DECIMATION));
    if (chosen(c, AUTO_GIVEN_DECIMATION)) {
        char reason[256];
        decimation_reason(c, dt, 0, reason, sizeof reason);
        printf(": %s", reason);
    }
    printf("\nobserver order %d (%s)", c->observer_order, origin(c, AUTO_GIVEN_OBSERVER));
    if (chosen(c, AUTO_GIVEN_OBSERVER)) {
        char reason[320];
        observer_reason(c, step, reason, sizeof reason);
        printf(": %s; slowest period %.3g s (1 / the 5 %% frequency)", reason, c->slowest_period_s);
    }
    printf("\nHankel %d x %d (%s)", c->hankel, c->hankel_cols, origin(c, AUTO_GIVEN_HANKEL));
    if (chosen(c, AUTO_GIVEN_HANKEL)) {
        printf(": %.3g s, three slowest periods; modes confirmed at %d and %d blocks (two and four periods)",
               c->hankel * step, c->windows[1], c->windows[2]);
    }
    printf("\n");
}

/* A reported mode's sensor shape C psi, scaled so that its largest component is 1 (real and positive). */
void auto_print_sensor_shape(const okid_mode *md, int m)
{
    int big = 0;
    for (int i = 1; i < m; ++i) {
        if (hypot((double)md->sensor_shape[i].re, (double)md->sensor_shape[i].im) >
            hypot((double)md->sensor_shape[big].re, (double)md->sensor_shape[big].im)) {
            big = i;
        }
    }
    const double br = (double)md->sensor_shape[big].re, bi = (double)md->sensor_shape[big].im;
    const double norm = br * br + bi * bi;
    for (int i = 0; i < m; ++i) {
        const double ar = (double)md->sensor_shape[i].re, ai = (double)md->sensor_shape[i].im;
        const double re = norm > 0 ? (ar * br + ai * bi) / norm : 0, im = norm > 0 ? (ai * br - ar * bi) / norm : 0;
        printf(" %+9.5f%+.5fi", re, im);
    }
    printf("\n");
}

/* How much the system Markov parameters Y_1..Y_L grow: the largest entry of the later half of the
   lags over that of the earlier half (a structure's decaying response gives less than 1; 0 when there
   are too few lags). */
static double markov_growth(const okid_result *res, int *lags)
{
    const int m = res->markov.rows, r = res->B.cols, count = r > 0 ? res->markov.cols / r : 0;
    *lags = count - 1;
    double early = 0, late = 0;
    for (int k = 1; k < count; ++k) {
        for (int j = k * r; j < (k + 1) * r; ++j) {
            for (int i = 0; i < m; ++i) {
                const double v = fabs((double)okid_matrix_at(res->markov, i, j));
                if (2 * k <= count) early = fmax(early, v);
                else late = fmax(late, v);
            }
        }
    }
    return early > 0 && count > 2 ? late / early : 0;
}

/* The warning of no physical mode, with the cause when the model's Markov parameters grow. */
static void print_no_mode_warning(const auto_modes *am, const okid_result *res, int observer_order)
{
    printf("warning: no physical mode found: no pole stays put across the orders%s", am->num_runs > 1 ? " and the Hankel windows" : "");
    int lags = 0, outside = -1;
    const double growth = markov_growth(res, &lags);
    double radius = 1;
    for (int i = 0; i < res->num_modes; ++i) {
        const double z = hypot((double)res->modes[i].eigenvalue.re, (double)res->modes[i].eigenvalue.im);
        if (z >= radius) radius = z, outside = i;
    }
    if (growth > 1 && outside >= 0) {
        /* beyond the observer's p lags the system Markov parameters are its extrapolation (eq. 51), whose
           poles are the model's: one outside the unit circle makes them grow, which a structure's do not */
        const double f = (double)res->modes[outside].frequency_hz;
        printf("; the system Markov parameters grow (their largest entry over the later half of the Hankel matrix's "
               "%d lags is %.3g times that over the earlier half), with the model's pole at %.4g Hz, |z| = %.6g: the "
               "observer's extrapolation beyond its %d lags is unstable, and the Hankel matrix holds that growth beside "
               "the structure's response", lags, growth, f, radius, observer_order);
        if (f > 0.25 / (double)res->dt) {
            printf("; the pole lies in the top half of the band, which a larger --decimation filters out: that may stop it");
        }
    }
    printf(" (--all-poles lists the model's poles and why each was rejected)\n");
}

void auto_print_modes(const auto_modes *am, const okid_result *res, const char *const *output_names, int m,
                      int all_poles)
{
    const auto_run *main_run = auto_main_run(am);
    const int orders = main_run->table.num_orders;
    if (orders == 0) {
        /* not one even order to compare: the rule's numbers would read "of the 0 orders 2..0" */
        printf("\nphysical modes: 0 (the main window's Hankel matrix has numerical rank %d: no model of order 2 or more",
               main_run->table.rank_limit);
    } else {
        printf("\nphysical modes: %d (stable in at least %d of the %d orders 2..%d of a Hankel window, in %s",
               am->num_modes, main_run->selection.min_orders, orders, main_run->table.orders[orders - 1].order,
               am->num_runs > 1 ? "each of its three windows" : "the one window");
    }
    if (orders > 0 && am->num_observers > 1) {
        printf(", and at a majority of its %d observer orders or at the shortest with EMAC and MPC >= %.1f",
               am->valid_observers, AUTO_UNCONFIRMED_MIN);
    }
    printf(")\n");
    if (main_run->selection.exact_last_order) {
        printf("(noise-free data: the Hankel matrix has numerical rank %d, so its order-%d model is exact and its modes "
               "need no higher order to confirm them)\n", main_run->table.rank_limit,
               main_run->table.orders[orders - 1].order);
    }
    if (am->num_modes == 0) {
        print_no_mode_warning(am, res, main_run->cfg.observer_order);
    } else {
        printf(" mode  frequency [Hz]  damping ratio  f std over orders  damping range    orders  windows  observers  EMAC   MPC\n");
        for (int k = 0; k < am->num_modes; ++k) {
            const auto_mode *md = &am->modes[k];
            const okid_selected_mode *s = md->selected;
            printf("%5d  %14.6f  %13.6f  %17.3g  %6.4f..%6.4f  %4d/%-3d  %3d/%-3d  %4d/%-4d  %5.3f  %5.3f\n", k + 1,
                   (double)s->mode.frequency_hz, (double)s->mode.damping_ratio, (double)s->frequency_std,
                   (double)s->damping_min, (double)s->damping_max, s->num_orders,
                   am->observers[md->observer].runs[md->window].table.num_orders, md->windows, am->num_runs,
                   md->observers, am->valid_observers, (double)s->mode.emac, (double)s->mode.mpc);
        }
        printf("\nsensor shapes C psi (largest component 1); columns:");
        for (int i = 0; i < m; ++i) printf(" %s", output_names[i]);
        printf("\n");
        for (int k = 0; k < am->num_modes; ++k) {
            printf("%5d", k + 1);
            auto_print_sensor_shape(&am->modes[k].selected->mode, m);
        }
    }
    printf("\nmodel: order %d of the %d-block window at observer order %d, %s\n", res->order, main_run->cfg.hankel_rows,
           main_run->cfg.observer_order, mode_windows_order_reason(am->num_modes, am->order_holds_all));
    if (!all_poles) {
        return;
    }
    printf("\npoles of the model (--all-poles)\n pole  frequency [Hz]  damping ratio   EMAC    MPC  verdict\n");
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_mode *md = &res->modes[i];
        const char *why = auto_pole_verdict(am, md, m);
        printf("%5d  %14.6f  %13.6f  %5.3f  %5.3f  %s%s\n", i + 1, (double)md->frequency_hz, (double)md->damping_ratio,
               (double)md->emac, (double)md->mpc, why ? "rejected: " : "physical", why ? why : "");
    }
}

static void json_setting(FILE *out, const char *name, int value, int chosen, const char *reason)
{
    fprintf(out, "\"%s\": {\"value\": %d, \"chosen\": %s, \"reason\": ", name, value, chosen ? "true" : "false");
    json_string(out, reason);
    fputc('}', out);
}

void auto_json_chosen(FILE *out, const auto_choice *c, double dt, int order, const char *order_reason)
{
    const double step = c->decimation * dt;
    char reason[320];
    fputs(",\n  \"chosen\": {\"band_hz\": [", out);
    json_number(out, c->band.low_hz);
    fputs(", ", out);
    json_number(out, c->band.high_hz);
    fputs("], \"slowest_period_seconds\": ", out);
    json_number(out, c->slowest_period_s);
    fputs(",\n    ", out);
    decimation_reason(c, dt, 1, reason, sizeof reason);
    json_setting(out, "decimation", c->decimation, chosen(c, AUTO_GIVEN_DECIMATION),
                 chosen(c, AUTO_GIVEN_DECIMATION) ? reason : origin(c, AUTO_GIVEN_DECIMATION));
    fputs(",\n    ", out);
    observer_reason(c, step, reason, sizeof reason);
    json_setting(out, "observer_order", c->observer_order, chosen(c, AUTO_GIVEN_OBSERVER),
                 chosen(c, AUTO_GIVEN_OBSERVER) ? reason : origin(c, AUTO_GIVEN_OBSERVER));
    fputs(",\n    ", out);
    snprintf(reason, sizeof reason, "%.6g s, three slowest periods", c->hankel * step);
    for (int i = 0; i < 2; ++i) {
        if (i) fputs(",\n    ", out);
        json_setting(out, i ? "hankel_cols" : "hankel_rows", i ? c->hankel_cols : c->hankel, chosen(c, AUTO_GIVEN_HANKEL),
                     chosen(c, AUTO_GIVEN_HANKEL) ? reason : origin(c, AUTO_GIVEN_HANKEL));
    }
    fprintf(out, ",\n    \"hankel_windows\": [%d", c->windows[0]);
    for (int i = 1; i < c->num_windows; ++i) fprintf(out, ", %d", c->windows[i]);
    fprintf(out, "], \"observer_orders\": [%d", c->observer_orders[0]);
    for (int i = 1; i < c->num_observers; ++i) fprintf(out, ", %d", c->observer_orders[i]);
    fprintf(out, "], \"max_order\": %d, \"selection_band_hz\": [", c->max_order);
    json_number(out, c->frequency_min_hz);
    fputs(", ", out);
    json_number(out, c->frequency_max_hz);
    fputc(']', out);
    if (order_reason != NULL) {
        fputs(",\n    ", out);
        json_setting(out, "order", order, 1, order_reason);
    }
    fputs("}", out);
}

void auto_json(FILE *out, const auto_choice *c, double dt, const auto_modes *am, const okid_result *res, int m)
{
    auto_json_chosen(out, c, dt, res->order,
                     am == NULL ? NULL : mode_windows_order_reason(am->num_modes, am->order_holds_all));
    if (am == NULL) { /* an order given: that model's modes */
        json_modes(out, res, m);
        return;
    }
    int orders[AUTO_OBSERVERS * 3] = {0};
    for (int j = 0; j < am->num_observers; ++j) {
        for (int w = 0; w < am->num_runs; ++w) orders[j * am->num_runs + w] = am->observers[j].runs[w].table.num_orders;
    }
    mode_windows_json(out, am->modes, am->num_modes, orders, am->num_runs, am->valid_observers, c->observer_orders,
                      res->modes,
                      res->num_modes, &am->criteria, m, AUTO_UNSTABLE_ACROSS);
}

/* SPDX-License-Identifier: Apache-2.0 */
/* The physical modes over the Hankel windows of the choice: identify, table, select, combine. */
#include "auto_modes.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>


/* The selection of table with criteria, in a workspace of bytes of its own (*workspace, freed by auto_modes_free). */
static okid_status select_into(const okid_stabilization *table, int m, const okid_mode_selection_criteria *criteria,
                               size_t bytes, void **workspace, okid_mode_selection *selection)
{
    if ((*workspace = mode_windows_workspace(bytes)) == NULL) return OKID_E_WORKSPACE_TOO_SMALL;
    return okid_select_modes(table, m, criteria, *workspace, bytes, selection, NULL);
}

/* window > 0: alpha = beta = window; 0 keeps cfg's Hankel size (given by the user). */
static okid_status run_window(auto_run *run, const okid_config *cfg, int window, int max_order, size_t n,
                              const okid_real *u, const okid_real *y, const okid_mode_selection_criteria *criteria)
{
    run->cfg = *cfg;
    if (window > 0) run->cfg.hankel_rows = run->cfg.hankel_cols = window;
    run->cfg.order = 0;
    size_t bytes = 0;
    okid_status st = okid_workspace_size(&run->cfg, &bytes);
    if (st != OKID_OK) return st;
    if ((run->workspace = mode_windows_workspace(bytes)) == NULL) return OKID_E_WORKSPACE_TOO_SMALL;
    st = okid_init(&run->id, &run->cfg, run->workspace, bytes, NULL);
    if (st == OKID_OK) {
        st = okid_push_block(&run->id, n, u, (size_t)cfg->num_inputs, y, (size_t)cfg->num_outputs, NULL);
    }
    if (st == OKID_OK) st = okid_identify(&run->id, &run->result);
    int top = max_order < run->result.num_singular_values ? max_order : run->result.num_singular_values;
    top -= top % 2;
    if (st == OKID_OK && top < 2) st = OKID_E_BAD_ORDER;
    if (st == OKID_OK) st = okid_stabilization_workspace_size(&run->id, top, 2, &bytes);
    if (st == OKID_OK && (run->table_workspace = mode_windows_workspace(bytes)) == NULL) st = OKID_E_WORKSPACE_TOO_SMALL;
    if (st == OKID_OK) st = okid_stabilization_compute(&run->id, top, 2, NULL, run->table_workspace, bytes, &run->table);
    if (st == OKID_OK) st = okid_mode_selection_workspace_size(top, 2, &bytes);
    if (st == OKID_OK) st = select_into(&run->table, cfg->num_outputs, criteria, bytes, &run->selection_workspace, &run->selection);
    /* without EMAC: a heavily damped mode decays below the noise within a long window, and its
       EMAC there (the last block row of the observability matrix) compares noise */
    okid_mode_selection_criteria unchecked = *criteria;
    unchecked.emac_min = 0;
    if (st == OKID_OK) st = select_into(&run->table, cfg->num_outputs, &unchecked, bytes, &run->unchecked_workspace, &run->unchecked);
    if (st == OKID_OK) {
        const okid_real *sv = run->result.singular_values;
        run->noise_floor = run->result.num_singular_values > top && sv[0] > 0 ? (double)(sv[top] / sv[0]) : 0;
    }
    return st;
}

okid_status auto_modes_find(const auto_choice *choice, const okid_config *cfg, size_t n, const okid_real *u,
                            const okid_real *y, auto_modes *out)
{
    memset(out, 0, sizeof *out);
    okid_mode_selection_criteria_default(&out->criteria);
    out->criteria.frequency_min_hz = (okid_real)choice->frequency_min_hz;
    out->criteria.frequency_max_hz = (okid_real)choice->frequency_max_hz;
    /* a mode damped up to 1/sqrt(2) still has a resonance peak in the frequency response; the
       selection's 0.2 is the rule of thumb for structures, and the paper's plant is damped 33 % */
    out->criteria.damping_max = (okid_real)AUTO_DAMPING_MAX;
    out->num_runs = choice->num_windows;
    for (int w = 0; w < out->num_runs; ++w) {
        const int window = (choice->given & AUTO_GIVEN_HANKEL) ? 0 : choice->windows[w];
        out->runs[w].status = run_window(&out->runs[w], cfg, window, choice->max_order, n, u, y, &out->criteria);
    }
    if (out->runs[0].status != OKID_OK) {
        return out->runs[0].status;
    }
    /* group the windows' modes: a mode of window w joins the first reported mode it matches */
    const int m = cfg->num_outputs;
    int support[OKID_MAX_ORDER] = {0};
    for (int w = 0; w < out->num_runs; ++w) {
        if (out->runs[w].status == OKID_OK) {
            mode_windows_add(&out->criteria, &out->runs[w].selection, w, m, out->modes, &out->num_modes, support);
        }
    }
    /* a window whose span outlasts a mode (its amplitude decays below the Hankel matrix's noise share
       over the window, |lambda|^(alpha - 1) < sigma_(top + 1) / sigma_1) cannot check its EMAC: there
       the mode counts when it is stable across orders without the EMAC criterion */
    for (int w = 0; w < out->num_runs; ++w) {
        const auto_run *run = &out->runs[w];
        if (run->status != OKID_OK) continue;
        for (int k = 0; k < run->unchecked.num_modes; ++k) {
            const okid_selected_mode *s = &run->unchecked.modes[k];
            const double magnitude = hypot((double)s->mode.eigenvalue.re, (double)s->mode.eigenvalue.im);
            if (!(pow(magnitude, run->cfg.hankel_rows - 1) < run->noise_floor)) continue;
            for (int g = 0; g < out->num_modes; ++g) {
                if (!(support[g] & (1 << w)) && mode_windows_same(&out->criteria, &out->modes[g].selected->mode, &s->mode, m)) {
                    support[g] |= 1 << w, ++out->modes[g].windows;
                    break;
                }
            }
        }
    }
    /* every window: a physical mode does not move with the window, and a window that outlasts it
       confirms it without EMAC (above); two of three let a mode at the edge of the cluster-size rule
       in two windows through (GWS 261: 1.32 Hz, zeta 0.08, docs/quality.md section 8) */
    mode_windows_keep(out->modes, &out->num_modes, out->num_runs);
    mode_windows_order(&out->runs[0].table, &out->criteria, out->modes, out->num_modes, m, &out->order,
                       &out->order_holds_all);
    return OKID_OK;
}

const char *auto_pole_verdict(const auto_modes *am, const okid_mode *pole, int m)
{
    return mode_windows_verdict(&am->criteria, am->modes, am->num_modes, pole, m, AUTO_UNSTABLE_ACROSS);
}

void auto_modes_free(auto_modes *am)
{
    for (int w = 0; w < am->num_runs; ++w) {
        free(am->runs[w].workspace);
        free(am->runs[w].table_workspace);
        free(am->runs[w].selection_workspace);
        free(am->runs[w].unchecked_workspace);
    }
    memset(am, 0, sizeof *am);
}

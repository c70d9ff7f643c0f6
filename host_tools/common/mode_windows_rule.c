/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The rule of the reported modes from the selections of several Hankel windows: group, keep,
 * order, verdicts (mode_windows.h). No heap and no I/O: the identifier FMU compiles this file too
 * (its mode outputs are the CLI's one-window modes, docs/fmu.md).
 */
#include <math.h>

#include "mode_windows.h"

int mode_windows_same(const okid_mode_selection_criteria *c, const okid_mode *a, const okid_mode *b, int m)
{
    const double fa = (double)a->frequency_hz, fb = (double)b->frequency_hz;
    return a->is_pair && b->is_pair && fabs(fa - fb) <= (double)c->frequency_distance * fa &&
           (double)okid_mac(a->sensor_shape, b->sensor_shape, m) >= (double)c->mac_min;
}

void mode_windows_add(const okid_mode_selection_criteria *c, const okid_mode_selection *selection, int w, int m,
                      auto_mode *modes, int *num_modes, int *support)
{
    for (int k = 0; k < selection->num_modes; ++k) {
        const okid_selected_mode *s = &selection->modes[k];
        int g = 0;
        while (g < *num_modes && !mode_windows_same(c, &modes[g].selected->mode, &s->mode, m)) ++g;
        if (g == *num_modes) {
            if (g == OKID_MAX_ORDER) continue;
            modes[g] = (auto_mode){s, w, 0, 0, 0};
            ++*num_modes;
        }
        if (!(support[g] & (1 << w))) support[g] |= 1 << w, ++modes[g].windows;
    }
}

void mode_windows_keep(auto_mode *modes, int *num_modes, int needed)
{
    int kept = 0;
    for (int g = 0; g < *num_modes; ++g) {
        if (modes[g].windows >= needed) modes[kept++] = modes[g];
    }
    *num_modes = kept;
    for (int i = 1; i < kept; ++i) { /* by increasing frequency */
        const auto_mode x = modes[i];
        int j = i;
        while (j > 0 && modes[j - 1].selected->mode.frequency_hz > x.selected->mode.frequency_hz) {
            modes[j] = modes[j - 1];
            --j;
        }
        modes[j] = x;
    }
}

void mode_windows_order(const okid_stabilization *table, const okid_mode_selection_criteria *c, const auto_mode *modes,
                        int num_modes, int m, int *order, int *holds_all)
{
    int best = -1, best_count = -1;
    for (int i = 0; i < table->num_orders; ++i) {
        const okid_stabilization_order *o = &table->orders[i];
        int count = 0;
        for (int k = 0; k < num_modes; ++k) {
            for (int j = 0; j < o->num_modes; ++j) {
                if (mode_windows_same(c, &modes[k].selected->mode, &table->modes[o->first + j], m)) {
                    ++count;
                    break;
                }
            }
        }
        if (count > best_count) best = o->order, best_count = count;
    }
    *order = best;
    *holds_all = best_count == num_modes;
}

const char *mode_windows_order_reason(int num_modes, int holds_all)
{
    return num_modes == 0 ? "no physical mode: the largest singular-value gap"
           : holds_all    ? "the lowest order whose poles hold every physical mode"
                          : "the order whose poles hold the most physical modes";
}

const char *mode_windows_verdict(const okid_mode_selection_criteria *c, const auto_mode *modes, int num_modes,
                                 const okid_mode *pole, int m, const char *unstable_across)
{
    for (int k = 0; k < num_modes; ++k) {
        if (mode_windows_same(c, &modes[k].selected->mode, pole, m)) return NULL;
    }
    const double f = (double)pole->frequency_hz, z = (double)pole->damping_ratio;
    const double magnitude = hypot((double)pole->eigenvalue.re, (double)pole->eigenvalue.im);
    if (!pole->is_pair) return "real pole";
    if (!(magnitude < 1)) return "unstable (|lambda| >= 1)";
    if (!(z > (double)c->damping_min)) return "damping ratio <= 0";
    if (z > (double)c->damping_max) return "damping ratio above 1/sqrt(2) (no resonance peak)";
    if (f < (double)c->frequency_min_hz || (c->frequency_max_hz > 0 && f > (double)c->frequency_max_hz)) {
        return "outside the band of the selection";
    }
    if ((double)pole->mpc < (double)c->mpc_min) return "MPC below 0.5";
    if ((double)pole->emac < (double)c->emac_min) return "EMAC below 0.5";
    return unstable_across;
}

/* SPDX-License-Identifier: Apache-2.0 */
/* The reported modes' heap workspace and JSON (the rule itself: mode_windows_rule.c). */
#include "mode_windows.h"

#include <stdlib.h>

#include "json_writer.h"

void *mode_windows_workspace(size_t bytes)
{
    return aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN *
                                                   OKID_WORKSPACE_ALIGN);
}

void mode_windows_json(FILE *out, const auto_mode *modes, int num_modes, const int *window_orders, int num_windows,
                       int num_observers, const int *observer_orders, const okid_mode *poles, int num_poles, const okid_mode_selection_criteria *c, int m,
                       const char *unstable_across)
{
    fputs(",\n  \"modes\": [", out);
    for (int k = 0; k < num_modes; ++k) {
        const okid_selected_mode *s = modes[k].selected;
        fputs(k ? ",\n    {" : "\n    {", out);
        json_mode_members(out, &s->mode, m);
        fprintf(out, ", \"order\": %d, \"num_orders\": %d, \"of_orders\": %d, \"lowest_order\": %d, \"highest_order\": %d",
                s->order, s->num_orders, window_orders[modes[k].observer * num_windows + modes[k].window], s->lowest_order,
                s->highest_order);
        const char *names[9] = {"frequency_mean", "frequency_std", "frequency_min", "frequency_max", "damping_mean",
                                "damping_std", "damping_min", "damping_max", "cmi_min"};
        const okid_real values[9] = {s->frequency_mean, s->frequency_std, s->frequency_min, s->frequency_max,
                                     s->damping_mean, s->damping_std, s->damping_min, s->damping_max, s->cmi_min};
        for (int i = 0; i < 9; ++i) {
            fprintf(out, ", \"%s\": ", names[i]);
            json_number(out, (double)values[i]);
        }
        fprintf(out, ", \"windows\": %d, \"of_windows\": %d", modes[k].windows, num_windows);
        if (num_observers > 0) {
            fprintf(out, ", \"observers\": %d, \"of_observers\": %d, \"observer_order\": %d", modes[k].observers,
                    num_observers, observer_orders[modes[k].observer]);
        }
        fputc('}', out);
    }
    fputs(num_modes ? "\n  ]" : "]", out);
    fputs(",\n  \"poles\": [", out);
    for (int i = 0; i < num_poles; ++i) {
        const char *why = mode_windows_verdict(c, modes, num_modes, &poles[i], m, unstable_across);
        fputs(i ? ",\n    {" : "\n    {", out);
        json_mode_members(out, &poles[i], m);
        fprintf(out, ", \"verdict\": \"%s\", \"reason\": ", why ? "rejected" : "physical");
        if (why) json_string(out, why); else fputs("null", out);
        fputc('}', out);
    }
    fputs(num_poles ? "\n  ]" : "]", out);
}

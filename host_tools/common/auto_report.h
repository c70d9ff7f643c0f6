/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify's report of the settings chosen from the data and of the physical modes (table and JSON). */
#ifndef OKID_CLI_AUTO_REPORT_H
#define OKID_CLI_AUTO_REPORT_H

#include <stdio.h>

#include "auto_modes.h"
#include "auto_settings.h"

/* One line per setting: its value and why (given, or the rule and the numbers it came from). */
void auto_print_choice(const auto_choice *choice, double dt);

/*
 * The physical modes (am non-NULL) with their spread, then their sensor shapes C psi by output
 * name; with all_poles, every pole of the model with its verdict.
 */
void auto_print_modes(const auto_modes *am, const okid_result *res, const char *const *output_names, int m,
                      int all_poles);

/* One row of sensor shapes C psi, scaled so that the largest component is 1 (the rest of the line). */
void auto_print_sensor_shape(const okid_mode *md, int m);

/* ",\n  "chosen": {...}": the settings of c and, with order_reason, "order": {"value": order, ...}. */
void auto_json_chosen(FILE *out, const auto_choice *c, double dt, int order, const char *order_reason);

/* ",\n  "chosen": {...}" and, with am, ",\n  "modes": [...]" and ",\n  "poles": [...]". */
void auto_json(FILE *out, const auto_choice *choice, double dt, const auto_modes *am, const okid_result *res, int m);

#endif

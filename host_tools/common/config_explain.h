/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Why okid_workspace_size() refused a configuration, in one line: the field okid_config_check()
 * names, its value and its valid range, and where that range comes from other settings (the order
 * against the Hankel sizes, instrumental variables' lags), with the combination's numbers. The CLI
 * the Python package and the identifier FMU print this one text; only the spelling of a setting
 * differs (--order, order= or the parameter order).
 */
#ifndef OKID_HOST_CONFIG_EXPLAIN_H
#define OKID_HOST_CONFIG_EXPLAIN_H

#include <stddef.h>

#include "okid/okid.h"

typedef enum config_explain_style {
    CONFIG_EXPLAIN_CLI,    /* settings spelled as the CLI's flags: --instrument-lags 3 */
    CONFIG_EXPLAIN_PYTHON, /* as Python keywords: instrument_lags=3 */
    CONFIG_EXPLAIN_FMU     /* as the FMU's parameters: instrument_lags = 3 (fmu/identifier/model.c) */
} config_explain_style;

/*
 * The refusal of cfg (st: what okid_workspace_size() returned) into out[size], as
 * "invalid settings (r = .., m = .., p = .., n = .., Hankel .. x ..): <status>; <field> = <value> is
 * outside <min>..<max>; <hint>". Returns the field okid_config_check() named (NULL: none).
 */
const char *config_explain(const okid_config *cfg, okid_status st, config_explain_style style, char *out,
                           size_t size);

/*
 * The data's sufficiency before the workspace is allocated: samples give at most
 * ceil(samples / K) - p regressor rows (every K-th kept, the first p only fill the observer's window
 * unless zero_initial_state), and q = r + (r + m) p are needed. 1 with the refusal in out[size]
 * when they cannot be enough, 0 when they may be.
 */
int config_data_shortfall(const okid_config *cfg, unsigned long long samples, char *out, size_t size);

#endif

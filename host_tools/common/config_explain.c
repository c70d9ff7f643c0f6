/* SPDX-License-Identifier: Apache-2.0 */
/* See config_explain.h. */
#include "config_explain.h"

#include <stdio.h>
#include <string.h>

static long long min3(long long a, long long b, long long c)
{
    const long long ab = a < b ? a : b;
    return ab < c ? ab : c;
}

/* "--instrument-lags " or "instrument_lags=": a setting as the user typed it, before its value. */
static const char *spelled(config_explain_style style, const char *field, char *buf, size_t size)
{
    if (style != CONFIG_EXPLAIN_CLI) {
        snprintf(buf, size, style == CONFIG_EXPLAIN_PYTHON ? "%s=" : "%s = ", field);
        return buf;
    }
    size_t k = (size_t)snprintf(buf, size, "--");
    for (const char *c = field; *c != '\0' && k + 2 < size; ++c) buf[k++] = *c == '_' ? '-' : *c;
    buf[k++] = ' ';
    buf[k] = '\0';
    return buf;
}

int config_data_shortfall(const okid_config *cfg, unsigned long long samples, char *out, size_t size)
{
    const unsigned long long k = cfg->decimation > 1 ? (unsigned long long)cfg->decimation : 1u;
    const unsigned long long kept = (samples + k - 1) / k;
    const unsigned long long window = cfg->zero_initial_state ? 0u : (unsigned long long)cfg->observer_order;
    const unsigned long long rows = kept > window ? kept - window : 0u;
    const long long q = (long long)cfg->num_inputs + (long long)(cfg->num_inputs + cfg->num_outputs) * cfg->observer_order;
    if (rows >= (unsigned long long)q) {
        return 0;
    }
    snprintf(out, size, "not enough data: %llu samples give at most %llu regressor rows, %lld needed "
             "(q = r + (r+m)p with p = %d)", samples, rows, q, cfg->observer_order);
    return 1;
}

const char *config_explain(const okid_config *cfg, okid_status st, config_explain_style style, char *out,
                           size_t size)
{
    okid_config_issue issue;
    (void)okid_config_check(cfg, &issue);
    char range[160] = "";
    if (issue.field != NULL && strcmp(issue.field, "rank_tolerance") == 0) {
        snprintf(range, sizeof range, "; rank_tolerance = %g must be 0 (the default) or in [%g, %g)", issue.value,
                 issue.min, issue.max);
    } else if (issue.field != NULL && strcmp(issue.field, "workspace bytes") == 0) {
        snprintf(range, sizeof range, "; the workspace would be %.4g bytes, more than this machine can address (%g)",
                 issue.value, issue.max);
    } else if (issue.field != NULL) {
        snprintf(range, sizeof range, "; %s = %.6g is outside %.6g..%.6g", issue.field, issue.value, issue.min,
                 issue.max);
    }
    const long long r = cfg->num_inputs, m = cfg->num_outputs, p = cfg->observer_order;
    const long long columns = r + (cfg->realization == OKID_REALIZATION_COMBINED ? m : 0);
    const long long hankel = cfg->hankel_rows * m, window = cfg->hankel_cols * columns;
    const long long largest = min3(hankel, window, m * p);
    char hint[256] = "", name[40];
    if (st == OKID_E_BAD_ORDER && cfg->order == 0) {
        snprintf(hint, sizeof hint, "; the automatic order would search up to min(alpha m, beta columns, m p) = "
                 "%lld, more than %d: give %s", largest, OKID_MAX_ORDER,
                 style == CONFIG_EXPLAIN_CLI ? "--order" : style == CONFIG_EXPLAIN_PYTHON ? "order=<n>"
                                                                       : "the parameter order a value");
    } else if (st == OKID_E_BAD_ORDER && cfg->order <= largest) { /* within the sizes: a build's limit */
        snprintf(hint, sizeof hint, "; %s%d is above %s", spelled(style, "order", name, sizeof name), cfg->order,
                 OKID_LINALG_EIGEN && cfg->order <= OKID_MAX_ORDER
                     ? "the Eigen backend's OKID_EIGEN_MAX_ORDER (its eigen-solver's fixed size)"
                     : "OKID_MAX_ORDER");
    } else if (st == OKID_E_BAD_ORDER) {
        snprintf(hint, sizeof hint, "; %s%d must be at most min(alpha m, beta columns, m p) = "
                 "min(%lld, %lld, %lld) = %lld", spelled(style, "order", name, sizeof name), cfg->order, hankel,
                 window, m * p, largest);
    } else if (cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL && st == OKID_E_BAD_SIZE) {
        snprintf(hint, sizeof hint, "; %s%d: instrumental variables need r (L + 1) >= q = %lld, "
                 "L >= p = %lld and L <= %d", spelled(style, "instrument_lags", name, sizeof name),
                 cfg->instrument_lags, r + (r + m) * p, p, OKID_MAX_INSTRUMENT_LAGS);
    }
    snprintf(out, size, "invalid settings (r = %d, m = %d, p = %d, n = %d, Hankel %d x %d): %s%s%s", cfg->num_inputs,
             cfg->num_outputs, cfg->observer_order, cfg->order, cfg->hankel_rows, cfg->hankel_cols,
             okid_status_str(st), range, hint);
    return issue.field;
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The physical modes of a record, without an expert: for each Hankel window of the choice
 * (auto_settings.h), the identification, its stabilization table and the automatic selection
 * (okid/mode_selection.h); a mode is reported when the selections of all three windows
 * hold it (one window: its own selection). The model reported is the main window's at the lowest
 * order whose poles hold every reported mode. docs/quality.md, section 8.
 */
#ifndef OKID_CLI_AUTO_MODES_H
#define OKID_CLI_AUTO_MODES_H

#include <stddef.h>

#include "auto_settings.h"
#include "mode_windows.h" /* auto_mode */
#include "okid/okid.h"

/* The selection's damping limit here: above 1/sqrt(2) a mode has no resonance peak. */
#define AUTO_DAMPING_MAX 0.70710678118654752
/* The verdict of a pole that passes every hard criterion but no window holds. */
#define AUTO_UNSTABLE_ACROSS "not stable across orders and windows"

/* One window's identification, table and selection (each in its own heap workspace). */
typedef struct auto_run {
    okid_config cfg;
    void *workspace, *table_workspace, *selection_workspace, *unchecked_workspace;
    okid_identifier id;
    okid_result result;
    okid_stabilization table;
    okid_mode_selection selection;
    okid_mode_selection unchecked;  /* the same selection without the EMAC criterion */
    double noise_floor;             /* sigma_(top + 1) / sigma_1 of the Hankel matrix: its noise's share */
    okid_status status;  /* OKID_OK when the selection is valid */
} auto_run;

typedef struct auto_modes {
    auto_run runs[3];
    int num_runs;
    okid_mode_selection_criteria criteria;
    auto_mode modes[OKID_MAX_ORDER];
    int num_modes;
    int order;            /* order of the reported model */
    int order_holds_all;  /* 1 when that order's poles hold every reported mode */
} auto_modes;

/*
 * Run the windows of choice on the record (n samples; u: r per sample, y: m per sample) with the
 * settings of cfg (its Hankel size is replaced by each window's), select and combine the modes.
 * Returns OKID_OK, or the main window's failure (its identifier then in runs[0].id for the message).
 */
okid_status auto_modes_find(const auto_choice *choice, const okid_config *cfg, size_t n, const okid_real *u,
                            const okid_real *y, auto_modes *out);

/* Why a pole of the reported model is not one of the reported modes, or NULL when it is. */
const char *auto_pole_verdict(const auto_modes *am, const okid_mode *pole, int m);

void auto_modes_free(auto_modes *am);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The reported modes from the selections of several Hankel windows (or sizes), one rule for the
 * input-output path (auto_modes.c) and the output-only one (ambient_modes.c): a window's selected
 * mode joins the first reported mode within the selection's clustering gates in frequency and
 * shape; a mode is kept when enough windows hold it; the model reported is the main table's
 * lowest order whose poles hold every kept mode; every other pole gets the first reason that
 * rejects it. docs/quality.md, section 8.
 */
#ifndef OKID_CLI_MODE_WINDOWS_H
#define OKID_CLI_MODE_WINDOWS_H

#include <stddef.h>
#include <stdio.h>

#include "okid/okid.h"

/* The stabilization tables' largest order: 60 (docs/quality.md section 8), or the Eigen backend's
   largest model when that is lower (OKID_EIGEN_MAX_ORDER: its eigen-solver holds no more). */
#if OKID_LINALG_EIGEN && OKID_EIGEN_MAX_ORDER < 60
#define MODE_WINDOWS_MAX_ORDER OKID_EIGEN_MAX_ORDER
#else
#define MODE_WINDOWS_MAX_ORDER 60
#endif

/* A reported mode: its representative (from the first window that holds it) and its support. */
typedef struct auto_mode {
    const okid_selected_mode *selected;
    int window;     /* index of the window of the representative */
    int windows;    /* windows whose selection holds the mode */
    int observer;   /* index of the observer order of the representative (input-output path; else 0) */
    int observers;  /* observer orders whose windows hold the mode (input-output path; else 0) */
} auto_mode;

/* A heap workspace of at least bytes, aligned as the library needs (free() it). */
void *mode_windows_workspace(size_t bytes);

/* The selection's clustering gates in frequency and shape: a and b are the same physical mode. */
int mode_windows_same(const okid_mode_selection_criteria *c, const okid_mode *a, const okid_mode *b, int m);

/*
 * Add window w's selection to the reported modes (at most OKID_MAX_ORDER): each selected mode
 * joins the first one it matches, or starts one; support[g] has bit w once window w holds mode g.
 */
void mode_windows_add(const okid_mode_selection_criteria *c, const okid_mode_selection *selection, int w, int m,
                      auto_mode *modes, int *num_modes, int *support);

/* Keep the modes that `needed` windows hold, by increasing frequency. */
void mode_windows_keep(auto_mode *modes, int *num_modes, int needed);

/*
 * The lowest order of table whose poles hold every mode (else the one holding the most): *order
 * (-1 for an empty table) and *holds_all.
 */
void mode_windows_order(const okid_stabilization *table, const okid_mode_selection_criteria *c, const auto_mode *modes,
                        int num_modes, int m, int *order, int *holds_all);

/* Why the model's order is the one reported (holds_all from mode_windows_order; no modes: the
   library's own order, the largest singular-value gap). */
const char *mode_windows_order_reason(int num_modes, int holds_all);

/*
 * Why pole is not one of the modes (NULL when it is): the first hard criterion it fails, else
 * `unstable_across` (not stable across orders and windows). The words name the path's defaults.
 */
const char *mode_windows_verdict(const okid_mode_selection_criteria *c, const auto_mode *modes, int num_modes,
                                 const okid_mode *pole, int m, const char *unstable_across);

/*
 * The JSON members ',\n  "modes": [...]' (the reported modes: each its representative, its
 * cluster's statistics and its support; window_orders: the tables' orders) and
 * ',\n  "poles": [...]' (every pole of the reported model with its verdict), as okid identify
 * writes them without an order. window_orders[j num_windows + w]: observer order j's (0 on the
 * output-only path); num_observers > 0 adds each mode's "observers" (of "of_observers", the observer
 * orders that hold it) and "observer_order" (its representative's, observer_orders[modes[k].observer]).
 */
void mode_windows_json(FILE *out, const auto_mode *modes, int num_modes, const int *window_orders, int num_windows,
                       int num_observers, const int *observer_orders, const okid_mode *poles, int num_poles, const okid_mode_selection_criteria *c, int m,
                       const char *unstable_across);

#endif

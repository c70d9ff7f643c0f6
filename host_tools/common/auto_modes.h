/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The physical modes of a record, without an expert: for each observer order and each Hankel window
 * of the choice (auto_settings.h), the identification, its stabilization table and the automatic
 * selection (okid/mode_selection.h); an observer order holds a mode when the selections of all
 * three windows hold it (one window: its own selection), and a mode is reported when most observer
 * orders hold it (one observer order given: its own). The model reported is that of the shortest
 * observer whose main window has an order whose poles hold every reported mode, at the lowest such
 * order. docs/quality.md, section 8.
 */
#ifndef OKID_CLI_AUTO_MODES_H
#define OKID_CLI_AUTO_MODES_H

#include <stddef.h>

#include "auto_settings.h"
#include "mode_windows.h" /* auto_mode */
#include "okid/okid.h"

/* The selection's damping limit here: above 1/sqrt(2) a mode has no resonance peak. */
#define AUTO_DAMPING_MAX 0.70710678118654752

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

/* The modes of one observer order: its windows' runs and the modes all of them hold. */
typedef struct auto_observer {
    auto_run runs[3];
    auto_mode modes[OKID_MAX_ORDER];
    int num_modes;
} auto_observer;

/* Two observer orders' modes are one mode when within this relative frequency distance (and of
   the selection's MAC): the observer's span moves a physical mode by up to 3 % on the real records
   (0.967-1.003 Hz on Hayward, 0.5-0.9 T), the consensus grid's own grouping (quality.md section 7). */
#define AUTO_OBSERVER_DISTANCE 0.03
/* A mode most observer orders do not hold is reported only when its own indicators confirm it:
   EMAC and MPC at least this, the MAC the grouping asks of one mode's shapes (the selection's own
   floor is 0.5). Weak Hayward events gave 18.5 Hz (MPC 0.71), 49.6 Hz (EMAC 0.85) and 1.94 Hz (EMAC
   0.58), each held by one observer order of five; the chain's 0.656 Hz (EMAC 0.999, MPC 1.000) stays. */
#define AUTO_UNCONFIRMED_MIN 0.9
/* The verdict of a pole that passes every hard criterion but no observer order's windows hold. */
#define AUTO_UNSTABLE_ACROSS "not stable across orders, windows and observer orders"

typedef struct auto_modes {
    auto_observer observers[AUTO_OBSERVERS];
    int num_observers;    /* observer orders run (choice->num_observers) */
    int valid_observers;  /* of them, those whose main window identified */
    int observer;         /* index of the observer order of the reported model */
    int num_runs;         /* windows per observer order */
    okid_mode_selection_criteria criteria;
    auto_mode modes[OKID_MAX_ORDER];
    int num_modes;
    /* the observer orders' modes pooled by frequency, each one's group and the groups' state
       (auto_modes.c's scratch: here, on the heap with the rest, not on the caller's stack) */
    struct {
        auto_mode all[AUTO_OBSERVERS * OKID_MAX_ORDER];
        int group_of[AUTO_OBSERVERS * OKID_MAX_ORDER], last[AUTO_OBSERVERS * OKID_MAX_ORDER];
        int held[AUTO_OBSERVERS * OKID_MAX_ORDER], size[AUTO_OBSERVERS * OKID_MAX_ORDER];
        int chosen[AUTO_OBSERVERS * OKID_MAX_ORDER];  /* each group's representative, or -1 */
        int most[AUTO_OBSERVERS * OKID_MAX_ORDER];    /* 1: enough observer orders hold the group */
    } pool;
    int order;            /* order of the reported model */
    int order_holds_all;  /* 1 when that order's poles hold every reported mode */
} auto_modes;

/*
 * Run the observer orders and windows of choice on the record (n samples; u: r per sample, y: m per
 * sample) with the settings of cfg (its observer order and Hankel size replaced by each run's),
 * select and combine the modes. Returns OKID_OK, or the first observer's main window's failure (its
 * identifier then in observers[0].runs[0].id for the message).
 */
okid_status auto_modes_find(const auto_choice *choice, const okid_config *cfg, size_t n, const okid_real *u,
                            const okid_real *y, auto_modes *out);

/* Why a pole of the reported model is not one of the reported modes, or NULL when it is. */
const char *auto_pole_verdict(const auto_modes *am, const okid_mode *pole, int m);

/* The main window of the reported model's observer order: its table and settings. */
const auto_run *auto_main_run(const auto_modes *am);

void auto_modes_free(auto_modes *am);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The physical modes of an output-only record (okid identify --inputs 0 without --order, and
 * okid.identify_ambient): the record's correlations summed once at the largest Hankel size of the
 * choice; for each size L, their stabilization table (okid_ambient_stabilization_compute_at()) and the selection of
 * okid/mode_selection.h; a mode is reported when the selections of two of the three sizes hold
 * it, and the model reported is the main size's at the lowest order whose poles hold every
 * reported mode: the rule auto_modes.h applies to input-output records (docs/ambient.md).
 */
#ifndef OKID_HOST_AMBIENT_MODES_H
#define OKID_HOST_AMBIENT_MODES_H

#include <stddef.h>
#include <stdio.h>

#include "auto_modes.h" /* auto_mode */
#include "okid/okid.h"

/* One Hankel size's table and selection (each in its own heap workspace), from the shared sums. */
typedef struct ambient_run {
    void *table_workspace, *selection_workspace;
    okid_stabilization table;
    okid_mode_selection selection;
    okid_status status; /* OKID_OK when the selection is valid */
} ambient_run;

/* The record's correlation sums, once, at the largest Hankel size: every size's table reads them
   (okid_ambient_stabilization_compute_at()). */
typedef struct ambient_sums {
    okid_ambient_config cfg;
    void *workspace;
    okid_ambient amb;
} ambient_sums;

/* What was chosen and why: the band, the sizes, the table's largest order, the selection's band. */
typedef struct ambient_choice {
    int hankel_given;              /* 1: L given (one size), else chosen from the band */
    int no_band;                   /* 1: the record has no band (too short or flat): L = 20 */
    double band_low_hz, band_high_hz;
    int windows[3];                /* L of each run, the main one first */
    int num_windows;
    int max_order;                 /* the tables' largest order (step 2) */
    double frequency_min_hz, frequency_max_hz;
} ambient_choice;

typedef struct ambient_modes {
    ambient_choice choice;
    ambient_sums sums;
    ambient_run runs[3];
    int num_runs;
    okid_mode_selection_criteria criteria;
    auto_mode modes[OKID_MAX_ORDER];
    int num_modes;
    int order;           /* order of the reported model (main size); 0 when no mode was found */
    int order_holds_all; /* 1 when that order's poles hold every reported mode */
} ambient_modes;

/*
 * Choose the sizes from the mean-removed record y (n samples of m values) unless cfg->hankel_rows
 * is given (hankel_given), sum the record once at the largest, table and select each size, and
 * combine. band: the record's (ambient_record_band()) when the caller has estimated it, NULL to
 * estimate it here. cfg holds everything else (references, dt, sensing); its order is ignored.
 * criteria: NULL for the defaults with the band [f5 / 3, 0.8 Nyquist]; else used as given.
 * Returns OKID_OK, or the main run's failure.
 */
okid_status ambient_modes_find(const okid_ambient_config *cfg, int hankel_given, const auto_band *band, size_t n,
                               const okid_real *y, const okid_mode_selection_criteria *criteria, ambient_modes *out);

/*
 * The physical modes of a streaming identifier's sums (okid.AmbientIdentifier with order 0): amb,
 * initialised with cfg (order 0, so that its workspace holds every order of the table), at its one
 * Hankel size: the table of the even orders 2..min(60, L min(m, r_ref)) and the selection in the
 * band [0, 0.8 Nyquist] (a stream has no record to take the 5 % frequency from, as in the
 * identifier FMU). amb's sums and last result are unchanged; out->order is the order to identify
 * at (okid_ambient_identify_order()), 0 when no mode was found. Returns OKID_OK or the table's failure.
 */
okid_status ambient_modes_of(okid_ambient *amb, const okid_ambient_config *cfg, ambient_modes *out);

/* Why a pole of the reported model is not one of the reported modes, or NULL when it is. */
const char *ambient_pole_verdict(const ambient_modes *am, const okid_mode *pole, int m);

/* The table's lines: the choice and the physical modes with their spread and shapes. */
void ambient_print_modes(const ambient_modes *am, const okid_ambient_result *res, const char *const *output_names,
                         int m);

/* ',\n  "chosen": {...}', ',\n  "modes": [...]' (the physical modes) and ',\n  "poles": [...]' (res's, with verdicts). */
void ambient_modes_json(FILE *out, const ambient_modes *am, const okid_ambient_result *res, int m);

void ambient_modes_free(ambient_modes *am);

#endif

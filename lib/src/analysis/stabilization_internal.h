/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The stabilization table's orders from one realization at the largest order (nested
 * truncation), shared by okid_stabilization_compute() (okid/stabilization.h) and
 * okid_ambient_stabilization_compute() (okid/ambient.h): the modal analysis, indicators and
 * stability flags of each leading block.
 */
#ifndef OKID_STABILIZATION_INTERNAL_H
#define OKID_STABILIZATION_INTERNAL_H

#include "okid/stabilization.h"
#include "pipeline/modal_internal.h"
#include "quality/modal_indicators_internal.h"

/* A realization at order top (leading dimensions top for a, b, ctrl_last; m for c, obs_last). */
typedef struct okid_stab_realization_ {
    int top, m, r, alpha, beta;
    okid_real dt;
    okid_sensing sensing;
    const okid_real *a, *b, *c, *obs_last, *ctrl_last;
} okid_stab_realization_;

/* Where the table goes (views sized for the orders step, 2 step, ..., top). */
typedef struct okid_stab_table_views_ {
    okid_modal_scratch *modal;
    okid_indicator_scratch *ind;
    okid_stabilization_order *orders;
    okid_mode *modes;
    okid_complex *shapes;
    unsigned *stability;
} okid_stab_table_views_;

/* Largest n with sigma_n > eps k sigma_1: the orders okid_era_realize() accepts. */
int okid_stab_hankel_rank_(const okid_real *sv, int k);

/* The orders step, 2 step, ..., rz->top into v; *count gets the number of orders. */
okid_status okid_stab_fill_orders_(const okid_stab_realization_ *rz, int step, const okid_stabilization_criteria *crit,
                                   const okid_stab_table_views_ *v, int *count);

/*
 * The criteria (NULL: the defaults) into *crit, the workspace's alignment and size (needed):
 * OKID_OK, OKID_E_BAD_PARAMETER (criteria), OKID_E_WORKSPACE_ALIGNMENT, OKID_E_WORKSPACE_TOO_SMALL.
 */
okid_status okid_stab_check_(const okid_stabilization_criteria *criteria, const void *workspace, size_t bytes,
                             size_t needed, okid_stabilization_criteria *crit);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's order and start from the physical-mode selection (okid identify --refine and
 * okid.identify(refine=True) without an order; docs/refinement.md): the order is 2 c for the c
 * physical modes the selection reports (auto_modes.h) plus 2 for each other pair of the selection's
 * model (the lowest order whose poles hold every physical mode) that is a mode by the hard criteria
 * (stable, damped 0..1/sqrt(2), in the band: the selection may reject a heavily damped mode on its
 * EMAC, the likelihood judges it) and lies outside the frequency gate of every physical mode. The
 * start is that model truncated to those pairs (modal truncation by its eigenvectors), so the
 * refined model has one pair per physical mode and no spare pair near one to split it with. Real
 * poles are left out: a structure's modes are pairs, and the refinement fits D, so the direct
 * feedthrough of an acceleration needs no state.
 */
#ifndef OKID_HOST_REFINE_SELECTION_H
#define OKID_HOST_REFINE_SELECTION_H

#include <stddef.h>

#include "auto_identify.h"
#include "okid/okid.h"

typedef struct refine_selection {
    int order;            /* the refinement's order, 2 x num_modes; 0 when no physical mode was selected */
    int num_modes;        /* physical modes kept (those the selection's model holds) */
    int num_other;        /* other pairs kept (the hard criteria, outside every physical mode's gate) */
    int selection_order;  /* the order of the selection's model the start is cut from */
    okid_result start;    /* the truncated model, its modes the kept poles (views into storage and the
                             selection's result: valid while both live) */
    okid_real *storage;   /* A, B, C, D, G of the start (heap) */
    okid_mode *modes;
    int poles[OKID_MAX_ORDER]; /* the kept pairs: their indices in the selection model's modes */
    char reason[256];     /* why this order, for "chosen"."order"."reason" and the table */
} refine_selection;

/*
 * The order and start from ai's physical modes (ai from auto_identify() with the order chosen).
 * Returns 0; out->order is 0 (and out->reason says why) when no mode was selected or a mode's
 * eigenvectors could not be computed: there is no start, and the callers refuse to refine.
 * -1: out of memory.
 */
int refine_selection_start(const auto_identification *ai, refine_selection *out);

void refine_selection_free(refine_selection *sel);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The start of the prediction-error refinement chosen from the data (okid identify --refine and
 * okid.identify(refine=True) without a horizon given; docs/refinement.md): OKID/ERA from each
 * (p, alpha = beta) of a grid, cheap first, each refined; the start whose refinement reaches the
 * lowest cost (the highest likelihood: same record, same order) wins, among the starts whose
 * refined model does not split one mode in two (OKID_W_MODE_SPLIT) when there are any. Written once here; the
 * caller refines (the CLI and the Python binding feed the refiner their own way).
 */
#ifndef OKID_HOST_START_SEARCH_H
#define OKID_HOST_START_SEARCH_H

#include <stddef.h>
#include <stdio.h>

#include "okid/okid.h"

enum { START_P = 4, START_H = 3 };
typedef struct start_candidate {
    int observer_order, hankel_blocks, identified, state; /* state: okid_refine_state, -1 when not refined */
    int split; /* its refinement has OKID_W_MODE_SPLIT: ranked after every start without */
    double cost;
} start_candidate;
typedef struct start_search {
    start_candidate candidates[START_P * START_H];
    int count, best; /* best: index of the chosen start, -1 when none refined */
} start_search;

/*
 * The passes each start is refined for at most (the callers cap max_passes at this): the costs after
 * 20 Gauss-Newton passes rank the starts (one from a good start converges in 4-30), and the chosen
 * start is refined again with the full max_passes. Uncapped, the search cost up to 12 x max_passes
 * passes: Hayward (4 in, 4 out, 12 600 samples, order 4) 10.6 s per start at 100 passes.
 */
enum { START_SEARCH_PASSES = 20 };
static inline int start_search_passes(int max_passes)
{
    return max_passes < START_SEARCH_PASSES ? max_passes : START_SEARCH_PASSES;
}

/* The refinement of one start's OKID/ERA model over the record: 0 with its final state
   (okid_refine_state), cost and warnings (okid_refine_result::warnings), positive when it failed,
   negative to stop the search (Ctrl-C). */
typedef int (*start_refine_fn)(void *context, const okid_result *start, int *state, double *cost,
                               unsigned *warnings);

/*
 * The grid over the record (n samples; u: r per sample, y: m per sample) with cfg's other
 * settings; cfg gets the chosen start's p and Hankel size (untouched when no start was refined).
 */
void start_search_run(okid_config *cfg, size_t n, const okid_real *u, const okid_real *y, start_refine_fn refine,
                      void *context, start_search *search);

/* ',\n  "start_search": {"chosen": i, "candidates": [...]}' of okid identify --refine --json. */
void json_start_search(FILE *out, const start_search *search);

#endif

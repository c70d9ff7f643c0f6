/* SPDX-License-Identifier: Apache-2.0 */
/* The refinement's start chosen from the data (start_search.h). */
#include "start_search.h"

#include <math.h>
#include <stdlib.h>

#include "json_writer.h"

/*
 * The lowest cost is the highest likelihood (the record and the model order are the same for
 * all starts). OKID/ERA's own settings matter little once refined, but a start whose modes are
 * wrong (a real pole for a lightly damped pair) ends in another, worse, local minimum. The grid
 * runs from cheap to costly and stops once two starts reach the same cost.
 */
static const int start_observer_orders[START_P] = {10, 20, 40, 80};
static const int start_hankel_blocks[START_H] = {20, 50, 100};
/* a thousandth of a log-likelihood unit is a tie: the earlier, cheaper start keeps it */
static const double start_tie = 1e-3;

/*
 * c beats the best so far: a model that splits one mode in two (more pairs than the record holds
 * there, which a lower cost does not make physical) loses to any that does not; otherwise the lower cost.
 */
static int better(const start_candidate *c, const start_candidate *best)
{
    if (best == NULL) return 1;
    if (c->split != best->split) return !c->split;
    return c->cost < best->cost - start_tie;
}

/* OKID/ERA from one start, then its refinement: c says how far it got. Negative: stop the search. */
static int try_start(const okid_config *trial, size_t n, const okid_real *u, const okid_real *y,
                      start_refine_fn refine, void *context, start_candidate *c)
{
    size_t bytes = 0;
    if (okid_workspace_size(trial, &bytes) != OKID_OK) return 0;
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + 15) / 16 * 16);
    okid_identifier id;
    okid_result res;
    int rc = 0;
    if (ws != NULL && okid_init(&id, trial, ws, bytes, NULL) == OKID_OK &&
        okid_push_block(&id, n, u, (size_t)trial->num_inputs, y, (size_t)trial->num_outputs, NULL) == OKID_OK &&
        okid_identify(&id, &res) == OKID_OK) {
        c->identified = 1;
        int state = -1;
        double cost = (double)NAN; /* NAN is a float (-Wdouble-promotion under zig cc) */
        unsigned warnings = 0;
        if ((rc = refine(context, &res, &state, &cost, &warnings)) == 0) {
            c->state = state;
            c->cost = cost;
            c->split = (warnings & OKID_W_MODE_SPLIT) != 0;
        }
    }
    free(ws);
    return rc < 0 ? -1 : 0;
}

void start_search_run(okid_config *cfg, size_t n, const okid_real *u, const okid_real *y, start_refine_fn refine,
                      void *context, start_search *search)
{
    search->count = 0;
    search->best = -1;
    int agree = 0, stop = 0;
    for (int i = 0; i < START_P && agree < 2 && !stop; ++i) {
        for (int j = 0; j < START_H && agree < 2 && !stop; ++j) {
            start_candidate *c = &search->candidates[search->count++];
            okid_config trial = *cfg;
            trial.observer_order = c->observer_order = start_observer_orders[i];
            trial.hankel_rows = trial.hankel_cols = c->hankel_blocks = start_hankel_blocks[j];
            c->identified = c->split = 0;
            c->state = -1;
            c->cost = (double)NAN;
            stop = try_start(&trial, n, u, y, refine, context, c) < 0;
            const int usable = c->state >= 0 && c->state != OKID_REFINE_DIVERGED && isfinite(c->cost);
            if (usable && better(c, search->best < 0 ? NULL : &search->candidates[search->best])) {
                search->best = search->count - 1;
            }
            /* two starts that end in the same optimum: the likely global one; stop before the costly starts */
            agree = 0;
            for (int k = 0; search->best >= 0 && k < search->count; ++k) {
                const start_candidate *b = &search->candidates[search->best], *o = &search->candidates[k];
                agree += o->split == b->split && fabs(o->cost - b->cost) <= start_tie;
            }
        }
    }
    if (search->best >= 0) {
        cfg->observer_order = search->candidates[search->best].observer_order;
        cfg->hankel_rows = cfg->hankel_cols = search->candidates[search->best].hankel_blocks;
    }
}

void json_start_search(FILE *out, const start_search *search)
{
    fprintf(out, ",\n  \"start_search\": {\"chosen\": %d, \"candidates\": [", search->best);
    for (int i = 0; i < search->count; ++i) {
        const start_candidate *c = &search->candidates[i];
        fprintf(out, "%s{\"observer_order\": %d, \"hankel_rows\": %d, \"hankel_cols\": %d, \"state\": ",
                i ? ",\n    " : "\n    ", c->observer_order, c->hankel_blocks, c->hankel_blocks);
        if (c->state >= 0) {
            fprintf(out, "\"%s\"", json_refine_state_name((okid_refine_state)c->state));
        } else {
            fputs(c->identified ? "\"refine_failed\"" : "\"identify_failed\"", out);
        }
        fputs(", \"cost\": ", out);
        json_number(out, c->cost);
        if (c->split) fputs(", \"mode_split\": true", out); /* OKID_W_MODE_SPLIT; absent otherwise */
        fputc('}', out);
    }
    fputs("]}", out);
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * refine_model = auto (docs/refinement.md, "Choosing the model from the residual test"): output
 * error first; only when its residual is not white the innovation form, which is kept only when
 * it converged, its residual is white on every output and uncorrelated with every input
 * (OKID_W_RESIDUAL_INPUT_CORRELATED: the same deterministic part cannot whiten what it misses of
 * the input's dynamics) and its modes agree with output error's
 * within REFINE_CHOICE_SIGMAS combined standard deviations. Otherwise output error stays, with its
 * residual warning (a drift, too low an order): never a success that hides a failed test.
 */
#ifndef OKID_HOST_REFINE_CHOICE_H
#define OKID_HOST_REFINE_CHOICE_H

#include <stddef.h>

#include "okid/refine.h"

/* The value of refine_model "auto" on the host surfaces (CLI, Python): not an okid_refine_model. */
#define REFINE_MODEL_AUTO 2
/* Modes of the two models agree when every frequency and damping ratio differs by at most this
   many combined standard deviations, sqrt(std_oe^2 + std_innovation^2). */
#define REFINE_CHOICE_SIGMAS 3.0

typedef enum refine_choice_reason {
    REFINE_CHOICE_WHITE = 0,          /* output error's residuals are white: output error */
    REFINE_CHOICE_INNOVATION,         /* not white; the innovation form's are and its modes agree */
    REFINE_CHOICE_OE_DIVERGED,        /* output error diverged: nothing to compare (output error) */
    REFINE_CHOICE_NOT_CONVERGED,      /* the innovation form did not converge (output error) */
    REFINE_CHOICE_STILL_NOT_WHITE,    /* the innovation form's residual is not white either (output error) */
    REFINE_CHOICE_MODES_DIFFER,       /* the two models' modes disagree (output error) */
    REFINE_CHOICE_INPUT_CORRELATED    /* the innovation form's residual is correlated with an input (output error) */
} refine_choice_reason;

typedef struct refine_choice {
    okid_refine_model chosen;
    refine_choice_reason reason;
    char detail[320]; /* one sentence: what was compared, with the numbers */
} refine_choice;

/* Whether output error's result calls for the innovation form (its residual is not white). */
int refine_choice_needs_innovation(const okid_refine_result *oe);

/*
 * The choice from output error's result and (NULL when not run) the innovation form's of the same
 * record and order. m outputs.
 */
void refine_choose(const okid_refine_result *oe, const okid_refine_result *inn, int m, refine_choice *choice);

/* "white", "innovation", ... (the JSON's refinement.refine_model_choice.reason). */
const char *refine_choice_reason_name(refine_choice_reason reason);

#endif

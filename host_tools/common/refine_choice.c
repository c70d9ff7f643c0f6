/* SPDX-License-Identifier: Apache-2.0 */
/* refine_model = auto: the choice between output error and the innovation form (refine_choice.h). */
#include "refine_choice.h"

#include <math.h>
#include <stdio.h>

static int first_not_white(const okid_refine_result *rr, int m)
{
    for (int i = 0; i < m; ++i) {
        if (rr->output_warnings[i] & OKID_W_RESIDUAL_NOT_WHITE) return i;
    }
    return -1;
}

/* The first output whose residual is correlated with an input (its first such input in *input), -1 if none. */
static int first_input_correlated(const okid_refine_result *rr, int m, int *input)
{
    const int r = rr->B.cols;
    for (int i = 0; i < m; ++i) {
        if (!(rr->output_warnings[i] & OKID_W_RESIDUAL_INPUT_CORRELATED)) continue;
        *input = 0;
        for (int j = 0; j < r; ++j) {
            if (rr->input_correlation[(size_t)i + (size_t)m * (size_t)j] > (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND) {
                *input = j;
                break;
            }
        }
        return i;
    }
    return -1;
}

int refine_choice_needs_innovation(const okid_refine_result *oe)
{
    return oe->state != OKID_REFINE_DIVERGED && (oe->warnings & OKID_W_RESIDUAL_NOT_WHITE) != 0;
}

/* |a - b| in combined standard deviations; INFINITY when a std is missing (-1) */
static double sigmas_apart(double a, double sa, double b, double sb)
{
    return sa >= 0 && sb >= 0 && sa + sb > 0 ? fabs(a - b) / sqrt(sa * sa + sb * sb) : (double)INFINITY;
}

/* The largest disagreement of the two models' modes, in combined stds (INFINITY: they do not correspond). */
static double modes_apart(const okid_refine_result *a, const okid_refine_result *b, int *worst)
{
    *worst = 0;
    if (a->num_modes != b->num_modes || a->num_modes == 0) return (double)INFINITY;
    double most = 0;
    for (int k = 0; k < a->num_modes; ++k) {
        const okid_mode *ma = &a->modes[k], *mb = &b->modes[k];
        const okid_mode_std *sa = &a->mode_std[k], *sb = &b->mode_std[k];
        if (ma->is_pair != mb->is_pair) return (double)INFINITY;
        double d = sigmas_apart(ma->frequency_hz, sa->frequency_hz, mb->frequency_hz, sb->frequency_hz);
        const double z = sigmas_apart(ma->damping_ratio, sa->damping_ratio, mb->damping_ratio, sb->damping_ratio);
        d = z > d ? z : d;
        if (!(d <= most)) {
            most = d;
            *worst = k;
        }
    }
    return most;
}

void refine_choose(const okid_refine_result *oe, const okid_refine_result *inn, int m, refine_choice *c)
{
    c->chosen = OKID_REFINE_OUTPUT_ERROR;
    const int oe_bad = first_not_white(oe, m);
    if (oe->state == OKID_REFINE_DIVERGED) {
        c->reason = REFINE_CHOICE_OE_DIVERGED;
        snprintf(c->detail, sizeof c->detail, "output error diverged: no residual test to choose from");
        return;
    }
    if (oe_bad < 0) {
        c->reason = REFINE_CHOICE_WHITE;
        snprintf(c->detail, sizeof c->detail, "output error's residuals are white on every output");
        return;
    }
    if (inn == NULL || inn->state != OKID_REFINE_CONVERGED) {
        c->reason = REFINE_CHOICE_NOT_CONVERGED;
        snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d) but the innovation "
                 "form did not converge (%s): output error kept, with its sandwich stds", oe_bad + 1,
                 inn != NULL ? okid_refine_state_str(inn->state) : "not run");
        return;
    }
    const int inn_bad = first_not_white(inn, m);
    if (inn_bad >= 0) {
        c->reason = REFINE_CHOICE_STILL_NOT_WHITE;
        snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d) and the innovation "
                 "form's is not white either (output %d, Ljung-Box Q %.4g): a drift, an offset or too low an order, "
                 "not a force nobody measured; output error kept, with its sandwich stds", oe_bad + 1, inn_bad + 1,
                 (double)inn->whiteness[inn_bad]);
        return;
    }
    int inn_input = 0;
    const int inn_corr = first_input_correlated(inn, m, &inn_input);
    if (inn_corr >= 0) {
        c->reason = REFINE_CHOICE_INPUT_CORRELATED;
        snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d); the innovation "
                 "form's is white but correlated with an input (output %d, input %d, statistic %.3g): it misses some "
                 "of the input's dynamics; output error kept, with its sandwich stds", oe_bad + 1, inn_corr + 1,
                 inn_input + 1,
                 (double)inn->input_correlation[(size_t)inn_corr + (size_t)m * (size_t)inn_input]);
        return;
    }
    int worst = 0;
    const double apart = modes_apart(oe, inn, &worst);
    if (!(apart <= REFINE_CHOICE_SIGMAS)) {
        c->reason = REFINE_CHOICE_MODES_DIFFER;
        if (isfinite(apart)) {
            snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d); the innovation "
                     "form's is white but its mode %d (%.6g Hz) differs from output error's (%.6g Hz) by %.3g combined "
                     "standard deviations (more than %g): output error kept, with its sandwich stds", oe_bad + 1,
                     worst + 1, (double)inn->modes[worst].frequency_hz, (double)oe->modes[worst].frequency_hz, apart,
                     REFINE_CHOICE_SIGMAS);
        } else {
            snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d); the innovation "
                     "form's is white but its modes do not correspond to output error's (count, pairs or a std "
                     "missing): output error kept, with its sandwich stds", oe_bad + 1);
        }
        return;
    }
    c->chosen = OKID_REFINE_INNOVATION;
    c->reason = REFINE_CHOICE_INNOVATION;
    snprintf(c->detail, sizeof c->detail, "output error's residual is not white (output %d); the innovation form "
             "converged, its residuals are white and uncorrelated with the inputs and its modes agree with output error's within %.3g combined "
             "standard deviations: a force nobody measured", oe_bad + 1, apart);
}

const char *refine_choice_reason_name(refine_choice_reason reason)
{
    switch (reason) {
    case REFINE_CHOICE_WHITE: return "output_error_white";
    case REFINE_CHOICE_INNOVATION: return "innovation_white_and_agrees";
    case REFINE_CHOICE_OE_DIVERGED: return "output_error_diverged";
    case REFINE_CHOICE_NOT_CONVERGED: return "innovation_not_converged";
    case REFINE_CHOICE_STILL_NOT_WHITE: return "innovation_not_white";
    case REFINE_CHOICE_MODES_DIFFER: return "modes_differ";
    case REFINE_CHOICE_INPUT_CORRELATED: return "innovation_input_correlated";
    }
    return "unknown";
}

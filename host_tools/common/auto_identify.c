/* SPDX-License-Identifier: Apache-2.0 */
/* The automatic identification of okid identify and okid.identify (auto_identify.h). */
#include "auto_identify.h"

#include <stdlib.h>
#include <string.h>

#include "config_explain.h"

okid_status auto_horizon_seconds(okid_config *cfg, double observer_seconds, double hankel_seconds)
{
    if (!(observer_seconds > 0 || hankel_seconds > 0)) {
        return OKID_OK;
    }
    const double step = (double)cfg->dt * (cfg->decimation > 1 ? cfg->decimation : 1);
    return okid_config_horizons(cfg, (okid_real)(observer_seconds > 0 ? observer_seconds : cfg->observer_order * step),
                                (okid_real)(hankel_seconds > 0 ? hankel_seconds : cfg->hankel_rows * step),
                                (okid_real)(hankel_seconds > 0 ? hankel_seconds : cfg->hankel_cols * step));
}

static okid_status push_and_identify(const auto_request *rq, auto_identification *out)
{
    const okid_config *cfg = &out->cfg;
    okid_status st = okid_init(&out->id, cfg, out->workspace, out->workspace_bytes, NULL);
    if (st == OKID_OK) {
        st = rq->push != NULL ? rq->push(rq->push_context, &out->id, rq->n, rq->u, rq->y)
                              : okid_push_block(&out->id, rq->n, rq->u, (size_t)cfg->num_inputs, rq->y,
                                                (size_t)cfg->num_outputs, NULL);
    }
    return st == OKID_OK ? okid_identify(&out->id, &out->result) : st;
}

static okid_status fail(auto_identification *out, auto_failure failure, okid_status st)
{
    out->failure = failure;
    return st;
}

okid_status auto_identify(const auto_request *rq, auto_identification *out)
{
    memset(out, 0, sizeof *out);
    okid_config *cfg = &out->cfg;
    *cfg = rq->cfg;
    const size_t n = rq->n;
    /* too short or flat to choose from, or a flat input (its rank check must see it undecimated):
       the library's defaults, and their refusals */
    auto_band band, input_band;
    if (auto_channel_band(rq->y, n, cfg->num_outputs, (double)cfg->dt, &band) != 0 ||
        auto_channel_band(rq->u, n, cfg->num_inputs, (double)cfg->dt, &input_band) != 0) {
        band = (auto_band){0, 0, 0};
    }
    auto_choice *choice = &out->choice;
    auto_choose(cfg, rq->given, n, &band, choice);                           /* the decimation first: */
    okid_status st = auto_horizon_seconds(cfg, rq->observer_seconds, rq->hankel_seconds);                               /* spans in seconds count K dt, */
    if (st != OKID_OK) return fail(out, AUTO_FAILED_HORIZONS, st);
    auto_choose(cfg, rq->given | AUTO_GIVEN_DECIMATION, n, &band, choice);   /* then the rest */
    choice->given = rq->given;
    size_t bytes = 0;
    if ((st = okid_workspace_size(cfg, &bytes)) != OKID_OK) return fail(out, AUTO_FAILED_SETTINGS, st);
    /* the data's sufficiency before any workspace */
    if (config_data_shortfall(cfg, n, out->shortfall, sizeof out->shortfall)) {
        return fail(out, AUTO_FAILED_DATA, OKID_E_NOT_ENOUGH_DATA);
    }
    int fallback = 0;
    if (cfg->order == 0) {
        if ((out->modes = calloc(1, sizeof *out->modes)) == NULL) return fail(out, AUTO_FAILED_MEMORY, OKID_E_WORKSPACE_TOO_SMALL);
        st = auto_modes_find(choice, cfg, n, rq->u, rq->y, out->modes);
        if (st == OKID_E_DECOMPOSITION_FAILED && cfg->estimator == OKID_ESTIMATOR_CORRELATION) {
            auto_modes_free(out->modes);
            cfg->estimator = OKID_ESTIMATOR_LEAST_SQUARES;
            fallback = 1;
            st = auto_modes_find(choice, cfg, n, rq->u, rq->y, out->modes);
        }
        if (st != OKID_OK) return fail(out, AUTO_FAILED_MODES, st);
        /* the model: the order whose poles hold the physical modes, else the library's own choice */
        const auto_modes *am = out->modes;
        cfg->order = am->num_modes > 0 ? am->order : am->observers[0].runs[0].result.order;
        /* and the observer order whose model holds them */
        if (am->num_modes > 0) cfg->observer_order = choice->observer_order = choice->observer_orders[am->observer];
    }
    if ((st = okid_workspace_size(cfg, &out->workspace_bytes)) != OKID_OK) return fail(out, AUTO_FAILED_SETTINGS, st);
    out->workspace = aligned_alloc(OKID_WORKSPACE_ALIGN, (out->workspace_bytes + 15) / 16 * 16);
    if (out->workspace == NULL) return fail(out, AUTO_FAILED_MEMORY, OKID_E_WORKSPACE_TOO_SMALL);
    st = push_and_identify(rq, out);
    if (st == OKID_E_DECOMPOSITION_FAILED && cfg->estimator == OKID_ESTIMATOR_CORRELATION) {
        cfg->estimator = OKID_ESTIMATOR_LEAST_SQUARES; /* the same workspace size: the QR fold needs no more */
        fallback = 1;
        st = push_and_identify(rq, out);
    }
    if (st != OKID_OK) return fail(out, AUTO_FAILED_MODEL, st);
    if (fallback) out->result.warnings |= OKID_W_CORRELATION_FALLBACK;
    /* the order chosen and no physical mode: the flag the identifier FMU sets, for every caller */
    if (out->modes != NULL && out->modes->num_modes == 0) out->result.warnings |= OKID_W_NO_PHYSICAL_MODE;
    return OKID_OK;
}

okid_identifier *auto_failed_identifier(auto_identification *out)
{
    return out->failure == AUTO_FAILED_MODES ? &out->modes->observers[0].runs[0].id
           : out->failure == AUTO_FAILED_MODEL ? &out->id
                                               : NULL;
}

void auto_identification_free(auto_identification *out)
{
    if (out->modes != NULL) {
        auto_modes_free(out->modes);
        free(out->modes);
    }
    free(out->workspace);
    out->modes = NULL;
    out->workspace = NULL;
}

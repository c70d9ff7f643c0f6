/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Stabilization diagram by nested truncation (okid/stabilization.h): one ERA at the largest order
 * into the caller's workspace, then the modal analysis and indicators of every leading block.
 * The ERA runs through okid_era_realize() on the last result's Markov parameters and scales, with
 * its outputs in the stabilization workspace: the same Hankel, scaling and realization as
 * okid_identify(), without touching the identifier's last result.
 */
#include "okid/stabilization.h"

#include "identifier/workspace_layout.h"
#include "numerics/carve.h"
#include "numerics/real_math.h"
#include "pipeline/era.h"
#include "analysis/stabilization_internal.h"

okid_status okid_stabilization_criteria_default(okid_stabilization_criteria *criteria)
{
    if (criteria == NULL) {
        return OKID_E_NULL_POINTER;
    }
    criteria->frequency_tolerance = OKID_R(0.01);
    criteria->damping_tolerance = OKID_R(0.05);
    criteria->mac_min = OKID_R(0.98);
    return OKID_OK;
}

/* Views of the stabilization workspace (one layout for the size and the carving). */
typedef struct stab_views {
    okid_real *sv, *era_t, *a, *b, *c, *d, *g, *obs_last, *ctrl_last;
    okid_modal_scratch modal;
    okid_indicator_scratch ind;
    okid_stabilization_order *orders;
    okid_mode *modes;
    okid_complex *shapes;
    unsigned *stability;
} stab_views;

/* The bytes in 64 bits (carve.h); with a base only after okid_stabilization_workspace_size() accepted them. */
static uint64_t stab_carve(const okid_identifier *id, int max_order, int step, unsigned char *base, stab_views *v)
{
    const okid_dims_ *d = &id->dims_;
    const uint64_t r = (uint64_t)d->r, m = (uint64_t)d->m, n = (uint64_t)max_order;
    const uint64_t orders = OKID__STAB_ORDERS(max_order, step), modes = OKID__STAB_MODES(max_order, step);
    okid_carver c = {base, 0};
    v->sv = okid_carve_reals(&c, (uint64_t)d->svd_size);
    v->era_t = okid_carve_reals(&c, (uint64_t)d->hankel_rows * n);
    v->a = okid_carve_reals(&c, n * n);
    v->b = okid_carve_reals(&c, n * r);
    v->ctrl_last = okid_carve_reals(&c, n * r);
    v->c = okid_carve_reals(&c, m * n);
    v->obs_last = okid_carve_reals(&c, m * n);
    v->d = okid_carve_reals(&c, m * r);
    v->g = (d->ncols > d->r) ? okid_carve_reals(&c, n * m) : NULL;
    okid_carve_modal_phase(&c, n, r, &v->modal, &v->ind);
    v->orders = (okid_stabilization_order *)okid_carve_bytes(&c, sizeof(okid_stabilization_order) * orders);
    v->modes = (okid_mode *)okid_carve_bytes(&c, sizeof(okid_mode) * modes);
    v->shapes = (okid_complex *)okid_carve_bytes(&c, sizeof(okid_complex) * 3u * m * modes);
    v->stability = (unsigned *)okid_carve_bytes(&c, sizeof(unsigned) * modes);
    return c.used;
}

okid_status okid_stabilization_workspace_size(const okid_identifier *id, int max_order, int step, size_t *bytes)
{
    okid_progress progress;
    if (id == NULL || bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    const okid_status st = okid_get_progress(id, &progress); /* rejects an uninitialised identifier */
    if (st != OKID_OK) {
        return st;
    }
    if (max_order < 1 || max_order > id->dims_.svd_size || max_order > OKID_MAX_ORDER) {
        return OKID_E_BAD_ORDER;
    }
    if (step < 1 || step > max_order) {
        return OKID_E_BAD_SIZE;
    }
    stab_views dry;
    return okid_carve_size(stab_carve(id, max_order, step, NULL, &dry), bytes);
}

static int criteria_valid(const okid_stabilization_criteria *c)
{
    return okid_is_finite(c->frequency_tolerance) && c->frequency_tolerance > 0 &&
           okid_is_finite(c->damping_tolerance) && c->damping_tolerance > 0 && okid_is_finite(c->mac_min) &&
           c->mac_min >= 0 && c->mac_min <= 1;
}

int okid_stab_hankel_rank_(const okid_real *sv, int k)
{
    int rank = 0;
    while (rank < k && sv[0] > 0 && sv[rank] > OKID_EPSILON * (okid_real)k * sv[0]) {
        ++rank;
    }
    return rank;
}

/* Flags of mode md against the modes of the previous order. */
static unsigned stability_flags(const okid_mode *md, const okid_mode *prev, int num_prev, int m,
                                const okid_stabilization_criteria *crit)
{
    const okid_mode *near = NULL;
    okid_real best = 0;
    for (int i = 0; i < num_prev; ++i) {
        const okid_real gap = okid_fabs(prev[i].frequency_hz - md->frequency_hz);
        if (near == NULL || gap < best) {
            near = &prev[i];
            best = gap;
        }
    }
    if (near == NULL) {
        return 0;
    }
    unsigned flags = 0;
    if (best <= crit->frequency_tolerance * near->frequency_hz) {
        flags |= OKID_STABLE_FREQUENCY;
    }
    if (okid_fabs(md->damping_ratio - near->damping_ratio) <= crit->damping_tolerance * okid_fabs(near->damping_ratio)) {
        flags |= OKID_STABLE_DAMPING;
    }
    if (okid_mac(md->sensor_shape, near->sensor_shape, m) >= crit->mac_min) {
        flags |= OKID_STABLE_SHAPE;
    }
    return flags;
}

okid_status okid_stab_fill_orders_(const okid_stab_realization_ *rz, int step, const okid_stabilization_criteria *crit,
                                   const okid_stab_table_views_ *v, int *count_out)
{
    const int m = rz->m, top = rz->top;
    int count = 0, first = 0;
    for (int n = step; n <= top; n += step) {
        int num_modes = 0;
        unsigned warnings = 0;
        okid_status st = okid_modal_compute(n, m, rz->a, top, rz->c, m, rz->dt, rz->sensing, v->modal,
                                            v->shapes + (size_t)first * 3u * (size_t)m, v->modes + first, &num_modes,
                                            &warnings);
        if (st != OKID_OK) {
            return st;
        }
        const okid_indicator_inputs in = {n, m, rz->r, rz->alpha, rz->beta, rz->b, top, rz->c, m,
                                          rz->obs_last, m, rz->ctrl_last, top};
        st = okid_modal_indicators(&in, v->modal->vr, v->modal->wr, v->modal->wi, v->ind, v->modes + first, num_modes);
        if (st != OKID_OK) {
            return st;
        }
        const okid_stabilization_order *prev = count > 0 ? &v->orders[count - 1] : NULL;
        for (int i = 0; i < num_modes; ++i) {
            v->stability[first + i] = prev ? stability_flags(&v->modes[first + i], v->modes + prev->first,
                                                             prev->num_modes, m, crit)
                                           : 0u;
        }
        v->orders[count].order = n;
        v->orders[count].first = first;
        v->orders[count].num_modes = num_modes;
        first += num_modes;
        ++count;
    }
    *count_out = count;
    return OKID_OK;
}

okid_status okid_stab_check_(const okid_stabilization_criteria *criteria, const void *workspace, size_t bytes,
                             size_t needed, okid_stabilization_criteria *crit)
{
    (void)okid_stabilization_criteria_default(crit);
    if (criteria != NULL) {
        if (!criteria_valid(criteria)) {
            return OKID_E_BAD_PARAMETER;
        }
        *crit = *criteria;
    }
    if (((size_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    return bytes < needed ? OKID_E_WORKSPACE_TOO_SMALL : OKID_OK;
}

/* ERA at order top on the last result's Markov parameters, into the stabilization views. */
static okid_status realize_largest(const okid_identifier *id, int top, const stab_views *v)
{
    okid_era_problem problem;
    okid_era_scratch scratch;
    okid_layout_era(id, &id->at_.result[id->result_], id->at_.r, &problem, &scratch);
    problem.order = top;
    scratch.t = v->era_t;
    const okid_era_output out = {v->sv, v->a, v->b, v->c, v->d, v->g};
    int order = 0;
    unsigned warnings = 0;
    const okid_status st = okid_era_realize(&problem, &scratch, &out, &order, &warnings);
    if (st == OKID_OK) {
        okid_indicators_capture(&problem, &scratch, v->sv, top, v->obs_last, v->ctrl_last);
    }
    return st;
}

okid_status okid_stabilization_compute(okid_identifier *id, int max_order, int step,
                                       const okid_stabilization_criteria *criteria, void *workspace, size_t bytes,
                                       okid_stabilization *out)
{
    size_t needed = 0;
    okid_status st = okid_stabilization_workspace_size(id, max_order, step, &needed);
    if (st != OKID_OK) {
        return st;
    }
    if (workspace == NULL || out == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!id->has_model_) {
        return OKID_E_NOT_AVAILABLE;
    }
    okid_stabilization_criteria crit;
    st = okid_stab_check_(criteria, workspace, bytes, needed, &crit);
    if (st != OKID_OK) {
        return st;
    }
    stab_views v;
    (void)stab_carve(id, max_order, step, (unsigned char *)workspace, &v);
    const int rank_limit = okid_stab_hankel_rank_(id->at_.result[id->result_].sv, id->dims_.svd_size); /* the SVD of the last identification */
    const int limit = rank_limit < max_order ? rank_limit : max_order;
    const int top = limit / step * step;
    if (top > 0) {
        st = realize_largest(id, top, &v);
        if (st != OKID_OK) {
            return st;
        }
    }
    const okid_stab_realization_ rz = {top, id->dims_.m, id->dims_.r, id->cfg_.hankel_rows, id->cfg_.hankel_cols,
                                       id->cfg_.dt, id->cfg_.sensing, v.a, v.b, v.c, v.obs_last, v.ctrl_last};
    const okid_stab_table_views_ tv = {&v.modal, &v.ind, v.orders, v.modes, v.shapes, v.stability};
    int count = 0;
    st = okid_stab_fill_orders_(&rz, step, &crit, &tv, &count);
    if (st != OKID_OK) {
        return st;
    }
    out->num_orders = count;
    out->rank_limit = rank_limit;
    /* the observer's Markov parameters obey an order-p recursion beyond lag p, so the Hankel matrix of
       a noisy record has rank m p at most (when smaller than its size): only a rank below that is noise-free */
    out->noise_free = rank_limit < id->dims_.svd_size && rank_limit < id->dims_.m * id->dims_.p;
    out->orders = v.orders;
    out->modes = v.modes;
    out->stability = v.stability;
    return OKID_OK;
}

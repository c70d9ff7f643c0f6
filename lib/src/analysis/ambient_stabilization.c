/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The stabilization diagram of an output-only identifier (okid/ambient.h): the correlations of
 * everything pushed, one ERA of their block Hankel (of the identifier's L block rows, or of fewer:
 * R(0 .. 2L') are among the sums) at the largest order into the caller's workspace (the
 * identifier's ERA scratch for H and the SVD work, V' of the table's orders in the caller's
 * workspace), then the orders by nested truncation exactly as okid_stabilization_compute() makes
 * them (analysis/stabilization_internal.h).
 */
#include "okid/ambient.h"

#include "analysis/ambient_internal.h"
#include "analysis/stabilization_internal.h"
#include "numerics/carve.h"
#include "numerics/real_math.h"
#include "pipeline/output_correlation.h"

/* The views, in the order of OKID__AMBIENT_STABILIZATION_BYTES64 (sizes.h); NULL base: sizes only. */
typedef struct amb_stab_views {
    okid_real *correlations, *scales, *sv, *era_t, *era_vt, *a, *g, *ctrl_last, *c, *obs_last, *d;
    int ldvt;
    okid_modal_scratch modal;
    okid_indicator_scratch ind;
    okid_stabilization_order *orders;
    okid_mode *modes;
    okid_complex *shapes;
    unsigned *stability;
} amb_stab_views;

/* The Hankel rank limit at L block rows: L min(m, r_ref). */
static int rank_bound(const okid_ambient *amb, int L)
{
    return L * (amb->sums_.m < amb->nref_ ? amb->sums_.m : amb->nref_);
}

static uint64_t amb_stab_carve(const okid_ambient *amb, int hankel_rows, int max_order, int step, unsigned char *base,
                               amb_stab_views *v)
{
    const uint64_t m = (uint64_t)amb->sums_.m, nref = (uint64_t)amb->nref_, L = (uint64_t)hankel_rows;
    const uint64_t n = (uint64_t)max_order;
    const uint64_t orders = OKID__STAB_ORDERS(max_order, step), modes = OKID__STAB_MODES(max_order, step);
    okid_carver c = {base, 0};
    v->correlations = okid_carve_reals(&c, m * nref * (2u * L + 1u));
    v->scales = okid_carve_reals(&c, nref + m);
    v->sv = okid_carve_reals(&c, (uint64_t)rank_bound(amb, hankel_rows));
    v->era_t = okid_carve_reals(&c, L * m * n);
    const uint64_t vt_rows = OKID__SVD_VT_ROWS(L * m, L * nref, n);
    v->era_vt = okid_carve_reals(&c, vt_rows * L * nref);
    v->ldvt = (int)vt_rows;
    v->a = okid_carve_reals(&c, n * n);
    v->g = okid_carve_reals(&c, n * nref);
    v->ctrl_last = okid_carve_reals(&c, n * nref);
    v->c = okid_carve_reals(&c, m * n);
    v->obs_last = okid_carve_reals(&c, m * n);
    v->d = okid_carve_reals(&c, m * nref);
    okid_carve_modal_phase(&c, n, nref, &v->modal, &v->ind);
    v->orders = (okid_stabilization_order *)okid_carve_bytes(&c, sizeof(okid_stabilization_order) * orders);
    v->modes = (okid_mode *)okid_carve_bytes(&c, sizeof(okid_mode) * modes);
    v->shapes = (okid_complex *)okid_carve_bytes(&c, sizeof(okid_complex) * 3u * m * modes);
    v->stability = (unsigned *)okid_carve_bytes(&c, sizeof(unsigned) * modes);
    return c.used;
}

okid_status okid_ambient_stabilization_workspace_size_at(const okid_ambient *amb, int hankel_rows, int max_order,
                                                         int step, size_t *bytes)
{
    if (amb == NULL || bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (amb->magic_ != OKID_AMBIENT_MAGIC_) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (hankel_rows < 1 || hankel_rows > amb->cfg_.hankel_rows) {
        return OKID_E_BAD_SIZE;
    }
    if (max_order < 1 || max_order > rank_bound(amb, hankel_rows) || max_order > OKID_MAX_ORDER) {
        return OKID_E_BAD_ORDER;
    }
    if (step < 1 || step > max_order) {
        return OKID_E_BAD_SIZE;
    }
    amb_stab_views dry;
    return okid_carve_size(amb_stab_carve(amb, hankel_rows, max_order, step, NULL, &dry), bytes);
}

okid_status okid_ambient_stabilization_workspace_size(const okid_ambient *amb, int max_order, int step,
                                                      size_t *bytes)
{
    return okid_ambient_stabilization_workspace_size_at(amb, amb != NULL && amb->magic_ == OKID_AMBIENT_MAGIC_ ? amb->cfg_.hankel_rows : 1, max_order, step,
                                                        bytes);
}

/* ERA at order top into the views; the problem and scratch for the indicators' capture. */
static okid_status realize_at(const okid_ambient *amb, int L, int top, const amb_stab_views *v,
                              okid_era_problem *problem, okid_era_scratch *era)
{
    const int m = amb->sums_.m, nref = amb->nref_;
    *problem = (okid_era_problem){nref, m, nref, L, L, top, top, v->correlations, NULL, v->scales};
    okid_ambient_era_scratch_(amb, era);
    era->ldh = L * m; /* H laid out as an identifier of L block rows lays it out (its region holds more) */
    era->t = v->era_t;
    era->vt = v->era_vt;
    era->ldvt = v->ldvt;
    const okid_era_output out = {v->sv, v->a, v->g, v->c, v->d, NULL};
    int order = 0;
    unsigned warnings = 0;
    return okid_era_realize(problem, era, &out, &order, &warnings);
}

okid_status okid_ambient_stabilization_compute(okid_ambient *amb, int max_order, int step,
                                               const okid_stabilization_criteria *criteria, void *workspace,
                                               size_t bytes, okid_stabilization *out)
{
    return okid_ambient_stabilization_compute_at(amb, amb != NULL && amb->magic_ == OKID_AMBIENT_MAGIC_ ? amb->cfg_.hankel_rows : 1, max_order, step,
                                                 criteria, workspace, bytes, out);
}

okid_status okid_ambient_stabilization_compute_at(okid_ambient *amb, int hankel_rows, int max_order, int step,
                                                  const okid_stabilization_criteria *criteria, void *workspace,
                                                  size_t bytes, okid_stabilization *out)
{
    size_t needed = 0;
    okid_status st = okid_ambient_stabilization_workspace_size_at(amb, hankel_rows, max_order, step, &needed);
    if (st != OKID_OK) {
        return st;
    }
    if (workspace == NULL || out == NULL) {
        return OKID_E_NULL_POINTER;
    }
    okid_stabilization_criteria crit;
    st = okid_stab_check_(criteria, workspace, bytes, needed, &crit);
    if (st != OKID_OK) {
        return st;
    }
    const okid_correlation_sums_ *sums = &amb->sums_;
    const int L = hankel_rows, k = rank_bound(amb, L);
    if (okid_corr_pairs(sums, -1, 2 * L) == 0) {
        return OKID_E_NOT_ENOUGH_DATA;
    }
    amb_stab_views v;
    (void)amb_stab_carve(amb, L, max_order, step, (unsigned char *)workspace, &v);
    okid_corr_estimate(sums, -1, 2 * L, v.correlations);
    st = okid_ambient_scales_(amb, v.scales);
    if (st != OKID_OK) {
        return st;
    }
    okid_era_problem problem;
    okid_era_scratch era;
    int top = max_order / step * step;
    st = realize_at(amb, L, top, &v, &problem, &era);
    /* the SVD ran before any rank refusal: the singular values are there for both */
    const int rank_limit = st == OKID_OK || st == OKID_E_RANK_DEFICIENT ? okid_stab_hankel_rank_(v.sv, k) : 0;
    if (st == OKID_E_RANK_DEFICIENT) {
        top = (rank_limit < max_order ? rank_limit : max_order) / step * step;
        st = top > 0 ? realize_at(amb, L, top, &v, &problem, &era) : OKID_E_RANK_DEFICIENT;
    }
    if (st != OKID_OK) {
        return st;
    }
    okid_indicators_capture(&problem, &era, v.sv, top, v.obs_last, v.ctrl_last);
    const okid_stab_realization_ rz = {top, sums->m, amb->nref_, L, L,
                                       amb->cfg_.dt, amb->cfg_.sensing, v.a, v.g, v.c, v.obs_last, v.ctrl_last};
    const okid_stab_table_views_ tv = {&v.modal, &v.ind, v.orders, v.modes, v.shapes, v.stability};
    int count = 0;
    st = okid_stab_fill_orders_(&rz, step, &crit, &tv, &count);
    if (st != OKID_OK) {
        return st;
    }
    for (int i = 0; i < v.orders[count - 1].first + v.orders[count - 1].num_modes; ++i) {
        if (!okid_is_finite(v.modes[i].frequency_hz) || !okid_is_finite(v.modes[i].damping_ratio)) {
            return OKID_E_DATA_RANGE;
        }
    }
    out->num_orders = count;
    out->rank_limit = rank_limit;
    out->noise_free = rank_limit < k;
    out->orders = v.orders;
    out->modes = v.modes;
    out->stability = v.stability;
    return OKID_OK;
}

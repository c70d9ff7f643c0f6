/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Configuration checks and workspace layout. Regions, in order: the persistent accumulation
 * (sample ring, pending regressor rows, triangular factor R), the results of the last
 * identification, then one scratch area that the push and identify phases take turns to use.
 * R's strict lower triangle is scratch too: identify's large matrices live there (the solves'
 * equilibrated copy, and ERA's Hankel matrix and V' when they fit), only the upper triangle persists.
 */
#include "identifier/workspace_layout.h"

#include <limits.h>

#include "numerics/carve.h"
#include "numerics/real_math.h"
#include "numerics/triangular_lstsq.h"
#include "pipeline/decimator.h"

#define MIN(a, b) ((a) < (b) ? (a) : (b))
#define MAX(a, b) ((a) > (b) ? (a) : (b))

/* Every matrix handed to LAPACK must be indexable with a 32-bit int. */
static int fits_int(long long rows, long long cols)
{
    return rows * cols < (long long)INT_MAX;
}

/* Refuse with status st and, when asked, which field, its value and its valid range. */
static okid_status refuse(okid_config_issue *issue, okid_status st, const char *field, double value, double min,
                          double max)
{
    if (issue != NULL) {
        issue->field = field;
        issue->value = value;
        issue->min = min;
        issue->max = max;
    }
    return st;
}

/* The first of the integer fields outside lo..hi, or OKID_OK. */
static okid_status check_int(okid_config_issue *issue, okid_status st, const char *field, int value, int lo, int hi)
{
    return (value < lo || value > hi) ? refuse(issue, st, field, value, lo, hi) : OKID_OK;
}

/* The fields checked on their own, in the order (and with the statuses) of okid_layout_dims. */
static okid_status check_fields(const okid_config *cfg, okid_config_issue *issue)
{
    const struct {
        const char *field;
        int value, lo, hi;
        okid_status st;
    } ints[] = {
        {"num_inputs", cfg->num_inputs, 1, OKID_MAX_DIMENSION, OKID_E_BAD_SIZE},
        {"num_outputs", cfg->num_outputs, 1, OKID_MAX_DIMENSION, OKID_E_BAD_SIZE},
        {"observer_order", cfg->observer_order, 1, OKID_MAX_HORIZON, OKID_E_BAD_SIZE},
        {"hankel_rows", cfg->hankel_rows, 1, OKID_MAX_HORIZON, OKID_E_BAD_SIZE},
        {"hankel_cols", cfg->hankel_cols, 1, OKID_MAX_HORIZON, OKID_E_BAD_SIZE},
        {"block_rows", cfg->block_rows, 0, 4096, OKID_E_BAD_SIZE},
        /* after dt, the forgetting factor and the tolerance: */
        {"sensing", (int)cfg->sensing, 0, 2, OKID_E_BAD_PARAMETER},
        {"realization", (int)cfg->realization, 0, 1, OKID_E_BAD_PARAMETER},
        {"zero_initial_state", cfg->zero_initial_state, 0, 1, OKID_E_BAD_PARAMETER},
        {"scaling", (int)cfg->scaling, 0, 1, OKID_E_BAD_PARAMETER},
        {"estimator", (int)cfg->estimator, 0, 2, OKID_E_BAD_PARAMETER},
        {"decimation", cfg->decimation, 0, OKID_MAX_DECIMATION, OKID_E_BAD_SIZE},
        {"instrument_lags", cfg->instrument_lags, 0, OKID_MAX_INSTRUMENT_LAGS, OKID_E_BAD_SIZE},
    };
    const size_t sizes = 6, count = sizeof ints / sizeof ints[0];
    for (size_t i = 0; i < sizes; ++i) {
        const okid_status st = check_int(issue, ints[i].st, ints[i].field, ints[i].value, ints[i].lo, ints[i].hi);
        if (st != OKID_OK) {
            return st;
        }
    }
    /* dt and K dt within the magnitudes whose poles ln(lambda) / (K dt) and their powers stay finite */
    const int k = cfg->decimation > 1 && cfg->decimation <= OKID_MAX_DECIMATION ? cfg->decimation : 1;
    if (!okid_in_magnitude_range(cfg->dt) || !okid_in_magnitude_range(cfg->dt * (okid_real)k)) {
        return refuse(issue, OKID_E_BAD_PARAMETER, "dt", (double)cfg->dt, (double)OKID_MAGNITUDE_MIN,
                      (double)OKID_MAGNITUDE_MAX / k);
    }
    if (!okid_is_finite(cfg->forgetting_factor) || cfg->forgetting_factor < 0 || cfg->forgetting_factor > 1) {
        return refuse(issue, OKID_E_BAD_PARAMETER, "forgetting_factor", (double)cfg->forgetting_factor, 0, 1);
    }
    /* 0 (the default), or from round-off up to below 1: a tolerance under epsilon means no rank test */
    if (!okid_is_finite(cfg->rank_tolerance) || cfg->rank_tolerance < 0 || cfg->rank_tolerance >= 1 ||
        (cfg->rank_tolerance > 0 && cfg->rank_tolerance < OKID_EPSILON)) {
        return refuse(issue, OKID_E_BAD_PARAMETER, "rank_tolerance", (double)cfg->rank_tolerance, (double)OKID_EPSILON,
                      1);
    }
    for (size_t i = sizes; i < count; ++i) {
        const okid_status st = check_int(issue, ints[i].st, ints[i].field, ints[i].value, ints[i].lo, ints[i].hi);
        if (st != OKID_OK) {
            return st;
        }
    }
    return OKID_OK;
}

okid_status okid_layout_dims(const okid_config *cfg, okid_dims_ *dims, okid_config_issue *issue)
{
    if (cfg == NULL || dims == NULL) {
        return OKID_E_NULL_POINTER;
    }
    okid_status st = check_fields(cfg, issue);
    if (st != OKID_OK) {
        return st;
    }
    const int r = cfg->num_inputs, m = cfg->num_outputs, p = cfg->observer_order;
    const int combined = cfg->realization == OKID_REALIZATION_COMBINED;
    dims->r = r;
    dims->m = m;
    dims->p = p;
    dims->q = r + (r + m) * p;
    dims->w = dims->q + m;
    dims->ncols = combined ? r + m : r;
    dims->hankel_rows = cfg->hankel_rows * m;
    dims->hankel_cols = cfg->hankel_cols * dims->ncols;
    dims->svd_size = MIN(dims->hankel_rows, dims->hankel_cols);
    dims->markov_count = cfg->hankel_rows + cfg->hankel_cols; /* Y_0 .. Y_(alpha+beta) */
    /* OKID__ERA_IN_R: the Hankel matrix and V' in R's unused triangle, or in the scratch */
    dims->era_in_r =
        dims->hankel_rows + dims->hankel_cols <= dims->w && 2 * dims->hankel_cols + dims->svd_size <= dims->w;
    dims->era_ldh = dims->era_in_r ? dims->w + 1 : dims->hankel_rows;
    dims->era_ldvt = dims->era_in_r ? dims->w + 1 : dims->svd_size;
    /* 0: from w and the cache (OKID__AUTO_BLOCK_ROWS says how; the macros use the same rule) */
    dims->block_rows = cfg->block_rows > 0 ? cfg->block_rows : (int)OKID__AUTO_BLOCK_ROWS(dims->w);
    /* Inner block of the blocked QR update (xTPQRT's NB): a narrow panel keeps the level-2 part
       small and hands the rest to level-3 BLAS; 8 up to w = 128, 16 above, was fastest with both
       the reference BLAS and OpenBLAS (2.2x at r = 1, m = 2, p = 20; docs/benchmarks.md). With
       block_rows 0 and w > 128 (LAPACK backend) the recursive panel's 64: OKID__TILE's rule. */
#if OKID_LINALG_EIGEN
    const int wide_tile = 16;
#else
    const int wide_tile = cfg->block_rows == 0 ? OKID__FOLD_PANEL_TILE : 16;
#endif
    dims->block_tile = MIN(MIN(dims->block_rows, dims->w), dims->w <= 128 ? 8 : wide_tile);
    dims->decimation = cfg->decimation > 1 ? cfg->decimation : 1;
    dims->instrument_lags = 0;
    dims->nz = 0;
    dims->correlation = cfg->estimator == OKID_ESTIMATOR_CORRELATION;
    if (cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL) {
        /* the same rule as OKID__IV_LAGS; at least q instruments, and at least the p lags of the window */
        const long long lags = cfg->instrument_lags > 0 ? cfg->instrument_lags : (dims->q + r - 1) / r + 2LL * p;
        const long long fewest = MAX((long long)p, (dims->q + r - 1) / r - 1);
        const long long most = MIN((long long)OKID_MAX_INSTRUMENT_LAGS, ((long long)INT_MAX - 1) / dims->w / r - 1);
        if (lags < fewest || lags > most) {
            return refuse(issue, OKID_E_BAD_SIZE, "instrument_lags", (double)lags, (double)fewest, (double)most);
        }
        dims->instrument_lags = (int)lags;
        dims->nz = r * (dims->instrument_lags + 1);
    }
    /* the largest value of each field that keeps its matrix indexable with an int */
    if (!fits_int(dims->w, dims->w)) {
        return refuse(issue, OKID_E_BAD_SIZE, "observer_order", p, 1, (46340 - r - m) / (r + m)); /* w^2 < 2^31 */
    }
    if (!fits_int(dims->hankel_rows, dims->hankel_cols)) {
        return refuse(issue, OKID_E_BAD_SIZE, "hankel_cols", cfg->hankel_cols, 1,
                      (double)(((long long)INT_MAX - 1) / dims->hankel_rows / dims->ncols));
    }
    if (!fits_int(dims->block_rows, MAX(dims->w, dims->nz))) {
        return refuse(issue, OKID_E_BAD_SIZE, "block_rows", dims->block_rows, 0,
                      (double)(((long long)INT_MAX - 1) / MAX(dims->w, dims->nz)));
    }
    const int order_limit = MIN(MIN(dims->svd_size, m * p), OKID_MAX_ORDER); /* the Hankel size, m p, the maximum */
    if (cfg->order < 0 || cfg->order > order_limit) {
        return refuse(issue, OKID_E_BAD_ORDER, "order", cfg->order, 0, order_limit);
    }
#if OKID_LINALG_EIGEN
    /* the eigen-solver's fixed size (CMake OKID_EIGEN_MAX_ORDER): a given order above it is refused
       here, not left to fail at identify */
    if (cfg->order > OKID_EIGEN_MAX_ORDER) {
        return refuse(issue, OKID_E_BAD_ORDER, "order", cfg->order, 0, OKID_EIGEN_MAX_ORDER);
    }
#endif
    if (cfg->order > 0) {
        dims->max_order = cfg->order;
    } else {
        dims->max_order = MIN(dims->svd_size, m * p);
        if (dims->max_order > OKID_MAX_ORDER) {
            /* automatic order over a Hankel matrix this large: give the order */
            return refuse(issue, OKID_E_BAD_ORDER, "order", 0, 1, OKID_MAX_ORDER);
        }
    }
    return OKID_OK;
}

/* The persistent regions of the options (decimation, scaling, instrumental variables); NULL when off. */
static void carve_options(const okid_dims_ *d, int scaled, okid_carver *c, okid_views_ *v)
{
    const uint64_t channels = (uint64_t)d->r + (uint64_t)d->m, nz = (uint64_t)d->nz;
    v->dec_coef = v->dec_state = v->dec_out = v->scales = v->iv_ring = v->iv_block = v->iv_m = NULL;
    if (d->decimation > 1) {
        v->dec_coef = okid_carve_reals(c, OKID_DECIMATOR_COEFS);
        v->dec_state = okid_carve_reals(c, OKID_DECIMATOR_STATE * channels);
        v->dec_out = okid_carve_reals(c, channels);
    }
    if (scaled) {
        v->scales = okid_carve_reals(c, channels);
    }
    if (nz > 0) {
        v->iv_ring = okid_carve_reals(c, (uint64_t)d->r * (uint64_t)d->instrument_lags);
        v->iv_block = okid_carve_reals(c, (uint64_t)d->block_rows * nz);
        v->iv_m = okid_carve_reals(c, nz * (uint64_t)d->w);
    }
}

/* One identification's output (OKID__ONE_RESULT_BYTES, and the scales' copy of OKID__SCALE_BYTES). */
static void carve_result(const okid_dims_ *d, int combined, int scaled, okid_carver *c, okid_result_views_ *v)
{
    const uint64_t r = (uint64_t)d->r, m = (uint64_t)d->m, n = (uint64_t)d->max_order, L = (uint64_t)d->markov_count;
    v->x = okid_carve_reals(c, (uint64_t)d->q * m);
    v->markov = okid_carve_reals(c, m * r * (L + 1));
    v->markov_obs = combined ? okid_carve_reals(c, m * m * L) : NULL;
    v->sv = okid_carve_reals(c, (uint64_t)d->svd_size);
    v->a = okid_carve_reals(c, n * n);
    v->b = okid_carve_reals(c, n * r);
    v->c = okid_carve_reals(c, m * n);
    v->d = okid_carve_reals(c, m * r);
    v->g = combined ? okid_carve_reals(c, n * m) : NULL;
    v->obs_last = okid_carve_reals(c, m * n);
    v->ctrl_last = okid_carve_reals(c, n * r);
    v->scales = scaled ? okid_carve_reals(c, r + m) : NULL;
    v->modes = (okid_mode *)okid_carve_bytes(c, sizeof(okid_mode) * n);
    v->shapes = (okid_complex *)okid_carve_bytes(c, sizeof(okid_complex) * n * 3u * m);
}

uint64_t okid_layout_carve(const okid_dims_ *d, int combined, int scaled, unsigned char *base, okid_views_ *v)
{
    okid_views_ dry;
    if (v == NULL) {
        v = &dry;
    }
    /* 64-bit products: with a 32-bit size_t, w * w alone can wrap for accepted dimensions */
    const uint64_t r = (uint64_t)d->r, m = (uint64_t)d->m, p = (uint64_t)d->p, q = (uint64_t)d->q, w = (uint64_t)d->w;
    const uint64_t n = (uint64_t)d->max_order, k = (uint64_t)d->svd_size, hr = (uint64_t)d->hankel_rows,
                   hc = (uint64_t)d->hankel_cols, nc = (uint64_t)d->ncols;
    okid_carver c = {base, 0};

    v->ring = okid_carve_reals(&c, p * (r + m));
    v->block = okid_carve_reals(&c, (uint64_t)d->block_rows * w);
    v->r = okid_carve_reals(&c, w * w);
    carve_options(d, scaled, &c, v);

    for (int i = 0; i < 2; ++i) {
        carve_result(d, combined, scaled, &c, &v->result[i]);
    }

    /* identify's copy of R (OKID__IDENTIFY_FOLD_BYTES) and of the instrument rows (OKID__IV_BYTES) */
    v->factor = v->iv_pending = v->iv_chunk = NULL;
    if (d->block_rows > 1 || d->correlation) {
        v->factor = okid_carve_reals(&c, w * w);
        if (d->nz > 0) {
            v->iv_pending = okid_carve_reals(&c, (uint64_t)d->block_rows * (uint64_t)d->nz);
            v->iv_chunk = okid_carve_reals(&c, (uint64_t)d->block_rows * w);
        }
    }
    /* the correlation form's Toeplitz Gram: the open run (persistent) and identify's scratch run,
       OKID__TOEPLITZ_RUN_REALS each; they take fold_t's place (the QR fold is not used) */
    okid_real *gram_runs = NULL;
#if !OKID_LINALG_EIGEN
    if (d->correlation) {
        gram_runs = okid_carve_reals(&c, 2u * ((r + m + 2u) * w + 1u));
    }
#endif
    const uint64_t phases = c.used;
    uint64_t end = phases;

    /* the folds: push's, and identify's of the pending rows (a copy of them) into the factor */
    v->fold_t = okid_carve_reals(&c, (uint64_t)d->block_tile * w);
    v->fold_work = okid_carve_reals(&c, (uint64_t)d->block_tile * w);
    if (gram_runs != NULL) {
        v->fold_t = gram_runs;
    }
    v->pending = (d->block_rows > 1) ? okid_carve_reals(&c, (uint64_t)d->block_rows * w) : NULL;
    end = MAX(end, c.used);

    c.used = phases;
    v->lsq_scale = okid_carve_reals(&c, q);
    v->lsq_column = okid_carve_reals(&c, q);
    v->lsq_perm = (int *)okid_carve_bytes(&c, sizeof(int) * q);
    v->lsq_work = okid_carve_reals(&c, OKID__LWORK_TRIANGULAR_LSTSQ(q));
    end = MAX(end, c.used);

    c.used = phases;
    if (d->era_in_r) {
        /* in the strict lower triangle of the factor identify solves on (R or its copy): element
           (i, j) at F(j + 1 + i, j), below the diagonal as hr + hc <= w (the Hankel matrix from
           column 0, V' from column hc); needed only between the SVD and the capture of the
           indicators' blocks, before the next solve writes there (okid_era_scratch_in_factor()) */
        v->era_h = v->era_vt = NULL;
    } else {
        v->era_h = okid_carve_reals(&c, hr * hc);
        v->era_vt = okid_carve_reals(&c, k * hc);
    }
    v->era_t = okid_carve_reals(&c, hr * n);
    v->era_scale = okid_carve_reals(&c, nc);
    v->era_work = okid_carve_reals(&c, OKID__LWORK_GESVD(hr, hc));
    end = MAX(end, c.used);

    c.used = phases;
    v->modal_a = okid_carve_reals(&c, n * n);
    v->modal_vr = okid_carve_reals(&c, n * n);
    v->modal_wr = okid_carve_reals(&c, n);
    v->modal_wi = okid_carve_reals(&c, n);
    v->modal_work = okid_carve_reals(&c, OKID__LWORK_GEEV(n));
    v->ind_rhs = okid_carve_reals(&c, n * 2u * r);
    v->ind_work = okid_carve_reals(&c, OKID__LWORK_GELSY(n, 2u * r));
    v->ind_jpvt = (int *)okid_carve_bytes(&c, sizeof(int) * n);
    end = MAX(end, c.used);

    return end;
}

void okid_layout_era(const okid_identifier *id, const okid_result_views_ *res, okid_real *factor,
                     okid_era_problem *pb, okid_era_scratch *s)
{
    const okid_dims_ *d = &id->dims_;
    const okid_era_problem problem = {d->r, d->m, d->ncols, id->cfg_.hankel_rows, id->cfg_.hankel_cols,
                                      id->cfg_.order, d->m * d->p, res->markov, res->markov_obs, res->scales};
    *pb = problem;
    const size_t below = (size_t)d->w + 1u; /* R(j + 1 + i, j): columns stepping down the diagonal */
    s->h = d->era_in_r ? factor + 1 : id->at_.era_h;
    s->ldh = d->era_ldh;
    s->vt = d->era_in_r ? factor + 1 + (size_t)d->hankel_cols * below : id->at_.era_vt;
    s->ldvt = d->era_ldvt;
    s->t = id->at_.era_t;
    s->col_scale = id->at_.era_scale;
    s->work = id->at_.era_work;
    s->leading = 0;
}

okid_status okid_layout_size(const okid_dims_ *dims, int combined, int scaled, size_t *bytes)
{
    return okid_carve_size(okid_layout_carve(dims, combined, scaled, NULL, NULL), bytes);
}

/*
 * Configuration checks and workspace layout. Regions, in order: the persistent accumulation
 * (sample ring, pending regressor rows, triangular factor R), the results of the last
 * identification, then one scratch area that the push and identify phases take turns to use.
 * R's strict lower triangle is scratch too: identify's large matrices live there (the solves'
 * equilibrated copy, and ERA's Hankel matrix and V' when they fit), only the upper triangle persists.
 */
#include "workspace_layout.h"

#include <limits.h>

#include "carve.h"
#include "decimator.h"
#include "real_math.h"
#include "triangular_lstsq.h"

#define MIN(a, b) ((a) < (b) ? (a) : (b))
#define MAX(a, b) ((a) > (b) ? (a) : (b))

/* Every matrix handed to LAPACK must be indexable with a 32-bit int. */
static int fits_int(long long rows, long long cols)
{
    return rows * cols < (long long)INT_MAX;
}

okid_status okid_layout_dims(const okid_config *cfg, okid_dims_ *dims)
{
    if (cfg == NULL || dims == NULL) {
        return OKID_E_NULL_POINTER;
    }
    const int r = cfg->num_inputs, m = cfg->num_outputs, p = cfg->observer_order;
    if (r < 1 || r > OKID_MAX_DIMENSION || m < 1 || m > OKID_MAX_DIMENSION || p < 1 || p > OKID_MAX_HORIZON ||
        cfg->hankel_rows < 1 || cfg->hankel_rows > OKID_MAX_HORIZON || cfg->hankel_cols < 1 ||
        cfg->hankel_cols > OKID_MAX_HORIZON || cfg->block_rows < 0 || cfg->block_rows > 4096) {
        return OKID_E_BAD_SIZE;
    }
    if (!okid_is_finite(cfg->dt) || cfg->dt <= 0 || !okid_is_finite(cfg->forgetting_factor) ||
        cfg->forgetting_factor < 0 || cfg->forgetting_factor > 1 || !okid_is_finite(cfg->rank_tolerance) ||
        cfg->rank_tolerance < 0 || cfg->rank_tolerance >= 1 ||
        (cfg->rank_tolerance > 0 && cfg->rank_tolerance < OKID_EPSILON) || /* below round-off: no rank test */ (unsigned)cfg->sensing > 2u ||
        (unsigned)cfg->realization > 1u || (cfg->zero_initial_state != 0 && cfg->zero_initial_state != 1) ||
        (unsigned)cfg->scaling > 1u || (unsigned)cfg->estimator > 1u) {
        return OKID_E_BAD_PARAMETER;
    }
    if (cfg->decimation < 0 || cfg->decimation > OKID_MAX_DECIMATION || cfg->instrument_lags < 0 ||
        cfg->instrument_lags > OKID_MAX_INSTRUMENT_LAGS) {
        return OKID_E_BAD_SIZE;
    }
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
    dims->block_rows = cfg->block_rows > 0 ? cfg->block_rows : 32;
    /* Inner block of the blocked QR update (xTPQRT's NB): a narrow panel keeps the level-2 part
       small and hands the rest to level-3 BLAS; 8 up to w = 128, 16 above, was fastest with both
       the reference BLAS and OpenBLAS (2.2x at r = 1, m = 2, p = 20; docs/benchmarks.md). */
    dims->block_tile = MIN(MIN(dims->block_rows, dims->w), dims->w <= 128 ? 8 : 16);
    dims->decimation = cfg->decimation > 1 ? cfg->decimation : 1;
    dims->instrument_lags = 0;
    dims->nz = 0;
    if (cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL) {
        /* the same rule as OKID__IV_LAGS; at least q instruments, and at least the p lags of the window */
        const long long lags = cfg->instrument_lags > 0 ? cfg->instrument_lags : (dims->q + r - 1) / r + 2LL * p;
        if (lags > OKID_MAX_INSTRUMENT_LAGS || lags < p || (long long)r * (lags + 1) < dims->q ||
            !fits_int((long long)r * (lags + 1), dims->w)) {
            return OKID_E_BAD_SIZE;
        }
        dims->instrument_lags = (int)lags;
        dims->nz = r * (dims->instrument_lags + 1);
    }
    if (!fits_int(dims->w, dims->w) || !fits_int(dims->hankel_rows, dims->hankel_cols) ||
        !fits_int(dims->block_rows, dims->w) || !fits_int(dims->block_rows, dims->nz)) {
        return OKID_E_BAD_SIZE;
    }
    if (cfg->order < 0 || cfg->order > OKID_MAX_ORDER) {
        return OKID_E_BAD_ORDER;
    }
    if (cfg->order > 0) {
        if (cfg->order > dims->svd_size || cfg->order > m * p) {
            return OKID_E_BAD_ORDER;
        }
        dims->max_order = cfg->order;
    } else {
        dims->max_order = MIN(dims->svd_size, m * p);
        if (dims->max_order > OKID_MAX_ORDER) {
            return OKID_E_BAD_ORDER; /* automatic order over a Hankel matrix this large: give the order */
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

uint64_t okid_layout_carve(const okid_dims_ *d, int combined, int scaled, unsigned char *base, okid_views_ *v)
{
    okid_views_ dry;
    if (v == NULL) {
        v = &dry;
    }
    /* 64-bit products: with a 32-bit size_t, w * w alone can wrap for accepted dimensions */
    const uint64_t r = (uint64_t)d->r, m = (uint64_t)d->m, p = (uint64_t)d->p, q = (uint64_t)d->q, w = (uint64_t)d->w;
    const uint64_t n = (uint64_t)d->max_order, k = (uint64_t)d->svd_size, hr = (uint64_t)d->hankel_rows,
                   hc = (uint64_t)d->hankel_cols, L = (uint64_t)d->markov_count, nc = (uint64_t)d->ncols;
    okid_carver c = {base, 0};

    v->ring = okid_carve_reals(&c, p * (r + m));
    v->block = okid_carve_reals(&c, (uint64_t)d->block_rows * w);
    v->r = okid_carve_reals(&c, w * w);
    carve_options(d, scaled, &c, v);

    v->markov = okid_carve_reals(&c, m * r * (L + 1));
    v->markov_obs = combined ? okid_carve_reals(&c, m * m * L) : NULL;
    v->sv = okid_carve_reals(&c, k);
    v->a = okid_carve_reals(&c, n * n);
    v->b = okid_carve_reals(&c, n * r);
    v->c = okid_carve_reals(&c, m * n);
    v->d = okid_carve_reals(&c, m * r);
    v->g = combined ? okid_carve_reals(&c, n * m) : NULL;
    v->obs_last = okid_carve_reals(&c, m * n);
    v->ctrl_last = okid_carve_reals(&c, n * r);
    v->modes = (okid_mode *)okid_carve_bytes(&c, sizeof(okid_mode) * n);
    v->shapes = (okid_complex *)okid_carve_bytes(&c, sizeof(okid_complex) * n * 3u * m);

    v->x = okid_carve_reals(&c, q * m);
    const uint64_t scratch = c.used;
    uint64_t end = scratch;

    v->fold_t = okid_carve_reals(&c, (uint64_t)d->block_tile * w);
    v->fold_work = okid_carve_reals(&c, (uint64_t)d->block_tile * w);
    end = MAX(end, c.used);

    c.used = scratch;
    v->lsq_scale = okid_carve_reals(&c, q);
    v->lsq_column = okid_carve_reals(&c, q);
    v->lsq_perm = (int *)okid_carve_bytes(&c, sizeof(int) * q);
    v->lsq_work = okid_carve_reals(&c, OKID__LWORK_TRIANGULAR_LSTSQ(q));
    end = MAX(end, c.used);

    c.used = scratch;
    if (d->era_in_r) {
        /* in R's strict lower triangle: element (i, j) at R(j + 1 + i, j), below the diagonal as
           hr + hc <= w (the Hankel matrix from column 0, V' from column hc); identify needs them
           only between the SVD and okid_indicators_capture(), before the next solve writes there */
        v->era_h = (v->r != NULL) ? v->r + 1 : NULL;
        v->era_vt = (v->r != NULL) ? v->r + 1 + (size_t)(hc * (w + 1u)) : NULL;
    } else {
        v->era_h = okid_carve_reals(&c, hr * hc);
        v->era_vt = okid_carve_reals(&c, k * hc);
    }
    v->era_t = okid_carve_reals(&c, hr * n);
    v->era_scale = okid_carve_reals(&c, nc);
    v->era_work = okid_carve_reals(&c, OKID__LWORK_GESVD(hr, hc));
    end = MAX(end, c.used);

    c.used = scratch;
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

okid_status okid_layout_size(const okid_dims_ *dims, int combined, int scaled, size_t *bytes)
{
    return okid_carve_size(okid_layout_carve(dims, combined, scaled, NULL, NULL), bytes);
}

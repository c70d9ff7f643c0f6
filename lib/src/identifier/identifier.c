/* SPDX-License-Identifier: Apache-2.0 */
/* The public identifier API: argument checks, state, and okid_identify() as a sequence of the
   stages of docs/design.md's data flow, each called with its own inputs, scratch and outputs. */
#include "okid/identifier.h"

#include "identifier/data_range.h"
#include "identifier/workspace_layout.h"
#include "numerics/carve.h"
#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "pipeline/channel_scaling.h"
#include "pipeline/decimator.h"
#include "pipeline/era.h"
#include "pipeline/instrumental.h"
#include "pipeline/least_squares.h"
#include "pipeline/markov.h"
#include "pipeline/modal_internal.h"
#include "pipeline/sample_buffer.h"
#include "pipeline/toeplitz_gram.h"
#include "quality/diagnostics.h"
#include "quality/modal_indicators_internal.h"

#define OKID_MAGIC 0x4F4B4944u /* "OKID" */

#if OKID_REAL_IS_FLOAT
#define DEFAULT_RANK_TOLERANCE OKID_R(1e-5)
#else
#define DEFAULT_RANK_TOLERANCE OKID_R(1e-10)
#endif

static int is_initialized(const okid_identifier *id)
{
    return id->magic_ == OKID_MAGIC;
}

okid_status okid_config_default(okid_config *cfg, int num_inputs, int num_outputs)
{
    if (cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    cfg->num_inputs = num_inputs;
    cfg->num_outputs = num_outputs;
    cfg->observer_order = 20;
    cfg->order = 0;
    cfg->hankel_rows = 20;
    cfg->hankel_cols = 20;
    cfg->block_rows = 0;
    cfg->dt = 1;
    cfg->forgetting_factor = 1;
    cfg->rank_tolerance = 0;
    cfg->sensing = OKID_SENSING_ACCELERATION;
    cfg->realization = OKID_REALIZATION_SYSTEM;
    cfg->zero_initial_state = 0;
    cfg->decimation = 1;
    cfg->scaling = OKID_SCALING_NONE;
    cfg->estimator = OKID_ESTIMATOR_LEAST_SQUARES;
    cfg->instrument_lags = 0;
    return OKID_OK;
}

/* seconds / step rounded to the nearest count (halves up), at least 1; -1 when out of range. */
static int blocks_of(okid_real seconds, okid_real step)
{
    const okid_real count = seconds / step + OKID_R(0.5);
    if (!(count < (okid_real)OKID_MAX_HORIZON + 1)) {
        return -1;
    }
    return count < 1 ? 1 : (int)count;
}

okid_status okid_config_horizons(okid_config *cfg, okid_real observer_seconds, okid_real hankel_rows_seconds,
                                 okid_real hankel_cols_seconds)
{
    if (cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (cfg->decimation < 0 || cfg->decimation > OKID_MAX_DECIMATION) {
        return OKID_E_BAD_SIZE;
    }
    const okid_real step = cfg->dt * (okid_real)(cfg->decimation > 1 ? cfg->decimation : 1);
    const okid_real seconds[3] = {observer_seconds, hankel_rows_seconds, hankel_cols_seconds};
    int counts[3];
    for (int i = 0; i < 3; ++i) {
        if (!okid_is_finite(seconds[i]) || !(seconds[i] > 0) || !okid_in_magnitude_range(cfg->dt) ||
            !okid_in_magnitude_range(step)) {
            return OKID_E_BAD_PARAMETER;
        }
        counts[i] = blocks_of(seconds[i], step);
        if (counts[i] < 0) {
            return OKID_E_BAD_SIZE;
        }
    }
    cfg->observer_order = counts[0];
    cfg->hankel_rows = counts[1];
    cfg->hankel_cols = counts[2];
    return OKID_OK;
}

okid_status okid_config_check(const okid_config *cfg, okid_config_issue *issue)
{
    if (cfg == NULL || issue == NULL) {
        return OKID_E_NULL_POINTER;
    }
    *issue = (okid_config_issue){NULL, 0, 0, 0};
    okid_dims_ dims;
    okid_status st = okid_layout_dims(cfg, &dims, issue);
    if (st == OKID_OK) {
        const uint64_t needed = okid_layout_carve(&dims, cfg->realization == OKID_REALIZATION_COMBINED,
                                                  cfg->scaling == OKID_SCALING_AUTO, NULL, NULL);
        size_t bytes = 0;
        st = okid_carve_size(needed, &bytes);
        if (st != OKID_OK) {
            *issue = (okid_config_issue){"workspace bytes", (double)needed, 0, (double)SIZE_MAX};
        }
    }
    return st;
}

okid_status okid_workspace_size(const okid_config *cfg, size_t *bytes)
{
    if (cfg == NULL || bytes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    okid_dims_ dims;
    const okid_status st = okid_layout_dims(cfg, &dims, NULL);
    if (st != OKID_OK) {
        return st;
    }
    return okid_layout_size(&dims, cfg->realization == OKID_REALIZATION_COMBINED, cfg->scaling == OKID_SCALING_AUTO,
                            bytes);
}

/* Start the sample history again (at init, reset, and after a rejected sample: a gap). */
static void restart_history(okid_identifier *id, int zero_history)
{
    okid_ring_restart(&id->window_, zero_history);
    okid_ring_restart(&id->inputs_, zero_history);
    if (id->at_.dec_state != NULL) {
        okid_decimator_reset(id->at_.dec_state, id->dims_.r + id->dims_.m);
    }
    id->dec_phase_ = 0;
}

/* The correlation form's Toeplitz Gram (LAPACK backend, no forgetting): its open run and identify's
   scratch run in fold_t; NULL elsewhere (weights break the shift structure: the rows are weighed
   in place and folded by xSYRK; docs/design.md "Toeplitz block Gram"). */
#if !OKID_LINALG_EIGEN
static okid_real *toeplitz_run(const okid_identifier *id)
{
    return id->dims_.correlation && id->forgetting_ >= 1 ? id->at_.fold_t : NULL;
}

static okid_real *toeplitz_scratch(const okid_identifier *id)
{
    const okid_dims_ *d = &id->dims_;
    return id->at_.fold_t + (size_t)(d->r + d->m + 2) * (size_t)d->w + 1u;
}
#endif

static void clear_samples(okid_identifier *id)
{
    const int w = id->dims_.w;
    okid_zero_matrix(w, w, id->at_.r, w);
    if (id->at_.iv_m != NULL) {
        okid_zero_matrix(id->dims_.nz, w, id->at_.iv_m, id->dims_.nz);
    }
    restart_history(id, id->cfg_.zero_initial_state);
#if !OKID_LINALG_EIGEN /* compiled out, not only unreached: the Eigen archive has no Toeplitz Gram */
    okid_real *run = toeplitz_run(id);
    if (run != NULL) {
        okid_toeplitz_restart(id->dims_.r, id->dims_.m, id->dims_.p, run);
    }
#endif
    id->scales_known_ = 0;
    id->block_fill_ = 0;
    id->samples_ = 0;
    id->rejected_ = 0;
    id->rows_ = 0;
    id->has_model_ = 0;
    id->result_ = 0;
}

okid_status okid_init(okid_identifier *id, const okid_config *cfg, void *workspace, size_t bytes,
                      size_t *bytes_needed)
{
    if (id == NULL || cfg == NULL) {
        return OKID_E_NULL_POINTER;
    }
    id->magic_ = 0;
    okid_dims_ dims;
    okid_status st = okid_layout_dims(cfg, &dims, NULL);
    if (st != OKID_OK) {
        return st;
    }
    const int combined = cfg->realization == OKID_REALIZATION_COMBINED, scaled = cfg->scaling == OKID_SCALING_AUTO;
    size_t needed = 0;
    st = okid_layout_size(&dims, combined, scaled, &needed);
    if (st != OKID_OK) {
        return st;
    }
    if (bytes_needed != NULL) {
        *bytes_needed = needed;
    }
    if (workspace == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (((size_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    if (bytes < needed) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    id->cfg_ = *cfg;
    id->cfg_.decimation = dims.decimation;
    id->cfg_.dt = cfg->dt * (okid_real)dims.decimation; /* the model's sample interval */
    id->cfg_.instrument_lags = dims.instrument_lags;
    id->dims_ = dims;
    id->forgetting_ = (cfg->forgetting_factor > 0) ? cfg->forgetting_factor : 1;
    id->rank_tolerance_ = (cfg->rank_tolerance > 0) ? cfg->rank_tolerance : DEFAULT_RANK_TOLERANCE;
    (void)okid_layout_carve(&dims, combined, scaled, (unsigned char *)workspace, &id->at_);
    const okid_ring_ window = {id->at_.ring, dims.r + dims.m, dims.p, 0, 0};
    const okid_ring_ inputs = {id->at_.iv_ring, dims.r, dims.instrument_lags, 0, 0};
    id->window_ = window;
    id->inputs_ = inputs;
    if (id->at_.dec_coef != NULL) {
        okid_decimator_design(dims.decimation, id->at_.dec_coef);
    }
    clear_samples(id);
    id->magic_ = OKID_MAGIC;
    return OKID_OK;
}

/* The correlation form at push: the rows' Gram into c (upper), by the Toeplitz run or xSYRK. */
static okid_status accumulate_gram(const okid_identifier *id, int w, int rows, okid_real *phi, int ld, okid_real *c)
{
#if !OKID_LINALG_EIGEN
    const okid_dims_ *d = &id->dims_;
    okid_real *run = toeplitz_run(id);
    if (run != NULL) {
        return okid_toeplitz_fold(d->r, d->m, d->p, rows, phi, ld, run, c, w);
    }
#endif
    return okid_lsq_accumulate(w, c, w, rows, phi, ld, id->forgetting_);
}

/* The correlation form at identify: c (a copy of R) gets the open run's Gram and the pending rows'. */
static okid_status complete_gram(const okid_identifier *id, int w, int rows, okid_real *phi, int ld, okid_real *c)
{
#if !OKID_LINALG_EIGEN
    const okid_dims_ *d = &id->dims_;
    const okid_real *run = toeplitz_run(id);
    if (run != NULL) {
        okid_real *scratch = toeplitz_scratch(id);
        okid_toeplitz_close(d->r, d->m, d->p, run, c, w, scratch);
        return okid_toeplitz_gram(d->r, d->m, d->p, rows, phi, ld, c, w, scratch);
    }
#endif
    return okid_lsq_accumulate(w, c, w, rows, phi, ld, id->forgetting_);
}

/* Fold the pending rows (push): the scales from them first if still unknown (OKID_SCALING_AUTO),
   then into R, or into the instruments' cross-product M; the block is empty afterwards. */
static okid_status fold_pending(okid_identifier *id)
{
    const okid_dims_ *d = &id->dims_;
    okid_views_ *v = &id->at_;
    const int rows = id->block_fill_, ld = d->block_rows;
    if (rows == 0) {
        return OKID_OK;
    }
    if (v->scales != NULL) {
        if (!id->scales_known_) {
            okid_scaling_measure(d->r, d->m, d->p, rows, v->block, ld, v->scales);
            id->scales_known_ = 1;
        }
        okid_scaling_apply(d->r, d->m, d->p, v->scales, rows, v->block, ld, v->iv_block, d->nz, ld);
    }
    okid_status st = OKID_OK;
    if (d->nz > 0) {
        okid_real decay = 1; /* the cross-product takes root^age from each side */
        if (id->forgetting_ < 1) {
            const okid_real rscale = okid_lsq_decay(rows, id->forgetting_);
            decay = rscale * rscale;
            okid_lsq_weigh_rows(rows, d->w, v->block, ld, id->forgetting_);
            okid_lsq_weigh_rows(rows, d->nz, v->iv_block, ld, id->forgetting_);
        }
        okid_iv_cross_product(0, d->nz, d->w, rows, v->iv_block, ld, v->block, ld, decay, v->iv_m, d->nz, v->iv_m,
                              d->nz);
    } else if (d->correlation) {
        st = accumulate_gram(id, d->w, rows, v->block, ld, v->r);
    } else {
        st = okid_lsq_fold(d->w, v->r, d->w, rows, v->block, ld, id->forgetting_, d->block_tile, v->fold_t,
                           v->fold_work);
    }
    id->block_fill_ = 0;
    return st;
}

/* One kept sample into the window and, once the window is full, one regressor row into the block. */
static okid_status accept_sample(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    okid_status st = OKID_OK;
    const size_t ld = (size_t)id->dims_.block_rows;
    if (okid_ring_full(&id->window_) && okid_ring_full(&id->inputs_)) {
        okid_buffer_write_row(&id->window_, id->dims_.r, u, y, id->at_.block + id->block_fill_, ld);
        if (id->dims_.nz > 0) {
            okid_iv_write_row(&id->inputs_, u, id->at_.iv_block + id->block_fill_, ld);
        }
        ++id->block_fill_;
        ++id->rows_;
        if (id->block_fill_ == id->dims_.block_rows) {
            st = fold_pending(id);
        }
    }
    okid_ring_append(&id->window_, u, id->dims_.r, y, id->dims_.m);
    okid_ring_append(&id->inputs_, u, id->dims_.r, NULL, 0);
    return st;
}

/* Decimation: filter every pushed sample, keep pushed samples 0, K, 2K, ... of each stretch. */
static okid_status decimate_sample(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    const int r = id->dims_.r, m = id->dims_.m;
    okid_real *v = id->at_.dec_out;
    for (int i = 0; i < r; ++i) {
        v[i] = u[i];
    }
    for (int i = 0; i < m; ++i) {
        v[r + i] = y[i];
    }
    okid_decimator_filter(id->at_.dec_coef, id->at_.dec_state, r + m, v);
    const int keep = id->dec_phase_ == 0;
    id->dec_phase_ = (id->dec_phase_ + 1) % id->dims_.decimation;
    return keep ? accept_sample(id, v, v + r) : OKID_OK;
}

/* Whether one sample's r inputs and m outputs are all finite (a sample that is not is a gap). */
static int sample_is_finite(const okid_dims_ *d, const okid_real *u, const okid_real *y)
{
    return okid_all_finite(d->r, 1, u, d->r) && okid_all_finite(d->m, 1, y, d->m);
}

#if !OKID_LINALG_EIGEN
/*
 * The block path of okid_push_block (host backend; the firmware's Eigen builds keep the per-sample
 * path and its flash): once the window is full, without decimation or instruments, the next
 * samples up to the end of the pending block are written as rows column by column
 * (okid_buffer_write_rows()), the same values as sample by sample, so the same bits. How many
 * samples of the `left` at u, y go at once: the finite ones before the first that is not (which
 * push_one() then takes, the gap as before), 0 when the path does not apply.
 */
static int rows_at_once(const okid_identifier *id, size_t left, const okid_real *u, size_t ldu, const okid_real *y,
                        size_t ldy)
{
    const okid_dims_ *d = &id->dims_;
    if (d->decimation > 1 || d->nz > 0 || !okid_ring_full(&id->window_) || !okid_ring_full(&id->inputs_)) {
        return 0;
    }
    const size_t room = (size_t)(d->block_rows - id->block_fill_);
    const int most = (int)(left < room ? left : room);
    int run = 0;
    while (run < most && sample_is_finite(d, u + (size_t)run * ldu, y + (size_t)run * ldy)) {
        ++run;
    }
    return run;
}

/* accept_sample() of `run` finite samples that fit in the pending block: their rows, the window's
   appends, the counters, the fold when the block is full. */
static okid_status accept_rows(okid_identifier *id, int run, const okid_real *u, size_t ldu, const okid_real *y,
                               size_t ldy)
{
    const okid_dims_ *d = &id->dims_;
    okid_buffer_write_rows(&id->window_, d->r, run, u, ldu, y, ldy, id->at_.block + id->block_fill_,
                           (size_t)d->block_rows);
    for (int t = 0; t < run; ++t) {
        okid_ring_append(&id->window_, u + (size_t)t * ldu, d->r, y + (size_t)t * ldy, d->m);
        okid_ring_append(&id->inputs_, u + (size_t)t * ldu, d->r, NULL, 0);
    }
    id->samples_ += (uint64_t)run;
    id->rows_ += (uint64_t)run;
    id->block_fill_ += run;
    return id->block_fill_ == d->block_rows ? fold_pending(id) : OKID_OK;
}
#endif

static okid_status push_one(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    if (!sample_is_finite(&id->dims_, u, y)) {
        ++id->rejected_;
        restart_history(id, 0); /* a gap: the next rows must not span it */
        return OKID_E_NONFINITE_SAMPLE;
    }
    ++id->samples_;
    return (id->dims_.decimation > 1) ? decimate_sample(id, u, y) : accept_sample(id, u, y);
}

okid_status okid_push(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    if (id == NULL || u == NULL || y == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    return push_one(id, u, y);
}

okid_status okid_push_block(okid_identifier *id, size_t count, const okid_real *u, size_t ldu,
                            const okid_real *y, size_t ldy, size_t *accepted)
{
    if (accepted != NULL) {
        *accepted = 0;
    }
    if (id == NULL || (count > 0 && (u == NULL || y == NULL))) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (ldu < (size_t)id->dims_.r || ldy < (size_t)id->dims_.m) {
        return OKID_E_BAD_SIZE;
    }
    okid_status result = OKID_OK;
    size_t taken = 0;
    for (size_t k = 0; k < count; ++k) {
#if !OKID_LINALG_EIGEN
        const int run = rows_at_once(id, count - k, u + k * ldu, ldu, y + k * ldy, ldy);
        if (run > 0) {
            const okid_status st = accept_rows(id, run, u + k * ldu, ldu, y + k * ldy, ldy);
            if (st != OKID_OK) {
                result = st; /* a backend failure: stop here */
                break;
            }
            taken += (size_t)run;
            k += (size_t)run - 1u;
            continue;
        }
#endif
        const okid_status st = push_one(id, u + k * ldu, y + k * ldy);
        if (st == OKID_OK) {
            ++taken;
        } else if (st == OKID_E_NONFINITE_SAMPLE) {
            result = st;
        } else {
            result = st; /* a backend failure: stop here */
            break;
        }
    }
    if (accepted != NULL) {
        *accepted = taken;
    }
    return result;
}

static okid_matrix view(const okid_real *data, int rows, int cols, int ld)
{
    okid_matrix v = {data, rows, cols, ld};
    return v;
}

/* The scales this identification uses, copied into its result: the known ones, or (OKID_SCALING_AUTO
   before the first fold, when every row is still pending) those of the pending rows, for this
   identification only. NULL without scaling. */
static const okid_real *identify_scales(const okid_identifier *id, okid_real *copy)
{
    const okid_dims_ *d = &id->dims_;
    if (id->at_.scales == NULL) {
        return NULL;
    }
    if (id->scales_known_) {
        okid_copy_matrix(d->r + d->m, 1, id->at_.scales, d->r + d->m, copy, d->r + d->m);
    } else {
        okid_scaling_measure(d->r, d->m, d->p, id->block_fill_, id->at_.block, d->block_rows, copy);
    }
    return copy;
}

/*
 * The factor identify solves on (*factor, w x w, leading dimension w): R itself when no row is
 * pending, else a copy of R with the pending rows folded in from a copy of them (the same
 * operations a fold at push makes), so that R, the pending rows and the counters stay as they
 * are and an identification changes no later result. Instruments: R rebuilt from M and the
 * pending rows, M left alone.
 */
static okid_status identify_factor(const okid_identifier *id, const okid_real *scales, okid_real **factor)
{
    const okid_dims_ *d = &id->dims_;
    const okid_views_ *v = &id->at_;
    const int rows = id->block_fill_, ld = d->block_rows, w = d->w, nz = d->nz;
    okid_real *phi = NULL, *z = NULL;
    if (rows > 0) {
        phi = v->pending;
        z = v->iv_pending;
        okid_copy_matrix(rows, w, v->block, ld, phi, ld);
        if (nz > 0) {
            okid_copy_matrix(rows, nz, v->iv_block, ld, z, ld);
        }
        if (scales != NULL) {
            okid_scaling_apply(d->r, d->m, d->p, scales, rows, phi, ld, z, nz, ld);
        }
    }
    if (nz > 0) {
        okid_real decay = 1;
        if (rows > 0 && id->forgetting_ < 1) {
            const okid_real rscale = okid_lsq_decay(rows, id->forgetting_);
            decay = rscale * rscale;
            okid_lsq_weigh_rows(rows, w, phi, ld, id->forgetting_);
            okid_lsq_weigh_rows(rows, nz, z, ld, id->forgetting_);
        }
        *factor = v->r; /* not kept between calls with instruments: M is the accumulation */
        return okid_iv_factor(nz, w, v->iv_m, nz, rows, z, ld, phi, ld, decay, v->r, w,
                              rows > 0 ? v->iv_chunk : v->block, ld, d->block_tile, v->fold_t, v->fold_work);
    }
    if (d->correlation) { /* C and the pending rows' C into the copy, then its Cholesky factor */
        okid_copy_matrix(w, w, v->r, w, v->factor, w);
        *factor = v->factor;
        const okid_lsq_scratch lsq = {v->lsq_scale, v->lsq_column, v->lsq_perm, v->lsq_work};
        const okid_status st = complete_gram(id, w, rows, phi, ld, v->factor);
        return st != OKID_OK ? st : okid_lsq_correlation_factor(d->q, d->m, v->factor, w, &lsq);
    }
    if (rows == 0) {
        *factor = v->r;
        return OKID_OK;
    }
    okid_copy_matrix(w, w, v->r, w, v->factor, w);
    *factor = v->factor;
    return okid_lsq_fold(w, v->factor, w, rows, phi, ld, id->forgetting_, d->block_tile, v->fold_t, v->fold_work);
}

/* What the stages of one identification report besides the result set. */
typedef struct identification {
    int regressor_rank, input_rank, order, num_modes;
    unsigned warnings;
    okid_regressor_diagnostics regressor;
    okid_real realization_condition;
} identification;

/* Observer Markov parameters (eq. 50) by the rank-revealing solve on the factor, in the data's
   units, then the system and observer-gain Markov parameters (eq. 51, 53). */
static okid_status observer_stage(const okid_identifier *id, okid_real *factor, const okid_real *scales,
                                  const okid_result_views_ *out, identification *info)
{
    const okid_dims_ *d = &id->dims_;
    const okid_views_ *v = &id->at_;
    const okid_lsq_scratch lsq = {v->lsq_scale, v->lsq_column, v->lsq_perm, v->lsq_work};
    const okid_status st = okid_lsq_solve(d->q, d->m, d->r * (d->p + 1), factor, d->w, id->rank_tolerance_, out->x,
                                          d->q, &lsq, &info->regressor_rank, &info->input_rank);
    if (st != OKID_OK) {
        return st;
    }
    info->warnings = (info->regressor_rank < d->q) ? OKID_W_REGRESSOR_RANK_DEFICIENT : 0u;
    okid_scaling_unscale_solution(d->r, d->m, d->p, scales, out->x, d->q);
    okid_markov_recover(d->r, d->m, d->p, d->markov_count, out->x, d->q, out->markov, out->markov_obs);
    return OKID_OK;
}

/* ERA (eq. 57-61), the blocks of its factors the indicators compare, then the regressor's
   diagnostics (their solves overwrite the Hankel matrix in the factor's triangle). */
static okid_status realization_stage(const okid_identifier *id, okid_real *factor, const okid_result_views_ *out,
                                     identification *info)
{
    const okid_dims_ *d = &id->dims_;
    const okid_views_ *v = &id->at_;
    okid_era_problem era;
    okid_era_scratch scratch;
    okid_layout_era(id, out, factor, &era, &scratch);
    const okid_era_output realization = {out->sv, out->a, out->b, out->c, out->d, out->g};
    okid_status st = okid_era_realize(&era, &scratch, &realization, &info->order, &info->warnings);
    if (st != OKID_OK) {
        return st;
    }
    okid_indicators_capture(&era, &scratch, out->sv, info->order, out->obs_last, out->ctrl_last);
    const okid_lsq_scratch lsq = {v->lsq_scale, v->lsq_column, v->lsq_perm, v->lsq_work};
    return okid_diagnose_regressor(d->q, d->r * (d->p + 1), factor, d->w, id->rank_tolerance_, info->order,
                                   info->regressor_rank, &lsq, &info->regressor, &info->warnings);
}

/* Modes (eq. 63-64), their indicators, and the realization's diagnostics. */
static int all_finite(int rows, int cols, const okid_real *x, int ld)
{
    for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) {
            if (!okid_is_finite(OKID_AT(x, ld, i, j))) {
                return 0;
            }
        }
    }
    return 1;
}

static okid_status modal_stage(const okid_identifier *id, const okid_result_views_ *out, identification *info)
{
    const okid_dims_ *d = &id->dims_;
    const okid_views_ *v = &id->at_;
    const int n = info->order, m = d->m;
    const okid_modal_scratch modal = {v->modal_a, v->modal_vr, v->modal_wr, v->modal_wi, v->modal_work};
    if (!all_finite(n, n, out->a, n) || !all_finite(m, n, out->c, m)) {
        return OKID_E_DATA_RANGE; /* S^-1/2 of singular values near underflow: no eigenproblem over Inf/NaN */
    }
    okid_status st = okid_modal_compute(n, m, out->a, n, out->c, m, id->cfg_.dt, id->cfg_.sensing, &modal,
                                        out->shapes, out->modes, &info->num_modes, &info->warnings);
    if (st != OKID_OK) {
        return st;
    }
    const okid_indicator_inputs ind = {n, m, d->r, id->cfg_.hankel_rows, id->cfg_.hankel_cols,
                                       out->b, n, out->c, m, out->obs_last, m, out->ctrl_last, n};
    const okid_indicator_scratch ind_scratch = {v->modal_a, v->ind_rhs, v->ind_jpvt, v->ind_work};
    st = okid_modal_indicators(&ind, v->modal_vr, v->modal_wr, v->modal_wi, &ind_scratch, out->modes,
                               info->num_modes);
    if (st != OKID_OK) {
        return st;
    }
    if (!okid_modes_finite(out->modes, info->num_modes, m)) {
        return OKID_E_DATA_RANGE; /* what the channel check cannot see (ratios of channels, scaling auto) */
    }
    const okid_real span = (okid_real)(id->cfg_.hankel_rows + id->cfg_.hankel_cols) * id->cfg_.dt;
    okid_diagnose_realization(out->sv, n, span, out->modes, info->num_modes, &info->realization_condition,
                              &info->warnings);
    return OKID_OK;
}

static void fill_result(const okid_identifier *id, const okid_result_views_ *out, const identification *info,
                        okid_result *result)
{
    const okid_dims_ *d = &id->dims_;
    const int r = d->r, m = d->m, L = d->markov_count, n = info->order;
    result->order = n;
    result->num_modes = info->num_modes;
    result->modes = out->modes;
    result->A = view(out->a, n, n, n);
    result->B = view(out->b, n, r, n);
    result->C = view(out->c, m, n, m);
    result->D = view(out->d, m, r, m);
    result->G = view(out->g, out->g ? n : 0, out->g ? m : 0, n);
    result->singular_values = out->sv;
    result->num_singular_values = d->svd_size;
    result->markov = view(out->markov, m, r * (L + 1), m);
    result->observer_gain_markov = view(out->markov_obs, m, out->markov_obs ? m * L : 0, m);
    result->dt = id->cfg_.dt;
    result->samples = id->samples_;
    result->rows = id->rows_;
    result->regressor_rank = info->regressor_rank;
    result->regressor_columns = d->q;
    result->input_rank = info->input_rank;
    result->warnings = info->warnings;
    result->regressor_rank_expected = info->regressor.expected_rank;
    result->lsq_condition = info->regressor.lsq_condition;
    result->input_condition = info->regressor.input_condition;
    result->realization_condition = info->realization_condition;
    result->decimation = d->decimation;
    result->instrument_lags = d->instrument_lags;
    result->input_scales = out->scales;
    result->output_scales = out->scales != NULL ? out->scales + r : NULL;
}

/*
 * The stages of docs/design.md on the accumulated factor, into the result set the last good one
 * is not: a failure anywhere leaves every observable as it was (last result, okid_predict(), the
 * counters, the accumulation); success makes the new result the last good one.
 */
okid_status okid_identify(okid_identifier *id, okid_result *result)
{
    if (id == NULL || result == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (id->rows_ < (uint64_t)id->dims_.q || okid_rows_remembered(id) < (uint64_t)id->dims_.q) {
        return OKID_E_NOT_ENOUGH_DATA; /* too few rows, or a forgetting factor that forgets them too fast */
    }
    const okid_result_views_ *out = &id->at_.result[1 - id->result_];
    const okid_real *scales = identify_scales(id, out->scales);
    okid_real *factor = NULL;
    identification info = {0};
    okid_status st = identify_factor(id, scales, &factor);
    if (st == OKID_OK) {
        st = okid_check_channel_range(id, factor); /* 1e155 or 1e-160: refused before the solve, not garbage after it */
    }
    if (st == OKID_OK) {
        st = observer_stage(id, factor, scales, out, &info);
    }
    if (st == OKID_OK) {
        st = realization_stage(id, factor, out, &info);
    }
    if (st == OKID_OK) {
        st = modal_stage(id, out, &info);
    }
    if (st != OKID_OK) {
        return st; /* the last good result is untouched */
    }
    fill_result(id, out, &info, result);
    id->result_ = 1 - id->result_;
    id->has_model_ = 1;
    return OKID_OK;
}

okid_status okid_predict(const okid_identifier *id, const okid_real *u, okid_real *y_hat)
{
    if (id == NULL || u == NULL || y_hat == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    if (!id->has_model_ || id->dims_.decimation > 1) {
        return OKID_E_NOT_AVAILABLE; /* with decimation the window holds filtered samples, not the pushed ones */
    }
    if (!okid_ring_full(&id->window_)) {
        return OKID_E_NOT_ENOUGH_DATA;
    }
    if (!okid_all_finite(id->dims_.r, 1, u, id->dims_.r)) {
        return OKID_E_NONFINITE_SAMPLE;
    }
    okid_buffer_predict(&id->window_, id->dims_.r, u, id->at_.result[id->result_].x, id->dims_.q, y_hat);
    return OKID_OK;
}

okid_status okid_set_scales(okid_identifier *id, const okid_real *input_scales, const okid_real *output_scales)
{
    if (id == NULL || input_scales == NULL || output_scales == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    const int r = id->dims_.r, m = id->dims_.m;
    for (int i = 0; i < r + m; ++i) {
        const okid_real s = i < r ? input_scales[i] : output_scales[i - r];
        if (!okid_is_finite(s) || !(s > 0)) {
            return OKID_E_BAD_PARAMETER;
        }
    }
    if (id->at_.scales == NULL || id->scales_known_) {
        return OKID_E_NOT_AVAILABLE;
    }
    for (int i = 0; i < r + m; ++i) {
        id->at_.scales[i] = i < r ? input_scales[i] : output_scales[i - r];
    }
    id->scales_known_ = 1;
    return OKID_OK;
}

okid_status okid_reset(okid_identifier *id)
{
    if (id == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    clear_samples(id);
    return OKID_OK;
}

okid_status okid_get_progress(const okid_identifier *id, okid_progress *progress)
{
    if (id == NULL || progress == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    progress->samples = id->samples_;
    progress->rejected = id->rejected_;
    progress->rows = id->rows_;
    progress->rows_needed = id->dims_.q;
    progress->rows_remembered = okid_rows_remembered(id);
    return OKID_OK;
}

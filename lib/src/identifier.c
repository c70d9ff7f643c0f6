/* The public identifier API: argument checks, state, and the identify pipeline (DESIGN.md data flow). */
#include "okid/identifier.h"

#include "carve.h"
#include "channel_scaling.h"
#include "data_range.h"
#include "decimator.h"
#include "dense.h"
#include "diagnostics.h"
#include "era.h"
#include "instrumental.h"
#include "least_squares.h"
#include "markov.h"
#include "modal_indicators_internal.h"
#include "modal_internal.h"
#include "real_math.h"
#include "sample_buffer.h"
#include "workspace_layout.h"

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
    cfg->observer_order = 10;
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
    okid_buffer_restart(id, zero_history);
    okid_iv_restart(id, zero_history);
    if (id->at_.dec_state != NULL) {
        okid_decimator_reset(id->at_.dec_state, id->dims_.r + id->dims_.m);
    }
    id->dec_phase_ = 0;
}

static void clear_samples(okid_identifier *id)
{
    const int w = id->dims_.w;
    okid_zero_matrix(w, w, id->at_.r, w);
    if (id->at_.iv_m != NULL) {
        okid_zero_matrix(id->dims_.nz, w, id->at_.iv_m, id->dims_.nz);
    }
    restart_history(id, id->cfg_.zero_initial_state);
    id->scales_known_ = 0;
    id->block_fill_ = 0;
    id->samples_ = 0;
    id->rejected_ = 0;
    id->rows_ = 0;
    id->has_model_ = 0;
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
    if (id->at_.dec_coef != NULL) {
        okid_decimator_design(dims.decimation, id->at_.dec_coef);
    }
    clear_samples(id);
    id->magic_ = OKID_MAGIC;
    return OKID_OK;
}

/* One kept sample into the window and, once the window is full, one regressor row into the block. */
static okid_status accept_sample(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    okid_status st = OKID_OK;
    if (okid_buffer_window_full(id) && okid_iv_ready(id)) {
        okid_buffer_write_row(id, u, y, id->block_fill_);
        if (id->dims_.nz > 0) {
            okid_iv_write_row(id, u, id->block_fill_);
        }
        ++id->block_fill_;
        ++id->rows_;
        if (id->block_fill_ == id->dims_.block_rows) {
            st = okid_lsq_fold_pending(id);
        }
    }
    okid_buffer_append(id, u, y);
    okid_iv_append(id, u);
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

static okid_status push_one(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    if (!okid_all_finite(id->dims_.r, 1, u, id->dims_.r) || !okid_all_finite(id->dims_.m, 1, y, id->dims_.m)) {
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

okid_status okid_identify(okid_identifier *id, okid_result *result)
{
    if (id == NULL || result == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!is_initialized(id)) {
        return OKID_E_NOT_INITIALIZED;
    }
    const okid_dims_ *d = &id->dims_;
    if (id->rows_ < (uint64_t)d->q || okid_rows_remembered(id) < (uint64_t)d->q) {
        return OKID_E_NOT_ENOUGH_DATA; /* too few rows, or a forgetting factor that forgets them too fast */
    }
    okid_status st = okid_lsq_fold_pending(id);
    if (st == OKID_OK) {
        st = okid_check_channel_range(id); /* 1e155 or 1e-160: refused before the solve, not garbage after it */
    }
    if (st == OKID_OK && d->nz > 0) {
        st = okid_iv_factor(id); /* the factor R is rebuilt from the instruments' cross-product */
    }
    if (st != OKID_OK) {
        return st;
    }
    id->has_model_ = 0; /* the solution X is rewritten below */
    int regressor_rank = 0, input_rank = 0;
    st = okid_lsq_solve(id, &regressor_rank, &input_rank);
    if (st != OKID_OK) {
        return st;
    }
    okid_scaling_unscale_solution(id);
    okid_markov_recover(id);

    unsigned warnings = (regressor_rank < d->q) ? OKID_W_REGRESSOR_RANK_DEFICIENT : 0u;
    int n = 0;
    st = okid_era_realize(id, &n, &warnings);
    if (st != OKID_OK) {
        return st;
    }
    okid_indicators_capture(id, n, id->at_.obs_last, id->at_.ctrl_last);
    okid_regressor_diagnostics diag;
    st = okid_diagnose_regressor(id, n, regressor_rank, &diag, &warnings);
    if (st != OKID_OK) {
        return st;
    }
    const okid_modal_scratch scratch = {id->at_.modal_a, id->at_.modal_vr, id->at_.modal_wr, id->at_.modal_wi,
                                        id->at_.modal_work};
    int num_modes = 0;
    st = okid_modal_compute(n, d->m, id->at_.a, n, id->at_.c, d->m, id->cfg_.dt, id->cfg_.sensing, &scratch,
                            id->at_.shapes, id->at_.modes, &num_modes, &warnings);
    if (st != OKID_OK) {
        return st;
    }
    const okid_indicator_inputs ind = {n, d->m, d->r, id->cfg_.hankel_rows, id->cfg_.hankel_cols,
                                       id->at_.b, n, id->at_.c, d->m, id->at_.obs_last, d->m, id->at_.ctrl_last, n};
    const okid_indicator_scratch ind_scratch = {id->at_.modal_a, id->at_.ind_rhs, id->at_.ind_jpvt, id->at_.ind_work};
    st = okid_modal_indicators(&ind, id->at_.modal_vr, id->at_.modal_wr, id->at_.modal_wi, &ind_scratch,
                               id->at_.modes, num_modes);
    if (st != OKID_OK) {
        return st;
    }
    if (!okid_modes_finite(id->at_.modes, num_modes, d->m)) {
        return OKID_E_DATA_RANGE; /* what the channel check cannot see (ratios of channels, scaling auto) */
    }
    okid_real realization_condition = 0;
    okid_diagnose_realization(id, n, id->at_.modes, num_modes, &realization_condition, &warnings);

    const int r = d->r, m = d->m, L = d->markov_count;
    result->order = n;
    result->num_modes = num_modes;
    result->modes = id->at_.modes;
    result->A = view(id->at_.a, n, n, n);
    result->B = view(id->at_.b, n, r, n);
    result->C = view(id->at_.c, m, n, m);
    result->D = view(id->at_.d, m, r, m);
    result->G = view(id->at_.g, id->at_.g ? n : 0, id->at_.g ? m : 0, n);
    result->singular_values = id->at_.sv;
    result->num_singular_values = d->svd_size;
    result->markov = view(id->at_.markov, m, r * (L + 1), m);
    result->observer_gain_markov = view(id->at_.markov_obs, m, id->at_.markov_obs ? m * L : 0, m);
    result->dt = id->cfg_.dt;
    result->samples = id->samples_;
    result->rows = id->rows_;
    result->regressor_rank = regressor_rank;
    result->regressor_columns = d->q;
    result->input_rank = input_rank;
    result->warnings = warnings;
    result->regressor_rank_expected = diag.expected_rank;
    result->lsq_condition = diag.lsq_condition;
    result->input_condition = diag.input_condition;
    result->realization_condition = realization_condition;
    result->decimation = d->decimation;
    result->instrument_lags = d->instrument_lags;
    const int scaled = id->at_.scales != NULL && id->scales_known_;
    result->input_scales = scaled ? id->at_.scales : NULL;
    result->output_scales = scaled ? id->at_.scales + r : NULL;
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
    if (!okid_buffer_window_full(id)) {
        return OKID_E_NOT_ENOUGH_DATA;
    }
    if (!okid_all_finite(id->dims_.r, 1, u, id->dims_.r)) {
        return OKID_E_NONFINITE_SAMPLE;
    }
    okid_buffer_predict(id, u, id->at_.x, y_hat);
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

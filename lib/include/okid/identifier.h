/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file identifier.h
 * \brief The OKID/ERA identifier: push input/output samples, identify {A, B, C, D, G} and modes.
 *
 * Fixed memory: the caller owns the identifier struct and one workspace buffer whose size
 * okid_workspace_size() (or the compile-time macro OKID_WORKSPACE_BYTES) gives. The struct's
 * members are in okid/identifier_storage.h and the size formulas in okid/sizes.h, neither of
 * which is API. Nothing is allocated, printed or read from the environment. Two identifiers share
 * nothing. One identifier must not be used from two threads at once.
 *
 * Typical use:
 * \code
 *   okid_config cfg;
 *   okid_config_default(&cfg, 1, 2);          // r = 1 force, m = 2 accelerometers
 *   cfg.dt = 0.01; cfg.observer_order = 20; cfg.order = 4;
 *   size_t bytes; okid_workspace_size(&cfg, &bytes);
 *   okid_identifier id;
 *   okid_init(&id, &cfg, workspace, bytes, NULL);
 *   for (k = 0; k < N; ++k) okid_push(&id, &u[k], &y[2 * k]);
 *   okid_result res;
 *   if (okid_identify(&id, &res) == OKID_OK)  // res.modes[i].frequency_hz, .damping_ratio, ...
 * \endcode
 *
 * Sections: configuration, lifetime, data, results.
 */
#ifndef OKID_IDENTIFIER_H
#define OKID_IDENTIFIER_H

#include <stddef.h>
#include <stdint.h>

#include "okid/limits.h"
#include "okid/modal.h"
#include "okid/sizes.h"
#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ======== Configuration ======== */

/** Which Markov parameters the ERA Hankel matrices are built from. */
typedef enum okid_realization {
    /** System Markov parameters Y_k only (eq. 51): the robust default; no observer gain. */
    OKID_REALIZATION_SYSTEM = 0,
    /**
     * Combined [Y_k, Y°_k] (eq. 54, 61): also yields the observer gain G. Each input column and
     * each observer-gain column is scaled to unit norm over the Hankel window before the SVD (and
     * unscaled after), so the units of forces and sensors do not decide the realization.
     */
    OKID_REALIZATION_COMBINED = 1
} okid_realization;

/** Per-channel scaling of the data before the least squares (docs/quality.md, "Scaling"). */
typedef enum okid_scaling {
    /** The data as pushed: results depend on the relative units of the channels. */
    OKID_SCALING_NONE = 0,
    /**
     * Each input and output channel is divided by its RMS over the first block of regressor rows
     * (block_rows samples after the first p, at the decimated rate; an okid_identify() before that
     * uses the rows pending then, for itself only; a channel that is zero there keeps scale 1), or
     * by scales given with okid_set_scales(). The rows are scaled when the block is folded, so the
     * scales must be known before the first fold. The ERA Hankel is built from the Markov
     * parameters of the scaled data, and A, B, C, D, G, the Markov parameters and the observer
     * solution are unscaled exactly before they are returned: the modes no longer depend on the
     * units.
     */
    OKID_SCALING_AUTO = 1
} okid_scaling;

/** How the observer Markov parameters (eq. 50) are estimated from the regressor. */
typedef enum okid_estimator {
    /** Least squares (eq. 50): biased when the outputs carry measurement noise. */
    OKID_ESTIMATOR_LEAST_SQUARES = 0,
    /**
     * Instrumental variables with delayed inputs (Soederstroem and Stoica, 1989, ch. 8): the
     * normal equations Phi'Phi X = Phi'y become Z'Phi X = Z'y with z(k) = [u(k); ...; u(k-L)],
     * L = instrument_lags, solved in the least-squares sense (extended IV). The inputs are
     * uncorrelated with the output noise, so the bias of eq. 50 under output noise vanishes;
     * the price is more variance. Fixed memory: Z'[Phi y] (r (L+1) x (q+m)) and a ring of L inputs.
     * The ranks and condition numbers of okid_result then describe Z'Phi, not Phi.
     */
    OKID_ESTIMATOR_INSTRUMENTAL = 1,
    /**
     * Least squares in correlation form (SLICOT IB01AD's ALG = 'C'): push accumulates
     * [Phi Y]'[Phi Y] by xSYRK (w^2 N flops against 2 w^2 N for the QR fold), identify takes its
     * Cholesky factor and solves as least squares does. Forming Phi'Phi squares the regressor's
     * condition: when the Cholesky fails or the column-equilibrated factor has numerical rank
     * below q at the reciprocal condition sqrt(machine epsilon), okid_identify() returns
     * OKID_E_DECOMPOSITION_FAILED and changes nothing (the data is gone: identify the record
     * again with least squares; the CLI and okid.identify() do so and set
     * OKID_W_CORRELATION_FALLBACK). Noise-free data with p above the minimum always trips this
     * guard. Same memory as least squares, plus w x w reals with block_rows 1.
     */
    OKID_ESTIMATOR_CORRELATION = 2
} okid_estimator;

/** Configuration of an identifier. okid_config_default() fills every field with a usable value. */
typedef struct okid_config {
    int num_inputs;          /**< r: inputs (forces) per sample, 1..OKID_MAX_DIMENSION */
    int num_outputs;         /**< m: outputs (sensors) per sample, 1..OKID_MAX_DIMENSION */
    int observer_order;      /**< p: observer Markov parameters identified, 1..OKID_MAX_HORIZON, m*p >= order */
    /**
     * n: model order (number of states), 1..min(alpha*m, beta*columns, m*p). 0 selects it
     * automatically: n is the index i of the largest ratio sigma_i / sigma_(i+1) between
     * consecutive Hankel singular values, i < min(alpha*m, beta*columns, m*p + 1); the workspace is
     * then sized for the largest order min(alpha*m, beta*columns, m*p). columns = r (system) or
     * r + m (combined).
     */
    int order;
    int hankel_rows;         /**< alpha: block rows of H(0) and H(1), 1..OKID_MAX_HORIZON */
    int hankel_cols;         /**< beta: block columns of H(0) and H(1), 1..OKID_MAX_HORIZON */
    /**
     * Regressor rows folded into the QR factor per update, 0..4096. 0 = automatic: with the LAPACK
     * backend 256 rows (128 or 64 when a block of 256 x w reals would not fit 2 MiB, w = q + m),
     * with the Eigen backend 32. The workspace holds two blocks (2 x block_rows x w reals).
     */
    int block_rows;
    okid_real dt;            /**< sample interval [s], finite and > 0 */
    /**
     * Exponential forgetting factor lambda in (0, 1]: a row folded k samples ago weighs
     * lambda^k. 1 (or 0, read as 1) keeps every sample with equal weight.
     */
    okid_real forgetting_factor;
    /**
     * Relative tolerance of the rank-revealing least squares (reciprocal condition number below
     * which columns of the column-equilibrated regressor count as dependent); 0 = 1e-10 (double)
     * or 1e-5 (float). A value in (0, machine epsilon of okid_real) is OKID_E_BAD_PARAMETER: below
     * round-off every column would count as independent.
     */
    okid_real rank_tolerance;
    okid_sensing sensing;          /**< what the outputs measure (eq. 64) */
    okid_realization realization;  /**< system (default) or combined with observer gain */
    /**
     * 1 when the record starts from rest (zero state, zero past inputs): the first p samples then
     * give regressor rows with zero history, as in eq. 49. 0 (default) waits for p samples.
     */
    int zero_initial_state;
    /**
     * Decimation factor K, 1..OKID_MAX_DECIMATION (0 is read as 1). K > 1 passes every pushed
     * input and output through the same anti-alias filter (Butterworth, order 2, -3 dB at half
     * the decimated Nyquist frequency, one biquad designed at init; docs/quality.md says why so
     * gentle) and keeps every K-th sample (pushed samples 0, K, 2K, ...) after a gap or reset. The
     * identified model and its modes have the sample interval K dt; p, alpha and beta count
     * decimated samples. One filter for inputs and outputs leaves the input-output dynamics as
     * they are. okid_predict() is not available with K > 1.
     */
    int decimation;
    okid_scaling scaling;      /**< per-channel scaling (default OKID_SCALING_NONE) */
    okid_estimator estimator;  /**< least squares (default) or instrumental variables */
    /**
     * Instrument lags L of OKID_ESTIMATOR_INSTRUMENTAL: r (L + 1) >= q and L >= p, at most
     * OKID_MAX_INSTRUMENT_LAGS. 0 selects ceil(q / r) + 2 p. Ignored by least squares.
     */
    int instrument_lags;
} okid_config;

/**
 * Fill a configuration with defaults for r inputs and m outputs: p = 20, automatic order,
 * alpha = beta = 20, dt = 1, no forgetting, default tolerance, acceleration sensing, system
 * realization, records not assumed to start at rest, no decimation, no scaling, least squares.
 * \param[out] cfg  configuration to fill
 * \param[in]  num_inputs  r
 * \param[in]  num_outputs m
 * \return OKID_OK, OKID_E_NULL_POINTER (the sizes are checked by okid_init())
 */
okid_status okid_config_default(okid_config *cfg, int num_inputs, int num_outputs);

/**
 * Set the observer order and the Hankel block rows and columns from horizons in seconds, for the
 * model's sample interval K dt (cfg->dt and cfg->decimation must be set first): each count is
 * seconds / (K dt) rounded to the nearest integer (halves up), at least 1. Example: dt = 0.01 s,
 * K = 5, 1 s gives 20 blocks. The configuration is left as it was on error.
 * \param[in,out] cfg                  configuration
 * \param[in]     observer_seconds     p K dt, the observer's memory
 * \param[in]     hankel_rows_seconds  alpha K dt
 * \param[in]     hankel_cols_seconds  beta K dt
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_PARAMETER (a horizon or dt not finite or <= 0),
 *         OKID_E_BAD_SIZE (decimation out of range, or a count above OKID_MAX_HORIZON)
 */
okid_status okid_config_horizons(okid_config *cfg, okid_real observer_seconds, okid_real hankel_rows_seconds,
                                 okid_real hankel_cols_seconds);

/** What okid_config_check() refused: the field, its value and the range valid for it with the other fields. */
typedef struct okid_config_issue {
    const char *field; /**< okid_config field name ("order", "dt", ...); "workspace bytes" when the
                            dimensions together exceed SIZE_MAX; NULL when the configuration is valid */
    double value;      /**< the field's value */
    double min, max;   /**< its valid range (rank_tolerance: 0, or min up to below max) */
} okid_config_issue;

/**
 * Check a configuration as okid_workspace_size() does, and say which field is wrong: messages can
 * name the value and the valid range instead of a status only.
 * \param[in]  cfg   configuration
 * \param[out] issue the first field refused (field NULL when valid)
 * \return the status okid_workspace_size() returns for cfg
 */
okid_status okid_config_check(const okid_config *cfg, okid_config_issue *issue);

/**
 * Check a configuration and compute the workspace it needs.
 * \param[in]  cfg   configuration
 * \param[out] bytes workspace bytes (the same as OKID_WORKSPACE_BYTES_OPTIONS for these values)
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (also when the dimensions, each in range,
 *         together need more than SIZE_MAX bytes: 4 GiB on a 32-bit target), OKID_E_BAD_ORDER,
 *         OKID_E_BAD_PARAMETER
 */
okid_status okid_workspace_size(const okid_config *cfg, size_t *bytes);

/**
 * Workspace bytes for a configuration, as a constant expression for static buffers:
 * \code
 *   static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char ws[OKID_WORKSPACE_BYTES(1, 2, 20, 20, 20, 4, 32, 0)];
 * \endcode
 * Arguments: r, m, p, alpha, beta, order (0 = automatic), block_rows (0 = default),
 * combined (1 for OKID_REALIZATION_COMBINED). Equals okid_workspace_size() for a valid configuration
 * without the quality options (see OKID_WORKSPACE_BYTES_OPTIONS). Computed in 64 bits; where the
 * size exceeds SIZE_MAX (32-bit targets) the value is SIZE_MAX, never a wrapped-around smaller
 * number: such an array does not compile, and okid_workspace_size() refuses with OKID_E_BAD_SIZE.
 */
#define OKID_WORKSPACE_BYTES(r, m, p, alpha, beta, order, block_rows, combined) \
    OKID__SIZE(OKID__WORKSPACE_BYTES64(r, m, p, alpha, beta, order, block_rows, combined))
/**
 * OKID_WORKSPACE_BYTES with the quality options: decimation (K, 0 or 1 = none), scaling
 * (okid_scaling), estimator (okid_estimator) and instrument_lags (0 = automatic). Equals
 * okid_workspace_size() for a valid configuration; saturates at SIZE_MAX like OKID_WORKSPACE_BYTES.
 */
#define OKID_WORKSPACE_BYTES_OPTIONS(r, m, p, alpha, beta, order, block_rows, combined, decimation, scaling,   \
                                     estimator, lags)                                                          \
    OKID__SIZE(OKID__WORKSPACE_OPTIONS_BYTES64(r, m, p, alpha, beta, order, block_rows, combined, decimation,     \
                                               scaling, estimator, lags))

/* ======== Lifetime ======== */

/**
 * An identifier: caller-owned (static, stack or heap), complete so that firmware can allocate it
 * statically; its members are private (okid/identifier_storage.h). Every call below checks it.
 */
typedef struct okid_identifier okid_identifier;

/**
 * Initialise an identifier over a caller-owned workspace. On error the identifier is left
 * uninitialised (every other call on it returns OKID_E_NOT_INITIALIZED).
 * \param[out] id            identifier to initialise
 * \param[in]  cfg           configuration (copied)
 * \param[in]  workspace     buffer of at least okid_workspace_size() bytes, aligned to OKID_WORKSPACE_ALIGN;
 *                           it must outlive the identifier and is used by nothing else meanwhile
 * \param[in]  bytes         size of the buffer
 * \param[out] bytes_needed  the size needed (also on OKID_E_WORKSPACE_TOO_SMALL); may be NULL
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_ORDER, OKID_E_BAD_PARAMETER,
 *         OKID_E_WORKSPACE_TOO_SMALL, OKID_E_WORKSPACE_ALIGNMENT
 */
okid_status okid_init(okid_identifier *id, const okid_config *cfg, void *workspace, size_t bytes,
                      size_t *bytes_needed);

/**
 * Forget every sample (configuration and workspace are kept).
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED
 */
okid_status okid_reset(okid_identifier *id);

/* ======== Data ======== */

/**
 * Push one sample: u(k) (r values) and y(k) (m values). A sample with a NaN or Inf is rejected:
 * no regressor row containing it is ever used, the regressor window restarts after it, and
 * everything folded in before is kept.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NONFINITE_SAMPLE,
 *         OKID_E_BAD_SIZE (a dimension too large for the backend), OKID_E_BACKEND_ARGUMENT
 */
okid_status okid_push(okid_identifier *id, const okid_real *u, const okid_real *y);

/**
 * Push count samples: sample k is u[k*ldu .. k*ldu + r - 1] and y[k*ldy .. k*ldy + m - 1]
 * (column-major r x count and m x count). Exactly equivalent to count calls of okid_push():
 * a non-finite sample is rejected and the later ones are still used.
 * \param[out] accepted samples accepted (may be NULL)
 * \return OKID_OK when all were accepted; OKID_E_NONFINITE_SAMPLE when one or more were rejected;
 *         OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (ldu < r or ldy < m), OKID_E_NOT_INITIALIZED (nothing pushed)
 */
okid_status okid_push_block(okid_identifier *id, size_t count, const okid_real *u, size_t ldu,
                            const okid_real *y, size_t ldy, size_t *accepted);

/**
 * Set the channel scales of OKID_SCALING_AUTO yourself (e.g. from the sensors' ranges) instead of
 * the first block's RMS. Only before the first block of rows is folded (after init or reset; an
 * okid_identify() does not fold); okid_reset() forgets them.
 * \param[in,out] id             identifier configured with OKID_SCALING_AUTO
 * \param[in]     input_scales   r values, finite and > 0
 * \param[in]     output_scales  m values, finite and > 0
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_PARAMETER (a scale not
 *         finite or not > 0: nothing is changed), OKID_E_NOT_AVAILABLE (no scaling configured, or
 *         rows already folded with other scales)
 */
okid_status okid_set_scales(okid_identifier *id, const okid_real *input_scales, const okid_real *output_scales);

/* ======== Results ======== */

/** Counters of an identifier, for progress displays. */
typedef struct okid_progress {
    uint64_t samples;       /**< samples accepted since init or reset */
    uint64_t rejected;      /**< samples rejected as non-finite */
    uint64_t rows;          /**< regressor rows folded into the least squares (pending ones included) */
    int rows_needed;        /**< rows needed before okid_identify() can succeed (the number of unknowns q) */
    /**
     * Rows the forgetting factor lambda still weighs above the rank tolerance (lambda^(age/2) >=
     * tolerance: 1 + 2 ln(tolerance) / ln(lambda) of them at most), or rows without forgetting.
     * Below rows_needed, okid_identify() returns OKID_E_NOT_ENOUGH_DATA: the memory is too short.
     */
    uint64_t rows_remembered;
} okid_progress;

/** The identified model. Every pointer points into the identifier's workspace. */
typedef struct okid_result {
    int order;                       /**< n, the realized order */
    int num_modes;                   /**< modes reported (conjugate pairs once) */
    const okid_mode *modes;          /**< sorted by frequency, then damping */
    okid_matrix A;                   /**< n x n */
    okid_matrix B;                   /**< n x r */
    okid_matrix C;                   /**< m x n */
    okid_matrix D;                   /**< m x r */
    okid_matrix G;                   /**< n x m observer gain (combined realization); data NULL otherwise */
    const okid_real *singular_values;/**< Hankel singular values, decreasing */
    int num_singular_values;
    okid_matrix markov;              /**< [Y_0 Y_1 ... Y_L], m x r(L+1), L = alpha + beta (eq. 51) */
    okid_matrix observer_gain_markov;/**< [Y°_1 ... Y°_L], m x mL (eq. 53); data NULL for system realization */
    okid_real dt;                    /**< sample interval of the model [s] */
    uint64_t samples;                /**< samples accepted */
    uint64_t rows;                   /**< regressor rows in the least squares */
    int regressor_rank;              /**< numerical rank of the regressor */
    int regressor_columns;           /**< q = r + (r + m) p */
    int input_rank;                  /**< numerical rank of the input part: r (p + 1) when persistently exciting */
    unsigned warnings;               /**< okid_warning bits */
    int regressor_rank_expected;     /**< min(q, r (p + 1) + n): the rank of noise-free data from an n-state system */
    /**
     * 1-norm condition number |R|_1 |R^-1|_1 of the column-equilibrated regressor factor R = R11
     * (computed exactly, O(q^3 / 6); within a factor q of the regressor's 2-norm condition; +inf when
     * singular): how much the least squares amplifies errors. Noise-free data with p above the
     * minimum makes it huge.
     */
    okid_real lsq_condition;
    /** The same for the input columns (leading r (p + 1)) alone: large when the input barely excites. */
    okid_real input_condition;
    /** sigma_1 / sigma_n of the Hankel matrix H(0) at the realized order n. */
    okid_real realization_condition;
    int decimation;                  /**< K: the model's dt is K times the pushed samples' interval */
    int instrument_lags;             /**< L of OKID_ESTIMATOR_INSTRUMENTAL (the automatic value resolved); 0 for least squares */
    /** Scale of each input (r values) and output (m values) with OKID_SCALING_AUTO; NULL otherwise. */
    const okid_real *input_scales, *output_scales;
} okid_result;

/**
 * Identify from everything pushed so far: observer Markov parameters (eq. 50) by rank-revealing
 * least squares, system and observer-gain Markov parameters (eq. 51, 53), ERA (eq. 57-61) and
 * modal parameters (eq. 63-64). Pushing can go on afterwards; calling it twice gives the same
 * result. A transaction: on failure every observable stays as it was (the last result and its
 * views, okid_predict(), the counters, okid_set_scales()'s availability), and no call, failed or
 * not, changes a later result (rows still pending in the block are folded into a copy of the
 * factor). The views in result stay valid until the next successful okid_identify(), okid_reset()
 * or okid_init() on this identifier.
 * \param[in,out] id     identifier
 * \param[out]    result filled on OKID_OK; untouched otherwise
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_ENOUGH_DATA,
 *         OKID_E_RANK_DEFICIENT, OKID_E_DECOMPOSITION_FAILED, OKID_E_BACKEND_ARGUMENT,
 *         OKID_E_DATA_RANGE (a channel's RMS outside [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX], or
 *         results that would not be finite)
 */
okid_status okid_identify(okid_identifier *id, okid_result *result);

/**
 * One-step-ahead prediction of y(k) from u(k) and the last p samples, with the observer Markov
 * parameters of the last successful okid_identify() (eq. 35: y(k) = D u(k) + sum_j Ybar_j v(k-j)).
 * Call it before pushing sample k; y(k) - y_hat is the innovation, a fault or change indicator.
 * \param[in]  id     identifier
 * \param[in]  u      u(k), r values
 * \param[out] y_hat  m values
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_AVAILABLE (no
 *         identification yet, or decimation > 1), OKID_E_NOT_ENOUGH_DATA (fewer than p samples since the start or
 *         the last gap), OKID_E_NONFINITE_SAMPLE
 */
okid_status okid_predict(const okid_identifier *id, const okid_real *u, okid_real *y_hat);

/**
 * Read the counters.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED
 */
okid_status okid_get_progress(const okid_identifier *id, okid_progress *progress);


#ifdef __cplusplus
}
#endif

#include "okid/identifier_storage.h" /* the struct's members: not API */

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file refine.h
 * \brief Prediction-error (output-error maximum-likelihood) refinement of an identified model,
 *        streamed over the record in passes, with the standard deviation of every mode.
 *
 * OKID/ERA is consistent but not efficient: under output noise its modes scatter two to five
 * times more than the Cramer-Rao bound allows. Starting from its model, the refinement minimises
 * the Gaussian negative log-likelihood of the output error, (N/2) sum_i log(sum_k e_i(k)^2), with
 * e(k) = y(k) - C x(k) - D u(k), x(k+1) = A x(k) + B u(k), by Levenberg-Marquardt on the real
 * modal form: A block diagonal with one 2 x 2 block [Re l, Im l; -Im l, Re l] per complex pair
 * and a 1 x 1 block per real eigenvalue, one entry of B per mode fixed (the mode's coordinate
 * scale), C, D and the initial state free. Parameters: n (r + m + 1) + m r at most. With
 * okid_refine_config::refine_model = OKID_REFINE_INNOVATION the predictor is the innovation form
 * x(k+1) = A x + B u + K e with K free as well (n m more parameters): the maximum-likelihood
 * estimate when forces nobody measures act (okid_refine_model).
 *
 * The identifier keeps no record, so the caller feeds it once per pass in blocks of any size
 * (from RAM, flash, a file): okid_refine_begin_pass(), okid_refine_push_block() ...,
 * okid_refine_end_pass(), which says whether another pass is needed. Pass 1 measures the starting
 * model's residuals (the channel weights); every later pass evaluates one candidate model and
 * its Jacobian (forward sensitivities, O(parameters^2 m) per sample). The refiner keeps only
 * parameter-sized state. Every pass must feed the same samples: the record the model describes,
 * at its sample interval (not a model of okid_config::decimation's filtered record: refine one
 * identified without it, or one identified on the lifted record of okid_lift()).
 *
 * \code
 *   okid_refine_config rc; okid_refine_config_default(&rc);
 *   size_t bytes; okid_refine_workspace_size(res.order, r, m, &bytes);
 *   okid_refiner rf; okid_refine_init(&rf, &rc, &res, OKID_SENSING_ACCELERATION, ws, bytes, NULL);
 *   okid_refine_state st = OKID_REFINE_NEED_PASS;
 *   while (st == OKID_REFINE_NEED_PASS) {
 *       okid_refine_begin_pass(&rf);
 *       for (each block) okid_refine_push_block(&rf, count, u, r, y, m);
 *       okid_refine_end_pass(&rf, &st);
 *   }
 *   okid_refine_result out; okid_refine_get_result(&rf, &out);  // modes and their std
 * \endcode
 */
#ifndef OKID_REFINE_H
#define OKID_REFINE_H

#include <stddef.h>
#include <stdint.h>

#include "okid/identifier.h"
#include "okid/modal.h"
#include "okid/sizes.h"
#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Where a refinement stands after a pass. */
typedef enum okid_refine_state {
    /** Feed the record once more. */
    OKID_REFINE_NEED_PASS = 0,
    /**
     * The Gauss-Newton step is below step_tolerance (or, on noise-free data, the model reproduces
     * the record to within 1000 epsilon relative RMS): the estimate is the maximum-likelihood one.
     */
    OKID_REFINE_CONVERGED = 1,
    /**
     * The starting model's predictions are not finite over the record (or no damped step keeps
     * the model stable and finite): nothing was refined; the result is the starting model.
     */
    OKID_REFINE_DIVERGED = 2,
    /** The damping grew to its limit without lowering the cost: the best model so far is kept. */
    OKID_REFINE_NOT_IMPROVING = 3,
    /** max_passes were fed before convergence: the best model so far is kept. */
    OKID_REFINE_ITERATION_LIMIT = 4
} okid_refine_state;

/**
 * Which predictor the refinement fits (docs/refinement.md, "Innovation form").
 */
typedef enum okid_refine_model {
    /**
     * Output error: yhat(k) = C x(k) + D u(k), x(k+1) = A x(k) + B u(k), the simulation from the
     * inputs alone. The maximum-likelihood estimate when only white output noise acts.
     */
    OKID_REFINE_OUTPUT_ERROR = 0,
    /**
     * Innovation form: the one-step predictor x(k+1) = A x(k) + B u(k) + K e(k), e(k) = y(k) -
     * C x(k) - D u(k), with the gain K (n x m) free as well. The maximum-likelihood estimate when
     * forces nobody measures (process noise) act besides the output noise. K starts from the OKID
     * observer gain (K = -G of a combined realization) when the start model has one and A - K C
     * is stable, else from K = 0 (the output-error predictor); every step keeps A - K C strictly
     * inside the unit circle. n m more parameters, and n (not 2) sensitivities per parameter.
     */
    OKID_REFINE_INNOVATION = 1
} okid_refine_model;

/** Settings of a refinement (docs/refinement.md); okid_refine_config_default() fills them. */
typedef struct okid_refine_config {
    /**
     * Passes over the record at most (the first measures the channel weights), 2..1000; 0 =
     * OKID_REFINE_MAX_PASSES.
     */
    int max_passes;
    /**
     * Converged when the Gauss-Newton decrement g' N^-1 g (the expected decrease of twice the
     * negative log-likelihood; a step of s standard deviations gives about s^2) falls below it.
     * Finite, >= 0; 0 = OKID_REFINE_STEP_TOLERANCE: 1e-6 in double (steps of a thousandth of a
     * standard deviation), 1e-2 in float (a tenth: float's round-off in the normal equations of a
     * long record is larger than 1e-6; a smaller value then ends in OKID_REFINE_NOT_IMPROVING).
     */
    okid_real step_tolerance;
    /** The predictor fitted: OKID_REFINE_OUTPUT_ERROR (the default) or OKID_REFINE_INNOVATION. */
    okid_refine_model refine_model;
} okid_refine_config;

/**
 * The default max_passes: 100. On the simulated benchmark records (white noise, an unmeasured
 * force, a drift; 200 + 50 + 50 records) the output-error form converged in at most 17 passes, the
 * innovation form in at most 85 (docs/refinement.md, "Passes"). A run that converged within the
 * former default 30 gives the same bits.
 */
#define OKID_REFINE_MAX_PASSES 100

/** The default step_tolerance for the working precision. */
#if OKID_REAL_IS_FLOAT
#define OKID_REFINE_STEP_TOLERANCE 1e-2f
#else
#define OKID_REFINE_STEP_TOLERANCE 1e-6
#endif

/**
 * The residual tests of every refined result (docs/refinement.md): the normalised autocorrelation
 * r_l = sum_k e(k) e(k-l) / sum_k e(k)^2 of each output's residual at lags 1..OKID_REFINE_LAGS and
 * its Ljung-Box statistic Q = N (N + 2) sum_l r_l^2 / (N - l), chi-square with OKID_REFINE_LAGS
 * degrees of freedom when the residual is white. OKID_REFINE_WHITENESS_BOUND is its 99.9 % quantile
 * (scipy.stats.chi2.ppf(0.999, 20) = 45.315): each output raises a false alarm on 0.1 % of white
 * records (a false alarm only swaps the Fisher stds for the sandwich ones), while an unmeasured
 * force or a drift gives Q in the hundreds to tens of thousands. An output the model reproduces
 * to round-off (residual RMS below 1000 epsilon of its RMS: noise-free data) fails no test.
 */
#define OKID_REFINE_LAGS ((int)OKID__REFINE_LAGS)
#define OKID_REFINE_WHITENESS_BOUND 45.3147
/**
 * The input-residual cross-correlation test (docs/refinement.md, Ljung 1999, section 16.6): per
 * (output i, input j) pair the centred, normalised cross-correlation
 * rho(l) = sum_k e_i(k) u_j(k - l) / sqrt(sum_k e_i(k)^2 sum_k u_j(k)^2), l = 0..OKID_REFINE_LAGS-1
 * (the input leading: a model that misses some of the input's dynamics, too low an order, a wrong
 * D, leaves residuals that the past input predicts; negative lags would test feedback from the
 * output into the input, not the model, so they are not tested). When the residual is independent
 * of the input each rho(l) is asymptotically normal with variance v / N, v = 1 + 2 sum_k r_e(k)
 * r_u(k) (Bartlett's formula over the lags held, at least 1), whatever the colour of either. The
 * statistic (okid_refine_result::input_correlation) is max_l |rho(l)| sqrt(N / v), compared with
 * the two-sided normal quantile for 0.1 % split over the OKID_REFINE_LAGS lags (Bonferroni:
 * NormalDist().inv_cdf(1 - 0.001 / 40) = 4.0556): a false alarm on at most 0.1 % of independent
 * (input, output) pairs, m r x 0.1 % of records at most. Above it the output gets
 * OKID_W_RESIDUAL_INPUT_CORRELATED.
 */
#define OKID_REFINE_INPUT_CORRELATION_BOUND 4.0556
/** Below this fit [%] (100 (1 - |e| / |y - mean y|)) an output is OKID_W_OUTPUT_NOT_EXPLAINED. */
#define OKID_REFINE_FIT_LOW 50.0
/**
 * The sandwich covariance sums the score over this many consecutive blocks of the record (batch
 * means of the score: valid when the residual's correlation is shorter than N / blocks samples).
 */
#define OKID_REFINE_SCORE_BLOCKS 20

/** Which covariance the standard deviations of a refined result come from. */
typedef enum okid_refine_covariance {
    /** The inverse Fisher information: exact when every output's residual is white. */
    OKID_REFINE_COVARIANCE_FISHER = 0,
    /**
     * The sandwich H^-1 S H^-1 (H the Fisher information, S the covariance of the score estimated
     * from its sums over OKID_REFINE_SCORE_BLOCKS blocks of the record): used when an output's
     * residual is not white (OKID_W_RESIDUAL_NOT_WHITE), where the Fisher-based stds are too small.
     */
    OKID_REFINE_COVARIANCE_SANDWICH = 1
} okid_refine_covariance;

/** Standard deviations of one mode, from the covariance okid_refine_result::covariance names. */
typedef struct okid_mode_std {
    okid_complex eigenvalue;   /**< std of Re and of Im of the discrete eigenvalue */
    okid_complex pole;         /**< std of Re and of Im of the continuous pole [1/s] */
    okid_real frequency_hz;    /**< std of the undamped natural frequency [Hz] */
    okid_real damping_ratio;   /**< std of the damping ratio */
    /** m values: std of Re and of Im of each component of the normalised okid_mode::sensor_shape. */
    const okid_complex *sensor_shape;
} okid_mode_std;

/** The refined model. Every pointer points into the refiner's workspace. */
typedef struct okid_refine_result {
    okid_refine_state state;
    int passes;                 /**< passes fed */
    int iterations;             /**< accepted Levenberg-Marquardt steps */
    int num_parameters;         /**< free parameters */
    int order;                  /**< n */
    int num_modes;
    const okid_mode *modes;     /**< sorted by frequency, then damping; indicators other than mpc are -1 */
    const okid_mode_std *mode_std; /**< num_modes entries, in the order of modes */
    okid_matrix A, B, C, D;     /**< the model in real modal form */
    okid_refine_model refine_model; /**< the predictor fitted (okid_refine_config::refine_model) */
    /** the innovation gain (n x m, modal form) of OKID_REFINE_INNOVATION; data NULL, 0 columns otherwise */
    okid_matrix K;
    const okid_real *initial_state; /**< n values: the estimated x(0) */
    /** m values: residual RMS of each output at the start (the starting model) and at the end. */
    const okid_real *residual_rms_start, *residual_rms;
    /**
     * The final cost: (N/2) sum_i log(s_i / N) (estimated noise) or sum_i s_i / (2 sigma_i^2)
     * (okid_refine_set_noise), N samples, s_i output i's residual sum of squares. Lower is more
     * likely: refinements of the same record from different starts compare by it. Not finite
     * when the refinement diverged.
     */
    okid_real cost;
    /**
     * The Gauss-Newton decrement g' N^-1 g at the returned model (about the squared step still to
     * go, in standard deviations), in the units of step_tolerance: below it when converged; when
     * the refinement stopped at max_passes it says how far it was (a few step_tolerance: more
     * passes will converge; orders of magnitude more: a slow valley, often a model that does not
     * describe the record, see the residual tests). -1 when the Gauss-Newton matrix at the
     * returned model is singular, or no Jacobian pass was completed.
     */
    okid_real decrement;
    okid_real dt;
    uint64_t samples;           /**< samples per pass */
    /** okid_warning bits of the refined modes and of the residual tests (not the start model's) */
    unsigned warnings;
    /**
     * OKID_W_MODE_SPLIT: indices into modes of the first two complex pairs found to be one mode split
     * in two (the rule of OKID_W_MODE_SPLIT); -1, -1 when none
     */
    int split_modes[2];
    /**
     * m values: the residual tests' okid_warning bits of each output (OKID_W_RESIDUAL_NOT_WHITE,
     * OKID_W_RESIDUAL_INPUT_CORRELATED: input_correlation says which inputs, OKID_W_OUTPUT_NOT_EXPLAINED)
     */
    const unsigned *output_warnings;
    /** m values: each output's Ljung-Box statistic Q (-1 when diverged) */
    const okid_real *whiteness;
    /** m values: each output's largest |r_l|, l = 1..OKID_REFINE_LAGS (-1 when diverged) */
    const okid_real *max_autocorrelation;
    /** 1.96 / sqrt(N): the 95 % band of each r_l for a white residual */
    okid_real autocorrelation_band;
    /** m values: each output's fit in percent, 100 (1 - |e| / |y - mean y|) (-1 when diverged) */
    const okid_real *fit_percent;
    /**
     * m x r values, output i and input j at [i + m j]: the cross-correlation statistic
     * max_l |rho_ij(l)| sqrt(N / v_ij), l = 0..OKID_REFINE_LAGS-1 (OKID_REFINE_INPUT_CORRELATION_BOUND;
     * -1 when diverged or the input or residual is constant)
     */
    const okid_real *input_correlation;
    /** m x r values ([i + m j]): the largest |rho_ij(l)|, l = 0..OKID_REFINE_LAGS-1 (-1 as above) */
    const okid_real *max_input_correlation;
    /** m x r values ([i + m j]): the band of |rho_ij(l)|, OKID_REFINE_INPUT_CORRELATION_BOUND sqrt(v_ij / N) */
    const okid_real *input_correlation_band;
    /** the covariance mode_std comes from */
    okid_refine_covariance covariance;
    /**
     * OKID_OK: every value of mode_std is a standard deviation. Otherwise the ones that cannot be
     * computed are -1 and this says why: OKID_E_RANK_DEFICIENT (the Fisher information is
     * singular at working precision: the record does not determine every parameter, e.g. a
     * constant force, an unexcited or unobserved mode), OKID_E_DATA_RANGE (a mode has no
     * continuous-time pole, a real non-positive eigenvalue, or a standard deviation is not
     * finite), OKID_E_NOT_AVAILABLE (the refinement diverged: no covariance).
     */
    okid_status std_status;
} okid_refine_result;

/**
 * The refiner: caller-owned (static, stack or heap), complete so that firmware can allocate it
 * statically; its members are private (okid/refine_storage.h).
 */
typedef struct okid_refiner okid_refiner;

/** Parameters of the refinement of an n-state model with r inputs and m outputs (at most). */
#define OKID_REFINE_PARAMETERS(n, r, m) ((size_t)OKID__REFINE_PARAMETERS64(n, r, m))

/**
 * Workspace bytes of a refinement of an n-state model with r inputs and m outputs, at compile
 * time (equal to okid_refine_workspace_size(); checked by test_refine). Computed in 64 bits; where
 * the size exceeds SIZE_MAX (n = 512, r = m = 64 on a 32-bit target: the normal matrix alone is
 * 70144^2 reals) the value is SIZE_MAX, never a wrapped-around smaller number, and
 * okid_refine_workspace_size() refuses with OKID_E_BAD_SIZE (test_workspace_overflow).
 */
#define OKID_REFINE_WORKSPACE_BYTES(n, r, m) OKID__SIZE(OKID__REFINE_WORKSPACE_BYTES64(n, r, m))

/**
 * Workspace bytes of a refinement fitting the given okid_refine_model (equal to
 * okid_refine_model_workspace_size(); OKID_REFINE_WORKSPACE_BYTES is the output-error one).
 */
#define OKID_REFINE_MODEL_WORKSPACE_BYTES(model, n, r, m) \
    OKID__SIZE(OKID__REFINE_MODEL_WORKSPACE_BYTES64((model) == OKID_REFINE_INNOVATION, n, r, m))

/**
 * Fill the settings with their defaults: max_passes OKID_REFINE_MAX_PASSES, step_tolerance OKID_REFINE_STEP_TOLERANCE,
 * refine_model OKID_REFINE_OUTPUT_ERROR.
 * \return OKID_OK, OKID_E_NULL_POINTER
 */
okid_status okid_refine_config_default(okid_refine_config *cfg);

/**
 * Workspace bytes a refinement of an n-state model with r inputs and m outputs needs.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (n outside 1..OKID_MAX_ORDER, r or m
 *         outside 1..OKID_MAX_DIMENSION, or more than SIZE_MAX bytes: 4 GiB on a 32-bit target)
 */
okid_status okid_refine_workspace_size(int n, int r, int m, size_t *bytes);

/**
 * Workspace bytes a refinement fitting model needs (okid_refine_workspace_size() is the output-error one).
 * \return as okid_refine_workspace_size(), and OKID_E_BAD_PARAMETER (model not an okid_refine_model)
 */
okid_status okid_refine_model_workspace_size(okid_refine_model model, int n, int r, int m, size_t *bytes);

/**
 * Start a refinement from an identified model (its A, B, C, D and dt). Unstable eigenvalues are
 * reflected into the unit circle.
 * \param[in] start    a result of okid_identify() (or any model in that form)
 * \param[in] sensing  what the outputs measure (the shapes' eq. 64 power)
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER (a setting out of
 *         range, model, dt, sensing, a non-finite matrix entry or observer gain),
 *         OKID_E_WORKSPACE_TOO_SMALL (size it with okid_refine_model_workspace_size()),
 *         OKID_E_WORKSPACE_ALIGNMENT, OKID_E_DECOMPOSITION_FAILED (A has no eigenvector basis),
 *         OKID_E_RANK_DEFICIENT (a mode that no input drives: B has a zero row in modal form)
 */
okid_status okid_refine_init(okid_refiner *rf, const okid_refine_config *cfg, const okid_result *start,
                             okid_sensing sensing, void *workspace, size_t bytes, size_t *bytes_needed);

/**
 * Fix the standard deviation of each output's noise (sensor specifications, or a planned
 * experiment) instead of estimating it from the residuals. Call it after okid_refine_init() and
 * before the first pass: the cost becomes sum_i s_i / (2 sigma_i^2) and the residual pass is
 * skipped. The Cramer-Rao bound of an experiment is the refinement of its true model over its
 * noise-free record with the planned noise: the first pass converges at once (zero residuals)
 * and okid_refine_result::mode_std holds the bound (okid crlb, docs/refinement.md).
 * The bound is linear in the noise: the weights are computed relative to a power of two near the
 * largest noise_std, so any finite positive noise (1e-200 or 1e200) gives a finite bound.
 * \param[in] noise_std  m values, finite and > 0, within a factor ~1e150 of each other (double)
 * 
eturn OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_PARAMETER (a value
 *         not finite or not > 0: nothing changes), OKID_E_NOT_AVAILABLE (a pass has begun)
 */
okid_status okid_refine_set_noise(okid_refiner *rf, const okid_real *noise_std);

/**
 * Begin a pass: the next samples pushed are the record from its first sample on.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_AVAILABLE (the
 *         refinement has finished)
 */
okid_status okid_refine_begin_pass(okid_refiner *rf);

/**
 * Feed count samples of the record (u: r x count, leading dimension ldu; y: m x count, ldy).
 * A sample with a non-finite output is left out of the cost (the model still runs through it).
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_SIZE (ldu < r, ldy < m),
 *         OKID_E_NOT_AVAILABLE (no pass begun), OKID_E_NONFINITE_SAMPLE (an input is not finite:
 *         the pass is void, begin it again; the refinement's state is unchanged)
 */
okid_status okid_refine_push_block(okid_refiner *rf, size_t count, const okid_real *u, size_t ldu,
                                   const okid_real *y, size_t ldy);

/**
 * End a pass and take the step it allows.
 * \param[out] state  OKID_REFINE_NEED_PASS, or the reason the refinement finished
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_AVAILABLE (no pass
 *         begun), OKID_E_NOT_ENOUGH_DATA (m samples <= parameters: nothing changes),
 *         OKID_E_BAD_SIZE (the pass fed another number of samples than the first: the pass is void)
 */
okid_status okid_refine_end_pass(okid_refiner *rf, okid_refine_state *state);

/**
 * Read the refined model, its modes and their standard deviations (after the refinement
 * finished; the views stay valid until the next okid_refine_init() on this refiner).
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_AVAILABLE (not finished)
 */
okid_status okid_refine_get_result(const okid_refiner *rf, okid_refine_result *result);

/** The name of a refinement model ("output_error", "innovation"; "unknown" otherwise; never NULL). */
const char *okid_refine_model_str(okid_refine_model model);

/** A short, static description of a refinement state (never NULL). */
const char *okid_refine_state_str(okid_refine_state state);

#ifdef __cplusplus
}
#endif

#include "okid/refine_storage.h" /* the refiner's members: not API */

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file status.h
 * \brief Status codes returned by every okid entry point.
 *
 * Errors are negative, OKID_OK is zero. Warnings are reported apart from errors, as a bit set in
 * the identification result (okid_result::warnings), never as a return value.
 */
#ifndef OKID_STATUS_H
#define OKID_STATUS_H

#ifdef __cplusplus
extern "C" {
#endif

typedef enum okid_status {
    OKID_OK = 0,
    /** A required pointer argument is NULL. */
    OKID_E_NULL_POINTER = -1,
    /**
     * A size is zero, negative, above OKID_MAX_DIMENSION, or an array's leading dimension is too
     * small; or sizes that are each in range together need a workspace above SIZE_MAX bytes (4 GiB
     * on a 32-bit target).
     */
    OKID_E_BAD_SIZE = -2,
    /**
     * The model order does not fit: m*p < n, the Hankel matrix is smaller than the order, n < 1, or
     * (Eigen backend) n exceeds the OKID_EIGEN_MAX_ORDER the library was built with.
     */
    OKID_E_BAD_ORDER = -3,
    /**
     * A real parameter is out of range or not finite (dt or K dt outside [OKID_MAGNITUDE_MIN,
     * OKID_MAGNITUDE_MAX], forgetting factor outside (0, 1], tolerance < 0...).
     */
    OKID_E_BAD_PARAMETER = -4,
    /** The workspace is smaller than okid_workspace_size() says; the size needed is reported. */
    OKID_E_WORKSPACE_TOO_SMALL = -5,
    /** The workspace is not aligned to OKID_WORKSPACE_ALIGN bytes. */
    OKID_E_WORKSPACE_ALIGNMENT = -6,
    /** The identifier was not initialised by okid_init() (or was corrupted). */
    OKID_E_NOT_INITIALIZED = -7,
    /** A sample holds NaN or Inf: it was rejected and the regressor window restarts after it. */
    OKID_E_NONFINITE_SAMPLE = -8,
    /**
     * Fewer regressor rows than unknowns have been folded in (push more samples), or the forgetting
     * factor remembers fewer than that (okid_progress::rows_remembered: raise it towards 1).
     */
    OKID_E_NOT_ENOUGH_DATA = -9,
    /** The input is not persistently exciting (zero or constant force), or the chosen order exceeds the Hankel rank. */
    OKID_E_RANK_DEFICIENT = -10,
    /** A decomposition (QR, SVD, eigenvalues) did not converge. */
    OKID_E_DECOMPOSITION_FAILED = -11,
    /** The linear-algebra backend rejected an argument (an internal error: please report it). */
    OKID_E_BACKEND_ARGUMENT = -12,
    /** A result to read does not exist (e.g. the observer gain of a system-only realization). */
    OKID_E_NOT_AVAILABLE = -13,
    /**
     * A property of the data, not of the settings: a channel's RMS in the regressor lies outside
     * [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX] (rescale it, or use OKID_SCALING_AUTO), or the
     * results would not be finite numbers.
     */
    OKID_E_DATA_RANGE = -14
} okid_status;

/** Warning bits of okid_result::warnings: the result is usable but deserves a look. */
enum okid_warning {
    /** The regressor is numerically rank deficient (noise-free data with p above the minimum is the usual cause). */
    OKID_W_REGRESSOR_RANK_DEFICIENT = 1u << 0,
    /** At least one identified discrete eigenvalue lies on or outside the unit circle. */
    OKID_W_UNSTABLE_POLE = 1u << 1,
    /** At least one identified eigenvalue is real and non-positive, so it has no continuous-time counterpart. */
    OKID_W_NONPHYSICAL_POLE = 1u << 2,
    /** The automatic order rule met the maximum order the Hankel matrix allows. */
    OKID_W_ORDER_AT_LIMIT = 1u << 3,
    /**
     * The regressor's numerical rank is below min(q, r (p + 1) + n), the rank that data from an
     * n-state system has: the order is larger than the data supports, or some mode is not excited.
     */
    OKID_W_RANK_BELOW_MODEL = 1u << 4,
    /**
     * The input is only weakly persistently exciting: the condition number (okid_result::input_condition)
     * of its column-equilibrated regressor factor exceeds 1 / sqrt(rank tolerance); near 1 / tolerance the
     * input rank drops and okid_identify() fails with OKID_E_RANK_DEFICIENT.
     */
    OKID_W_WEAK_EXCITATION = 1u << 5,
    /**
     * The data is (near) noise-free and m p > n: even at the looser tolerance sqrt(rank tolerance) the
     * equilibrated regressor's numerical rank is at most r (p + 1) + n (noise would fill every column).
     * The observer Markov parameters are then not unique (the system ones are); p = ceil(n / m) gives
     * the unique deadbeat observer.
     */
    OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM = 1u << 6,
    /**
     * The Hankel span (alpha + beta) dt is shorter than 0.9 times the period of the slowest consistent
     * mode (a stable complex pair with CMI >= 0.5): the window sees less than about one period.
     */
    OKID_W_HANKEL_SPAN_SHORT = 1u << 7,
    /** The realization condition sigma_1 / sigma_n of H(0) exceeds 1 / sqrt(machine epsilon). */
    OKID_W_REALIZATION_ILL_CONDITIONED = 1u << 8,
    /**
     * Refinement (okid_refine_result): an output's residual is not white (its Ljung-Box statistic
     * over OKID_REFINE_LAGS lags exceeds OKID_REFINE_WHITENESS_BOUND): a force nobody measured, a
     * drift, or too low an order. The standard deviations are then the sandwich ones.
     * okid_refine_result::output_warnings says which output.
     */
    OKID_W_RESIDUAL_NOT_WHITE = 1u << 9,
    /**
     * Refinement: the model explains less than half of an output (fit below OKID_REFINE_FIT_LOW
     * percent): a drift, an offset, a sensor the model does not describe.
     */
    OKID_W_OUTPUT_NOT_EXPLAINED = 1u << 10,
    /**
     * Set by the tools that hold the whole record (CLI, okid.identify()), never by okid_identify():
     * the correlation estimator's guard refused (OKID_ESTIMATOR_CORRELATION), and the record was
     * identified again with the QR fold (least squares), whose result this is (SLICOT IWARN = 2).
     */
    OKID_W_CORRELATION_FALLBACK = 1u << 11,
    /**
     * Set by the tools that hold the whole record (CLI, okid.identify()), never by okid_identify():
     * the model's response from rest explains less than OKID_REFINE_FIT_LOW percent of every
     * output (MATLAB's compare fit; host_tools/common/output_fit.h): pure noise, or an input that
     * does not drive the outputs. OKID_W_OUTPUT_NOT_EXPLAINED is the refinement's bit for one output.
     */
    OKID_W_NO_OUTPUT_EXPLAINED = 1u << 12,
    /**
     * Refinement (okid_refine_result): an output's residual is correlated with an input (the
     * cross-correlation statistic over lags 0..OKID_REFINE_LAGS-1 exceeds
     * OKID_REFINE_INPUT_CORRELATION_BOUND): the model misses some of the input's dynamics (too low
     * an order, a wrong D, a mode the start did not have). okid_refine_result::output_warnings says
     * which output, okid_refine_result::input_correlation which input.
     */
    OKID_W_RESIDUAL_INPUT_CORRELATED = 1u << 13,
    /**
     * Set by the identifier FMU (all_poles false, order 0), by okid identify (the JSON) and
     * okid.identify() / okid.identify_ambient() without an order, never by okid_identify(): the
     * automatic selection (okid/mode_selection.h) found no physical mode, so no mode is published
     * (num_modes 0; the CLI's table says why on its "no physical mode found" line).
     */
    OKID_W_NO_PHYSICAL_MODE = 1u << 14,
    /**
     * Refinement (okid_refine_result): two refined complex pairs are one mode split in two: the
     * same sensor shape (MAC >= the mode selection's mac_min) and either inside the mode
     * selection's clustering gates of each other or with frequencies their standard deviations
     * cannot tell apart (lib/src/analysis/refine_split.c). The order is higher than the record supports
     * there; okid_refine_result::split_modes says which pairs.
     */
    OKID_W_MODE_SPLIT = 1u << 15
};

/** A short, static, human-readable description of a status (never NULL, also for unknown codes). */
const char *okid_status_str(okid_status status);

/** A short, static description of one warning bit (never NULL). */
const char *okid_warning_str(unsigned warning_bit);

#ifdef __cplusplus
}
#endif

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file ambient.h
 * \brief Output-only (ambient, operational) identification: modes from the responses alone, no
 *        measured force (covariance-driven SSI, NExT-ERA).
 *
 * An unmeasured white force excites the structure; the outputs' correlations are then
 *   R(k) = E[y(t+k) y_ref(t)'] = C A^(k-1) G,  k >= 1,  G = E[x(t+1) y_ref(t)'],
 * Markov parameters in all but name. Push accumulates, sample by sample, the sums
 *   S(k) = sum_t y(t+k) y_ref(t)',  k = 0 .. 2L,
 * over a ring of the last 2L reference samples (push_block: in batches of samples, one matrix
 * product per lag; docs/ambient.md "Batched sums"), so any record length takes the same memory;
 * identify divides each S(k) by its number of pairs (N - k without gaps: the unbiased estimate),
 * builds the block Hankel of R(1 .. 2L) (L block rows and L block columns) and realizes it with
 * the same ERA as okid_identify() (the references play the inputs, G the input matrix B), then
 * the modal analysis and the indicators of okid/modal_indicators.h (their input side is G's).
 * White output noise only biases R(0), which the Hankel does not use.
 *
 * The references (reference-based SSI) are a subset of the outputs: with many channels a few well
 * placed ones carry every mode at a fraction of the memory (m x r_ref blocks instead of m x m).
 *
 * Channels in different units weigh alike: R(k) is divided by the RMS of its output and of its
 * reference (a correlation coefficient) before the SVD and C is unscaled afterwards, as
 * OKID_SCALING_AUTO does for okid_identify(). The data should have zero mean (a mean is a
 * constant, not a mode: remove it or high-pass the record first; the CLI and Python remove the
 * record's mean).
 *
 * Fixed memory: the caller owns the okid_ambient struct and a workspace of
 * okid_ambient_workspace_size() (or OKID_AMBIENT_WORKSPACE_BYTES) bytes; nothing is allocated.
 * \code
 *   okid_ambient_config cfg;
 *   okid_ambient_config_default(&cfg, 2);   // m = 2 accelerometers, every one a reference
 *   cfg.dt = 0.05; cfg.hankel_rows = 20; cfg.order = 4;
 *   size_t bytes; okid_ambient_workspace_size(&cfg, &bytes);
 *   okid_ambient amb;
 *   okid_ambient_init(&amb, &cfg, workspace, bytes, NULL);
 *   for (k = 0; k < N; ++k) okid_ambient_push(&amb, &y[2 * k]);
 *   okid_ambient_result res;
 *   if (okid_ambient_identify(&amb, &res) == OKID_OK)  // res.modes[i].frequency_hz, ...
 * \endcode
 */
#ifndef OKID_AMBIENT_H
#define OKID_AMBIENT_H

#include <stddef.h>
#include <stdint.h>

#include "okid/identifier.h"
#include "okid/limits.h"
#include "okid/modal.h"
#include "okid/sizes.h"
#include "okid/stabilization.h"
#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Configuration of an output-only identifier. okid_ambient_config_default() fills every field. */
typedef struct okid_ambient_config {
    int num_outputs;    /**< m: outputs per sample, 1..OKID_MAX_DIMENSION */
    /**
     * r_ref: references, 0..m; 0 means every output is a reference (reference_channels ignored).
     */
    int num_references;
    /** The outputs used as references: num_references distinct indices in 0..m-1, increasing. */
    int reference_channels[OKID_MAX_DIMENSION];
    /**
     * L: block rows (and block columns) of the correlation Hankel matrix, 1..OKID_MAX_HORIZON; the
     * correlations of lags 0..2L are accumulated. L dt should span about one period of the slowest
     * mode (docs/ambient.md). The same name and meaning as okid_config::hankel_rows.
     */
    int hankel_rows;
    /**
     * n: model order, 1..min(L m, L r_ref, OKID_MAX_ORDER); 0 selects it at the largest ratio of
     * consecutive Hankel singular values, as okid_config::order.
     */
    int order;
    okid_real dt;         /**< sample interval [s], in [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX] */
    okid_sensing sensing; /**< what the outputs measure (eq. 64) */
    /**
     * nb: 0 or 1 for none, else 2..OKID_AMBIENT_MAX_SEGMENTS segments whose sums are kept apart
     * (nb times the sums' memory): the record is dealt out in blocks of segment_samples
     * consecutive samples, block b to segment b mod nb, and identify also realizes each
     * segment's correlations at the record's order. A mode's standard deviations are then the
     * spread of its nearest segment modes (frequency within 20 %) over sqrt(segments_used): the
     * standard error of a mean of nb nearly independent estimates (docs/ambient.md).
     */
    int segments;
    /** Samples per block of a segment, 0 = 20 (2L + 1); at least 2L + 1 (a block much longer than the correlations). */
    int segment_samples;
} okid_ambient_config;

/** Largest number of segments (okid_ambient_config::segments). */
#define OKID_AMBIENT_MAX_SEGMENTS 64

/**
 * Defaults for m outputs: every output a reference, L = 20, automatic order, dt = 1, acceleration,
 * no segments.
 * \return OKID_OK, OKID_E_NULL_POINTER (the sizes are checked by okid_ambient_init())
 */
okid_status okid_ambient_config_default(okid_ambient_config *cfg, int num_outputs);

/**
 * Check a configuration and say which field is wrong (field, value, valid range), as
 * okid_config_check() does for okid_config.
 * \return the status okid_ambient_workspace_size() returns for cfg
 */
okid_status okid_ambient_config_check(const okid_ambient_config *cfg, okid_config_issue *issue);

/**
 * Check a configuration and compute its workspace.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (also a workspace above SIZE_MAX),
 *         OKID_E_BAD_ORDER, OKID_E_BAD_PARAMETER
 */
okid_status okid_ambient_workspace_size(const okid_ambient_config *cfg, size_t *bytes);

/**
 * Workspace bytes as a constant expression: m outputs, r_ref references (0 = m), L block rows,
 * order (0 = automatic), segments (0 or 1 = none). Equals okid_ambient_workspace_size() for a valid
 * configuration; saturates at SIZE_MAX like OKID_WORKSPACE_BYTES.
 */
#define OKID_AMBIENT_WORKSPACE_BYTES(m, num_references, hankel_rows, order, segments)                 \
    OKID__SIZE(OKID__AMBIENT_WORKSPACE_BYTES64(m, OKID__AMB_NREF(m, num_references), hankel_rows, order, \
                                               segments, sizeof(okid_mode)))

/** An output-only identifier: caller-owned; members private (okid/ambient_storage.h). */
typedef struct okid_ambient okid_ambient;

/**
 * Initialise over a caller-owned workspace (aligned to OKID_WORKSPACE_ALIGN). On error the
 * identifier is left uninitialised.
 * \param[out] bytes_needed the size needed (also on OKID_E_WORKSPACE_TOO_SMALL); may be NULL
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_ORDER, OKID_E_BAD_PARAMETER,
 *         OKID_E_WORKSPACE_TOO_SMALL, OKID_E_WORKSPACE_ALIGNMENT
 */
okid_status okid_ambient_init(okid_ambient *amb, const okid_ambient_config *cfg, void *workspace, size_t bytes,
                              size_t *bytes_needed);

/** Forget every sample and the last result. \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED */
okid_status okid_ambient_reset(okid_ambient *amb);

/**
 * Push one sample y(t) (m values): O(m r_ref L) operations, summed at once (after the samples a
 * push_block left pending, if any). A sample with a NaN or Inf is
 * rejected (OKID_E_NONFINITE_SAMPLE): no product with it is summed, the lags restart after it
 * (a gap), and everything summed before is kept.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NONFINITE_SAMPLE
 */
okid_status okid_ambient_push(okid_ambient *amb, const okid_real *y);

/**
 * Push count samples, sample k at y[k * ldy .. k * ldy + m - 1]: the samples, gaps, segments and
 * pair counts of count calls of okid_ambient_push() (a rejected sample does not stop the others).
 * With the LAPACK backend the products are summed in batches of OKID__AMB_BATCH (256) samples,
 * one matrix product per lag, kept across calls (how the record is cut changes no bit); the sums
 * then equal the sample-by-sample ones to round-off, not bit for bit (docs/ambient.md, "Batched
 * sums"). The workspace holds the batch: r_ref (2L + 256) reals, and m 256 more when some output
 * is no reference. With the Eigen backend (the firmware's) it is count pushes, bit for bit.
 * \param[out] accepted samples accepted (may be NULL)
 * \return OKID_OK when all were accepted, OKID_E_NONFINITE_SAMPLE when some were rejected,
 *         OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (ldy < m), OKID_E_NOT_INITIALIZED
 */
okid_status okid_ambient_push_block(okid_ambient *amb, size_t count, const okid_real *y, size_t ldy,
                                    size_t *accepted);

/** The identified model. Every pointer points into the workspace. */
typedef struct okid_ambient_result {
    int order;                        /**< n, the realized order */
    int num_modes;                    /**< modes reported (conjugate pairs once) */
    const okid_mode *modes;           /**< sorted by frequency, then damping; emac_input judges G */
    okid_matrix A;                    /**< n x n */
    okid_matrix C;                    /**< m x n */
    okid_matrix G;                    /**< n x r_ref: E[x(t+1) y_ref(t)'], the "input" matrix of R(k) */
    /** [R(0) R(1) ... R(2L)], m x r_ref (2L + 1): the correlation estimates the Hankel was built from. */
    okid_matrix correlations;
    const okid_real *singular_values; /**< Hankel singular values, decreasing */
    int num_singular_values;
    okid_real realization_condition;  /**< sigma_1 / sigma_n of the Hankel matrix at order n */
    okid_real dt;                     /**< sample interval [s] */
    uint64_t samples;                 /**< samples accepted */
    uint64_t pairs;                   /**< products summed at the largest lag 2L (N - 2L without gaps) */
    unsigned warnings;                /**< okid_warning bits */
    /**
     * With segments: each mode's standard deviation of frequency [Hz] and of damping ratio (NaN when
     * fewer than two segments hold it), num_modes values each; NULL without segments.
     */
    const okid_real *frequency_std, *damping_std;
    int segments_used;                /**< segments whose correlations were realized at the order (0 without) */
} okid_ambient_result;

/**
 * Identify from everything pushed so far. Pushing can go on; calling it twice gives the same
 * result. A transaction: on failure the last result and its views stay as they were, and the sums
 * are never changed by identify. Views stay valid until the next successful identify, reset or init.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_ENOUGH_DATA (no pair at
 *         lag 2L yet: fewer than 2L + 1 consecutive samples), OKID_E_RANK_DEFICIENT,
 *         OKID_E_DECOMPOSITION_FAILED, OKID_E_DATA_RANGE (a channel's RMS outside
 *         [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX], or sums that overflowed)
 */
okid_status okid_ambient_identify(okid_ambient *amb, okid_ambient_result *result);

/**
 * okid_ambient_identify() at a given order, the configuration's order unchanged: after the
 * physical modes of okid_ambient_stabilization_compute() and okid_select_modes(), the model at
 * the lowest order that holds them, from the same sums (no second pass over the record). With the
 * configuration's order 0 the workspace holds every order up to min(L min(m, r_ref),
 * OKID_MAX_ORDER); with a given order, that order at most. order = the configuration's order
 * (> 0) gives okid_ambient_identify()'s result bit for bit.
 * \return those of okid_ambient_identify(); OKID_E_BAD_ORDER for order outside 1..the largest
 *         the workspace holds (the sums and the last result unchanged)
 */
okid_status okid_ambient_identify_order(okid_ambient *amb, int order, okid_ambient_result *result);

/**
 * Stabilization workspace bytes as a constant expression: m outputs, r_ref references (0 = m), L
 * block rows, the largest order and the order step. Equals okid_ambient_stabilization_workspace_size();
 * saturates at SIZE_MAX.
 */
#define OKID_AMBIENT_STABILIZATION_WORKSPACE_BYTES(m, num_references, hankel_rows, max_order, step)        \
    OKID__SIZE(OKID__AMBIENT_STABILIZATION_BYTES64(m, OKID__AMB_NREF(m, num_references), hankel_rows, max_order, \
                                                   step))

/**
 * Workspace bytes of okid_ambient_stabilization_compute() for this identifier.
 * \param[in]  amb       an initialised output-only identifier
 * \param[in]  max_order largest order, 1..min(L min(m, r_ref), OKID_MAX_ORDER)
 * \param[in]  step      order step, 1..max_order
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_ORDER (max_order),
 *         OKID_E_BAD_SIZE (step, or above SIZE_MAX)
 */
okid_status okid_ambient_stabilization_workspace_size(const okid_ambient *amb, int max_order, int step,
                                                      size_t *bytes);

/**
 * The stabilization diagram (okid/stabilization.h) of everything pushed so far: one ERA of the
 * correlations' block Hankel matrix at the largest order, the modes of the orders step, 2 step,
 * ... max_order (fewer when the Hankel rank is lower: rank_limit) by nested truncation, with
 * their indicators (G's side in the role of B) and stability flags. okid_select_modes() then
 * gives the physical modes (docs/ambient.md). The correlations, the scales and the realization
 * live in the caller's workspace; the ERA scratch is the identifier's, so its last result stays
 * valid and the sums are not changed.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_ENOUGH_DATA (no pair at
 *         lag 2L), OKID_E_BAD_ORDER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER (criteria),
 *         OKID_E_WORKSPACE_ALIGNMENT, OKID_E_WORKSPACE_TOO_SMALL, OKID_E_DATA_RANGE,
 *         OKID_E_RANK_DEFICIENT (not even order step is supported), OKID_E_DECOMPOSITION_FAILED
 */
okid_status okid_ambient_stabilization_compute(okid_ambient *amb, int max_order, int step,
                                               const okid_stabilization_criteria *criteria, void *workspace,
                                               size_t bytes, okid_stabilization *out);

/**
 * okid_ambient_stabilization_workspace_size() for the table of a smaller Hankel matrix: L' block
 * rows (and columns), 1..the identifier's L (okid_ambient_stabilization_compute_at()).
 * OKID_AMBIENT_STABILIZATION_WORKSPACE_BYTES(m, r_ref, L', max_order, step) equals it.
 * \param[in] hankel_rows L', 1..okid_ambient_config::hankel_rows of amb
 * \param[in] max_order   largest order, 1..min(L' min(m, r_ref), OKID_MAX_ORDER)
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_SIZE (hankel_rows, step, or
 *         above SIZE_MAX), OKID_E_BAD_ORDER (max_order)
 */
okid_status okid_ambient_stabilization_workspace_size_at(const okid_ambient *amb, int hankel_rows, int max_order,
                                                         int step, size_t *bytes);

/**
 * okid_ambient_stabilization_compute() of the block Hankel of R(1 .. 2L') for L' <= L: the sums
 * hold lags 0..2L, and R(k) = S(k) / pairs(k) does not depend on how many lags are summed, so one
 * identifier (one pass over the record, at the largest L) gives the table of every smaller Hankel
 * size, bit for bit the table of an identifier initialised at L' over the same pushes (the same
 * sums, scales and ERA; tests/test_ambient_modes.c). The ERA scratch is the identifier's (it holds
 * L's, which is larger); the rest lives in the caller's workspace of
 * okid_ambient_stabilization_workspace_size_at() bytes. hankel_rows = L is
 * okid_ambient_stabilization_compute().
 * \return those of okid_ambient_stabilization_compute(), OKID_E_NOT_ENOUGH_DATA meaning no pair at
 *         lag 2L'; OKID_E_BAD_SIZE also for hankel_rows outside 1..L
 */
okid_status okid_ambient_stabilization_compute_at(okid_ambient *amb, int hankel_rows, int max_order, int step,
                                                  const okid_stabilization_criteria *criteria, void *workspace,
                                                  size_t bytes, okid_stabilization *out);

#ifdef __cplusplus
}
#endif

#include "okid/ambient_storage.h"

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file stabilization.h
 * \brief Stabilization diagram data: the modes (frequency, damping, shape, indicators) of every
 *        model order step, 2 step, ..., max_order, from one SVD of the Hankel matrix.
 *
 * Nested truncation: with H(0) = U S V', the realization of order n is the leading n x n block of
 * A_N = S_N^-1/2 U_N' H(1) V_N S_N^-1/2 (and the leading rows of B, columns of C), so one SVD and
 * one realization at the largest order N give every smaller order. Physical poles stay put as the
 * order grows; computational ones wander. Each mode is flagged against the nearest-frequency mode
 * of the previous order of the list:
 *   - OKID_STABLE_FREQUENCY: |f - f_prev| <= frequency_tolerance * f_prev
 *   - OKID_STABLE_DAMPING:   |zeta - zeta_prev| <= damping_tolerance * |zeta_prev|
 *   - OKID_STABLE_SHAPE:     MAC(sensor shapes) >= mac_min
 * (defaults 1 %, 5 %, 0.98: the classic diagram's criteria). The first order has no flags.
 *
 * Memory: a caller-owned workspace of okid_stabilization_workspace_size() bytes (or the constant
 * OKID_STABILIZATION_WORKSPACE_BYTES) holds the realization and the table; the Hankel matrix and
 * its SVD use the identifier's own scratch, so the identifier's workspace does not grow and its
 * last okid_result stays valid.
 */
#ifndef OKID_STABILIZATION_H
#define OKID_STABILIZATION_H

#include <stddef.h>

#include "okid/identifier.h"
#include "okid/sizes.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Stability flags of a mode against the previous order (bits of okid_stabilization::stability). */
enum okid_stability {
    OKID_STABLE_FREQUENCY = 1u << 0,
    OKID_STABLE_DAMPING = 1u << 1,
    OKID_STABLE_SHAPE = 1u << 2,
    /** All three: a "stable pole" of the diagram. */
    OKID_STABLE_ALL = 7u
};

/** Stability criteria; okid_stabilization_criteria_default() gives 0.01, 0.05, 0.98. */
typedef struct okid_stabilization_criteria {
    okid_real frequency_tolerance; /**< relative, > 0 */
    okid_real damping_tolerance;   /**< relative, > 0 */
    okid_real mac_min;             /**< in [0, 1] */
} okid_stabilization_criteria;

/** The modes of one order: modes[first .. first + num_modes - 1] of the table, sorted by frequency. */
typedef struct okid_stabilization_order {
    int order;
    int first;
    int num_modes;
} okid_stabilization_order;

/** The diagram data. Every pointer points into the caller's stabilization workspace. */
typedef struct okid_stabilization {
    int num_orders;                         /**< orders computed (step, 2 step, ... up to min(max_order, rank_limit)) */
    int rank_limit;                         /**< largest order the Hankel matrix supports (sigma_n > eps k sigma_1) */
    int noise_free;                         /**< 1 when the singular values beyond rank_limit are round-off that no noise
                                                 explains: rank_limit below the Hankel matrix's size and, input-output,
                                                 below the m p that an observer of order p gives any noisy record */
    const okid_stabilization_order *orders; /**< num_orders entries, increasing order */
    const okid_mode *modes;                 /**< every order's modes, with indicators and shapes */
    const unsigned *stability;              /**< per mode: okid_stability bits */
} okid_stabilization;

/**
 * Stabilization workspace bytes as a constant expression: r, m, alpha, beta, the largest order,
 * the order step, combined (1 for OKID_REALIZATION_COMBINED). Equals okid_stabilization_workspace_size();
 * computed in 64 bits and saturated at SIZE_MAX (OKID__SIZE).
 */
#define OKID_STABILIZATION_WORKSPACE_BYTES(r, m, alpha, beta, nmax, step, combined) \
    OKID__SIZE(OKID__STABILIZATION_WORKSPACE_BYTES64(r, m, alpha, beta, nmax, step, combined))

/**
 * Fill criteria with the defaults (1 % frequency, 5 % damping, MAC 0.98).
 * \return OKID_OK, OKID_E_NULL_POINTER
 */
okid_status okid_stabilization_criteria_default(okid_stabilization_criteria *criteria);

/**
 * Workspace bytes of okid_stabilization_compute() for this identifier's configuration.
 * \param[in]  id        an initialised identifier
 * \param[in]  max_order largest order, 1..min(alpha m, beta columns) and <= OKID_MAX_ORDER
 * \param[in]  step      order step, 1..max_order (2 gives the even orders)
 * \param[out] bytes     bytes needed
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_BAD_SIZE (step), OKID_E_BAD_ORDER (max_order)
 */
okid_status okid_stabilization_workspace_size(const okid_identifier *id, int max_order, int step, size_t *bytes);

/**
 * The stabilization diagram of the Markov parameters of the last successful okid_identify():
 * orders step, 2 step, ... up to max_order (fewer when the Hankel rank is lower: see rank_limit).
 * Uses the identifier's scratch for the Hankel SVD; the last okid_result stays valid.
 * \param[in,out] id        identifier after a successful okid_identify()
 * \param[in]     max_order largest order (see okid_stabilization_workspace_size())
 * \param[in]     step      order step
 * \param[in]     criteria  stability criteria; NULL = defaults
 * \param[out]    workspace okid_stabilization_workspace_size() bytes, aligned to OKID_WORKSPACE_ALIGN
 * \param[in]     bytes     size of workspace
 * \param[out]    out       the table (views into workspace); untouched on error
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_NOT_INITIALIZED, OKID_E_NOT_AVAILABLE (no identification
 *         yet), OKID_E_BAD_SIZE, OKID_E_BAD_ORDER, OKID_E_BAD_PARAMETER (criteria), OKID_E_WORKSPACE_TOO_SMALL,
 *         OKID_E_WORKSPACE_ALIGNMENT, OKID_E_DECOMPOSITION_FAILED, OKID_E_BACKEND_ARGUMENT
 */
okid_status okid_stabilization_compute(okid_identifier *id, int max_order, int step,
                                       const okid_stabilization_criteria *criteria, void *workspace, size_t bytes,
                                       okid_stabilization *out);

#ifdef __cplusplus
}
#endif

#endif

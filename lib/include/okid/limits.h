/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file limits.h
 * \brief Every limit of the library in one place: the largest dimensions, horizons, orders,
 *        decimation and instrument lags a configuration may ask for, the magnitudes the
 *        computation keeps accurate, and the workspace alignment. okid/types.h includes it.
 */
#ifndef OKID_LIMITS_H
#define OKID_LIMITS_H

#include "okid/okid_build_config.h"

/** Largest number of inputs or outputs. */
#define OKID_MAX_DIMENSION 64
/** Largest observer order p and largest number of Hankel block rows or columns. */
#define OKID_MAX_HORIZON 1000
/** Largest model order n. */
#define OKID_MAX_ORDER 512
/** Largest decimation factor K. */
#define OKID_MAX_DECIMATION 64
/** Largest number of instrument lags (OKID_ESTIMATOR_INSTRUMENTAL). */
#define OKID_MAX_INSTRUMENT_LAGS 8000

/**
 * The magnitudes the computation keeps finite and accurate (its squares and fourth powers stay
 * normal numbers): dt, K dt, and the RMS of each channel as it enters the regressor (after the
 * scaling of OKID_SCALING_AUTO) must lie in [OKID_MAGNITUDE_MIN, OKID_MAGNITUDE_MAX]: 1e-75..1e75
 * in double, 1e-9..1e9 in float. Outside, okid_init() says OKID_E_BAD_PARAMETER (dt) and
 * okid_identify() OKID_E_DATA_RANGE (a channel: rescale it, or use OKID_SCALING_AUTO).
 */
#if OKID_REAL_IS_FLOAT
#define OKID_MAGNITUDE_MIN 1e-9f
#define OKID_MAGNITUDE_MAX 1e9f
#else
#define OKID_MAGNITUDE_MIN 1e-75
#define OKID_MAGNITUDE_MAX 1e75
#endif

/** Alignment, in bytes, that every okid workspace must have (and that each of its regions keeps). */
#define OKID_WORKSPACE_ALIGN 16u

#endif

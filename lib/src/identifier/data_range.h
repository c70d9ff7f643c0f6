/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The data's magnitudes against the range the computation can use (OKID_MAGNITUDE_MIN/MAX,
 * types.h): a property of the data, reported as OKID_E_DATA_RANGE, never as a backend error or a
 * result of NaN and Inf.
 */
#ifndef OKID_DATA_RANGE_H
#define OKID_DATA_RANGE_H

#include "okid/identifier.h"

/*
 * Least squares: the RMS of each channel as it entered the regressor (scaled by OKID_SCALING_AUTO),
 * from the norms of the columns u(k) and y(k) of the factor identify solves on (R, or its copy with
 * the pending rows folded in; a rotation keeps a column's norm),
 * must be 0 (left to the rank tests) or within the range. OKID_OK or OKID_E_DATA_RANGE. The
 * instrumental-variable estimator keeps no factor of the regressor: not checked there.
 */
okid_status okid_check_channel_range(const okid_identifier *id, const okid_real *factor);

/* okid_progress::rows_remembered: the rows whose forgetting weight lambda^(age/2) is at least the
   rank tolerance (the rest cannot raise the numerical rank), at most the rows folded. */
uint64_t okid_rows_remembered(const okid_identifier *id);

/* 1 when every number of the n modes (frequency, damping, indicators, shapes of m outputs) is finite. */
int okid_modes_finite(const okid_mode *modes, int num_modes, int m);

#endif

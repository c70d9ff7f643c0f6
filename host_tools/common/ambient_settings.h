/* SPDX-License-Identifier: Apache-2.0 */
/*
 * What the host tools do to a whole record before output-only identification (okid/ambient.h,
 * docs/ambient.md), once for the CLI and the Python binding: remove each channel's mean, and
 * choose L (hankel_rows) from the outputs' band when it is not given.
 */
#ifndef OKID_HOST_AMBIENT_SETTINGS_H
#define OKID_HOST_AMBIENT_SETTINGS_H

#include <stddef.h>

#include "okid/okid.h"

/* Each of the m channels' (1..OKID_MAX_DIMENSION) mean of its finite values, summed in double in
   sample order, into mean: what ambient_remove_mean() subtracts. */
void ambient_channel_means(const okid_real *y, size_t n, int m, okid_real *mean);

/* Subtract from each of the m channels of y (n samples, m values each) the mean of its finite values. */
void ambient_remove_mean(okid_real *y, size_t n, int m);

/* The largest L chosen for n samples of m outputs: a twentieth of the record, a Hankel of 1000 rows. */
int ambient_hankel_rows_most(size_t n, int m);

/*
 * L when hankel_rows is not given: one slowest period per block side, L dt = 1 / f5 (f5: 5 % of
 * the outputs' energy lies below, auto_channel_band()), so the Hankel matrix of R(1..2L) spans
 * two periods of the slowest mode; at least what the order needs (L min(m, nref) >= order), at
 * most a twentieth of the record and a Hankel matrix of 1000 rows. *band_hz gets f5, or 0 when the
 * record has no band (too short or flat): then 20, okid_ambient_config_default()'s.
 */
int ambient_choose_hankel_rows(const okid_real *y, size_t n, int m, double dt, int order, int nref, double *band_hz);

#endif

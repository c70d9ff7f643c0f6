/* SPDX-License-Identifier: Apache-2.0 */
/*
 * What the host tools do to a whole record before output-only identification (okid/ambient.h,
 * docs/ambient.md), once for the CLI and the Python binding: remove each channel's mean, and
 * choose L (hankel_rows) from the outputs' band when it is not given.
 */
#ifndef OKID_HOST_AMBIENT_SETTINGS_H
#define OKID_HOST_AMBIENT_SETTINGS_H

#include <stddef.h>

#include "auto_settings.h" /* auto_band */
#include "okid/okid.h"

/* Each of the m channels' (1..OKID_MAX_DIMENSION) mean of its finite values, summed in double in
   sample order, into mean: what ambient_remove_mean() subtracts. */
void ambient_channel_means(const okid_real *y, size_t n, int m, okid_real *mean);

/* Subtract from each of the m channels of y (n samples, m values each) the mean of its finite values. */
void ambient_remove_mean(okid_real *y, size_t n, int m);

/* The largest L chosen for n samples of m outputs: a twentieth of the record, a Hankel of 1000 rows. */
int ambient_hankel_rows_most(size_t n, int m);

/* The outputs' band (auto_channel_band()), estimated once per record; low_hz = 0 when the record
   has none (too short or flat). Returns 1 when it has one. */
int ambient_record_band(const okid_real *y, size_t n, int m, double dt, auto_band *band);

/*
 * L when hankel_rows is not given, from the record's band (ambient_record_band()): one slowest
 * period per block side, L dt = 1 / f5 (f5 = band->low_hz: 5 % of the outputs' energy lies
 * below), so the Hankel matrix of R(1..2L) spans two periods of the slowest mode; at least what the
 * order needs (L min(m, nref) >= order), at most a twentieth of the n samples and a Hankel matrix
 * of 1000 rows. No band (low_hz 0): 20, okid_ambient_config_default()'s.
 */
int ambient_band_hankel_rows(const auto_band *band, size_t n, int m, double dt, int order, int nref);

#endif

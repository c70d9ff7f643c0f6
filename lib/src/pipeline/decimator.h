/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Anti-alias decimation inside the buffering step: every channel (inputs and outputs alike)
 * passes through one low-pass filter, then every K-th sample is kept. The filter is a
 * second-order Butterworth low-pass (one biquad) with its -3 dB edge at half the decimated Nyquist
 * frequency, designed at init by the bilinear transform with prewarping, unit gain at 0 Hz.
 *
 * Why so gentle (docs/quality.md, "Decimation"): a sharp filter (Chebyshev I of order 8 at 0.8,
 * as scipy.signal.decimate) empties the top of the decimated band, and the least squares then fits
 * an unstable observer to that empty band (the paper's case with 2 % noise: no model at K = 5 and
 * 10, measured); the gentle filter keeps every decimated frequency excited.
 */
#ifndef OKID_DECIMATOR_H
#define OKID_DECIMATOR_H

#include "okid/types.h"

/* Reals of the coefficients, and of the state of one channel. */
enum { OKID_DECIMATOR_COEFS = 5, OKID_DECIMATOR_STATE = 2 };

/* Coefficients for factor k >= 2: b1, b2, a1, a2, gain; the filter is
   gain (1 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2) with b1 = 2, b2 = 1. */
void okid_decimator_design(int k, okid_real *coef);

/* Zero the filter state of `channels` channels. */
void okid_decimator_reset(okid_real *state, int channels);

/* Filter one sample x (channels values) in place, updating the state. */
void okid_decimator_filter(const okid_real *coef, okid_real *state, int channels, okid_real *x);

#endif

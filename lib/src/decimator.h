/*
 * Anti-alias decimation inside the buffering step: every channel (inputs and outputs alike)
 * passes through one low-pass filter, then every K-th sample is kept. The filter is a Chebyshev
 * type I low-pass of order 8 with 0.05 dB passband ripple and its edge at 0.8 of the decimated
 * Nyquist frequency (the default of scipy.signal.decimate), as four biquads (second-order
 * sections) designed at init by the bilinear transform, normalised to unit gain at 0 Hz.
 */
#ifndef OKID_DECIMATOR_H
#define OKID_DECIMATOR_H

#include "okid/types.h"

/* Coefficients of the four sections for factor k >= 2: per section b1, b2, a1, a2, gain (20 reals);
   section s is gain (1 + b1 z^-1 + b2 z^-2) / (1 + a1 z^-1 + a2 z^-2), b1 = 2, b2 = 1. */
void okid_decimator_design(int k, okid_real *coef);

/* Zero the filter state of `channels` channels (8 reals each). */
void okid_decimator_reset(okid_real *state, int channels);

/* Filter one sample x (channels values) in place through the sections, updating the state. */
void okid_decimator_filter(const okid_real *coef, okid_real *state, int channels, okid_real *x);

#endif

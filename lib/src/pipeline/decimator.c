/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Butterworth design (Oppenheim and Schafer, Discrete-Time Signal Processing, 3rd ed., 7.2; the
 * steps of scipy.signal.butter): the analog poles of order 2, s = W (-1 +- i) / sqrt(2), at the
 * prewarped edge W = 2 tan(pi fc / 2) (fc relative to the Nyquist frequency, sample interval 1),
 * mapped by z = (2 + s) / (2 - s); both zeros of the low-pass fall on z = -1.
 */
#include "pipeline/decimator.h"

#include "numerics/real_math.h"

#define EDGE OKID_R(0.5) /* -3 dB edge as a fraction of the decimated Nyquist frequency */

void okid_decimator_design(int k, okid_real *coef)
{
    const okid_real half_angle = OKID_PI * EDGE / (okid_real)(2 * k);
    const okid_real warp = 2 * okid_sin(half_angle) / okid_cos(half_angle);
    const okid_real sr = -warp * OKID_R(0.70710678118654752), si = -sr; /* the pole of the upper half plane */
    const okid_real dr = 2 - sr, di = -si, den = dr * dr + di * di;     /* z = (2 + s) / (2 - s) */
    const okid_real zr = ((2 + sr) * dr + si * di) / den, zi = (si * dr - (2 + sr) * di) / den;
    coef[0] = 2;
    coef[1] = 1;
    coef[2] = -2 * zr;
    coef[3] = zr * zr + zi * zi;
    coef[4] = (1 + coef[2] + coef[3]) / 4; /* unit gain at z = 1: (1 + a1 + a2) / (1 + b1 + b2) */
}

void okid_decimator_reset(okid_real *state, int channels)
{
    for (int i = 0; i < OKID_DECIMATOR_STATE * channels; ++i) {
        state[i] = 0;
    }
}

void okid_decimator_filter(const okid_real *coef, okid_real *state, int channels, okid_real *x)
{
    for (int ch = 0; ch < channels; ++ch) {
        /* transposed direct form II */
        okid_real *w = state + OKID_DECIMATOR_STATE * ch;
        const okid_real in = coef[4] * x[ch];
        const okid_real out = in + w[0];
        w[0] = coef[0] * in - coef[2] * out + w[1];
        w[1] = coef[1] * in - coef[3] * out;
        x[ch] = out;
    }
}

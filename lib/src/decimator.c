/*
 * Chebyshev type I design (Oppenheim and Schafer, Discrete-Time Signal Processing, 3rd ed., 7.2;
 * the same steps as scipy.signal.cheby1): analog prototype poles
 *   s_j = -sinh(mu) sin(theta_j) + i cosh(mu) cos(theta_j), theta_j = pi (2j + 1) / (2N),
 *   mu = asinh(1 / eps) / N, eps^2 = 10^(ripple / 10) - 1,
 * scaled to the prewarped edge W = 2 tan(pi fc / 2) (fc relative to the Nyquist frequency, sample
 * interval 1), mapped by z = (2 + s) / (2 - s); the N zeros of the low-pass fall on z = -1.
 */
#include "decimator.h"

#include "real_math.h"

enum { SECTIONS = 4 }; /* order 8 */

#define RIPPLE_DB OKID_R(0.05)
#define EDGE OKID_R(0.8) /* passband edge as a fraction of the decimated Nyquist frequency */

void okid_decimator_design(int k, okid_real *coef)
{
    const okid_real eps = okid_sqrt(okid_pow(OKID_R(10.0), RIPPLE_DB / 10) - 1);
    const okid_real inv = 1 / eps;
    const okid_real mu = okid_log(inv + okid_sqrt(inv * inv + 1)) / (okid_real)(2 * SECTIONS); /* asinh */
    const okid_real sinh_mu = (okid_exp(mu) - okid_exp(-mu)) / 2, cosh_mu = (okid_exp(mu) + okid_exp(-mu)) / 2;
    const okid_real half_angle = OKID_PI * EDGE / (okid_real)(2 * k);
    const okid_real warp = 2 * okid_sin(half_angle) / okid_cos(half_angle);
    for (int j = 0; j < SECTIONS; ++j) {
        /* the pole of the upper half plane of pair j; its conjugate completes the section */
        const okid_real theta = OKID_PI * (okid_real)(2 * j + 1) / (okid_real)(4 * SECTIONS);
        const okid_real sr = -warp * sinh_mu * okid_sin(theta), si = warp * cosh_mu * okid_cos(theta);
        /* z = (2 + s) / (2 - s) */
        const okid_real dr = 2 - sr, di = -si, den = dr * dr + di * di;
        const okid_real zr = ((2 + sr) * dr + si * di) / den, zi = (si * dr - (2 + sr) * di) / den;
        okid_real *c = coef + 5 * j;
        c[0] = 2;
        c[1] = 1;
        c[2] = -2 * zr;
        c[3] = zr * zr + zi * zi;
        c[4] = (1 + c[2] + c[3]) / 4; /* unit gain at z = 1: (1 + a1 + a2) / (1 + b1 + b2) */
    }
}

void okid_decimator_reset(okid_real *state, int channels)
{
    for (int i = 0; i < 2 * SECTIONS * channels; ++i) {
        state[i] = 0;
    }
}

void okid_decimator_filter(const okid_real *coef, okid_real *state, int channels, okid_real *x)
{
    for (int ch = 0; ch < channels; ++ch) {
        okid_real v = x[ch];
        okid_real *w = state + 2 * SECTIONS * ch;
        for (int j = 0; j < SECTIONS; ++j) {
            /* transposed direct form II: two states per section */
            const okid_real *c = coef + 5 * j;
            const okid_real in = c[4] * v;
            const okid_real out = in + w[2 * j];
            w[2 * j] = c[0] * in - c[2] * out + w[2 * j + 1];
            w[2 * j + 1] = c[1] * in - c[3] * out;
            v = out;
        }
        x[ch] = v;
    }
}

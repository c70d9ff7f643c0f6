/* SPDX-License-Identifier: Apache-2.0 */
/* Per-channel scaling: see channel_scaling.h; column order of the rows in sample_buffer.h. */
#include "pipeline/channel_scaling.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"

/* The channel (input i, or r + output a) of regressor column col. */
static int regressor_channel(int r, int m, int p, int col)
{
    const int past_inputs_end = r * (p + 1), q = r + (r + m) * p;
    if (col < past_inputs_end) {
        return col % r; /* u(k), then u(k-1) .. u(k-p) */
    }
    if (col < q) {
        return r + (col - past_inputs_end) % m; /* y(k-1) .. y(k-p) */
    }
    return r + (col - q); /* y(k) */
}

/* RMS of column col of the rows; 1 when it is zero there (the channel keeps its units). */
/*
 * RMS of column col of the rows; 1 when it is zero there (the channel keeps its units). Channels
 * far from 1 (1e155, 1e-160) are what scaling is for, but their squares overflow or underflow:
 * the sum is then taken over v / max|v|. Within the range where the plain squares are exact to
 * rounding, the plain sum is kept (the same bits as before for ordinary data).
 */
static okid_real column_rms(int nrows, const okid_real *rows, int ld, int col)
{
    okid_real amax = 0;
    for (int i = 0; i < nrows; ++i) {
        const okid_real v = okid_fabs(OKID_AT(rows, ld, i, col));
        amax = v > amax ? v : amax;
    }
    if (amax == 0) {
        return 1;
    }
    const int plain =
        amax >= okid_sqrt(OKID_REAL_MIN) / OKID_EPSILON && amax <= okid_sqrt(OKID_REAL_MAX / (okid_real)nrows);
    const okid_real unit = plain ? 1 : amax;
    okid_real s = 0;
    for (int i = 0; i < nrows; ++i) {
        const okid_real v = OKID_AT(rows, ld, i, col) / unit;
        s += v * v;
    }
    return unit * okid_sqrt(s / (okid_real)nrows);
}

void okid_scaling_measure(int r, int m, int p, int nrows, const okid_real *rows, int ld, okid_real *scales)
{
    const int q = r + (r + m) * p;
    for (int i = 0; i < r; ++i) {
        scales[i] = column_rms(nrows, rows, ld, i); /* u(k) */
    }
    for (int a = 0; a < m; ++a) {
        scales[r + a] = column_rms(nrows, rows, ld, q + a); /* y(k) */
    }
}

void okid_scaling_apply(int r, int m, int p, const okid_real *scales, int nrows, okid_real *rows, int ld,
                        okid_real *zrows, int nz, int ldz)
{
    const int w = r + (r + m) * p + m;
    for (int col = 0; col < w; ++col) {
        const okid_real inv = 1 / scales[regressor_channel(r, m, p, col)];
        for (int i = 0; i < nrows; ++i) {
            OKID_AT(rows, ld, i, col) *= inv;
        }
    }
    for (int col = 0; col < nz; ++col) { /* instruments: u(k - j), input col % r */
        const okid_real inv = 1 / scales[col % r];
        for (int i = 0; i < nrows; ++i) {
            OKID_AT(zrows, ldz, i, col) *= inv;
        }
    }
}

void okid_scaling_unscale_solution(int r, int m, int p, const okid_real *scales, okid_real *x, int ldx)
{
    const int q = r + (r + m) * p;
    if (scales == NULL) {
        return;
    }
    for (int a = 0; a < m; ++a) {
        const okid_real out = scales[r + a];
        for (int i = 0; i < q; ++i) {
            OKID_AT(x, ldx, i, a) *= out / scales[regressor_channel(r, m, p, i)];
        }
    }
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Per-channel scaling (OKID_SCALING_AUTO): the scales are the RMS of each input and output over
 * the first block of regressor rows. The least squares and the instruments see the data divided
 * by them; the observer solution is unscaled right after the solve, and ERA balances its Hankel
 * with the same scales (era.c), so every returned quantity is in the units of the data.
 * scales: r input scales, then m output scales. Rows in the column order of sample_buffer.h.
 */
#ifndef OKID_CHANNEL_SCALING_H
#define OKID_CHANNEL_SCALING_H

#include "okid/types.h"

/* The scales from nrows regressor rows (leading dimension ld): the RMS of u(k) and y(k); 1 for a channel that is zero there. */
void okid_scaling_measure(int r, int m, int p, int nrows, const okid_real *rows, int ld, okid_real *scales);

/* Divide every column of the regressor rows (nrows x (q + m)) by its channel's scale, and of the
   instrument rows (nrows x nz, u(k - j) in column j r + i; none when nz is 0). */
void okid_scaling_apply(int r, int m, int p, const okid_real *scales, int nrows, okid_real *rows, int ld,
                        okid_real *zrows, int nz, int ldz);

/* X (q x m) of the scaled data to X of the data: X(i, a) * s(output a) / s(channel of column i). No-op for scales NULL. */
void okid_scaling_unscale_solution(int r, int m, int p, const okid_real *scales, okid_real *x, int ldx);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The Gram matrix of regressor rows from their Toeplitz structure (correlation form,
 * OKID_ESTIMATOR_CORRELATION without forgetting; docs/design.md "Toeplitz block Gram"). A row of
 * sample k holds z(k), z(k-1) .. z(k-p), z = [u; y] (sample_buffer.h's column order), so over
 * consecutive rows k0..k1 the (r+m) x (r+m) blocks G_ij = sum_k z(k-i) z(k-j)' satisfy
 *     G_(i+1)(j+1) = G_ij + z(k0-1-i) z(k0-1-j)' - z(k1-i) z(k1-j)',
 * both edge samples in the first and last rows. Only the first block row G_0j is a product
 * (2 (r+m) w flops a row against xSYRK's w^2); the rest follows along the block diagonals, once
 * per run of consecutive rows (a gap ends a run), not once per block: blocks of one run only add
 * to its first block row (okid_toeplitz_fold), and the w x w Gram is assembled when the run ends
 * or for identify (okid_toeplitz_close). Rows count as consecutive when each is the one before
 * shifted by a sample, compared exactly, so a gap or any other break starts a new run.
 * LAPACK backend only (xGEMM for the first block row).
 */
#ifndef OKID_TOEPLITZ_GRAM_H
#define OKID_TOEPLITZ_GRAM_H

#include "okid/status.h"
#include "okid/types.h"

/* The open run's state in `run` (OKID__TOEPLITZ_RUN_REALS(r, m, p) = (r + m + 2) w + 1 reals):
   its first block row summed so far ((r + m) x w), its first and last row by (channel, lag), and
   whether a run is open. okid_toeplitz_restart(): none (at init and reset). */
void okid_toeplitz_restart(int r, int m, int p, okid_real *run);

/* The nrows x w regressor rows (leading dimension ldrows, only read) into the run; each run that
   ends inside them adds its Gram to c (w x w, upper triangle, leading dimension ldc). */
okid_status okid_toeplitz_fold(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *run,
                               okid_real *c, int ldc);

/* c += the open run's Gram, run unchanged. work: (r + m) x w reals. */
void okid_toeplitz_close(int r, int m, int p, const okid_real *run, okid_real *c, int ldc, okid_real *work);

/* c += rows' rows in one call (a scratch run, `work`: OKID__TOEPLITZ_RUN_REALS reals). */
okid_status okid_toeplitz_gram(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *c,
                               int ldc, okid_real *work);

#endif

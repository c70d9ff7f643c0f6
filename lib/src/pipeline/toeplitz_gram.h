/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The Gram matrix of a block of regressor rows from its Toeplitz structure (correlation form,
 * OKID_ESTIMATOR_CORRELATION; docs/design.md "Toeplitz block Gram"). A row of sample k holds
 * z(k), z(k-1) .. z(k-p), z = [u; y] (sample_buffer.h's column order), so over consecutive rows
 * k0..k1 the (r+m) x (r+m) blocks G_ij = sum_k z(k-i) z(k-j)' satisfy
 *     G_(i+1)(j+1) = G_ij + z(k0-1-i) z(k0-1-j)' - z(k1-i) z(k1-j)',
 * both edge samples in the block's first and last rows. Only the first block row G_0j is a
 * product (2 B (r+m) w flops against xSYRK's B w^2); the rest follows along the diagonals.
 */
#ifndef OKID_TOEPLITZ_GRAM_H
#define OKID_TOEPLITZ_GRAM_H

#include "okid/status.h"
#include "okid/types.h"

/*
 * c (w x w, upper triangle, leading dimension ldc; w = (r + m)(p + 1)) += rows' rows for the
 * nrows x w regressor rows (leading dimension ldrows, only read). Rows need not be consecutive:
 * each run in which every row is the previous one shifted by a sample (checked exactly, so a gap
 * or any other break starts a new run) is summed on its own. work: (r + m + 2) x w reals
 * (OKID__TOEPLITZ_GRAM_REALS). LAPACK backend only (xGEMM for the first block row).
 */
okid_status okid_toeplitz_gram(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *c,
                               int ldc, okid_real *work);

#endif

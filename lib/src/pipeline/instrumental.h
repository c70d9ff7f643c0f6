/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Instrumental-variable estimation of the observer Markov parameters (OKID_ESTIMATOR_INSTRUMENTAL).
 * Instead of the factor of [Phi y], the fixed-memory state is the cross-product
 * M = sum_k z(k) [phi(k)' y(k)'] (nz x w, nz = r (L + 1)), z(k) = [u(k); u(k-1); ...; u(k-L)].
 * At identify, M is reduced by Householder QR to the w x w triangular factor of the same layout as
 * the least squares keeps, so the rank-revealing solve and the diagnostics run unchanged on it:
 * the solve then minimises |M_phi X - M_y|, the extended IV estimate (Soederstroem and Stoica 1989).
 */
#ifndef OKID_INSTRUMENTAL_H
#define OKID_INSTRUMENTAL_H

#include "okid/ring_storage.h" /* okid_ring_ */
#include "okid/status.h"

/* Write z(k) = [u(k); u(k-1); ...; u(k-L)] of input u (r values) and the ring of the last L inputs
   to row (stride ld between columns). */
void okid_iv_write_row(const okid_ring_ *inputs, const okid_real *u, okid_real *row, size_t ld);

/*
 * Rows first .. first + count - 1 of decay M + Z' Phi into out (count x w, leading dimension
 * ldout; out = M + first with ldout = ldm accumulates in place): M is nz x w (leading dimension
 * ldm), Z the nrows x nz instrument rows, Phi the nrows x w regressor rows (both already weighted
 * and scaled).
 */
void okid_iv_cross_product(int first, int count, int w, int nrows, const okid_real *z, int ldz, const okid_real *phi,
                           int ldphi, okid_real decay, const okid_real *mat, int ldm, okid_real *out, int ldout);

/*
 * The triangular factor r (w x w) of M (nz x w), or of decay M + Z' Phi when nrows > 0 (the
 * pending rows, which stay as they are), folded chunk by chunk of ldc rows through chunk
 * (ldc x w). t and work as okid_lsq_fold().
 */
okid_status okid_iv_factor(int nz, int w, const okid_real *mat, int ldm, int nrows, const okid_real *z, int ldz,
                           const okid_real *phi, int ldphi, okid_real decay, okid_real *r, int ldr, okid_real *chunk,
                           int ldc, int nbt, okid_real *t, okid_real *work);

#endif

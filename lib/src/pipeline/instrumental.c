/* SPDX-License-Identifier: Apache-2.0 */
/* Instrumental variables with delayed inputs: see instrumental.h. */
#include "pipeline/instrumental.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "pipeline/sample_buffer.h"

void okid_iv_write_row(const okid_ring_ *inputs, const okid_real *u, okid_real *row, size_t ld)
{
    const int r = inputs->width, lags = inputs->depth;
    for (int i = 0; i < r; ++i) {
        row[(size_t)i * ld] = u[i];
    }
    for (int j = 1; j <= lags; ++j) {
        const okid_real *past = okid_ring_past(inputs, j); /* u(k - j) */
        for (int i = 0; i < r; ++i) {
            row[(size_t)(j * r + i) * ld] = past[i];
        }
    }
}

void okid_iv_cross_product(int first, int count, int w, int nrows, const okid_real *z, int ldz, const okid_real *phi,
                           int ldphi, okid_real decay, const okid_real *mat, int ldm, okid_real *out, int ldout)
{
    for (int j = 0; j < w; ++j) {
        const okid_real *phi_j = phi + (size_t)j * (size_t)ldphi;
        for (int i = first; i < first + count; ++i) {
            const okid_real *z_i = z + (size_t)i * (size_t)ldz;
            okid_real s = 0;
            for (int k = 0; k < nrows; ++k) {
                s += z_i[k] * phi_j[k];
            }
            OKID_AT(out, ldout, i - first, j) = decay * OKID_AT(mat, ldm, i, j) + s;
        }
    }
}

okid_status okid_iv_factor(int nz, int w, const okid_real *mat, int ldm, int nrows, const okid_real *z, int ldz,
                           const okid_real *phi, int ldphi, okid_real decay, okid_real *r, int ldr, okid_real *chunk,
                           int ldc, int nbt, okid_real *t, okid_real *work)
{
    okid_zero_matrix(w, w, r, ldr);
    for (int first = 0; first < nz; first += ldc) {
        const int rows = (nz - first < ldc) ? nz - first : ldc;
        if (nrows > 0) {
            okid_iv_cross_product(first, rows, w, nrows, z, ldz, phi, ldphi, decay, mat, ldm, chunk, ldc);
        } else {
            okid_copy_matrix(rows, w, mat + first, ldm, chunk, ldc);
        }
        const okid_status st = okid_la_fold_rows(w, r, ldr, rows, chunk, ldc, nbt, t, work);
        if (st != OKID_OK) {
            return st;
        }
    }
    return OKID_OK;
}

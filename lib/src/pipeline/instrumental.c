/* Instrumental variables with delayed inputs: see instrumental.h. */
#include "instrumental.h"

#include "dense.h"
#include "linalg.h"

void okid_iv_restart(okid_identifier *id, int zero_history)
{
    const int lags = id->dims_.instrument_lags;
    id->iv_head_ = lags > 0 ? lags - 1 : 0;
    id->iv_fill_ = zero_history ? lags : 0;
    if (lags > 0) {
        okid_zero_matrix(id->dims_.r, lags, id->at_.iv_ring, id->dims_.r);
    }
}

int okid_iv_ready(const okid_identifier *id)
{
    return id->iv_fill_ >= id->dims_.instrument_lags;
}

void okid_iv_write_row(const okid_identifier *id, const okid_real *u, int row)
{
    const int r = id->dims_.r, lags = id->dims_.instrument_lags, ld = id->dims_.block_rows;
    okid_real *out = id->at_.iv_block + row;
    for (int i = 0; i < r; ++i) {
        out[(size_t)i * (size_t)ld] = u[i];
    }
    for (int j = 1; j <= lags; ++j) {
        const int slot = (id->iv_head_ - (j - 1) + lags) % lags; /* u(k - j) */
        for (int i = 0; i < r; ++i) {
            out[(size_t)(j * r + i) * (size_t)ld] = id->at_.iv_ring[(size_t)slot * (size_t)r + (size_t)i];
        }
    }
}

void okid_iv_append(okid_identifier *id, const okid_real *u)
{
    const int r = id->dims_.r, lags = id->dims_.instrument_lags;
    if (lags == 0) {
        return;
    }
    id->iv_head_ = (id->iv_head_ + 1) % lags;
    for (int i = 0; i < r; ++i) {
        id->at_.iv_ring[(size_t)id->iv_head_ * (size_t)r + (size_t)i] = u[i];
    }
    if (id->iv_fill_ < lags) {
        ++id->iv_fill_;
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

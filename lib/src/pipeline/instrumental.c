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

void okid_iv_accumulate(okid_identifier *id, okid_real decay)
{
    const int nz = id->dims_.nz, w = id->dims_.w, rows = id->block_fill_, ld = id->dims_.block_rows;
    okid_real *mat = id->at_.iv_m;
    for (int j = 0; j < w; ++j) {
        const okid_real *phi = id->at_.block + (size_t)j * (size_t)ld;
        for (int i = 0; i < nz; ++i) {
            const okid_real *z = id->at_.iv_block + (size_t)i * (size_t)ld;
            okid_real s = 0;
            for (int k = 0; k < rows; ++k) {
                s += z[k] * phi[k];
            }
            OKID_AT(mat, nz, i, j) = decay * OKID_AT(mat, nz, i, j) + s;
        }
    }
}

okid_status okid_iv_factor(okid_identifier *id)
{
    const okid_dims_ *d = &id->dims_;
    const int nz = d->nz, w = d->w, ld = d->block_rows;
    okid_zero_matrix(w, w, id->at_.r, w);
    for (int first = 0; first < nz; first += ld) {
        const int rows = (nz - first < ld) ? nz - first : ld;
        okid_copy_matrix(rows, w, id->at_.iv_m + first, nz, id->at_.block, ld);
        const okid_status st = okid_la_fold_rows(w, id->at_.r, w, rows, id->at_.block, ld, d->block_tile,
                                                 id->at_.fold_t, id->at_.fold_work);
        if (st != OKID_OK) {
            return st;
        }
    }
    return OKID_OK;
}

/* Block QR accumulation and rank-revealing solve: see least_squares.h. */
#include "least_squares.h"

#include "channel_scaling.h"
#include "dense.h"
#include "instrumental.h"
#include "linalg.h"
#include "real_math.h"
#include "triangular_lstsq.h"

okid_status okid_lsq_fold_pending(okid_identifier *id)
{
    const int rows = id->block_fill_, w = id->dims_.w, ld = id->dims_.block_rows, nz = id->dims_.nz;
    if (rows == 0) {
        return OKID_OK;
    }
    okid_scaling_apply_pending(id);
    const okid_real lambda = id->forgetting_;
    okid_real decay = 1; /* of what is already accumulated: `rows` samples older than the newest row */
    if (lambda < 1) {
        /* Row i of the block (0 = oldest) is rows-1-i samples older than the newest one. The factor
           R weighs rows by root^age (its square by lambda^age); the instruments' cross-product
           takes root^age from each side. */
        const okid_real root = okid_sqrt(lambda);
        const okid_real rscale = okid_pow(root, (okid_real)rows);
        decay = rscale * rscale;
        if (nz == 0) {
            for (int j = 0; j < w; ++j) {
                for (int i = 0; i <= j; ++i) {
                    OKID_AT(id->at_.r, w, i, j) *= rscale;
                }
            }
        }
        okid_real weight = 1;
        for (int i = rows - 1; i >= 0; --i) {
            for (int j = 0; j < w; ++j) {
                OKID_AT(id->at_.block, ld, i, j) *= weight;
            }
            for (int j = 0; j < nz; ++j) {
                OKID_AT(id->at_.iv_block, ld, i, j) *= weight;
            }
            weight *= root;
        }
    }
    okid_status st = OKID_OK;
    if (nz > 0) {
        okid_iv_accumulate(id, decay);
    } else {
        st = okid_la_fold_rows(w, id->at_.r, w, rows, id->at_.block, ld, id->dims_.block_tile, id->at_.fold_t,
                               id->at_.fold_work);
    }
    id->block_fill_ = 0;
    return st;
}

void okid_lsq_column_norms(const okid_real *r, int ldr, int n, okid_real *scale)
{
    for (int j = 0; j < n; ++j) {
        okid_real s = 0;
        for (int i = 0; i <= j; ++i) {
            s += OKID_AT(r, ldr, i, j) * OKID_AT(r, ldr, i, j);
        }
        s = okid_sqrt(s);
        scale[j] = (s > 0) ? s : 1; /* a zero column stays zero: it lowers the rank */
    }
}

okid_real *okid_lsq_equilibrated_copy(okid_identifier *id, int n, const okid_real *scale)
{
    const int w = id->dims_.w;
    okid_real *s = id->at_.r + 1; /* s(i, j) = s[i w + j] is R(j + 1, i): below R's diagonal, as j + 1 <= q < w */
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i <= j; ++i) {
            s[(size_t)i * (size_t)w + (size_t)j] = OKID_AT(id->at_.r, w, i, j) / scale[j];
        }
    }
    return s;
}

okid_status okid_lsq_solve(okid_identifier *id, int *regressor_rank, int *input_rank)
{
    const okid_dims_ *d = &id->dims_;
    const int q = d->q, m = d->m, w = d->w, nu = d->r * (d->p + 1);
    const okid_real tol = id->rank_tolerance_;
    okid_views_ *v = &id->at_;
    okid_lsq_column_norms(v->r, w, q, v->lsq_scale);

    /* Persistence of excitation: rank of the input-only regressor (leading nu columns). */
    okid_real *s = okid_lsq_equilibrated_copy(id, nu, v->lsq_scale);
    *input_rank = okid_triangular_lstsq(nu, 0, s, w, NULL, q, tol, v->lsq_perm, v->lsq_work);
    if (*input_rank < nu) {
        return OKID_E_RANK_DEFICIENT;
    }

    /* Minimum-norm solution of the equilibrated R11 x~ = R12, then x = diag(1/scale) x~. */
    okid_copy_matrix(q, m, v->r + (size_t)q * (size_t)w, w, v->x, q);
    s = okid_lsq_equilibrated_copy(id, q, v->lsq_scale);
    *regressor_rank = okid_triangular_lstsq(q, m, s, w, v->x, q, tol, v->lsq_perm, v->lsq_work);
    for (int j = 0; j < m; ++j) {
        for (int i = 0; i < q; ++i) {
            OKID_AT(v->x, q, i, j) /= v->lsq_scale[i];
        }
    }
    return OKID_OK;
}

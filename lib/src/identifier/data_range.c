/* SPDX-License-Identifier: Apache-2.0 */
/* See data_range.h. */
#include "identifier/data_range.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"

/* Norm of column j of the upper triangle of R, by the largest entry first (no overflow or underflow of squares). */
static okid_real column_norm(const okid_real *r, int ld, int j)
{
    okid_real amax = 0;
    for (int i = 0; i <= j; ++i) {
        const okid_real v = okid_fabs(OKID_AT(r, ld, i, j));
        amax = v > amax ? v : amax;
    }
    if (!(amax > 0) || !okid_is_finite(amax)) {
        return amax; /* 0, Inf or NaN */
    }
    okid_real s = 0;
    for (int i = 0; i <= j; ++i) {
        const okid_real v = OKID_AT(r, ld, i, j) / amax;
        s += v * v;
    }
    return amax * okid_sqrt(s);
}

okid_status okid_check_channel_range(const okid_identifier *id, const okid_real *factor)
{
    const okid_dims_ *d = &id->dims_;
    if (d->nz > 0 || id->rows_ == 0) {
        return OKID_OK;
    }
    /* rows weighed by lambda^age: sum of the weights, the rows' effective count */
    const okid_real lambda = id->forgetting_, rows = (okid_real)id->rows_;
    const okid_real weight = lambda < 1 ? (1 - okid_pow(lambda, rows)) / (1 - lambda) : rows;
    for (int ch = 0; ch < d->r + d->m; ++ch) {
        const int col = ch < d->r ? ch : d->q + (ch - d->r); /* u(k), then y(k) */
        const okid_real rms = column_norm(factor, d->w, col) / okid_sqrt(weight);
        if (rms != 0 && !okid_in_magnitude_range(rms)) {
            return OKID_E_DATA_RANGE;
        }
    }
    return OKID_OK;
}

uint64_t okid_rows_remembered(const okid_identifier *id)
{
    const okid_real lambda = id->forgetting_;
    if (lambda >= 1) {
        return id->rows_;
    }
    /* ages 0 .. 2 ln(tol) / ln(lambda); lambda in (0, 1), so the quotient is positive */
    const okid_real ages = 2 * okid_log(id->rank_tolerance_) / okid_log(lambda);
    const uint64_t remembered = ages < (okid_real)id->rows_ ? 1u + (uint64_t)ages : id->rows_;
    return remembered < id->rows_ ? remembered : id->rows_;
}

static int complex_finite(okid_complex z)
{
    return okid_is_finite(z.re) && okid_is_finite(z.im);
}

int okid_modes_finite(const okid_mode *modes, int num_modes, int m)
{
    for (int i = 0; i < num_modes; ++i) {
        const okid_mode *md = &modes[i];
#define OKID_X_NONE(...)
#define OKID_X_VALUE(name) md->name,
        const okid_real values[] = {OKID_MODE_FIELDS(OKID_X_NONE, OKID_X_VALUE, OKID_X_NONE, OKID_X_NONE)};
        for (size_t k = 0; k < sizeof values / sizeof values[0]; ++k) {
            if (!okid_is_finite(values[k])) {
                return 0;
            }
        }
#define OKID_X_NOT_FINITE(name) !complex_finite(md->name) ||
        if (OKID_MODE_FIELDS(OKID_X_NOT_FINITE, OKID_X_NONE, OKID_X_NONE, OKID_X_NONE) 0) {
            return 0;
        }
#undef OKID_X_NOT_FINITE
#undef OKID_X_VALUE
#undef OKID_X_NONE
        for (int a = 0; a < m; ++a) {
            if (!complex_finite(md->sensor_shape[a]) || !complex_finite(md->shape[a]) ||
                !complex_finite(md->shape[m + a])) {
                return 0;
            }
        }
    }
    return 1;
}

/* SPDX-License-Identifier: Apache-2.0 */
/* Small dense helpers in plain C; see dense.h. */
#include "numerics/dense.h"

#include "numerics/real_math.h"

void okid_copy_matrix(int rows, int cols, const okid_real *a, int lda, okid_real *b, int ldb)
{
    for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) {
            OKID_AT(b, ldb, i, j) = OKID_AT(a, lda, i, j);
        }
    }
}

void okid_zero_matrix(int rows, int cols, okid_real *a, int lda)
{
    for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) {
            OKID_AT(a, lda, i, j) = 0;
        }
    }
}

void okid_gemm(char transa, char transb, int m, int n, int k, okid_real alpha, const okid_real *a, int lda,
               const okid_real *b, int ldb, okid_real beta, okid_real *c, int ldc)
{
    const int ta = (transa == 'T');
    const int tb = (transb == 'T');
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < m; ++i) {
            okid_real sum = 0;
            for (int l = 0; l < k; ++l) {
                const okid_real x = ta ? OKID_AT(a, lda, l, i) : OKID_AT(a, lda, i, l);
                const okid_real y = tb ? OKID_AT(b, ldb, j, l) : OKID_AT(b, ldb, l, j);
                sum += x * y;
            }
            /* beta == 0 must not propagate NaN from uninitialised c, as in BLAS. */
            OKID_AT(c, ldc, i, j) = (beta == 0) ? alpha * sum : alpha * sum + beta * OKID_AT(c, ldc, i, j);
        }
    }
}

int okid_all_finite(int rows, int cols, const okid_real *a, int lda)
{
    for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) {
            if (!okid_is_finite(OKID_AT(a, lda, i, j))) {
                return 0;
            }
        }
    }
    return 1;
}

okid_status okid_lu_solve(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb)
{
    okid_real scale = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            const okid_real v = okid_fabs(OKID_AT(a, lda, i, j));
            scale = v > scale ? v : scale;
        }
    }
    if (scale == 0) {
        return OKID_E_DECOMPOSITION_FAILED;
    }
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i) {
            if (okid_fabs(OKID_AT(a, lda, i, k)) > okid_fabs(OKID_AT(a, lda, p, k))) {
                p = i;
            }
        }
        if (okid_fabs(OKID_AT(a, lda, p, k)) <= (okid_real)n * OKID_EPSILON * scale) {
            return OKID_E_DECOMPOSITION_FAILED;
        }
        if (p != k) {
            for (int j = 0; j < n; ++j) {
                const okid_real t = OKID_AT(a, lda, k, j);
                OKID_AT(a, lda, k, j) = OKID_AT(a, lda, p, j);
                OKID_AT(a, lda, p, j) = t;
            }
            for (int j = 0; j < nrhs; ++j) {
                const okid_real t = OKID_AT(b, ldb, k, j);
                OKID_AT(b, ldb, k, j) = OKID_AT(b, ldb, p, j);
                OKID_AT(b, ldb, p, j) = t;
            }
        }
        const okid_real pivot = OKID_AT(a, lda, k, k);
        for (int i = k + 1; i < n; ++i) {
            const okid_real f = OKID_AT(a, lda, i, k) / pivot;
            OKID_AT(a, lda, i, k) = f;
            for (int j = k + 1; j < n; ++j) {
                OKID_AT(a, lda, i, j) -= f * OKID_AT(a, lda, k, j);
            }
            for (int j = 0; j < nrhs; ++j) {
                OKID_AT(b, ldb, i, j) -= f * OKID_AT(b, ldb, k, j);
            }
        }
    }
    for (int j = 0; j < nrhs; ++j) {
        for (int i = n - 1; i >= 0; --i) {
            okid_real s = OKID_AT(b, ldb, i, j);
            for (int l = i + 1; l < n; ++l) {
                s -= OKID_AT(a, lda, i, l) * OKID_AT(b, ldb, l, j);
            }
            OKID_AT(b, ldb, i, j) = s / OKID_AT(a, lda, i, i);
        }
    }
    return OKID_OK;
}

okid_complex okid_cmul(okid_complex a, okid_complex b)
{
    okid_complex c = {a.re * b.re - a.im * b.im, a.re * b.im + a.im * b.re};
    return c;
}

okid_complex okid_cdiv(okid_complex a, okid_complex b)
{
    /* Smith's algorithm: avoids overflow in |b|^2. */
    okid_complex c;
    if (okid_fabs(b.re) >= okid_fabs(b.im)) {
        const okid_real ratio = b.im / b.re;
        const okid_real den = b.re + b.im * ratio;
        c.re = (a.re + a.im * ratio) / den;
        c.im = (a.im - a.re * ratio) / den;
    } else {
        const okid_real ratio = b.re / b.im;
        const okid_real den = b.re * ratio + b.im;
        c.re = (a.re * ratio + a.im) / den;
        c.im = (a.im * ratio - a.re) / den;
    }
    return c;
}

okid_real okid_cabs(okid_complex a)
{
    return okid_hypot(a.re, a.im);
}

okid_complex okid_clog(okid_complex a)
{
    okid_complex c = {okid_log(okid_cabs(a)), okid_atan2(a.im, a.re)};
    return c;
}

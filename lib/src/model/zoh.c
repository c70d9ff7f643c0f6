/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Exact zero-order-hold discretisation (eq. 13-14) from the exponential of the augmented matrix
 * E = [Ac Bc; 0 0] dt, whose exponential is [A B; 0 I]. The exponential is Higham's (2005)
 * scaling and squaring with the degree-13 Pade approximant.
 */
#include "okid/model.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "okid/limits.h"

static okid_real norm1(int n, const okid_real *a)
{
    okid_real best = 0;
    for (int j = 0; j < n; ++j) {
        okid_real s = 0;
        for (int i = 0; i < n; ++i) {
            s += okid_fabs(OKID_AT(a, n, i, j));
        }
        best = s > best ? s : best;
    }
    return best;
}

/* out = c1 x1 + c2 x2 + c3 x3 (+ c0 I when c0 != 0), all n x n. */
static void combine(int n, okid_real *out, okid_real c1, const okid_real *x1, okid_real c2, const okid_real *x2,
                    okid_real c3, const okid_real *x3, okid_real c0)
{
    const size_t nn = (size_t)n * (size_t)n;
    for (size_t k = 0; k < nn; ++k) {
        out[k] = c1 * x1[k] + c2 * x2[k] + c3 * x3[k];
    }
    for (int i = 0; i < n; ++i) {
        OKID_AT(out, n, i, i) += c0;
    }
}

/* expm of e (n x n, overwritten by the scaled copy) into out; work holds 6 n^2 reals. */
static okid_status expm_pade13(int n, okid_real *e, okid_real *out, okid_real *work)
{
    static const double b[14] = {64764752532480000.0, 32382376266240000.0, 7771770303897600.0,
                                 1187353796428800.0,  129060195264000.0,   10559470521600.0,
                                 670442572800.0,      33522128640.0,       1323241920.0,
                                 40840800.0,          960960.0,            16380.0,
                                 182.0,               1.0};
    const double theta13 = 5.371920351148152;
    const size_t nn = (size_t)n * (size_t)n;
    okid_real *a2 = work, *a4 = work + nn, *a6 = work + 2 * nn, *w = work + 3 * nn, *u = work + 4 * nn,
              *v = work + 5 * nn;

    int squarings = 0;
    const okid_real norm = norm1(n, e);
    if ((double)norm > theta13) {
        squarings = (int)ceil(log2((double)norm / theta13));
        const okid_real scale = okid_pow(OKID_R(2.0), (okid_real)-squarings);
        for (size_t k = 0; k < nn; ++k) {
            e[k] *= scale;
        }
    }
#define B(i) ((okid_real)b[i])
    okid_gemm('N', 'N', n, n, n, 1, e, n, e, n, 0, a2, n);
    okid_gemm('N', 'N', n, n, n, 1, a2, n, a2, n, 0, a4, n);
    okid_gemm('N', 'N', n, n, n, 1, a4, n, a2, n, 0, a6, n);
    /* U = E [A6 (b13 A6 + b11 A4 + b9 A2) + b7 A6 + b5 A4 + b3 A2 + b1 I] */
    combine(n, w, B(13), a6, B(11), a4, B(9), a2, 0);
    okid_gemm('N', 'N', n, n, n, 1, a6, n, w, n, 0, v, n);
    combine(n, w, B(7), a6, B(5), a4, B(3), a2, B(1));
    for (size_t k = 0; k < nn; ++k) {
        w[k] += v[k];
    }
    okid_gemm('N', 'N', n, n, n, 1, e, n, w, n, 0, u, n);
    /* V = A6 (b12 A6 + b10 A4 + b8 A2) + b6 A6 + b4 A4 + b2 A2 + b0 I */
    combine(n, w, B(12), a6, B(10), a4, B(8), a2, 0);
    okid_gemm('N', 'N', n, n, n, 1, a6, n, w, n, 0, v, n);
    combine(n, w, B(6), a6, B(4), a4, B(2), a2, B(0));
    for (size_t k = 0; k < nn; ++k) {
        v[k] += w[k];
    }
#undef B
    /* R = (V - U)^-1 (V + U) */
    for (size_t k = 0; k < nn; ++k) {
        const okid_real vk = v[k], uk = u[k];
        a2[k] = vk - uk;
        out[k] = vk + uk;
    }
    if (okid_lu_solve(n, n, a2, n, out, n) != OKID_OK) {
        return OKID_E_DECOMPOSITION_FAILED;
    }
    for (int s = 0; s < squarings; ++s) {
        okid_copy_matrix(n, n, out, n, a4, n);
        okid_gemm('N', 'N', n, n, n, 1, a4, n, a4, n, 0, out, n);
    }
    return OKID_OK;
}

okid_status okid_discretize_zoh(int n, int r, const okid_real *ac, const okid_real *bc, okid_real dt,
                                okid_real *a, okid_real *b, okid_real *work, size_t work_len)
{
    if (ac == NULL || a == NULL || work == NULL || (r > 0 && (bc == NULL || b == NULL))) {
        return OKID_E_NULL_POINTER;
    }
    if (n < 1 || n > OKID_MAX_ORDER || r < 0 || r > OKID_MAX_DIMENSION) {
        return OKID_E_BAD_SIZE;
    }
    if (work_len < OKID_ZOH_WORK_REALS(n, r)) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    if (!okid_is_finite(dt) || dt <= 0 || !okid_all_finite(n, n, ac, n) ||
        (r > 0 && !okid_all_finite(n, r, bc, n))) {
        return OKID_E_BAD_PARAMETER;
    }
    const int na = n + r;
    const size_t nn = (size_t)na * (size_t)na;
    okid_real *e = work, *expe = work + nn;
    okid_zero_matrix(na, na, e, na);
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) {
            OKID_AT(e, na, i, j) = OKID_AT(ac, n, i, j) * dt;
        }
    }
    for (int j = 0; j < r; ++j) {
        for (int i = 0; i < n; ++i) {
            OKID_AT(e, na, i, n + j) = OKID_AT(bc, n, i, j) * dt;
        }
    }
    const okid_status st = expm_pade13(na, e, expe, work + 2 * nn);
    if (st != OKID_OK) {
        return st;
    }
    if (!okid_all_finite(na, na, expe, na)) {
        return OKID_E_BAD_PARAMETER; /* Ac dt so large that e^(Ac dt) overflows */
    }
    okid_copy_matrix(n, n, expe, na, a, n);
    if (r > 0) {
        okid_copy_matrix(n, r, expe + (size_t)n * (size_t)na, na, b, n);
    }
    return OKID_OK;
}

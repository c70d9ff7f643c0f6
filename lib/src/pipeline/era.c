/* SPDX-License-Identifier: Apache-2.0 */
/*
 * ERA after Juang (1994), which corrects the paper's eq. 61: with H(0) = U S V',
 *   A = S^-1/2 U_n' H(1) V_n S^-1/2,  C = E_m' U_n S^1/2,  [B G] = S^1/2 V_n' E_(r+m),  D = Y_0.
 * Hankel blocks are Gamma_k = [Y_k, Y°_k] (m x (r + m), eq. 54 side by side, as E_(r+m) in eq. 61
 * requires) or Y_k alone. In the combined case each column of Gamma is scaled to unit norm over
 * the Hankel window first, so forces and sensors in any units weigh alike in the SVD; B and G
 * are unscaled exactly afterwards. With OKID_SCALING_AUTO the blocks are first balanced by the
 * channel scales, Gamma~_k = S_y^-1 [Y_k S_u, Y°_k S_y] (the Markov parameters of the scaled
 * data), and C = S_y C~ afterwards: the realization no longer depends on the channels' units.
 * H(1) is never formed: H(1) V_n is summed block by block.
 */
#include "pipeline/era.h"

#include "numerics/dense.h"
#include "okid/sizes.h" /* OKID__LWORK_GESVD: the SVD work's size */
#include "numerics/linalg.h"
#include "numerics/real_math.h"

/* Scale of input i (0 <= i < r) or output a (index r + a); 1 without scaling. */
static okid_real channel_scale(const okid_era_problem *pb, int channel)
{
    return pb->scales != NULL ? pb->scales[channel] : 1;
}

/* Gamma_k(a, l), k = 1..L, scaled by the column factor and by the scale of output a. */
static okid_real gamma_at(const okid_era_problem *pb, const okid_real *col_scale, int k, int a, int l)
{
    const int r = pb->r, m = pb->m;
    const okid_real raw = (l < r) ? OKID_AT(pb->markov, m, a, k * r + l)
                                  : OKID_AT(pb->markov_obs, m, a, (k - 1) * m + (l - r));
    return raw * col_scale[l] / channel_scale(pb, r + a);
}

static void column_scales(const okid_era_problem *pb, okid_real *col_scale)
{
    const int m = pb->m, nc = pb->ncols, L = pb->alpha + pb->beta;
    for (int l = 0; l < nc; ++l) {
        col_scale[l] = channel_scale(pb, l); /* input l, then the outputs of the observer block */
    }
    if (pb->markov_obs == NULL) {
        return;
    }
    for (int l = 0; l < nc; ++l) {
        okid_real s = 0;
        for (int k = 1; k <= L; ++k) {
            for (int a = 0; a < m; ++a) {
                const okid_real g = gamma_at(pb, col_scale, k, a, l);
                s += g * g;
            }
        }
        col_scale[l] *= (s > 0) ? 1 / okid_sqrt(s) : 1;
    }
}

/* Index of the largest ratio sigma_i / sigma_(i+1), i = 1..limit (1-based); a zero sigma_(i+1) wins at once. */
static int largest_gap(const okid_real *sv, int limit)
{
    int best = 1;
    okid_real best_ratio = -1;
    for (int i = 1; i <= limit; ++i) {
        if (sv[i] <= 0) {
            return (sv[i - 1] > 0) ? i : best;
        }
        const okid_real ratio = sv[i - 1] / sv[i];
        if (ratio > best_ratio) {
            best_ratio = ratio;
            best = i;
        }
    }
    return best;
}

okid_status okid_era_realize(const okid_era_problem *pb, const okid_era_scratch *v, const okid_era_output *out,
                             int *order, unsigned *warnings)
{
    const int m = pb->m, r = pb->r, nc = pb->ncols, alpha = pb->alpha, beta = pb->beta;
    const int hr = alpha * m, hc = beta * nc, k = hr < hc ? hr : hc;
    const int ldh = v->ldh, ldvt = v->ldvt;
    okid_real *col_scale = v->col_scale;
    column_scales(pb, col_scale);

    for (int j = 0; j < beta; ++j) {
        for (int l = 0; l < nc; ++l) {
            for (int i = 0; i < alpha; ++i) {
                for (int a = 0; a < m; ++a) {
                    OKID_AT(v->h, ldh, i * m + a, j * nc + l) = gamma_at(pb, col_scale, i + j + 1, a, l);
                }
            }
        }
    }
    /* Markov parameters that overflowed (data at the edge of the range, an ill-posed solve) would
       send the SVD into NaN arithmetic (reference LAPACK's xBDSQR then iterates for seconds): a
       property of the data, reported as such */
    for (int j = 0; j < hc; ++j) {
        for (int i = 0; i < hr; ++i) {
            if (!okid_is_finite(OKID_AT(v->h, ldh, i, j))) {
                return OKID_E_DATA_RANGE;
            }
        }
    }
    /* with v->leading, the singular vectors of the realized order only: the given one, or the
       automatic rule's largest (V' then holds OKID__SVD_VT_ROWS(hr, hc, that) rows) */
    const int limit = (k - 1 < pb->order_limit) ? k - 1 : pb->order_limit;
    const int nvec = !v->leading ? k : pb->order > 0 ? pb->order : (limit >= 1 ? limit : 1);
    const okid_status st = okid_la_svd(hr, hc, nvec, v->h, ldh, out->sv, v->vt, ldvt, v->work);
    if (st != OKID_OK) {
        return st;
    }
    const okid_real *u = v->h, *sv = out->sv;

    int n = pb->order;
    if (n == 0) {
        n = (limit >= 1) ? largest_gap(sv, limit) : 1;
        if (n == limit && limit < k - 1) {
            *warnings |= OKID_W_ORDER_AT_LIMIT;
        }
    }
    if (!(sv[0] > 0) || !(sv[n - 1] > OKID_EPSILON * (okid_real)k * sv[0])) {
        return OKID_E_RANK_DEFICIENT;
    }

    /* T = H(1) V_n. Each of its sums runs in the order of H(1)'s columns, the bits of one sum at a
       time; each element of H(1) is formed once, and V' is read down its columns (a row of V' at a
       time strode ldvt and formed every element n times: half of a 5-observer automatic
       identification's time). With room for one column of H(1) in the SVD's work, free now, each
       column updates T's columns as contiguous multiply-adds; else (a tiny Hankel matrix on the
       Eigen backend) each row of T at a time. */
    if ((size_t)hr <= (size_t)OKID__LWORK_GESVD(hr, hc)) {
        okid_real *column = v->work;
        for (int t = 0; t < n; ++t) {
            for (int row = 0; row < hr; ++row) OKID_AT(v->t, hr, row, t) = 0;
        }
        for (int j = 0; j < beta; ++j) {
            for (int l = 0; l < nc; ++l) {
                for (int i = 0; i < alpha; ++i) {
                    for (int a = 0; a < m; ++a) column[i * m + a] = gamma_at(pb, col_scale, i + j + 2, a, l);
                }
                for (int t = 0; t < n; ++t) {
                    const okid_real vt_tc = OKID_AT(v->vt, ldvt, t, j * nc + l);
                    okid_real *t_col = &OKID_AT(v->t, hr, 0, t);
                    for (int row = 0; row < hr; ++row) t_col[row] += column[row] * vt_tc;
                }
            }
        }
    } else {
        for (int i = 0; i < alpha; ++i) {
            for (int a = 0; a < m; ++a) {
                okid_real *row = &OKID_AT(v->t, hr, i * m + a, 0);
                for (int t = 0; t < n; ++t) row[(size_t)t * (size_t)hr] = 0;
                for (int j = 0; j < beta; ++j) {
                    for (int l = 0; l < nc; ++l) {
                        const okid_real g = gamma_at(pb, col_scale, i + j + 2, a, l);
                        const okid_real *vt_col = &OKID_AT(v->vt, ldvt, 0, j * nc + l);
                        for (int t = 0; t < n; ++t) row[(size_t)t * (size_t)hr] += g * vt_col[t];
                    }
                }
            }
        }
    }
    /* A = S^-1/2 U_n' T S^-1/2: four of its sums side by side (one add's latency per row had bound
       each alone), each still in row order */
    for (int t = 0; t < n; ++t) {
        const okid_real *t_col = &OKID_AT(v->t, hr, 0, t);
        int s = 0;
        for (; s + 4 <= n; s += 4) {
            const okid_real *u0 = &OKID_AT(u, ldh, 0, s), *u1 = u0 + ldh, *u2 = u1 + ldh, *u3 = u2 + ldh;
            okid_real acc0 = 0, acc1 = 0, acc2 = 0, acc3 = 0;
            for (int row = 0; row < hr; ++row) {
                const okid_real x = t_col[row];
                acc0 += u0[row] * x, acc1 += u1[row] * x, acc2 += u2[row] * x, acc3 += u3[row] * x;
            }
            OKID_AT(out->a, n, s, t) = acc0 / okid_sqrt(sv[s] * sv[t]);
            OKID_AT(out->a, n, s + 1, t) = acc1 / okid_sqrt(sv[s + 1] * sv[t]);
            OKID_AT(out->a, n, s + 2, t) = acc2 / okid_sqrt(sv[s + 2] * sv[t]);
            OKID_AT(out->a, n, s + 3, t) = acc3 / okid_sqrt(sv[s + 3] * sv[t]);
        }
        for (; s < n; ++s) {
            okid_real acc = 0;
            for (int row = 0; row < hr; ++row) {
                acc += OKID_AT(u, ldh, row, s) * t_col[row];
            }
            OKID_AT(out->a, n, s, t) = acc / okid_sqrt(sv[s] * sv[t]);
        }
    }
    for (int t = 0; t < n; ++t) {
        const okid_real root = okid_sqrt(sv[t]);
        for (int a = 0; a < m; ++a) {
            OKID_AT(out->c, m, a, t) = OKID_AT(u, ldh, a, t) * root * channel_scale(pb, r + a);
        }
        for (int l = 0; l < nc; ++l) {
            const okid_real value = root * OKID_AT(v->vt, ldvt, t, l) / col_scale[l];
            if (l < r) {
                OKID_AT(out->b, n, t, l) = value;
            } else {
                OKID_AT(out->g, n, t, l - r) = value;
            }
        }
    }
    okid_copy_matrix(m, r, pb->markov, m, out->d, m);
    *order = n;
    return OKID_OK;
}

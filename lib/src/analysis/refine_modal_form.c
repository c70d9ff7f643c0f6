/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's parametrisation: the real modal form of the start model. With A's
 * eigenvectors T (LAPACK layout: Re v, Im v per pair) A T = T diag(blocks), so B -> T^-1 B and
 * C -> C T. A pair's coordinates still admit a rotation-scaling S = [p q; -q p] that commutes with
 * its block: it is fixed by making the block's column of its strongest input [1; 0] (a real
 * mode's entry 1), which leaves n (r + m + 1) + m r free parameters at most. The innovation form
 * adds its gain K, transformed like B (T^-1 K, then S^-1 per block), n m parameters after D.
 */
#include "analysis/refine_internal.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"

/* Largest |lambda| the start model keeps: an unstable eigenvalue is reflected to 1 / conj(lambda). */
#define OKID_REFINE_MAX_MODULUS OKID_R(0.9999)

static void add_param(okid_refiner *rf, int *np, int kind, int block, int row, int col)
{
    int *t = rf->ptab_ + 4 * *np;
    t[0] = kind;
    t[1] = block;
    t[2] = row;
    t[3] = col;
    ++*np;
}

/* Reflect an eigenvalue on or outside the unit circle to inside it (same angle). */
static void pull_inside(okid_real *re, okid_real *im)
{
    const okid_real mod = okid_hypot(*re, *im);
    if (mod < OKID_REFINE_MAX_MODULUS) {
        return;
    }
    okid_real target = 1 / mod;
    if (target > OKID_REFINE_MAX_MODULUS) {
        target = OKID_REFINE_MAX_MODULUS;
    }
    *re *= target / mod;
    *im *= target / mod;
}

/* Make the block's column of its strongest input [1; 0] (or 1) by the commuting similarity S. */
static okid_status fix_block_scale(okid_refiner *rf, int first, int size, int *fixed_input)
{
    const int n = rf->n_, r = rf->r_, m = rf->m_;
    int best = 0;
    okid_real best_mag = -1;
    for (int j = 0; j < r; ++j) {
        const okid_real b1 = OKID_AT(rf->b_, n, first, j);
        const okid_real b2 = size == 2 ? OKID_AT(rf->b_, n, first + 1, j) : 0;
        const okid_real mag = okid_hypot(b1, b2);
        if (mag > best_mag) {
            best_mag = mag;
            best = j;
        }
    }
    if (!(best_mag > 0)) {
        return OKID_E_RANK_DEFICIENT;
    }
    *fixed_input = best;
    if (size == 1) {
        const okid_real p = OKID_AT(rf->b_, n, first, best);
        for (int j = 0; j < r; ++j) {
            OKID_AT(rf->b_, n, first, j) /= p;
        }
        for (int j = 0; rf->k_ != NULL && j < m; ++j) {
            OKID_AT(rf->k_, n, first, j) /= p;
        }
        for (int i = 0; i < m; ++i) {
            OKID_AT(rf->c_, m, i, first) *= p;
        }
        return OKID_OK;
    }
    /* S [1; 0] = b: p = b1, q = -b2; B <- S^-1 B, C <- C S. */
    const okid_real p = OKID_AT(rf->b_, n, first, best), q = -OKID_AT(rf->b_, n, first + 1, best);
    const okid_real det = p * p + q * q;
    for (int j = 0; j < r; ++j) {
        const okid_real b1 = OKID_AT(rf->b_, n, first, j), b2 = OKID_AT(rf->b_, n, first + 1, j);
        OKID_AT(rf->b_, n, first, j) = (p * b1 - q * b2) / det;
        OKID_AT(rf->b_, n, first + 1, j) = (q * b1 + p * b2) / det;
    }
    for (int j = 0; rf->k_ != NULL && j < m; ++j) {
        const okid_real k1 = OKID_AT(rf->k_, n, first, j), k2 = OKID_AT(rf->k_, n, first + 1, j);
        OKID_AT(rf->k_, n, first, j) = (p * k1 - q * k2) / det;
        OKID_AT(rf->k_, n, first + 1, j) = (q * k1 + p * k2) / det;
    }
    OKID_AT(rf->b_, n, first, best) = 1; /* exactly */
    OKID_AT(rf->b_, n, first + 1, best) = 0;
    for (int i = 0; i < m; ++i) {
        const okid_real c1 = OKID_AT(rf->c_, m, i, first), c2 = OKID_AT(rf->c_, m, i, first + 1);
        OKID_AT(rf->c_, m, i, first) = c1 * p - c2 * q;
        OKID_AT(rf->c_, m, i, first + 1) = c1 * q + c2 * p;
    }
    return OKID_OK;
}

okid_status okid_refine_modal_form(okid_refiner *rf, const okid_result *start)
{
    const int n = rf->n_, r = rf->r_, m = rf->m_;
    okid_real *a_copy = rf->nrm_[1], *vr = a_copy + (size_t)n * n, *wr = vr + (size_t)n * n, *wi = wr + n;
    okid_real *work = wi + n;
    okid_copy_matrix(n, n, start->A.data, start->A.ld, a_copy, n);
    okid_status st = okid_la_eig(n, a_copy, n, wr, wi, vr, n, work);
    if (st != OKID_OK) {
        return st;
    }
    /* C T, then T^-1 B (the LU overwrites T: the innovation form solves for K with a copy of T,
       into the eigenvalue scratch that is free now) */
    okid_gemm('N', 'N', m, n, n, 1, start->C.data, start->C.ld, vr, n, 0, rf->c_, m);
    const int observer_gain = rf->k_ != NULL && start->G.data != NULL && start->G.rows == n && start->G.cols == m;
    if (observer_gain) {
        okid_copy_matrix(n, n, vr, n, a_copy, n);
    }
    okid_copy_matrix(n, r, start->B.data, start->B.ld, rf->b_, n);
    st = okid_lu_solve(n, r, vr, n, rf->b_, n);
    if (st != OKID_OK) {
        return st;
    }
    if (rf->k_ != NULL) {
        /* the OKID observer x(k+1) = A x + B u - G (y - C x - D u) is the predictor with K = -G */
        for (int j = 0; j < m; ++j) {
            for (int i = 0; i < n; ++i) {
                OKID_AT(rf->k_, n, i, j) = observer_gain ? -OKID_AT(start->G.data, start->G.ld, i, j) : 0;
            }
        }
        if (observer_gain && okid_lu_solve(n, m, a_copy, n, rf->k_, n) != OKID_OK) {
            okid_zero_matrix(n, m, rf->k_, n);
        }
    }
    okid_copy_matrix(m, r, start->D.data, start->D.ld, rf->d_, m);

    /* blocks, the start eigenvalues and the scale of each mode's coordinates */
    int nb = 0;
    for (int j = 0; j < n; ++nb) {
        const int size = (wi[j] != 0 && j + 1 < n) ? 2 : 1;
        int *b = rf->blk_ + OKID_RB_INTS * nb;
        b[OKID_RB_FIRST] = j;
        b[OKID_RB_SIZE] = size;
        rf->lam_re_[nb] = wr[j];
        rf->lam_im_[nb] = size == 2 ? wi[j] : 0;
        if (size == 2) {
            pull_inside(&rf->lam_re_[nb], &rf->lam_im_[nb]);
        } else if (okid_fabs(wr[j]) >= OKID_REFINE_MAX_MODULUS) {
            rf->lam_re_[nb] = okid_copysign(OKID_REFINE_MAX_MODULUS, wr[j]);
        }
        st = fix_block_scale(rf, j, size, &b[OKID_RB_FIXED]);
        if (st != OKID_OK) {
            return st;
        }
        j += size;
    }
    rf->nblocks_ = nb;

    /* parameter table: per block its eigenvalue, free B entries and x0; then C and D */
    int np = 0;
    for (int k = 0; k < nb; ++k) {
        const int *b = rf->blk_ + OKID_RB_INTS * k;
        const int first = b[OKID_RB_FIRST], size = b[OKID_RB_SIZE];
        rf->blk_[OKID_RB_INTS * k + OKID_RB_LAMBDA] = np;
        add_param(rf, &np, OKID_RP_LAMBDA_RE, k, first, 0);
        if (size == 2) {
            add_param(rf, &np, OKID_RP_LAMBDA_IM, k, first, 0);
        }
        for (int j = 0; j < r; ++j) {
            for (int s = 0; s < size && j != b[OKID_RB_FIXED]; ++s) {
                add_param(rf, &np, OKID_RP_B, k, first + s, j);
            }
        }
        for (int s = 0; s < size; ++s) {
            add_param(rf, &np, OKID_RP_X0, k, first + s, 0);
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < m; ++i) {
            add_param(rf, &np, OKID_RP_C, -1, i, j);
        }
    }
    for (int j = 0; j < r; ++j) {
        for (int i = 0; i < m; ++i) {
            add_param(rf, &np, OKID_RP_D, -1, i, j);
        }
    }
    for (int j = 0; rf->k_ != NULL && j < m; ++j) {
        for (int i = 0; i < n; ++i) {
            add_param(rf, &np, OKID_RP_K, -1, i, j);
        }
    }
    rf->np_ = np;
    for (int i = 0; i < n; ++i) {
        rf->x0_[i] = 0;
    }
    /* the observer's gain is a start only where its predictor is stable with the (reflected) A;
       else the documented start K = 0, the output-error predictor */
    if (rf->k_ != NULL && (!okid_all_finite(n, m, rf->k_, n) || !okid_refine_stable(rf))) {
        okid_zero_matrix(n, m, rf->k_, n);
    }
    /* theta from the arrays */
    for (int p = 0; p < np; ++p) {
        const int *t = rf->ptab_ + 4 * p;
        okid_real v = 0;
        switch (t[0]) {
        case OKID_RP_LAMBDA_RE: v = rf->lam_re_[t[1]]; break;
        case OKID_RP_LAMBDA_IM: v = rf->lam_im_[t[1]]; break;
        case OKID_RP_B: v = OKID_AT(rf->b_, n, t[2], t[3]); break;
        case OKID_RP_X0: v = rf->x0_[t[2]]; break;
        case OKID_RP_C: v = OKID_AT(rf->c_, m, t[2], t[3]); break;
        case OKID_RP_K: v = OKID_AT(rf->k_, n, t[2], t[3]); break;
        default: v = OKID_AT(rf->d_, m, t[2], t[3]); break;
        }
        rf->theta_best_[p] = rf->theta_[p] = v;
    }
    return okid_all_finite(n, r, rf->b_, n) && okid_all_finite(m, n, rf->c_, m) ? OKID_OK
                                                                               : OKID_E_DECOMPOSITION_FAILED;
}

void okid_refine_apply(okid_refiner *rf, const okid_real *theta)
{
    const int n = rf->n_, m = rf->m_;
    for (int p = 0; p < rf->np_; ++p) {
        const int *t = rf->ptab_ + 4 * p;
        switch (t[0]) {
        case OKID_RP_LAMBDA_RE: rf->lam_re_[t[1]] = theta[p]; break;
        case OKID_RP_LAMBDA_IM: rf->lam_im_[t[1]] = theta[p]; break;
        case OKID_RP_B: OKID_AT(rf->b_, n, t[2], t[3]) = theta[p]; break;
        case OKID_RP_X0: rf->x0_[t[2]] = theta[p]; break;
        case OKID_RP_C: OKID_AT(rf->c_, m, t[2], t[3]) = theta[p]; break;
        case OKID_RP_K: OKID_AT(rf->k_, n, t[2], t[3]) = theta[p]; break;
        default: OKID_AT(rf->d_, m, t[2], t[3]) = theta[p]; break;
        }
    }
}

int okid_refine_stable(okid_refiner *rf)
{
    for (int k = 0; k < rf->nblocks_; ++k) {
        if (!(okid_hypot(rf->lam_re_[k], rf->lam_im_[k]) < 1)) {
            return 0;
        }
    }
    if (rf->k_ == NULL) {
        return 1;
    }
    /* the predictor's A - K C: its eigenvalues, in the spare normal-matrix buffer */
    const int n = rf->n_, m = rf->m_;
    okid_real *f = rf->nrm_[1 - rf->best_], *vr = f + (size_t)n * n, *wr = vr + (size_t)n * n, *wi = wr + n;
    okid_zero_matrix(n, n, f, n);
    for (int k = 0; k < rf->nblocks_; ++k) {
        const int first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
        OKID_AT(f, n, first, first) = rf->lam_re_[k];
        if (rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE] == 2) {
            OKID_AT(f, n, first, first + 1) = rf->lam_im_[k];
            OKID_AT(f, n, first + 1, first) = -rf->lam_im_[k];
            OKID_AT(f, n, first + 1, first + 1) = rf->lam_re_[k];
        }
    }
    okid_gemm('N', 'N', n, n, m, -1, rf->k_, n, rf->c_, m, 1, f, n);
    if (!okid_all_finite(n, n, f, n) || okid_la_eig(n, f, n, wr, wi, vr, n, wi + n) != OKID_OK) {
        return 0;
    }
    for (int i = 0; i < n; ++i) {
        if (!(okid_hypot(wr[i], wi[i]) < 1)) {
            return 0;
        }
    }
    return 1;
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's residual tests (refine.h, docs/refinement.md): per output the lagged products
 * of the residual (a ring of its last OKID_REFINE_LAGS values, so fixed memory), the Ljung-Box
 * statistic and fit they give at the end, and the block sums of the score that the sandwich
 * covariance needs when the residual is not white.
 */
#include "analysis/refine_internal.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"

void okid_refine_tests_begin_pass(okid_refiner *rf)
{
    const int m = rf->m_, np = rf->np_, lags = OKID_REFINE_LAGS;
    for (int k = 0; k < m * lags; ++k) {
        rf->lag_ring_[k] = rf->acf_[k] = 0;
    }
    for (int i = 0; i < m; ++i) {
        rf->ysum_[i] = 0;
    }
    rf->lag_pos_ = 0;
    /* the score's blocks: only in Jacobian passes once the record's length is known */
    const int spare = 1 - rf->best_;
    rf->score_ok_[spare] = rf->passes_ > 0 && rf->samples_ > 0;
    rf->block_len_ = (rf->samples_ + OKID_REFINE_SCORE_BLOCKS - 1) / OKID_REFINE_SCORE_BLOCKS;
    if (rf->score_ok_[spare]) {
        okid_real *s = rf->score_[spare];
        for (size_t k = 0; k < (size_t)np * (size_t)np; ++k) {
            s[k] = 0;
        }
        for (size_t k = 0; k < (size_t)m * (size_t)np; ++k) {
            rf->grad_mark_[k] = 0;
        }
    }
}

void okid_refine_tests_sample(okid_refiner *rf, const okid_real *e, const okid_real *y)
{
    const int m = rf->m_, lags = OKID_REFINE_LAGS;
    /* the ring holds e(k-1) at lag_pos_, e(k-2) before it, ...; zeros before the record's start */
    for (int i = 0; i < m; ++i) {
        const okid_real *ring = rf->lag_ring_ + (size_t)i * (size_t)lags;
        okid_real *acf = rf->acf_ + (size_t)i * (size_t)lags;
        int pos = rf->lag_pos_;
        for (int l = 0; l < lags; ++l) {
            acf[l] += e[i] * ring[pos];
            pos = pos == 0 ? lags - 1 : pos - 1;
        }
        rf->ysum_[i] += y[i];
    }
    rf->lag_pos_ = rf->lag_pos_ + 1 == lags ? 0 : rf->lag_pos_ + 1;
    for (int i = 0; i < m; ++i) {
        rf->lag_ring_[(size_t)i * (size_t)lags + (size_t)rf->lag_pos_] = e[i];
    }
}

void okid_refine_tests_close_block(okid_refiner *rf)
{
    const int m = rf->m_, np = rf->np_, spare = 1 - rf->best_;
    if (!rf->score_ok_[spare]) {
        return;
    }
    /* the block's score sum_k J_k' W e_k with the weights of the normal matrix */
    okid_real *g = rf->score_sum_, *s = rf->score_[spare];
    for (int p = 0; p < np; ++p) {
        okid_real v = 0;
        for (int i = 0; i < m; ++i) {
            const size_t at = (size_t)i * (size_t)np + (size_t)p;
            v += rf->weight_[i] * (rf->grad_[at] - rf->grad_mark_[at]);
            rf->grad_mark_[at] = rf->grad_[at];
        }
        g[p] = v;
    }
    for (int q = 0; q < np; ++q) {
        if (g[q] == 0) {
            continue;
        }
        okid_real *sq = s + (size_t)q * (size_t)np;
        for (int p = 0; p <= q; ++p) {
            sq[p] += g[p] * g[q];
        }
    }
}

void okid_refine_tests_accept(okid_refiner *rf)
{
    for (int k = 0; k < rf->m_ * OKID_REFINE_LAGS; ++k) {
        rf->acf_best_[k] = rf->acf_[k];
    }
}

void okid_refine_tests_finish(okid_refiner *rf, int diverged)
{
    const int m = rf->m_, lags = OKID_REFINE_LAGS;
    const okid_real n = (okid_real)rf->samples_used_;
    rf->covariance_ = OKID_REFINE_COVARIANCE_FISHER;
    unsigned all = 0;
    for (int i = 0; i < m; ++i) {
        rf->out_warn_[i] = 0;
        if (diverged || !(n > lags)) {
            rf->whiteness_[i] = rf->max_acf_[i] = rf->fit_[i] = -1;
            continue;
        }
        const okid_real ss = rf->rms_[i] * rf->rms_[i] * n;
        const okid_real *acf = rf->acf_best_ + (size_t)i * (size_t)lags;
        okid_real q = 0, largest = 0;
        for (int l = 0; l < lags; ++l) {
            const okid_real r = ss > 0 ? acf[l] / ss : 0;
            q += r * r / (n - (okid_real)(l + 1));
            largest = okid_fabs(r) > largest ? okid_fabs(r) : largest;
        }
        rf->whiteness_[i] = n * (n + 2) * q;
        rf->max_acf_[i] = largest;
        const okid_real centred = rf->yy_[i] - rf->ysum_[i] * rf->ysum_[i] / n;
        rf->fit_[i] = centred > 0 ? 100 * (1 - okid_sqrt(ss / centred)) : -1;
        /* a model that reproduces the output to round-off (noise-free data, the refinement's exact
           convergence) leaves residuals that are round-off, not noise: no test to fail */
        const okid_real exact = (1000 * OKID_EPSILON) * (1000 * OKID_EPSILON) * rf->yy_[i];
        if (ss <= exact) {
            continue;
        }
        if (rf->whiteness_[i] > (okid_real)OKID_REFINE_WHITENESS_BOUND) {
            rf->out_warn_[i] |= OKID_W_RESIDUAL_NOT_WHITE;
        }
        if (centred > 0 && rf->fit_[i] < (okid_real)OKID_REFINE_FIT_LOW) {
            rf->out_warn_[i] |= OKID_W_OUTPUT_NOT_EXPLAINED;
        }
        all |= rf->out_warn_[i];
    }
    rf->test_warnings_ = all;
    if ((all & OKID_W_RESIDUAL_NOT_WHITE) && rf->score_ok_[rf->best_]) {
        rf->covariance_ = OKID_REFINE_COVARIANCE_SANDWICH;
    }
}

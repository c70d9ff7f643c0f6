/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's residual tests (refine.h, docs/refinement.md): per output the lagged products
 * of the residual (a ring of its last OKID_REFINE_LAGS values, so fixed memory), the Ljung-Box
 * statistic and fit they give at the end; per (input, output) pair the lagged products of the
 * residual with the input (a ring of the last OKID_REFINE_LAGS inputs) and the cross-correlation
 * test they give at the end; and the block sums of the score that the sandwich
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
        rf->ysum_[i] = rf->esum_[i] = 0;
    }
    rf->lag_pos_ = 0;
    const int r = rf->r_;
    for (int k = 0; k < m * r * lags; ++k) {
        rf->ccf_[k] = 0;
    }
    for (int k = 0; k < r * lags; ++k) {
        rf->u_ring_[k] = rf->uacf_[k] = 0;
    }
    for (int j = 0; j < r; ++j) {
        rf->usum_[j] = 0;
    }
    rf->u_pos_ = 0;
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

void okid_refine_tests_sample(okid_refiner *rf, const okid_real *e, const okid_real *y, const okid_real *u)
{
    const int m = rf->m_, r = rf->r_, lags = OKID_REFINE_LAGS;
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
        rf->esum_[i] += e[i];
    }
    /* the input ring: u(k) at u_pos_ once stored, u(k-1) before it, ...; lag 0 is this sample.
       Like the residual's, its lags count used samples (a gap in the outputs is skipped). */
    const int pos = rf->u_pos_ = rf->u_pos_ + 1 == lags ? 0 : rf->u_pos_ + 1;
    for (int j = 0; j < r; ++j) {
        okid_real *ring = rf->u_ring_ + (size_t)j * (size_t)lags;
        ring[pos] = u[j];
        /* lag l is ring[pos - l] for l <= pos, ring[lags + pos - l] after the wrap: two plain loops */
        const okid_real *wrap = ring + lags + pos;
        okid_real *uacf = rf->uacf_ + (size_t)j * (size_t)lags;
        for (int l = 0; l <= pos; ++l) {
            uacf[l] += u[j] * ring[pos - l];
        }
        for (int l = pos + 1; l < lags; ++l) {
            uacf[l] += u[j] * wrap[-l];
        }
        okid_real *ccf = rf->ccf_ + (size_t)m * (size_t)j * (size_t)lags;
        for (int i = 0; i < m; ++i, ccf += lags) {
            const okid_real ei = e[i];
            for (int l = 0; l <= pos; ++l) {
                ccf[l] += ei * ring[pos - l];
            }
            for (int l = pos + 1; l < lags; ++l) {
                ccf[l] += ei * wrap[-l];
            }
        }
        rf->usum_[j] += u[j];
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
    for (int k = 0; k < rf->m_ * rf->r_ * OKID_REFINE_LAGS; ++k) {
        rf->ccf_best_[k] = rf->ccf_[k];
    }
    for (int i = 0; i < rf->m_; ++i) {
        rf->esum_best_[i] = rf->esum_[i];
    }
}

/*
 * The cross-correlation test of output i's residual with each input j (refine.h): the centred,
 * normalised rho(l) = sum_k e~(k) u~(k - l) / sqrt(sum e~^2 sum u~^2), l = 0..lags-1 (the centring
 * through the sums: exact at lag 0, O(l / N) at lag l). Under independence of the residual and the
 * input rho(l) is asymptotically normal with variance v / N, v = 1 + 2 sum_{k>=1} r_e(k) r_u(k)
 * (Bartlett; Ljung 1999, section 16.6: P = sum_k R_e(k) R_u(k)), here summed over the lags the
 * ring holds and taken >= 1 (conservative where the truncated estimate dips below). The statistic
 * is the largest |rho(l)| sqrt(N / v); returns 1 when it exceeds OKID_REFINE_INPUT_CORRELATION_BOUND.
 */
static int cross_correlation(okid_refiner *rf, int i, okid_real n, okid_real ss)
{
    const int m = rf->m_, r = rf->r_, lags = OKID_REFINE_LAGS;
    const okid_real emean = rf->esum_best_[i] / n;
    const okid_real see = ss - emean * rf->esum_best_[i];
    const okid_real *acf = rf->acf_best_ + (size_t)i * (size_t)lags; /* acf[l]: lag l + 1 */
    int fails = 0;
    for (int j = 0; j < r; ++j) {
        const size_t at = (size_t)i + (size_t)m * (size_t)j;
        const okid_real *uacf = rf->uacf_ + (size_t)j * (size_t)lags; /* uacf[l]: lag l */
        const okid_real umean = rf->usum_[j] / n;
        const okid_real suu = uacf[0] - umean * rf->usum_[j];
        if (!(see > 0) || !(suu > 0)) { /* a constant input (or residual) cannot correlate */
            rf->xcorr_[at] = rf->max_xcorr_[at] = rf->xcorr_band_[at] = -1;
            continue;
        }
        okid_real v = 1;
        for (int l = 1; l < lags; ++l) {
            const okid_real re = (acf[l - 1] - n * emean * emean) / see;
            const okid_real ru = (uacf[l] - n * umean * umean) / suu;
            v += 2 * re * ru;
        }
        v = v > 1 ? v : 1;
        const okid_real norm = okid_sqrt(see * suu), sd = okid_sqrt(v / n);
        const okid_real *ccf = rf->ccf_best_ + at * (size_t)lags;
        okid_real largest = 0;
        for (int l = 0; l < lags; ++l) {
            const okid_real rho = okid_fabs(ccf[l] - n * emean * umean) / norm;
            largest = rho > largest ? rho : largest;
        }
        rf->max_xcorr_[at] = largest;
        rf->xcorr_[at] = largest / sd;
        rf->xcorr_band_[at] = (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND * sd;
        fails |= rf->xcorr_[at] > (okid_real)OKID_REFINE_INPUT_CORRELATION_BOUND;
    }
    return fails;
}

void okid_refine_tests_finish(okid_refiner *rf, int diverged)
{
    const int m = rf->m_, lags = OKID_REFINE_LAGS;
    const okid_real n = (okid_real)rf->samples_used_;
    rf->covariance_ = OKID_REFINE_COVARIANCE_FISHER;
    unsigned all = 0;
    for (int i = 0; i < m; ++i) {
        rf->out_warn_[i] = 0;
        for (int j = 0; j < rf->r_; ++j) {
            const size_t at = (size_t)i + (size_t)m * (size_t)j;
            rf->xcorr_[at] = rf->max_xcorr_[at] = rf->xcorr_band_[at] = -1;
        }
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
        const int correlated = cross_correlation(rf, i, n, ss);
        /* a model that reproduces the output to round-off (noise-free data, the refinement's exact
           convergence) leaves residuals that are round-off, not noise: no test to fail */
        const okid_real exact = (1000 * OKID_EPSILON) * (1000 * OKID_EPSILON) * rf->yy_[i];
        if (ss <= exact) {
            continue;
        }
        if (rf->whiteness_[i] > (okid_real)OKID_REFINE_WHITENESS_BOUND) {
            rf->out_warn_[i] |= OKID_W_RESIDUAL_NOT_WHITE;
        }
        if (correlated) {
            rf->out_warn_[i] |= OKID_W_RESIDUAL_INPUT_CORRELATED;
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

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's linear algebra and its error bars: the damped normal equations (scaled to a
 * unit diagonal, Cholesky), the covariance of the parameters as the inverse of the Fisher
 * information (the Gauss-Newton matrix with the weights N / s_i), and its propagation to each
 * mode by the delta method: eigenvalue -> pole s = ln(lambda) / dt -> frequency |s| / 2 pi and
 * damping -Re s / |s| analytically, the normalised sensor shape by central differences in C.
 */
#include "analysis/refine_internal.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"
#include "pipeline/modal_internal.h"

/* Upper Cholesky factor of the unit-diagonal scaling of N + mu diag(N) into f; d gets sqrt(diag N). */
static int scaled_cholesky(int np, const okid_real *nrm, okid_real mu, okid_real *f, okid_real *d)
{
    for (int p = 0; p < np; ++p) {
        const okid_real v = OKID_AT(nrm, np, p, p);
        if (!(v > 0) || !okid_is_finite(v)) {
            return 0;
        }
        d[p] = okid_sqrt(v);
    }
    for (int j = 0; j < np; ++j) {
        for (int i = 0; i <= j; ++i) {
            okid_real v = (i == j) ? 1 + mu : OKID_AT(nrm, np, i, j) / (d[i] * d[j]);
            for (int k = 0; k < i; ++k) {
                v -= OKID_AT(f, np, k, i) * OKID_AT(f, np, k, j);
            }
            if (i == j) {
                if (!(v > OKID_EPSILON * 4)) {
                    return 0;
                }
                OKID_AT(f, np, j, j) = okid_sqrt(v);
            } else {
                OKID_AT(f, np, i, j) = v / OKID_AT(f, np, i, i);
            }
        }
    }
    return 1;
}

/* x = (U'U)^-1 x in place. */
static void cholesky_solve(int np, const okid_real *f, okid_real *x)
{
    for (int i = 0; i < np; ++i) {
        okid_real v = x[i];
        for (int k = 0; k < i; ++k) {
            v -= OKID_AT(f, np, k, i) * x[k];
        }
        x[i] = v / OKID_AT(f, np, i, i);
    }
    for (int i = np - 1; i >= 0; --i) {
        okid_real v = x[i];
        for (int k = i + 1; k < np; ++k) {
            v -= OKID_AT(f, np, i, k) * x[k];
        }
        x[i] = v / OKID_AT(f, np, i, i);
    }
}

int okid_refine_damped_solve(int np, const okid_real *nrm, okid_real mu, const okid_real *g, okid_real *f,
                             okid_real *d, okid_real *x)
{
    if (!scaled_cholesky(np, nrm, mu, f, d)) {
        return 0;
    }
    for (int p = 0; p < np; ++p) {
        x[p] = g[p] / d[p];
    }
    cholesky_solve(np, f, x);
    for (int p = 0; p < np; ++p) {
        x[p] /= d[p];
        if (!okid_is_finite(x[p])) {
            return 0;
        }
    }
    return 1;
}

/* P = N^-1 into out (np x np, full) from the scaled factor f and scales d. */
static void covariance(int np, const okid_real *f, const okid_real *d, okid_real *out)
{
    for (int j = 0; j < np; ++j) {
        okid_real *col = out + (size_t)j * (size_t)np;
        for (int i = 0; i < np; ++i) {
            col[i] = (i == j) ? 1 / d[j] : 0;
        }
        cholesky_solve(np, f, col);
        for (int i = 0; i < np; ++i) {
            col[i] /= d[i];
        }
    }
}

/*
 * The sandwich P S P (P = H^-1 full, S the score's block covariance, upper triangle) into s; t is
 * np x np scratch. The weights of H and S are relative to noise_scale_, which cancels in P S P:
 * divided by its square here so that the common scaling by noise_scale_ below leaves it right.
 */
static void sandwich(int np, const okid_real *p, okid_real *s, okid_real *t, okid_real noise_scale)
{
    for (int j = 0; j < np; ++j) {
        for (int i = j + 1; i < np; ++i) {
            OKID_AT(s, np, i, j) = OKID_AT(s, np, j, i);
        }
    }
    /* plain loops, not the BLAS: the same sums in the same order on every backend and target */
    for (int j = 0; j < np; ++j) {
        for (int i = 0; i < np; ++i) {
            okid_real v = 0;
            for (int k = 0; k < np; ++k) {
                v += OKID_AT(p, np, i, k) * OKID_AT(s, np, k, j);
            }
            OKID_AT(t, np, i, j) = v;
        }
    }
    /* the block sums add up to the gradient, zero at the optimum: blocks - 1 degrees of freedom */
    const int blocks = OKID_REFINE_SCORE_BLOCKS;
    const okid_real w = (okid_real)blocks / (okid_real)(blocks - 1) / (noise_scale * noise_scale);
    for (int j = 0; j < np; ++j) {
        for (int i = 0; i < np; ++i) {
            okid_real v = 0;
            for (int k = 0; k < np; ++k) {
                v += OKID_AT(t, np, i, k) * OKID_AT(p, np, k, j);
            }
            OKID_AT(s, np, i, j) = v * w;
        }
    }
}

/* The block whose eigenvalue is the mode's. */
static int block_of(const okid_refiner *rf, const okid_mode *mode)
{
    int best = -1;
    okid_real best_dist = 0;
    for (int k = 0; k < rf->nblocks_; ++k) {
        if ((rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE] == 2) != (mode->is_pair != 0)) {
            continue;
        }
        const okid_real dist = okid_hypot(mode->eigenvalue.re - rf->lam_re_[k], mode->eigenvalue.im - rf->lam_im_[k]);
        if (best < 0 || dist < best_dist) {
            best = k;
            best_dist = dist;
        }
    }
    return best;
}

/* The normalised sensor shape of block k with C perturbed by h in entry (i, first + s). */
static void block_shape(const okid_refiner *rf, int k, int pi, int ps, okid_real h, okid_complex *out)
{
    const int m = rf->m_, first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
    const int pair = rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE] == 2;
    for (int i = 0; i < m; ++i) {
        out[i].re = OKID_AT(rf->c_, m, i, first) + (i == pi && ps == 0 ? h : 0);
        out[i].im = pair ? OKID_AT(rf->c_, m, i, first + 1) + (i == pi && ps == 1 ? h : 0) : 0;
    }
    okid_normalise_shape(out, m);
}

/* Standard deviations of one mode from the covariance p of theta (np x np). */
static void mode_std(okid_refiner *rf, const okid_mode *mode, int k, const okid_real *p, okid_mode_std *out,
                     okid_complex *shape_std)
{
    const int np = rf->np_, m = rf->m_, size = rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE];
    const int il = rf->blk_[OKID_RB_INTS * k + OKID_RB_LAMBDA];
    /* covariance of (Re lambda, Im lambda) */
    const okid_real prr = OKID_AT(p, np, il, il);
    const okid_real pii = size == 2 ? OKID_AT(p, np, il + 1, il + 1) : 0;
    const okid_real pri = size == 2 ? OKID_AT(p, np, il, il + 1) : 0;
    out->eigenvalue.re = okid_sqrt(prr);
    out->eigenvalue.im = okid_sqrt(pii);
    /* d(sigma, omega) / d(a, b) = [a b; -b a] / (|lambda|^2 dt) (Cauchy-Riemann) */
    const okid_real a = mode->eigenvalue.re, b = mode->eigenvalue.im;
    const okid_real scale = 1 / ((a * a + b * b) * rf->dt_);
    const okid_real j11 = a * scale, j12 = b * scale, j21 = -b * scale, j22 = a * scale;
    const okid_real css = j11 * j11 * prr + 2 * j11 * j12 * pri + j12 * j12 * pii;
    const okid_real cww = j21 * j21 * prr + 2 * j21 * j22 * pri + j22 * j22 * pii;
    const okid_real csw = j11 * j21 * prr + (j11 * j22 + j12 * j21) * pri + j12 * j22 * pii;
    out->pole.re = okid_sqrt(css);
    out->pole.im = okid_sqrt(cww);
    const okid_real sg = mode->pole.re, om = mode->pole.im, mag = okid_hypot(sg, om);
    if (mag > 0) {
        const okid_real fs = sg / (2 * OKID_PI * mag), fw = om / (2 * OKID_PI * mag);
        const okid_real m3 = mag * mag * mag, zs = -om * om / m3, zw = sg * om / m3;
        const okid_real vf = fs * fs * css + 2 * fs * fw * csw + fw * fw * cww;
        const okid_real vz = zs * zs * css + 2 * zs * zw * csw + zw * zw * cww;
        out->frequency_hz = okid_sqrt(vf > 0 ? vf : 0);
        out->damping_ratio = okid_sqrt(vz > 0 ? vz : 0);
    } else {
        out->frequency_hz = out->damping_ratio = -1;
    }
    /* shape: central differences of the normalised C psi in the block's C columns */
    const int first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
    int cbase = 0;
    while (rf->ptab_[4 * cbase] != OKID_RP_C) {
        ++cbase;
    }
    okid_real norm = 0;
    for (int i = 0; i < m; ++i) {
        for (int s = 0; s < size; ++s) {
            norm += OKID_AT(rf->c_, m, i, first + s) * OKID_AT(rf->c_, m, i, first + s);
        }
        shape_std[i].re = shape_std[i].im = 0;
    }
    const okid_real h = okid_sqrt(OKID_EPSILON) * okid_sqrt(norm);
    /* in the spare normal-matrix buffer (np^2 >= 4 m^2 + 8 m reals): the 2 m x (size m) derivatives,
       a column per C parameter, then the two perturbed shapes */
    okid_real *grad = rf->nrm_[1 - rf->best_];
    okid_complex *plus = (okid_complex *)(grad + 4u * (size_t)m * (size_t)m), *minus = plus + m;
    const int cols = size * m;
    for (int c = 0; c < cols; ++c) {
        const int pi = c % m, ps = c / m;
        block_shape(rf, k, pi, ps, h, plus);
        block_shape(rf, k, pi, ps, -h, minus);
        for (int i = 0; i < m; ++i) {
            grad[(size_t)c * 2u * (size_t)m + 2u * (size_t)i] = (plus[i].re - minus[i].re) / (2 * h);
            grad[(size_t)c * 2u * (size_t)m + 2u * (size_t)i + 1u] = (plus[i].im - minus[i].im) / (2 * h);
        }
    }
    for (int i = 0; i < 2 * m; ++i) {
        okid_real v = 0;
        for (int c1 = 0; c1 < cols; ++c1) {
            const int q1 = cbase + (first + c1 / m) * m + c1 % m; /* C(i, j) is parameter cbase + i + j m */
            for (int c2 = 0; c2 < cols; ++c2) {
                const int q2 = cbase + (first + c2 / m) * m + c2 % m;
                v += grad[(size_t)c1 * 2u * (size_t)m + (size_t)i] * OKID_AT(p, np, q1, q2) *
                     grad[(size_t)c2 * 2u * (size_t)m + (size_t)i];
            }
        }
        v = okid_sqrt(v > 0 ? v : 0);
        if (i % 2 == 0) {
            shape_std[i / 2].re = v;
        } else {
            shape_std[i / 2].im = v;
        }
    }
    out->sensor_shape = shape_std;
}

okid_status okid_refine_modes_and_std(okid_refiner *rf, int with_covariance)
{
    const int n = rf->n_, m = rf->m_, np = rf->np_;
    okid_real *spare = rf->nrm_[1 - rf->best_], *p = rf->nrm_[rf->best_];
    rf->std_status_ = with_covariance ? OKID_OK : OKID_E_NOT_AVAILABLE;
    if (with_covariance) {
        with_covariance = scaled_cholesky(np, p, 0, spare, rf->diag_);
        if (!with_covariance) {
            rf->std_status_ = OKID_E_RANK_DEFICIENT;
        }
        if (with_covariance) {
            covariance(np, spare, rf->diag_, p);
            if (rf->covariance_ == OKID_REFINE_COVARIANCE_SANDWICH) {
                sandwich(np, p, rf->score_[rf->best_], rf->score_[1 - rf->best_], rf->noise_scale_);
                p = rf->score_[rf->best_];
            }
        }
    }
    if (!with_covariance) {
        rf->covariance_ = OKID_REFINE_COVARIANCE_FISHER; /* no stds at all: nothing was sandwiched */
    }
    /* the block-diagonal A and its modes */
    okid_zero_matrix(n, n, rf->a_full_, n);
    for (int k = 0; k < rf->nblocks_; ++k) {
        const int first = rf->blk_[OKID_RB_INTS * k + OKID_RB_FIRST];
        OKID_AT(rf->a_full_, n, first, first) = rf->lam_re_[k];
        if (rf->blk_[OKID_RB_INTS * k + OKID_RB_SIZE] == 2) {
            OKID_AT(rf->a_full_, n, first, first + 1) = rf->lam_im_[k];
            OKID_AT(rf->a_full_, n, first + 1, first) = -rf->lam_im_[k];
            OKID_AT(rf->a_full_, n, first + 1, first + 1) = rf->lam_re_[k];
        }
    }
    okid_modal_scratch scratch;
    scratch.a_copy = spare;
    scratch.vr = spare + (size_t)n * (size_t)n;
    scratch.wr = scratch.vr + (size_t)n * (size_t)n;
    scratch.wi = scratch.wr + n;
    scratch.work = scratch.wi + n;
    unsigned warnings = 0;
    const okid_status st = okid_modal_compute(n, m, rf->a_full_, n, rf->c_, m, rf->dt_, rf->sensing_, &scratch,
                                              rf->shapes_, rf->modes_, &rf->num_modes_, &warnings);
    if (st != OKID_OK) {
        return st;
    }
    rf->warnings_ = warnings;
    for (int j = 0; j < rf->num_modes_; ++j) {
        okid_mode_std *out = &rf->mode_std_[j];
        okid_complex *shape_std = rf->shape_std_ + (size_t)j * (size_t)m;
        const int k = block_of(rf, &rf->modes_[j]);
        if (with_covariance && k >= 0) {
            mode_std(rf, &rf->modes_[j], k, p, out, shape_std);
            /* the weights are relative to noise_scale_ (a power of two): the stds scale with it */
            const okid_real s = rf->noise_scale_;
            out->eigenvalue.re *= s, out->eigenvalue.im *= s, out->pole.re *= s, out->pole.im *= s;
            int finite = okid_is_finite(out->eigenvalue.re) && okid_is_finite(out->eigenvalue.im) &&
                         okid_is_finite(out->pole.re) && okid_is_finite(out->pole.im);
            if (out->frequency_hz >= 0) {
                out->frequency_hz *= s, out->damping_ratio *= s;
                finite &= okid_is_finite(out->frequency_hz) && okid_is_finite(out->damping_ratio);
            } else if (rf->std_status_ == OKID_OK) {
                rf->std_status_ = OKID_E_DATA_RANGE; /* no continuous-time pole */
            }
            for (int i = 0; i < m; ++i) {
                shape_std[i].re *= s, shape_std[i].im *= s;
                finite &= okid_is_finite(shape_std[i].re) && okid_is_finite(shape_std[i].im);
            }
            if (!finite && rf->std_status_ == OKID_OK) {
                rf->std_status_ = OKID_E_DATA_RANGE;
            }
        } else {
            if (rf->std_status_ == OKID_OK) {
                rf->std_status_ = OKID_E_RANK_DEFICIENT; /* no block of the model has this mode */
            }
            out->eigenvalue.re = out->eigenvalue.im = out->pole.re = out->pole.im = -1;
            out->frequency_hz = out->damping_ratio = -1;
            for (int i = 0; i < m; ++i) {
                shape_std[i].re = shape_std[i].im = -1;
            }
            out->sensor_shape = shape_std;
        }
    }
    return OKID_OK;
}

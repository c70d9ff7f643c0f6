/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Modal parameters of a discrete model (eq. 56, 63, 64): eigenvalues of A, continuous poles
 * s = ln(lambda)/dt, natural frequencies, damping ratios, mode shapes at the sensors (C psi) and
 * in the displacement/velocity basis. Eq. 64 applies the power of the continuous pole (A and Ac
 * share eigenvectors): acceleration is s^2 times displacement, not lambda^2 times.
 */
#include "pipeline/modal_internal.h"

#include "numerics/carve.h"
#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"
#include "okid/limits.h"
#include "okid/sizes.h"

/* Unit 2-norm, largest-modulus component real and positive: a canonical representative of the shape. */
void okid_normalise_shape(okid_complex *v, int len)
{
    okid_real norm2 = 0, best = -1;
    int at = 0;
    for (int i = 0; i < len; ++i) {
        const okid_real mag = okid_cabs(v[i]);
        norm2 += mag * mag;
        if (mag > best) {
            best = mag;
            at = i;
        }
    }
    if (best <= 0) {
        return;
    }
    /* multiply by conj(v[at]) / (|v[at]| * norm) */
    const okid_real scale = 1 / (best * okid_sqrt(norm2));
    const okid_complex rot = {v[at].re * scale, -v[at].im * scale};
    for (int i = 0; i < len; ++i) {
        v[i] = okid_cmul(v[i], rot);
    }
    v[at].im = 0;
}

/* z^k for a small integer k (here -2..1). */
static okid_complex cpow_int(okid_complex z, int k)
{
    okid_complex out = {1, 0};
    for (int i = 0; i < (k < 0 ? -k : k); ++i) {
        out = okid_cmul(out, z);
    }
    if (k < 0) {
        const okid_complex one = {1, 0};
        out = okid_cdiv(one, out);
    }
    return out;
}

static void fill_mode(okid_mode *mode, okid_complex lambda, const okid_complex *psi_c, int m, okid_real dt,
                      okid_sensing sensing, okid_complex *storage, unsigned *warnings)
{
    mode->eigenvalue = lambda;
    const okid_real mag = okid_cabs(lambda);
    if (mag >= 1) {
        *warnings |= OKID_W_UNSTABLE_POLE;
    }
    if (lambda.im == 0 && lambda.re <= 0) {
        *warnings |= OKID_W_NONPHYSICAL_POLE;
    }
    okid_complex s;
    if (mag > 0) {
        s = okid_clog(lambda);
        s.re /= dt;
        s.im /= dt;
    } else {
        s.re = okid_log(OKID_REAL_MIN) / dt; /* the fastest pole representable */
        s.im = 0;
    }
    mode->pole = s;
    const okid_real smag = okid_cabs(s);
    mode->frequency_hz = smag / (2 * OKID_PI);
    mode->damping_ratio = (smag > 0) ? -s.re / smag : 0;

    okid_complex *sensor = storage, *shape = storage + m;
    const int c = (int)sensing;
    const okid_complex top = smag > 0 ? cpow_int(s, -c) : (okid_complex){1, 0};
    const okid_complex bottom = smag > 0 ? cpow_int(s, 1 - c) : (okid_complex){1, 0};
    for (int i = 0; i < m; ++i) {
        sensor[i] = psi_c[i];
        shape[i] = okid_cmul(psi_c[i], top);
        shape[m + i] = okid_cmul(psi_c[i], bottom);
    }
    okid_normalise_shape(sensor, m);
    okid_normalise_shape(shape, 2 * m);
    mode->sensor_shape = sensor;
    mode->shape = shape;
    mode->mpc = okid_mpc(sensor, m);
    mode->emac_output = mode->emac_input = mode->emac = mode->msv = mode->cmi = -1; /* need a realization */
}

static int mode_before(const okid_mode *a, const okid_mode *b)
{
    if (a->frequency_hz != b->frequency_hz) {
        return a->frequency_hz < b->frequency_hz;
    }
    return a->damping_ratio < b->damping_ratio;
}

okid_status okid_modal_compute(int n, int m, const okid_real *a, int lda, const okid_real *c, int ldc,
                               okid_real dt, okid_sensing sensing, const okid_modal_scratch *scratch,
                               okid_complex *shapes, okid_mode *modes, int *num_modes, unsigned *warnings)
{
    okid_copy_matrix(n, n, a, lda, scratch->a_copy, n);
    const okid_status st = okid_la_eig(n, scratch->a_copy, n, scratch->wr, scratch->wi, scratch->vr, n, scratch->work);
    if (st != OKID_OK) {
        return st;
    }
    int count = 0;
    for (int j = 0; j < n; ++j) {
        okid_complex *storage = shapes + (size_t)count * 3u * (size_t)m;
        const int pair = scratch->wi[j] != 0 && j + 1 < n;
        for (int i = 0; i < m; ++i) { /* C psi, psi = vr(:, j) + i vr(:, j + 1) for a pair */
            okid_real re = 0, im = 0;
            for (int k = 0; k < n; ++k) {
                re += OKID_AT(c, ldc, i, k) * OKID_AT(scratch->vr, n, k, j);
                im += pair ? OKID_AT(c, ldc, i, k) * OKID_AT(scratch->vr, n, k, j + 1) : 0;
            }
            storage[i].re = re;
            storage[i].im = im;
        }
        okid_complex lambda = {scratch->wr[j], pair ? scratch->wi[j] : 0};
        if (lambda.im < 0) { /* LAPACK lists the positive member first; keep Im > 0 regardless */
            lambda.im = -lambda.im;
            for (int i = 0; i < m; ++i) {
                storage[i].im = -storage[i].im;
            }
        }
        fill_mode(&modes[count], lambda, storage, m, dt, sensing, storage, warnings);
        modes[count].is_pair = pair;
        ++count;
        if (pair) {
            ++j; /* the conjugate is the same mode */
        }
    }
    /* insertion sort: n is small */
    for (int i = 1; i < count; ++i) {
        const okid_mode key = modes[i];
        int k = i - 1;
        while (k >= 0 && mode_before(&key, &modes[k])) {
            modes[k + 1] = modes[k];
            --k;
        }
        modes[k + 1] = key;
    }
    *num_modes = count;
    return OKID_OK;
}

okid_status okid_modal_analysis(int n, int m, const okid_real *a, int lda, const okid_real *c, int ldc,
                                okid_real dt, okid_sensing sensing, void *workspace, size_t bytes,
                                okid_mode *modes, int *num_modes, unsigned *warnings)
{
    if (a == NULL || c == NULL || workspace == NULL || modes == NULL || num_modes == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (n < 1 || n > OKID_MAX_ORDER || m < 1 || m > OKID_MAX_DIMENSION || lda < n || ldc < m) {
        return OKID_E_BAD_SIZE;
    }
    if (!okid_in_magnitude_range(dt) || (unsigned)sensing > 2u || !okid_all_finite(n, n, a, lda) ||
        !okid_all_finite(m, n, c, ldc)) {
        return OKID_E_BAD_PARAMETER;
    }
    if (bytes < OKID_MODAL_WORKSPACE_BYTES(n, m)) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    if (((size_t)workspace % OKID_WORKSPACE_ALIGN) != 0) {
        return OKID_E_WORKSPACE_ALIGNMENT;
    }
    okid_carver carver = {(unsigned char *)workspace, 0};
    okid_modal_scratch scratch;
    scratch.a_copy = okid_carve_reals(&carver, (size_t)n * (size_t)n);
    scratch.vr = okid_carve_reals(&carver, (size_t)n * (size_t)n);
    scratch.wr = okid_carve_reals(&carver, (size_t)n);
    scratch.wi = okid_carve_reals(&carver, (size_t)n);
    okid_complex *shapes = (okid_complex *)okid_carve_bytes(&carver, sizeof(okid_complex) * (size_t)n * 3u * (size_t)m);
    scratch.work = okid_carve_reals(&carver, OKID__LWORK_GEEV(n));
    unsigned local_warnings = 0;
    const okid_status st =
        okid_modal_compute(n, m, a, lda, c, ldc, dt, sensing, &scratch, shapes, modes, num_modes, &local_warnings);
    if (warnings != NULL) {
        *warnings = local_warnings;
    }
    return st;
}

okid_real okid_mpc(const okid_complex *shape, int len)
{
    if (shape == NULL || len < 1) {
        return 0;
    }
    okid_real sum_re = 0, sum_im = 0, norm2 = 0; /* phi^T phi and phi^H phi */
    for (int i = 0; i < len; ++i) {
        const okid_real re = shape[i].re, im = shape[i].im;
        sum_re += re * re - im * im;
        sum_im += 2 * re * im;
        norm2 += re * re + im * im;
    }
    if (norm2 <= 0) {
        return 0;
    }
    const okid_real mpc = (sum_re * sum_re + sum_im * sum_im) / (norm2 * norm2);
    return mpc > 1 ? 1 : mpc; /* round-off */
}

okid_real okid_mac(const okid_complex *a, const okid_complex *b, int len)
{
    if (a == NULL || b == NULL || len < 1) {
        return 0;
    }
    okid_real aa = 0, bb = 0, re = 0, im = 0;
    for (int i = 0; i < len; ++i) {
        aa += a[i].re * a[i].re + a[i].im * a[i].im;
        bb += b[i].re * b[i].re + b[i].im * b[i].im;
        /* a^H b */
        re += a[i].re * b[i].re + a[i].im * b[i].im;
        im += a[i].re * b[i].im - a[i].im * b[i].re;
    }
    if (aa <= 0 || bb <= 0) {
        return 0;
    }
    return (re * re + im * im) / (aa * bb);
}

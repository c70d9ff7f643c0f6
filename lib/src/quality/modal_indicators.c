/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Modal accuracy indicators (EMAC, MPC, MSV, CMI), formulas in okid/modal_indicators.h. Modal
 * input rows need Psi^-1: with LAPACK's real eigenvector basis Vr (a pair's real and imaginary
 * parts as two columns) Vr xi = z is a real solve, and the complex modal coordinate of
 * psi = v_j + i v_(j+1) is (xi_j - i xi_(j+1)) / 2 (x = psi q + conj(psi q) = v_j 2Re q - v_(j+1) 2Im q).
 */
#include "quality/modal_indicators_internal.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"

okid_real okid_amplitude_coherence(okid_complex predicted, okid_complex identified)
{
    const okid_real mp = okid_cabs(predicted), mq = okid_cabs(identified);
    const okid_real big = mp > mq ? mp : mq, small = mp > mq ? mq : mp;
    if (!(big > 0)) {
        return 0;
    }
    /* identified * conj(predicted): its argument is the phase difference */
    const okid_real re = identified.re * predicted.re + identified.im * predicted.im;
    const okid_real im = identified.im * predicted.re - identified.re * predicted.im;
    const okid_real phase = okid_fabs(okid_atan2(im, re));
    const okid_real limit = OKID_PI / 4;
    return phase < limit ? (small / big) * (1 - phase / limit) : 0;
}

/* lambda^k by magnitude and angle: no error growth with k, underflow to 0 for decaying modes. */
static okid_complex complex_power(okid_complex lambda, int k)
{
    const okid_real mag = okid_pow(okid_cabs(lambda), (okid_real)k);
    const okid_real angle = (okid_real)k * okid_atan2(lambda.im, lambda.re);
    const okid_complex out = {mag * okid_cos(angle), mag * okid_sin(angle)};
    return out;
}

/* (row j) + i sign (row j + 1) of a real n x cols matrix times a column; pair = 0 takes row j alone. */
static okid_complex row_times_psi(const okid_real *mat, int ld, int row, const okid_real *vr, int n, int j, int pair)
{
    okid_complex out = {0, 0};
    for (int k = 0; k < n; ++k) {
        const okid_real x = OKID_AT(mat, ld, row, k);
        out.re += x * OKID_AT(vr, n, k, j);
        out.im += pair ? x * OKID_AT(vr, n, k, j + 1) : 0;
    }
    return out;
}

/* Complex modal coordinate of eigen-column j from the real-basis solution xi (column col of rhs). */
static okid_complex modal_coordinate(const okid_real *xi, int ld, int j, int col, int pair)
{
    okid_complex out = {OKID_AT(xi, ld, j, col), 0};
    if (pair) {
        out.re *= OKID_R(0.5);
        out.im = -OKID_R(0.5) * OKID_AT(xi, ld, j + 1, col);
    }
    return out;
}

/* The indicators of eigen-column j (a pair when pair = 1) into mode. */
static void column_indicators(const okid_indicator_inputs *in, const okid_real *vr, okid_complex lambda, int j,
                              int pair, const okid_real *xi, okid_mode *mode)
{
    const int n = in->n;
    const okid_complex grow_out = complex_power(lambda, in->alpha - 1), grow_in = complex_power(lambda, in->beta - 1);
    okid_real weight = 0, sum = 0, c_norm2 = 0, b_norm2 = 0;
    for (int a = 0; a < in->m; ++a) {
        const okid_complex c = row_times_psi(in->c, in->ldc, a, vr, n, j, pair);
        const okid_complex o = row_times_psi(in->obs_last, in->ldo, a, vr, n, j, pair);
        const okid_real w = c.re * c.re + c.im * c.im;
        sum += w * okid_amplitude_coherence(okid_cmul(c, grow_out), o);
        weight += w;
    }
    c_norm2 = weight;
    mode->emac_output = weight > 0 ? sum / weight : 0;
    weight = sum = 0;
    for (int l = 0; l < in->r; ++l) {
        const okid_complex b = modal_coordinate(xi, n, j, l, pair);
        const okid_complex g = modal_coordinate(xi, n, j, in->r + l, pair);
        const okid_real w = b.re * b.re + b.im * b.im;
        sum += w * okid_amplitude_coherence(okid_cmul(b, grow_in), g);
        weight += w;
    }
    b_norm2 = weight;
    mode->emac_input = weight > 0 ? sum / weight : 0;
    mode->emac = mode->emac_output * mode->emac_input;
    mode->cmi = mode->emac * mode->mpc;

    const okid_real mag = okid_cabs(lambda);
    okid_real geometric = 0, power = 1;
    for (int k = 0; k < in->alpha + in->beta - 1; ++k) {
        geometric += power;
        power *= mag;
    }
    mode->msv = okid_sqrt(okid_sqrt(c_norm2) * okid_sqrt(b_norm2) * geometric);
}

okid_status okid_modal_indicators(const okid_indicator_inputs *in, const okid_real *vr, const okid_real *wr,
                                  const okid_real *wi, const okid_indicator_scratch *scratch, okid_mode *modes,
                                  int num_modes)
{
    const int n = in->n, r = in->r;
    /* xi = Vr^-1 [B, last block column of Q]: one solve for both right-hand sides. */
    okid_copy_matrix(n, n, vr, n, scratch->vr_copy, n);
    okid_copy_matrix(n, r, in->b, in->ldb, scratch->rhs, n);
    okid_copy_matrix(n, r, in->ctrl_last, in->ldq, scratch->rhs + (size_t)n * (size_t)r, n);
    int rank = 0;
    const okid_status st = okid_la_lstsq_rank(n, 2 * r, scratch->vr_copy, n, scratch->rhs, n, OKID_EPSILON * (okid_real)n,
                                              &rank, scratch->jpvt, scratch->work);
    if (st != OKID_OK) {
        return st;
    }
    int *used = scratch->jpvt; /* free again after the solve */
    for (int j = 0; j < n; ++j) {
        used[j] = 0;
    }
    for (int i = 0; i < num_modes; ++i) {
        okid_mode *mode = &modes[i];
        for (int j = 0; j < n; ++j) {
            const int pair = wi[j] != 0 && j + 1 < n;
            const okid_real im = pair ? okid_fabs(wi[j]) : 0;
            if (!used[j] && wr[j] == mode->eigenvalue.re && im == mode->eigenvalue.im) {
                const okid_complex lambda = {wr[j], wi[j] * (okid_real)pair};
                column_indicators(in, vr, lambda, j, pair, scratch->rhs, mode);
                used[j] = 1;
                break;
            }
            j += pair; /* the conjugate column is the same mode */
        }
    }
    return OKID_OK;
}

void okid_indicators_capture(const okid_era_problem *pb, const okid_era_scratch *v, const okid_real *sv, int n,
                             okid_real *obs_last, okid_real *ctrl_last)
{
    const int m = pb->m, r = pb->r, ldh = v->ldh, ldvt = v->ldvt;
    const int last_row = (pb->alpha - 1) * m, last_col = (pb->beta - 1) * pb->ncols;
    for (int t = 0; t < n; ++t) {
        const okid_real root = okid_sqrt(sv[t]);
        for (int a = 0; a < m; ++a) {
            const okid_real scale = pb->scales != NULL ? pb->scales[r + a] : 1;
            OKID_AT(obs_last, m, a, t) = OKID_AT(v->h, ldh, last_row + a, t) * root * scale;
        }
        for (int l = 0; l < r; ++l) {
            OKID_AT(ctrl_last, n, t, l) = root * OKID_AT(v->vt, ldvt, t, last_col + l) / v->col_scale[l];
        }
    }
}

void okid_carve_modal_phase(okid_carver *c, uint64_t n, uint64_t r, okid_modal_scratch *modal,
                            okid_indicator_scratch *ind)
{
    modal->a_copy = okid_carve_reals(c, n * n);
    modal->vr = okid_carve_reals(c, n * n);
    modal->wr = okid_carve_reals(c, n);
    modal->wi = okid_carve_reals(c, n);
    modal->work = okid_carve_reals(c, OKID__LWORK_GEEV(n));
    ind->vr_copy = modal->a_copy; /* free once the eigenvectors are out */
    ind->rhs = okid_carve_reals(c, n * 2u * r);
    ind->work = okid_carve_reals(c, OKID__LWORK_GELSY(n, 2u * r));
    ind->jpvt = (int *)okid_carve_bytes(c, sizeof(int) * n);
}

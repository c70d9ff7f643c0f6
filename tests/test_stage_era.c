/* SPDX-License-Identifier: Apache-2.0 */
/*
 * ERA on its own (pipeline/era.h): from the exact Markov parameters of the reference cases
 * (tests/reference/make_reference.py, numpy), the Hankel singular values, the eigenvalues of the
 * realized A and the Markov parameters C A^(k-1) B the realization reproduces, against numpy's.
 */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

#include "pipeline/era.h"
#include "numerics/linalg.h"
#include "quality/modal_indicators_internal.h"

enum { ALPHA = 20, BETA = 20 };

/* |C A^(k-1) B - Y_k| / max |Y| over k = 1 .. L: the realization reproduces the impulse response. */
static double markov_misfit(const ref_case *rc, int n, const okid_real *a, const okid_real *b, const okid_real *c)
{
    const int r = rc->r, m = rc->m, L = ALPHA + BETA;
    double x[TEST_MAX_STATES * TEST_MAX_IO], next[TEST_MAX_STATES * TEST_MAX_IO], worst = 0, scale = 0;
    for (int i = 0; i < n * r; ++i) {
        x[i] = b[i]; /* A^(k-1) B, n x r */
    }
    for (int i = 0; i < m * r * (L + 1); ++i) {
        scale = fmax(scale, fabs((double)rc->markov[i]));
    }
    for (int k = 1; k <= L; ++k) {
        for (int l = 0; l < r; ++l) {
            for (int i = 0; i < m; ++i) {
                double s = 0;
                for (int t = 0; t < n; ++t) {
                    s += (double)c[i + t * m] * x[t + l * n];
                }
                worst = fmax(worst, fabs(s - (double)rc->markov[i + (k * r + l) * m]));
            }
            for (int i = 0; i < n; ++i) {
                double s = 0;
                for (int t = 0; t < n; ++t) {
                    s += (double)a[i + t * n] * x[t + l * n];
                }
                next[i + l * n] = s;
            }
        }
        for (int i = 0; i < n * r; ++i) {
            x[i] = next[i];
        }
    }
    return worst / scale;
}

/* leading: only the order's singular vectors (the output-only identifier's route, okid_era_scratch). */
static void realize_case(const ref_case *rc, int leading)
{
    const int r = rc->r, m = rc->m, n = 2 * rc->dofs, hr = ALPHA * m, hc = BETA * r, k = hr < hc ? hr : hc;
    okid_real *h = calloc((size_t)(hr * hc), sizeof(okid_real)), *vt = calloc((size_t)(k * hc), sizeof(okid_real));
    okid_real *t = calloc((size_t)(hr * n), sizeof(okid_real)), *col = calloc((size_t)r, sizeof(okid_real));
    okid_real *work = calloc(OKID__LWORK_GESVD(hr, hc), sizeof(okid_real)), *sv = calloc((size_t)k, sizeof(okid_real));
    okid_real a[64], b[16], c[16], d[16], wr[8], wi[8], vr[64], eig_work[OKID__LWORK_GEEV(8)], obs[16], ctrl[16];
    const okid_era_problem problem = {r, m, r, ALPHA, BETA, n, m * 20, rc->markov, NULL, NULL};
    const okid_era_scratch scratch = {h, hr, vt, k, t, col, work, leading};
    const okid_era_output out = {sv, a, b, c, d, NULL};
    int order = 0;
    unsigned warnings = 0;
    assert_int_equal(okid_era_realize(&problem, &scratch, &out, &order, &warnings), OKID_OK);
    assert_int_equal(order, n);
    /* Weyl: each sigma moves by at most the norm of H's perturbation: its entries' rounding to okid_real,
       u |H|_F, plus the SVD's backward error, a modest multiple of u sigma_1 (4 max(rows, cols) u sigma_1) */
    double frobenius = 0;
    for (int i = 0; i < n; ++i) frobenius += (double)rc->hankel_sv[i] * (double)rc->hankel_sv[i];
    const double u = OKID_REAL_IS_FLOAT ? FLT_EPSILON / 2.0 : DBL_EPSILON / 2;
    const double weyl = u * sqrt(frobenius) + 4.0 * (hr > hc ? hr : hc) * u * (double)rc->hankel_sv[0];
    for (int i = 0; i < n; ++i) {
        assert_within(fabs((double)sv[i] - (double)rc->hankel_sv[i]), weyl);
    }
    assert_within(sv[n], weyl); /* rank n: the next sigma is round-off */
    for (int i = 0; i < m * r; ++i) {
        assert_true(d[i] == rc->markov[i]); /* D = Y_0 */
    }
    const double misfit = markov_misfit(rc, n, a, b, c);
    /* measured over five BLAS backends (scripts/blas_kernels.sh): 2.5e-14 in double, 1.8e-5 in float
       (A^k amplifying the round-off of the realization); tolerance 3x and more */
    assert_within(misfit, TOL(1e-13, 6e-5));

    okid_real a_copy[64];
    for (int i = 0; i < n * n; ++i) {
        a_copy[i] = a[i];
    }
    assert_int_equal(okid_la_eig(n, a_copy, n, wr, wi, vr, n, eig_work), OKID_OK);
    for (int j = 0; j < rc->num_modes; ++j) { /* each exact eigenvalue is one of A's */
        double nearest = 1e9;
        for (int i = 0; i < n; ++i) {
            nearest = fmin(nearest, hypot((double)wr[i] - (double)rc->eig_re[j], fabs((double)wi[i]) - (double)rc->eig_im[j]));
        }
        assert_within(nearest, TOL(1e-12, identify_tol(rc)) * hypot((double)rc->eig_re[j], (double)rc->eig_im[j]));
    }
    /* the indicators' blocks are the last block row of the observability matrix, C A^(alpha-1),
       and the last block column of the controllability matrix, A^(beta-1) B (here alpha = beta) */
    okid_indicators_capture(&problem, &scratch, sv, n, obs, ctrl);
    double power[64], next[64], worst_obs = 0, worst_ctrl = 0, norm_obs = 0, norm_ctrl = 0;
    for (int i = 0; i < n * n; ++i) {
        power[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
    }
    for (int step = 1; step < ALPHA; ++step) { /* power = A^(alpha-1) */
        for (int i = 0; i < n; ++i) {
            for (int j = 0; j < n; ++j) {
                double s = 0;
                for (int l = 0; l < n; ++l) {
                    s += (double)a[i + l * n] * power[l + j * n];
                }
                next[i + j * n] = s;
            }
        }
        for (int i = 0; i < n * n; ++i) {
            power[i] = next[i];
        }
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < m; ++i) {
            double s = 0;
            for (int l = 0; l < n; ++l) {
                s += (double)c[i + l * m] * power[l + j * n];
            }
            worst_obs = fmax(worst_obs, fabs(s - (double)obs[i + j * m]));
            norm_obs = fmax(norm_obs, fabs(s));
        }
        for (int l = 0; l < r; ++l) {
            double s = 0;
            for (int t2 = 0; t2 < n; ++t2) {
                s += power[j + t2 * n] * (double)b[t2 + l * n];
            }
            worst_ctrl = fmax(worst_ctrl, fabs(s - (double)ctrl[j + l * n]));
            norm_ctrl = fmax(norm_ctrl, fabs(s));
        }
    }
    assert_within(worst_obs, TOL(1e-11, 1e-3) * norm_obs); /* measured 1e-13 and 5e-5 */
    assert_within(worst_ctrl, TOL(1e-11, 1e-3) * norm_ctrl);
    free(h);
    free(vt);
    free(t);
    free(col);
    free(work);
    free(sv);
}

static void test_era_exact_markov_paper(void **state)
{
    (void)state;
    realize_case(&REF_PAPER, 0);
    realize_case(&REF_PAPER, 1);
}

static void test_era_exact_markov_mimo(void **state)
{
    (void)state;
    realize_case(&REF_MIMO, 0);
    realize_case(&REF_MIMO, 1);
}

/* The automatic order finds the gap of the exact Hankel matrix; an order above its rank is refused. */
static void test_era_order(void **state)
{
    (void)state;
    const ref_case *rc = &REF_PAPER;
    const int m = rc->m, hr = ALPHA * m, hc = BETA, k = hc;
    okid_real *h = calloc((size_t)(hr * hc), sizeof(okid_real)), *vt = calloc((size_t)(k * hc), sizeof(okid_real));
    okid_real *t = calloc((size_t)(hr * 8), sizeof(okid_real)), col[1], *sv = calloc((size_t)k, sizeof(okid_real));
    okid_real *work = calloc(OKID__LWORK_GESVD(hr, hc), sizeof(okid_real));
    okid_real a[64], b[8], c[16], d[2];
    okid_era_problem problem = {1, m, 1, ALPHA, BETA, 0, m * 20, rc->markov, NULL, NULL};
    const okid_era_scratch scratch = {h, hr, vt, k, t, col, work, 0};
    const okid_era_output out = {sv, a, b, c, d, NULL};
    int order = 0;
    unsigned warnings = 0;
    problem.order_limit = 8; /* keeps the buffers at 8 states */
    assert_int_equal(okid_era_realize(&problem, &scratch, &out, &order, &warnings), OKID_OK);
    assert_int_equal(order, 4);
    problem.order = 8; /* sigma_8 is round-off: rank deficient, not a model */
    assert_int_equal(okid_era_realize(&problem, &scratch, &out, &order, &warnings), OKID_E_RANK_DEFICIENT);
    free(h);
    free(vt);
    free(t);
    free(sv);
    free(work);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_era_exact_markov_paper),
        cmocka_unit_test(test_era_exact_markov_mimo),
        cmocka_unit_test(test_era_order),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

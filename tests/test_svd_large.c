/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The thin SVD of a Hankel-sized matrix (numerics/linalg.h) on both sides of the divide-and-conquer
 * threshold (LAPACK backend: xGESDD from OKID__SVD_DC_MIN columns, xGESVD below): A = U0 S0 V0'
 * with orthonormal U0, V0 (Gram-Schmidt twice on white noise) and singular values 10^(-6 i / n)
 * known exactly; okid_la_svd must return S0, orthonormal vectors and A = U S V' to round-off.
 * Asked for the leading nvec vectors only (the Eigen backend's pivoted-QR Jacobi route when
 * m >= n), every singular value, nvec orthonormal vectors and A v_j = s_j u_j to round-off.
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "numerics/linalg.h"
#include "numerics/real_math.h"
#include "okid/sizes.h"

/* Columns of q (rows x cols) orthonormalised in place, twice (classical GS loses orthogonality
   once; twice is enough to round-off). */
static void orthonormalize(double *q, int rows, int cols)
{
    for (int pass = 0; pass < 2; ++pass) {
        for (int j = 0; j < cols; ++j) {
            for (int k = 0; k < j; ++k) {
                double d = 0;
                for (int i = 0; i < rows; ++i) {
                    d += q[i + k * rows] * q[i + j * rows];
                }
                for (int i = 0; i < rows; ++i) {
                    q[i + j * rows] -= d * q[i + k * rows];
                }
            }
            double norm = 0;
            for (int i = 0; i < rows; ++i) {
                norm += q[i + j * rows] * q[i + j * rows];
            }
            for (int i = 0; i < rows; ++i) {
                q[i + j * rows] /= sqrt(norm);
            }
        }
    }
}

static void check_svd(int m, int n, int nvec)
{
    const int ldvt = (int)OKID__SVD_VT_ROWS(m, n, nvec);
    double *u0 = malloc(sizeof(double) * (size_t)m * (size_t)n), *v0 = malloc(sizeof(double) * (size_t)n * (size_t)n);
    double *s0 = malloc(sizeof(double) * (size_t)n), *a0 = malloc(sizeof(double) * (size_t)m * (size_t)n);
    okid_real *a = malloc(sizeof(okid_real) * (size_t)m * (size_t)n), *vt = malloc(sizeof(okid_real) * (size_t)n * (size_t)n);
    okid_real *s = malloc(sizeof(okid_real) * (size_t)n), *work = malloc(sizeof(okid_real) * OKID__LWORK_GESVD(m, n));
    okid_real *noise = test_white_noise(1, (size_t)m * (size_t)n + (size_t)n * (size_t)n, 11);
    for (int i = 0; i < m * n; ++i) {
        u0[i] = (double)noise[i];
    }
    for (int i = 0; i < n * n; ++i) {
        v0[i] = (double)noise[m * n + i];
    }
    free(noise);
    orthonormalize(u0, m, n);
    orthonormalize(v0, n, n);
    const double decades = sizeof(okid_real) == sizeof(double) ? 6 : 3; /* above float's noise floor */
    for (int i = 0; i < n; ++i) {
        s0[i] = pow(10, -decades * i / n);
    }
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < m; ++i) {
            double x = 0;
            for (int k = 0; k < n; ++k) {
                x += u0[i + k * m] * s0[k] * v0[j + k * n];
            }
            a0[i + j * m] = x;
            a[i + j * m] = (okid_real)x;
        }
    }
    assert_int_equal(okid_la_svd(m, n, nvec, a, m, s, vt, ldvt, work), OKID_OK);
    /* backward stable: each singular value within a few n eps s1 of S0 (Weyl), 10 n eps the margin;
       the vectors orthonormal and the product A to the same order */
    const double tol = 10.0 * n * OKID_EPSILON;
    for (int i = 0; i < n; ++i) {
        assert_true(fabs((double)s[i] - s0[i]) <= tol);
    }
    double worst_u = 0, worst_v = 0, worst_a = 0, worst_r = 0;
    for (int j = 0; j < nvec; ++j) {
        for (int k = 0; k < nvec; ++k) {
            double du = 0, dv = 0;
            for (int i = 0; i < m; ++i) {
                du += (double)a[i + j * m] * (double)a[i + k * m];
            }
            for (int i = 0; i < n; ++i) {
                dv += (double)vt[j + i * ldvt] * (double)vt[k + i * ldvt];
            }
            worst_u = fmax(worst_u, fabs(du - (j == k)));
            worst_v = fmax(worst_v, fabs(dv - (j == k)));
        }
        for (int i = 0; i < m; ++i) { /* A v_j - s_j u_j */
            double x = 0;
            for (int k = 0; k < n; ++k) {
                x += a0[i + k * m] * (double)vt[j + k * ldvt];
            }
            worst_r = fmax(worst_r, fabs(x - (double)s[j] * (double)a[i + j * m]));
        }
    }
    for (int j = 0; j < n && nvec == n; ++j) {
        for (int i = 0; i < m; ++i) {
            double x = 0;
            for (int k = 0; k < n; ++k) {
                x += (double)a[i + k * m] * (double)s[k] * (double)vt[k + j * ldvt];
            }
            worst_a = fmax(worst_a, fabs(x - a0[i + j * m]));
        }
    }
    assert_true(worst_r <= tol);
    assert_true(worst_u <= tol && worst_v <= tol && worst_a <= tol);
    free(u0);
    free(v0);
    free(s0);
    free(a0);
    free(a);
    free(vt);
    free(s);
    free(work);
}

#ifndef OKID__SVD_DC_MIN
#define OKID__SVD_DC_MIN 150u /* the Eigen backend has one SVD at every size: the same sizes check it */
#endif

static void test_svd_below_threshold(void **state)
{
    (void)state;
    check_svd(170, (int)OKID__SVD_DC_MIN - 1, (int)OKID__SVD_DC_MIN - 1);
}

/* The leading vectors only: tall, and square as the ambient Hankel matrix (40 x 40 for m = 2, L = 20). */
static void test_svd_leading(void **state)
{
    (void)state;
    check_svd(170, 40, 4);
    check_svd(40, 40, 4);
    check_svd(60, 40, 39);
}

static void test_svd_divide_and_conquer(void **state)
{
    (void)state;
    check_svd(170, (int)OKID__SVD_DC_MIN, (int)OKID__SVD_DC_MIN); /* the threshold itself, m < 11 n / 6 */
    check_svd(300, (int)OKID__SVD_DC_MIN, (int)OKID__SVD_DC_MIN); /* m >= 11 n / 6: xGESDD's QR-first path */
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_svd_below_threshold),
        cmocka_unit_test(test_svd_divide_and_conquer),
        cmocka_unit_test(test_svd_leading),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

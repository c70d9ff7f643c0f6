/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Markov recovery on its own (pipeline/markov.h, eq. 51 and 53) from an exact observer solution:
 * for a system whose output matrix C is invertible, the observer gain G = -A C^-1 is deadbeat in
 * one step (A + G C = 0), so its observer Markov parameters are exactly
 *   Ybar1_1 = C (B + G D), Ybar2_1 = C G, and zero from j = 2 on.
 * Recovery must give the system Markov parameters Y_0 = D, Y_k = C A^(k-1) B and the observer-gain
 * Markov parameters Y°_k = C A^(k-1) G, computed here directly by powers of A, also beyond p.
 */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "pipeline/markov.h"

enum { N = 3, R = 2, M = 3, P = 3, L = 12, Q = R + (R + M) * P, LDX = Q + 3 };

static const double A[N * N] = {0.9, -0.2, 0.05, 0.3, 0.8, -0.1, -0.05, 0.15, 0.7}; /* column-major */
static const double B[N * R] = {1.0, 0.5, -0.25, 0.0, -1.0, 2.0};
static const double C_DIAG[N] = {2.0, -1.0, 0.5};
static const double D[M * R] = {0.1, 0.0, -0.3, 0.2, 0.4, 0.0};

static double c_at(int i, int j) { return i == j ? C_DIAG[i] : 0.0; }

/* G = -A C^-1 (C diagonal). */
static double g_at(int i, int j) { return -A[i + j * N] / C_DIAG[j]; }

static void test_markov_from_deadbeat_observer(void **state)
{
    (void)state;
    okid_real x[LDX * M];
    memset(x, 0, sizeof x);
    for (int a = 0; a < M; ++a) {
        for (int b = 0; b < R; ++b) {
            x[b + a * LDX] = (okid_real)D[a + b * M];
            double bgd = 0; /* (C (B + G D))(a, b) */
            for (int t = 0; t < N; ++t) {
                double inner = B[t + b * N];
                for (int l = 0; l < M; ++l) {
                    inner += g_at(t, l) * D[l + b * M];
                }
                bgd += c_at(a, t) * inner;
            }
            x[R + b + a * LDX] = (okid_real)bgd;
        }
        for (int b = 0; b < M; ++b) {
            double cg = 0;
            for (int t = 0; t < N; ++t) {
                cg += c_at(a, t) * g_at(t, b);
            }
            x[R * (P + 1) + b + a * LDX] = (okid_real)(-cg); /* the regressor holds -Ybar2 */
        }
    }
    okid_real markov[M * R * (L + 1)], markov_obs[M * M * L];
    okid_markov_recover(R, M, P, L, x, LDX, markov, markov_obs);

    double power_b[N * R], power_g[N * M], next[N * M], worst = 0, worst_obs = 0;
    memcpy(power_b, B, sizeof power_b);
    for (int i = 0; i < N; ++i) {
        for (int j = 0; j < M; ++j) {
            power_g[i + j * N] = g_at(i, j);
        }
    }
    for (int i = 0; i < M * R; ++i) {
        assert_true(markov[i] == (okid_real)D[i]); /* Y_0 = D, copied */
    }
    for (int k = 1; k <= L; ++k) { /* power_b = A^(k-1) B, power_g = A^(k-1) G */
        for (int a = 0; a < M; ++a) {
            for (int b = 0; b < R; ++b) {
                const double want = c_at(a, a) * power_b[a + b * N];
                worst = fmax(worst, fabs((double)markov[a + (k * R + b) * M] - want));
            }
            for (int b = 0; b < M; ++b) {
                const double want = c_at(a, a) * power_g[a + b * N];
                worst_obs = fmax(worst_obs, fabs((double)markov_obs[a + ((k - 1) * M + b) * M] - want));
            }
        }
        for (int cols = R, pass = 0; pass < 2; ++pass, cols = M) {
            double *pw = pass == 0 ? power_b : power_g;
            for (int i = 0; i < N; ++i) {
                for (int j = 0; j < cols; ++j) {
                    double s = 0;
                    for (int t = 0; t < N; ++t) {
                        s += A[i + t * N] * pw[t + j * N];
                    }
                    next[i + j * N] = s;
                }
            }
            memcpy(pw, next, sizeof(double) * (size_t)(N * cols));
        }
    }
    assert_within(worst, TOL(1e-14, 1e-5));
    assert_within(worst_obs, TOL(1e-14, 1e-5));
}

/* The system realization passes no observer-gain buffer: only Y_k is written. */
static void test_markov_system_only(void **state)
{
    (void)state;
    okid_real x[LDX * M];
    for (int i = 0; i < LDX * M; ++i) {
        x[i] = (okid_real)(0.01 * (i % 7) - 0.02);
    }
    okid_real with_obs[M * R * (L + 1)], without[M * R * (L + 1)], obs[M * M * L];
    okid_markov_recover(R, M, P, L, x, LDX, with_obs, obs);
    okid_markov_recover(R, M, P, L, x, LDX, without, NULL);
    assert_memory_equal(with_obs, without, sizeof without);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_markov_from_deadbeat_observer),
        cmocka_unit_test(test_markov_system_only),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

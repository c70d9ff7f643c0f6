/* SPDX-License-Identifier: Apache-2.0 */
/* Modal analysis (eq. 56, 63, 64) of the exact discrete models against numpy's eigenvectors of Ac,
   MAC against hand-computed values, and the warnings for poles without a physical meaning. */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdlib.h>

static _Alignas(16) unsigned char workspace[OKID_MODAL_WORKSPACE_BYTES(8, 4)];

static void check_exact(const ref_case *rc)
{
    const int n = 2 * rc->dofs;
    okid_mode modes[TEST_MAX_STATES];
    int count = 0;
    unsigned warnings = 123;
    assert_int_equal(okid_modal_analysis(n, rc->m, rc->a, n, rc->c, rc->m, rc->dt, rc->sensing, workspace,
                                         sizeof workspace, modes, &count, &warnings),
                     OKID_OK);
    assert_int_equal(warnings, 0);
    /* Re(s) = ln|lambda| / dt of the chain's lightest mode (|lambda| = 0.99965) turns one rounding of
       lambda (2e-16) into 6e-13 relative; the eigensolvers of five BLAS backends gave up to 8.9e-13 in
       double and 1.4e-6 (12 eps) in float (scripts/blas_kernels.sh): 3x that. */
    assert_modes_match(rc, modes, count, TOL(3e-12, 5e-6), 1 - TOL(1e-14, 1e-6));
    for (int i = 0; i < count; ++i) { /* C psi at the sensors has unit norm and a real largest component */
        okid_real norm = 0;
        for (int a = 0; a < rc->m; ++a) {
            norm += modes[i].sensor_shape[a].re * modes[i].sensor_shape[a].re +
                    modes[i].sensor_shape[a].im * modes[i].sensor_shape[a].im;
        }
        /* a sum of m <= 4 squares, scaled once: a few roundings each; 10 eps (measured: 3 eps in float) */
        assert_relative(norm, 1, TOL(1e-14, 10 * FLT_EPSILON), "sensor shape norm", i);
    }
}

static void test_paper_exact_modes(void **state)
{
    (void)state;
    check_exact(&REF_PAPER);
}

static void test_mimo_exact_modes(void **state)
{
    (void)state;
    check_exact(&REF_MIMO);
}

static void test_chain3_exact_modes(void **state)
{
    (void)state;
    check_exact(&REF_CHAIN3);
}

/* Real eigenvalues: reported once each, damping 1; lambda <= 0 and |lambda| >= 1 raise warnings. */
static void test_real_and_unphysical_eigenvalues(void **state)
{
    (void)state;
    const okid_real a[9] = {0.5, 0, 0, 0, 1.2, 0, 0, 0, -0.3}, c[3] = {1, 1, 1};
    okid_mode modes[3];
    int count = 0;
    unsigned warnings = 0;
    assert_int_equal(okid_modal_analysis(3, 1, a, 3, c, 1, 0.1, OKID_SENSING_DISPLACEMENT, workspace,
                                         sizeof workspace, modes, &count, &warnings),
                     OKID_OK);
    assert_int_equal(count, 3);
    assert_true(warnings & OKID_W_UNSTABLE_POLE);
    assert_true(warnings & OKID_W_NONPHYSICAL_POLE);
    int seen_half = 0;
    for (int i = 0; i < 3; ++i) {
        assert_int_equal(modes[i].is_pair, 0);
        if (modes[i].eigenvalue.re == 0.5) {
            seen_half = 1;
            assert_relative(modes[i].pole.re, log(0.5) / 0.1, TOL(1e-14, 1e-6), "real pole", i);
            assert_relative(modes[i].frequency_hz, -log(0.5) / 0.1 / (2 * 3.14159265358979323846), TOL(1e-14, 1e-6), "real pole frequency", i);
            assert_relative(modes[i].damping_ratio, 1, TOL(1e-15, 1e-7), "real pole damping", i);
        }
    }
    assert_true(seen_half);
}

static void test_mac_hand_computed(void **state)
{
    (void)state;
    const okid_complex a[2] = {{1, 0}, {0, 0}}, b[2] = {{1, 0}, {1, 0}};
    const okid_complex c[2] = {{1, 0}, {0, 1}}, d[2] = {{0, 1}, {-1, 0}}; /* d = i c */
    const okid_complex e[2] = {{1, 0}, {0, -1}};                         /* orthogonal to c */
    const okid_complex zero[2] = {{0, 0}, {0, 0}};
    assert_relative(okid_mac(a, b, 2), 0.5, TOL(1e-15, 1e-7), "MAC", 0);
    assert_relative(okid_mac(c, d, 2), 1, TOL(1e-15, 1e-7), "MAC", 1);
    assert_true(okid_mac(c, e, 2) == 0);
    assert_true(okid_mac(c, zero, 2) == 0);
    assert_true(okid_mac(NULL, c, 2) == 0);
    assert_true(okid_mac(c, c, 0) == 0);
}

static void test_modal_bad_input(void **state)
{
    (void)state;
    okid_mode modes[4];
    int count = 0;
    const okid_real *a = REF_PAPER.a, *c = REF_PAPER.c;
    const size_t bytes = OKID_MODAL_WORKSPACE_BYTES(4, 2);
    assert_int_equal(okid_modal_analysis(4, 2, a, 4, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace, bytes, NULL,
                                         &count, NULL),
                     OKID_E_NULL_POINTER);
    assert_int_equal(okid_modal_analysis(4, 2, a, 3, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace, bytes, modes,
                                         &count, NULL),
                     OKID_E_BAD_SIZE);
    assert_int_equal(okid_modal_analysis(0, 2, a, 4, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace, bytes, modes,
                                         &count, NULL),
                     OKID_E_BAD_SIZE);
    assert_int_equal(okid_modal_analysis(4, 2, a, 4, c, 2, -0.01, OKID_SENSING_ACCELERATION, workspace, bytes, modes,
                                         &count, NULL),
                     OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_modal_analysis(4, 2, a, 4, c, 2, 0.01, (okid_sensing)3, workspace, bytes, modes, &count, NULL),
                     OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_modal_analysis(4, 2, a, 4, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace, bytes - 1,
                                         modes, &count, NULL),
                     OKID_E_WORKSPACE_TOO_SMALL);
    assert_int_equal(okid_modal_analysis(4, 2, a, 4, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace + 8, bytes,
                                         modes, &count, NULL),
                     OKID_E_WORKSPACE_ALIGNMENT);
    okid_real nan_a[16];
    for (int i = 0; i < 16; ++i) nan_a[i] = a[i];
    nan_a[3] = NAN;
    assert_int_equal(okid_modal_analysis(4, 2, nan_a, 4, c, 2, 0.01, OKID_SENSING_ACCELERATION, workspace, bytes,
                                         modes, &count, NULL),
                     OKID_E_BAD_PARAMETER);
}

/* The Eigen backend holds its eigenproblem in a fixed maximum order: one more is refused, not overrun. */
static void test_order_above_backend_maximum(void **state)
{
    (void)state;
#if OKID_LINALG_EIGEN
    enum { N = OKID_EIGEN_MAX_ORDER + 1 };
    okid_real *a = calloc((size_t)N * N, sizeof *a), *c = calloc(N, sizeof *c);
    const size_t bytes = OKID_MODAL_WORKSPACE_BYTES(N, 1);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (bytes + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN);
    assert_non_null(a);
    assert_non_null(c);
    assert_non_null(ws);
    for (int i = 0; i < N; ++i) {
        a[(size_t)i * N + (size_t)i] = (okid_real)0.5;
        c[i] = 1;
    }
    okid_mode modes[N];
    int count = -1;
    assert_int_equal(okid_modal_analysis(N, 1, a, N, c, 1, (okid_real)0.01, OKID_SENSING_ACCELERATION, ws, bytes, modes,
                                         &count, NULL),
                     OKID_E_BAD_ORDER);
    assert_int_equal(okid_modal_analysis(N - 1, 1, a, N, c, 1, (okid_real)0.01, OKID_SENSING_ACCELERATION, ws, bytes,
                                         modes, &count, NULL),
                     OKID_OK);
    assert_int_equal(count, N - 1);
    free(ws);
    free(c);
    free(a);
#else
    skip(); /* LAPACK takes any order up to OKID_MAX_ORDER */
#endif
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper_exact_modes),  cmocka_unit_test(test_mimo_exact_modes),
        cmocka_unit_test(test_chain3_exact_modes), cmocka_unit_test(test_real_and_unphysical_eigenvalues),
        cmocka_unit_test(test_mac_hand_computed),  cmocka_unit_test(test_modal_bad_input),
        cmocka_unit_test(test_order_above_backend_maximum),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

/* SPDX-License-Identifier: Apache-2.0 */
/* Mechanical model (eq. 1-9), chain matrices and zero-order hold (eq. 13-14) against numpy/scipy. */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>

#include "reference/reference_data.h"

/* The largest difference of two arrays, relative to want's largest entry, within tol. */
#define assert_close_array(got, want, count, tol) \
    check_within_at(__FILE__, __LINE__, #got, 0, max_relative_difference(got, want, count), tol)

static void check_case(const ref_case *rc, const okid_real *masses, const okid_real *dampers, const okid_real *springs)
{
    const int n2 = rc->dofs, n = 2 * n2, r = rc->r, m = rc->m;
    okid_real mass[16], damping[16], stiffness[16];
    assert_int_equal(okid_chain_model(n2, masses, dampers, springs, mass, damping, stiffness), OKID_OK);
    assert_close_array(mass, rc->mass, (size_t)(n2 * n2), TOL(0, 2e-7));
    assert_close_array(damping, rc->damping, (size_t)(n2 * n2), TOL(0, 2e-7));
    assert_close_array(stiffness, rc->stiffness, (size_t)(n2 * n2), TOL(0, 2e-7));

    const okid_mechanical_model model = {n2, r, m, mass, damping, stiffness, rc->b2, rc->ca, rc->cv, rc->cd};
    okid_real ac[64], bc[16], c[32], d[16], a[64], b[16];
    okid_real work[OKID_STATE_SPACE_WORK_REALS(4, 4)], zoh_work[OKID_ZOH_WORK_REALS(8, 4)];
    assert_int_equal(okid_model_state_space(&model, ac, bc, c, d, work, sizeof work / sizeof work[0]), OKID_OK);
    assert_close_array(ac, rc->ac, (size_t)(n * n), TOL(1e-15, 2e-7));
    assert_close_array(bc, rc->bc, (size_t)(n * r), TOL(1e-15, 2e-7));
    assert_close_array(c, rc->c, (size_t)(m * n), TOL(1e-15, 2e-7));
    assert_close_array(d, rc->d, (size_t)(m * r), TOL(1e-15, 2e-7));
    assert_int_equal(okid_discretize_zoh(n, r, ac, bc, rc->dt, a, b, zoh_work, sizeof zoh_work / sizeof zoh_work[0]),
                     OKID_OK);
    assert_close_array(a, rc->a, (size_t)(n * n), TOL(1e-14, 1e-6));
    assert_close_array(b, rc->b, (size_t)(n * r), TOL(1e-13, 1e-6));
}

static void test_paper_model(void **state)
{
    (void)state;
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    check_case(&REF_PAPER, masses, dampers, springs);
    /* Eq. 79-82 as printed. */
    assert_relative(REF_PAPER.ac[2 + 0 * 4], -30.00, TOL(1e-15, 1e-7), "Ac(3,1)", 0);
    assert_relative(REF_PAPER.ac[3 + 1 * 4], -23.333333333333332, TOL(1e-15, 1e-7), "Ac(4,2)", 0);
}

static void test_mimo_model(void **state)
{
    (void)state;
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    check_case(&REF_MIMO, masses, dampers, springs);
}

static void test_chain3_model(void **state)
{
    (void)state;
    const okid_real masses[3] = {1, 1.5, 2}, dampers[4] = {0.4, 0.3, 0.2, 0.1}, springs[4] = {40, 30, 20, 10};
    check_case(&REF_CHAIN3, masses, dampers, springs);
}

/* A non-normal matrix of norm ~ 40 dt: the scaling-and-squaring path. */
static void test_zoh_non_normal(void **state)
{
    (void)state;
    okid_real a[25], b[10], work[OKID_ZOH_WORK_REALS(5, 2)];
    assert_int_equal(okid_discretize_zoh(5, 2, ZOH5_AC, ZOH5_BC, 0.5, a, b, work, sizeof work / sizeof work[0]), OKID_OK);
    assert_close_array(a, ZOH5_A, 25, TOL(1e-11, 2e-5));
    assert_close_array(b, ZOH5_B, 10, TOL(1e-11, 2e-5));
}

static void test_zoh_without_inputs(void **state)
{
    (void)state;
    okid_real a[25], work[OKID_ZOH_WORK_REALS(5, 0)];
    assert_int_equal(okid_discretize_zoh(5, 0, ZOH5_AC, NULL, 0.5, a, NULL, work, sizeof work / sizeof work[0]), OKID_OK);
    assert_close_array(a, ZOH5_A, 25, TOL(1e-11, 2e-5));
}

static void test_simulator_matches_recursion(void **state)
{
    (void)state;
    enum { N = 200 };
    okid_real *u = test_white_noise(1, N, 8);
    okid_real want[2 * N], got[2 * N], x[4], tmp[4];
    test_simulate(&REF_PAPER, N, u, want, NULL);
    okid_simulator sim;
    assert_int_equal(okid_simulator_init(&sim, 4, 1, 2, REF_PAPER.a, REF_PAPER.b, REF_PAPER.c, REF_PAPER.d, x, tmp),
                     OKID_OK);
    assert_int_equal(okid_simulate(&sim, N / 2, u, 1, got, 2), OKID_OK); /* in two calls: the state carries over */
    assert_int_equal(okid_simulate(&sim, N / 2, u + N / 2, 1, got + N, 2), OKID_OK);
    assert_close_array(got, want, 2 * N, TOL(1e-15, 1e-6));
    const okid_real bad = NAN;
    assert_int_equal(okid_simulate(&sim, 1, &bad, 1, got, 2), OKID_E_NONFINITE_SAMPLE);
    assert_int_equal(okid_simulate(&sim, 1, u, 0, got, 2), OKID_E_BAD_SIZE);
    assert_int_equal(okid_simulate(NULL, 1, u, 1, got, 2), OKID_E_NULL_POINTER);
    free(u);
}

static void test_model_bad_input(void **state)
{
    (void)state;
    const okid_real masses[2] = {2, 3}, dampers[3] = {2, 4, 3}, springs[3] = {20, 40, 30};
    const okid_real zero_mass[2] = {0, 3}, negative_spring[3] = {20, -1, 30}, nan_damper[3] = {2, NAN, 3};
    okid_real mm[4], rr[4], kk[4];
    assert_int_equal(okid_chain_model(2, masses, dampers, NULL, mm, rr, kk), OKID_E_NULL_POINTER);
    assert_int_equal(okid_chain_model(0, masses, dampers, springs, mm, rr, kk), OKID_E_BAD_SIZE);
    assert_int_equal(okid_chain_model(2, zero_mass, dampers, springs, mm, rr, kk), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_chain_model(2, masses, dampers, negative_spring, mm, rr, kk), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_chain_model(2, masses, nan_damper, springs, mm, rr, kk), OKID_E_BAD_PARAMETER);

    const okid_real singular[4] = {1, 1, 1, 1}, b2[2] = {1, 0}, ca[4] = {1, 0, 0, 1};
    okid_real ac[16], bc[4], c[8], d[2], work[OKID_STATE_SPACE_WORK_REALS(2, 1)];
    const size_t wl = sizeof work / sizeof work[0];
    okid_mechanical_model model = {2, 1, 2, singular, REF_PAPER.damping, REF_PAPER.stiffness, b2, ca, NULL, NULL};
    assert_int_equal(okid_model_state_space(&model, ac, bc, c, d, work, wl), OKID_E_BAD_PARAMETER);
    model.mass = REF_PAPER.mass;
    assert_int_equal(okid_model_state_space(&model, ac, bc, c, d, work, wl - 1), OKID_E_WORKSPACE_TOO_SMALL);
    assert_int_equal(okid_model_state_space(NULL, ac, bc, c, d, work, wl), OKID_E_NULL_POINTER);
    model.dofs = 0;
    assert_int_equal(okid_model_state_space(&model, ac, bc, c, d, work, wl), OKID_E_BAD_SIZE);

    okid_real a[16], b[4], zw[OKID_ZOH_WORK_REALS(4, 1)];
    const size_t zl = sizeof zw / sizeof zw[0];
    assert_int_equal(okid_discretize_zoh(4, 1, REF_PAPER.ac, REF_PAPER.bc, 0, a, b, zw, zl), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_discretize_zoh(4, 1, REF_PAPER.ac, REF_PAPER.bc, NAN, a, b, zw, zl), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_discretize_zoh(4, 1, REF_PAPER.ac, REF_PAPER.bc, 0.01, a, b, zw, zl - 1),
                     OKID_E_WORKSPACE_TOO_SMALL);
    assert_int_equal(okid_discretize_zoh(0, 1, REF_PAPER.ac, REF_PAPER.bc, 0.01, a, b, zw, zl), OKID_E_BAD_SIZE);
    okid_real nan_ac[16];
    for (int i = 0; i < 16; ++i) nan_ac[i] = REF_PAPER.ac[i];
    nan_ac[5] = INFINITY;
    assert_int_equal(okid_discretize_zoh(4, 1, nan_ac, REF_PAPER.bc, 0.01, a, b, zw, zl), OKID_E_BAD_PARAMETER);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_paper_model),        cmocka_unit_test(test_mimo_model),
        cmocka_unit_test(test_chain3_model),       cmocka_unit_test(test_zoh_non_normal),
        cmocka_unit_test(test_zoh_without_inputs), cmocka_unit_test(test_simulator_matches_recursion),
        cmocka_unit_test(test_model_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

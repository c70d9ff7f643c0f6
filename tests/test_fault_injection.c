/* SPDX-License-Identifier: Apache-2.0 */
/*
 * LAPACK failures injected under the library (the linker wraps the LAPACKE calls of libokid.a,
 * see tests/CMakeLists.txt) surface as documented statuses, never as garbage modes, and leave
 * the result untouched; the non-terminating xerbla_ returns control after a bad argument.
 */
#include "test_support.h"

#include <lapacke.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Which routine fails next, and with which INFO (0: none). */
static const char *fail_routine;
static lapack_int fail_info;

static int should_fail(const char *routine)
{
    return fail_routine != NULL && strcmp(fail_routine, routine) == 0;
}

lapack_int __real_LAPACKE_dgesvd_work(int layout, char jobu, char jobvt, lapack_int m, lapack_int n, double *a,
                                      lapack_int lda, double *s, double *u, lapack_int ldu, double *vt,
                                      lapack_int ldvt, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgesvd_work(int layout, char jobu, char jobvt, lapack_int m, lapack_int n, double *a,
                                      lapack_int lda, double *s, double *u, lapack_int ldu, double *vt,
                                      lapack_int ldvt, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgesvd_work(int layout, char jobu, char jobvt, lapack_int m, lapack_int n, double *a,
                                      lapack_int lda, double *s, double *u, lapack_int ldu, double *vt,
                                      lapack_int ldvt, double *work, lapack_int lwork)
{
    if (should_fail("gesvd")) {
        for (lapack_int i = 0; i < (m < n ? m : n); ++i) s[i] = NAN; /* what a half-done SVD may leave */
        return fail_info;
    }
    return __real_LAPACKE_dgesvd_work(layout, jobu, jobvt, m, n, a, lda, s, u, ldu, vt, ldvt, work, lwork);
}

lapack_int __real_LAPACKE_dgeev_work(int layout, char jobvl, char jobvr, lapack_int n, double *a, lapack_int lda,
                                     double *wr, double *wi, double *vl, lapack_int ldvl, double *vr,
                                     lapack_int ldvr, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgeev_work(int layout, char jobvl, char jobvr, lapack_int n, double *a, lapack_int lda,
                                     double *wr, double *wi, double *vl, lapack_int ldvl, double *vr,
                                     lapack_int ldvr, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgeev_work(int layout, char jobvl, char jobvr, lapack_int n, double *a, lapack_int lda,
                                     double *wr, double *wi, double *vl, lapack_int ldvl, double *vr,
                                     lapack_int ldvr, double *work, lapack_int lwork)
{
    if (should_fail("geev")) return fail_info;
    return __real_LAPACKE_dgeev_work(layout, jobvl, jobvr, n, a, lda, wr, wi, vl, ldvl, vr, ldvr, work, lwork);
}

lapack_int __real_LAPACKE_dgelsy_work(int layout, lapack_int m, lapack_int n, lapack_int nrhs, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, lapack_int *jpvt, double rcond,
                                      lapack_int *rank, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgelsy_work(int layout, lapack_int m, lapack_int n, lapack_int nrhs, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, lapack_int *jpvt, double rcond,
                                      lapack_int *rank, double *work, lapack_int lwork);
lapack_int __wrap_LAPACKE_dgelsy_work(int layout, lapack_int m, lapack_int n, lapack_int nrhs, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, lapack_int *jpvt, double rcond,
                                      lapack_int *rank, double *work, lapack_int lwork)
{
    if (should_fail("gelsy")) return fail_info;
    return __real_LAPACKE_dgelsy_work(layout, m, n, nrhs, a, lda, b, ldb, jpvt, rcond, rank, work, lwork);
}

lapack_int __real_LAPACKE_dtpqrt_work(int layout, lapack_int m, lapack_int n, lapack_int l, lapack_int nb, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, double *t, lapack_int ldt,
                                      double *work);
lapack_int __wrap_LAPACKE_dtpqrt_work(int layout, lapack_int m, lapack_int n, lapack_int l, lapack_int nb, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, double *t, lapack_int ldt,
                                      double *work);
lapack_int __wrap_LAPACKE_dtpqrt_work(int layout, lapack_int m, lapack_int n, lapack_int l, lapack_int nb, double *a,
                                      lapack_int lda, double *b, lapack_int ldb, double *t, lapack_int ldt,
                                      double *work)
{
    if (should_fail("tpqrt")) return fail_info;
    return __real_LAPACKE_dtpqrt_work(layout, m, n, l, nb, a, lda, b, ldb, t, ldt, work);
}

typedef struct fixture {
    okid_config cfg;
    okid_identifier id;
    void *ws;
    size_t bytes;
} fixture;

static int setup(void **state)
{
    fixture *f = calloc(1, sizeof *f);
    okid_config cfg;
    test_config(&REF_PAPER, &cfg);
    f->cfg = cfg;
    f->ws = test_workspace(&f->cfg, &f->bytes);
    assert_int_equal(okid_init(&f->id, &f->cfg, f->ws, f->bytes, NULL), OKID_OK);
    double *u = test_white_noise(1, 1001, 3), y[2 * 1001];
    test_simulate(&REF_PAPER, 1001, u, y, NULL);
    assert_int_equal(okid_push_block(&f->id, 1001, u, 1, y, 2, NULL), OKID_OK);
    free(u);
    fail_routine = NULL;
    *state = f;
    return 0;
}

static int teardown(void **state)
{
    fixture *f = *state;
    free(f->ws);
    free(f);
    fail_routine = NULL;
    return 0;
}

/* A failure of `routine` with INFO = info gives `want`, leaves the result untouched, and the
   next identification (without the fault) is exact. */
static void check_fault(fixture *f, const char *routine, lapack_int info, okid_status want)
{
    okid_result res, untouched;
    memset(&res, 0x3c, sizeof res);
    untouched = res;
    fail_routine = routine;
    fail_info = info;
    assert_int_equal(okid_identify(&f->id, &res), want);
    assert_memory_equal(&res, &untouched, sizeof res);
    fail_routine = NULL;
    assert_int_equal(okid_identify(&f->id, &res), OKID_OK);
    assert_modes_match(&REF_PAPER, res.modes, res.num_modes, 1e-9, 0.999999);
}

static void test_svd_not_converging(void **state) { check_fault(*state, "gesvd", 3, OKID_E_DECOMPOSITION_FAILED); }
static void test_svd_bad_argument(void **state) { check_fault(*state, "gesvd", -5, OKID_E_BACKEND_ARGUMENT); }
static void test_eigen_not_converging(void **state) { check_fault(*state, "geev", 2, OKID_E_DECOMPOSITION_FAILED); }
static void test_least_squares_bad_argument(void **state) { check_fault(*state, "gelsy", -7, OKID_E_BACKEND_ARGUMENT); }

/* A fold failing during a push is reported by that push (and by identify, which folds the rest). */
static void test_fold_failure_is_reported(void **state)
{
    fixture *f = *state;
    okid_result res;
    const double u = 0.5, y[2] = {0.1, 0.2};
    fail_routine = "tpqrt";
    fail_info = -3;
    okid_status worst = OKID_OK;
    for (int k = 0; k < 64; ++k) { /* at least one full block of 32 rows */
        const okid_status st = okid_push(&f->id, &u, y);
        if (st != OKID_OK) worst = st;
    }
    assert_int_equal(worst, OKID_E_BACKEND_ARGUMENT);
    fail_routine = NULL;
    assert_int_not_equal(okid_identify(&f->id, &res), OKID_E_BACKEND_ARGUMENT); /* works again */
}

/* The stock XERBLA of the static reference LAPACK stops the process; okid's returns. */
static void test_xerbla_returns_control(void **state)
{
    (void)state;
    double a[4] = {1, 2, 3, 4}, s[2], vt[4], work[64];
    /* JOBU = 'Z' is illegal: DGESVD calls XERBLA('DGESVD', 1) and must come back with INFO = -1,
       which LAPACKE shifts to -2 (its argument 1 is the matrix layout). */
    const lapack_int info = __real_LAPACKE_dgesvd_work(LAPACK_COL_MAJOR, 'Z', 'S', 2, 2, a, 2, s, NULL, 1, vt, 2,
                                                       work, 64);
    assert_int_equal(info, -2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test_setup_teardown(test_svd_not_converging, setup, teardown),
        cmocka_unit_test_setup_teardown(test_svd_bad_argument, setup, teardown),
        cmocka_unit_test_setup_teardown(test_eigen_not_converging, setup, teardown),
        cmocka_unit_test_setup_teardown(test_least_squares_bad_argument, setup, teardown),
        cmocka_unit_test_setup_teardown(test_fold_failure_is_reported, setup, teardown),
        cmocka_unit_test(test_xerbla_returns_control),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

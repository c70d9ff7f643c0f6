/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Workspace sizes of refinements whose dimensions are each accepted but whose workspace exceeds
 * the address space: n = 512, r = m = 64 has P = 70144 parameters and two P x P normal matrices
 * (79 GB in double, 39 GB in float). With a 32-bit size_t (the m32 preset, the firmware
 * targets) okid_refine_workspace_size() and okid_refine_init() must refuse with OKID_E_BAD_SIZE
 * and OKID_REFINE_WORKSPACE_BYTES must saturate at SIZE_MAX; with a 64-bit size_t they fit. In both, every size is at least an
 * independent lower bound (the two normal matrices), computed here in 64 bits.
 */
#include "test_support.h"

#include <stdlib.h>
#include <string.h>

#include "okid/refine.h"

/* The two normal matrices alone: 2 P^2 reals, P = n (r + m + 1) + m r (+ n m: the innovation form's K). */
static unsigned long long model_lower_bound(int inn, int n, int r, int m)
{
    const unsigned long long p = (unsigned long long)n * (unsigned long long)(r + m + 1) + (unsigned long long)m * (unsigned long long)r +
                                 (unsigned long long)inn * (unsigned long long)n * (unsigned long long)m;
    return 2ull * sizeof(okid_real) * p * p;
}

static unsigned long long lower_bound(int n, int r, int m)
{
    return model_lower_bound(0, n, r, m);
}

static void test_largest_dimensions(void **state)
{
    (void)state;
    const int n = OKID_MAX_ORDER, r = OKID_MAX_DIMENSION, m = OKID_MAX_DIMENSION;
    assert_int_equal(n, 512);
    assert_int_equal(r, 64);
    const unsigned long long bound = lower_bound(n, r, m);
    assert_true(bound == 2ull * sizeof(okid_real) * 70144ull * 70144ull); /* 79 GB in double, 39 GB in float */
    assert_true(bound > 0xffffffffull);                                   /* beyond any 32-bit size_t */
    size_t bytes = 12345;
    const okid_status st = okid_refine_workspace_size(n, r, m, &bytes);
    if (sizeof(size_t) < 8) {
        assert_int_equal(st, OKID_E_BAD_SIZE);
        assert_int_equal(bytes, 12345); /* untouched */
        assert_true(OKID_REFINE_WORKSPACE_BYTES(512, 64, 64) == (size_t)-1);
    } else {
        assert_int_equal(st, OKID_OK);
        assert_true(bytes >= bound);
        assert_true(OKID_REFINE_WORKSPACE_BYTES(512, 64, 64) == bytes);
    }

    /* okid_refine_init() refuses the same start before it lays out anything (32-bit), or says how
     * much it needs (64-bit): never a wrapped-around size that a small buffer would satisfy. */
    okid_real *a = calloc((size_t)n * (size_t)n, sizeof(okid_real));
    okid_real *b = calloc((size_t)n * (size_t)r, sizeof(okid_real));
    okid_real *c = calloc((size_t)m * (size_t)n, sizeof(okid_real));
    okid_real *d = calloc((size_t)m * (size_t)r, sizeof(okid_real));
    assert_non_null(a), assert_non_null(b), assert_non_null(c), assert_non_null(d);
    okid_result start;
    memset(&start, 0, sizeof start);
    start.order = n;
    start.dt = (okid_real)0.01;
    start.A = (okid_matrix){a, n, n, n};
    start.B = (okid_matrix){b, n, r, n};
    start.C = (okid_matrix){c, m, n, m};
    start.D = (okid_matrix){d, m, r, m};
    okid_refine_config rc;
    assert_int_equal(okid_refine_config_default(&rc), OKID_OK);
    enum { SMALL = 1 << 16 };
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, SMALL);
    assert_non_null(ws);
    okid_refiner rf;
    size_t needed = 0;
    const okid_status init = okid_refine_init(&rf, &rc, &start, OKID_SENSING_ACCELERATION, ws, SMALL, &needed);
    if (sizeof(size_t) < 8) {
        assert_int_equal(init, OKID_E_BAD_SIZE);
    } else {
        assert_int_equal(init, OKID_E_WORKSPACE_TOO_SMALL);
        assert_true(needed == bytes);
    }
    assert_int_equal(okid_refine_begin_pass(&rf), OKID_E_NOT_INITIALIZED);
    free(ws), free(a), free(b), free(c), free(d);
}

/* Every accepted (n, r, m) on a grid, for one model: refused exactly when the 64-bit size
 * exceeds SIZE_MAX, otherwise equal to the macro and at least the lower bound. */
static void grid_of_model(int inn, int *fitted, int *refused)
{
    static const int orders[] = {1, 2, 4, 16, 64, 128, 200, 256, 384, 512};
    static const int dims[] = {1, 2, 8, 16, 32, 48, 64};
    const okid_refine_model model = inn ? OKID_REFINE_INNOVATION : OKID_REFINE_OUTPUT_ERROR;
    for (size_t i = 0; i < sizeof orders / sizeof orders[0]; ++i) {
        for (size_t j = 0; j < sizeof dims / sizeof dims[0]; ++j) {
            for (size_t k = 0; k < sizeof dims / sizeof dims[0]; ++k) {
                const int n = orders[i], r = dims[j], m = dims[k];
                const unsigned long long bound = model_lower_bound(inn, n, r, m);
                size_t bytes = 0;
                const okid_status st = okid_refine_model_workspace_size(model, n, r, m, &bytes);
                const size_t macro = OKID_REFINE_MODEL_WORKSPACE_BYTES(model, n, r, m);
                if (!inn) {
                    size_t plain = 0; /* the output-error size function and macro are these */
                    assert_int_equal(okid_refine_workspace_size(n, r, m, &plain), st);
                    assert_true(OKID_REFINE_WORKSPACE_BYTES(n, r, m) == macro && (st != OKID_OK || plain == bytes));
                }
                if (st == OKID_E_BAD_SIZE) {
                    ++*refused;
                    assert_true(sizeof(size_t) < 8);
                    assert_true(macro == (size_t)-1);
                } else {
                    ++*fitted;
                    assert_int_equal(st, OKID_OK);
                    assert_true(bytes == macro);
                    assert_true((unsigned long long)bytes >= bound);
                }
                /* anything the bound alone puts above SIZE_MAX must have been refused */
                if (bound > (unsigned long long)(size_t)-1) assert_int_equal(st, OKID_E_BAD_SIZE);
            }
        }
    }
}

static void test_grid(void **state)
{
    (void)state;
    for (int inn = 0; inn < 2; ++inn) {
        int refused = 0, fitted = 0;
        grid_of_model(inn, &fitted, &refused);
        print_message("%s: %d (n, r, m) fitted, %d refused as above SIZE_MAX\n", inn ? "innovation" : "output error",
                      fitted, refused);
        assert_true(fitted > 0);
        if (sizeof(size_t) < 8) assert_true(refused > 0);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_largest_dimensions),
        cmocka_unit_test(test_grid),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

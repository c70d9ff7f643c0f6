/* SPDX-License-Identifier: Apache-2.0 */
/* The random generator against a Python re-implementation of xoshiro256** / splitmix64. */
#include "test_support.h"

#include <math.h>

#include "reference/reference_data.h"

static void test_uniform_sequence(void **state)
{
    (void)state;
    okid_rng rng;
    assert_int_equal(okid_rng_seed(&rng, 2024), OKID_OK);
    for (int i = 0; i < 8; ++i) {
#if OKID_REAL_IS_FLOAT
        /* the top 24 bits (truncated) against the 53-bit reference rounded to float: one step apart at most */
        assert_true(fabs((double)okid_rng_uniform(&rng) - (double)RNG_SEED2024_UNIFORM[i]) <= 0x1p-24);
#else
        assert_true(okid_rng_uniform(&rng) == RNG_SEED2024_UNIFORM[i]); /* exact: integer arithmetic */
#endif
    }
}

static void test_normal_sequence(void **state)
{
    (void)state;
    okid_rng rng;
    okid_real out[18];
    assert_int_equal(okid_rng_seed(&rng, 2024), OKID_OK);
    assert_int_equal(okid_rng_normal(&rng, 2.0, 9, out, 2), OKID_OK); /* stride 2 */
    for (int i = 0; i < 9; ++i) {
        assert_relative(out[2 * i], 2.0 * RNG_SEED2024_NORMAL[i], TOL(1e-15, 1e-4), "normal", i);
    }
}

static void test_normal_statistics(void **state)
{
    (void)state;
    enum { N = 200000 };
    static okid_real x[N];
    okid_rng rng;
    okid_rng_seed(&rng, 1);
    assert_int_equal(okid_rng_normal(&rng, 1, N, x, 1), OKID_OK);
    double mean = 0, var = 0;
    for (int i = 0; i < N; ++i) mean += x[i];
    mean /= N;
    for (int i = 0; i < N; ++i) var += (x[i] - mean) * (x[i] - mean);
    var /= N - 1;
    assert_true(fabs(mean) < 5.0 / sqrt(N)); /* 5 standard errors */
    assert_true(fabs(var - 1) < 5.0 * sqrt(2.0 / N));
}

static void test_bad_input(void **state)
{
    (void)state;
    okid_rng rng;
    okid_real x[2];
    assert_int_equal(okid_rng_seed(NULL, 1), OKID_E_NULL_POINTER);
    okid_rng_seed(&rng, 1);
    assert_int_equal(okid_rng_normal(&rng, 1, 2, x, 0), OKID_E_BAD_SIZE);
    assert_int_equal(okid_rng_normal(&rng, -1, 2, x, 1), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_rng_normal(&rng, NAN, 2, x, 1), OKID_E_BAD_PARAMETER);
    assert_int_equal(okid_rng_normal(NULL, 1, 2, x, 1), OKID_E_NULL_POINTER);
    assert_true(okid_rng_uniform(NULL) == 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_uniform_sequence),
        cmocka_unit_test(test_normal_sequence),
        cmocka_unit_test(test_normal_statistics),
        cmocka_unit_test(test_bad_input),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

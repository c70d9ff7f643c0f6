/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Workspace sizes of configurations whose dimensions are each accepted but whose workspace exceeds
 * the address space. With a 32-bit size_t (the m32 preset, the firmware targets) they must be
 * refused with OKID_E_BAD_SIZE and the macro must saturate at SIZE_MAX; with a 64-bit size_t they
 * fit, and every size must be at least an independent lower bound. In both, nothing is written
 * outside the buffer (oversize_check.c).
 */
#include "test_support.h"

#include <stdio.h>
#include <stdlib.h>

#include "oversize_check.h"

enum { CAPACITY = 1 << 20, RANDOM_CONFIGS = 2000 };

static void print_failure(const char *what, const okid_config *c)
{
    print_error("%s: r %d m %d p %d alpha %d beta %d order %d block_rows %d combined %d decimation %d scaling %d "
                "estimator %d\n",
                what, c->num_inputs, c->num_outputs, c->observer_order, c->hankel_rows, c->hankel_cols, c->order,
                c->block_rows, c->realization, c->decimation, (int)c->scaling, (int)c->estimator);
}

static unsigned char *guarded_buffer(void)
{
    unsigned char *buf = aligned_alloc(OKID_WORKSPACE_ALIGN, CAPACITY + OVERSIZE_GUARD);
    assert_non_null(buf);
    return buf;
}

/* The issue's example: R alone is 32745^2 reals (8.6 GB in double), accepted with 1.7 MB before. */
static void test_issue_example(void **state)
{
    (void)state;
    okid_config cfg;
    assert_int_equal(okid_config_default(&cfg, 15, 44), OKID_OK);
    cfg.observer_order = 554;
    cfg.hankel_rows = cfg.hankel_cols = 1;
    cfg.order = 1;
    cfg.block_rows = 1;
    const uint64_t bound = oversize_lower_bound(&cfg);
    assert_true(bound >= sizeof(okid_real) * 32745ull * 32745ull);
    size_t bytes = 0;
    const okid_status st = okid_workspace_size(&cfg, &bytes);
    if (sizeof(size_t) < 8) {
        assert_int_equal(st, OKID_E_BAD_SIZE);
        assert_true(OKID_WORKSPACE_BYTES(15, 44, 554, 1, 1, 1, 1, 0) == (size_t)-1);
    } else {
        assert_int_equal(st, OKID_OK);
        assert_true(bytes >= bound);
        assert_true(OKID_WORKSPACE_BYTES(15, 44, 554, 1, 1, 1, 1, 0) == bytes);
    }
    unsigned char *buf = guarded_buffer();
    oversize_tally tally = {0};
    oversize_check_config(&cfg, buf, CAPACITY, &tally, print_failure);
    assert_int_equal(tally.failures, 0);
    free(buf);
}

static void test_random_configurations(void **state)
{
    (void)state;
    unsigned char *buf = guarded_buffer();
    oversize_tally tally = {0};
    oversize_run(20261129u, RANDOM_CONFIGS, buf, CAPACITY, &tally, print_failure);
    free(buf);
    printf("%d configurations: %d above SIZE_MAX (%d refused), %d initialised and fed\n", tally.tried,
           tally.oversized, tally.refused, tally.fitted);
    assert_int_equal(tally.failures, 0);
    assert_int_equal(tally.tried, RANDOM_CONFIGS);
    assert_true(tally.fitted >= RANDOM_CONFIGS / 4); /* the small half mostly fits */
    if (sizeof(size_t) < 8) {
        assert_true(tally.oversized >= RANDOM_CONFIGS / 10);
        assert_int_equal(tally.refused, tally.oversized);
    } else {
        assert_int_equal(tally.oversized, 0); /* no accepted dimensions reach 2^64 bytes */
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_issue_example),
        cmocka_unit_test(test_random_configurations),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

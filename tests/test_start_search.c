/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement's start search (host_tools/common/start_search.h) with a scripted refinement:
 * a start whose refined model splits one mode in two (OKID_W_MODE_SPLIT) loses to any that does
 * not, whatever its cost; among starts of one kind the lowest cost wins; two starts of the chosen
 * kind at the same cost end the search; when every start splits, the lowest cost among them.
 * OKID/ERA runs for real on a noise-free record of the paper's system at each start.
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <stdlib.h>
#include <cmocka.h>

#include "okid/okid.h"
#include "start_search.h"
#include "test_support.h"

typedef struct script {
    int calls, count;
    const double *cost;
    const int *split;
} script;

static int scripted(void *context, const okid_result *start, int *state, double *cost, unsigned *warnings)
{
    script *s = context;
    assert_true(start->order == 4 && s->calls < s->count);
    *state = (int)OKID_REFINE_CONVERGED;
    *cost = s->cost[s->calls];
    *warnings = s->split[s->calls] ? (unsigned)OKID_W_MODE_SPLIT : 0u;
    ++s->calls;
    return 0;
}

/* The search over the record with the script; returns the chosen index, checks cfg got its horizons. */
static int search_with(const double *cost, const int *split, int count, int expect_tried)
{
    okid_real *u, *y;
    const size_t n = 1500;
    test_paper_record(0.05, n, 3, 0, &u, &y);
    okid_config cfg;
    okid_config_default(&cfg, 1, 2);
    cfg.dt = (okid_real)0.05;
    cfg.order = 4;
    script s = {0, count, cost, split};
    start_search search;
    start_search_run(&cfg, n, u, y, scripted, &s, &search);
    assert_int_equal(search.count, expect_tried);
    assert_int_equal(s.calls, expect_tried);
    for (int i = 0; i < search.count; ++i) {
        assert_int_equal(search.candidates[i].split, split[i]);
    }
    assert_true(search.best >= 0);
    assert_int_equal(cfg.observer_order, search.candidates[search.best].observer_order);
    assert_int_equal(cfg.hankel_rows, search.candidates[search.best].hankel_blocks);
    free(u);
    free(y);
    return search.best;
}

static void test_a_split_start_loses_to_a_costlier_whole_one(void **state)
{
    (void)state;
    /* start 0 splits at cost 10, start 1 is whole at 20, start 2 splits at 5, start 3 is whole at 20 (a tie: stop) */
    const double cost[] = {10, 20, 5, 20};
    const int split[] = {1, 0, 1, 0};
    assert_int_equal(search_with(cost, split, 4, 4), 1);
}

static void test_split_ties_do_not_end_the_search_for_a_whole_start(void **state)
{
    (void)state;
    /* two split starts at the same cost do not stop the search once a whole one is chosen */
    const double cost[] = {30, 5, 5, 40, 30};
    const int split[] = {0, 1, 1, 0, 0};
    assert_int_equal(search_with(cost, split, 5, 5), 0);
}

static void test_every_start_splits(void **state)
{
    (void)state;
    const double cost[] = {10, 5, 5};
    const int split[] = {1, 1, 1};
    assert_int_equal(search_with(cost, split, 3, 3), 1);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_a_split_start_loses_to_a_costlier_whole_one),
        cmocka_unit_test(test_split_ties_do_not_end_the_search_for_a_whole_start),
        cmocka_unit_test(test_every_start_splits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

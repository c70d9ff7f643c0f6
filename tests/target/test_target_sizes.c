/* SPDX-License-Identifier: Apache-2.0 */
/*
 * On the target (32-bit size_t): randomised configurations whose dimensions are each accepted but
 * whose workspace exceeds 4 GiB must be refused with OKID_E_BAD_SIZE (okid_workspace_size and
 * okid_init, OKID_WORKSPACE_BYTES_OPTIONS saturated at SIZE_MAX), and no call may write past the
 * buffer (tests/oversize_check.c, the same check as the host's test_workspace_overflow).
 */
#include <stdint.h>

#include "oversize_check.h"
#include "target_check.h"

enum { CAPACITY = 64 * 1024, RANDOM_CONFIGS = 400 };

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char buffer[CAPACITY + OVERSIZE_GUARD];

static void print_failure(const char *what, const okid_config *c)
{
    printf("FAIL %s: r %d m %d p %d alpha %d beta %d order %d block_rows %d\n", what, c->num_inputs,
           c->num_outputs, c->observer_order, c->hankel_rows, c->hankel_cols, c->order, c->block_rows);
}

int main(void)
{
    CHECK(sizeof(size_t) == 4);

    okid_config cfg; /* the example: R alone is 32745^2 reals */
    CHECK(okid_config_default(&cfg, 15, 44) == OKID_OK);
    cfg.observer_order = 554;
    cfg.hankel_rows = cfg.hankel_cols = 1;
    cfg.order = 1;
    cfg.block_rows = 1;
    size_t bytes = 0;
    CHECK(okid_workspace_size(&cfg, &bytes) == OKID_E_BAD_SIZE);
    CHECK(OKID_WORKSPACE_BYTES(15, 44, 554, 1, 1, 1, 1, 0) == SIZE_MAX);

    oversize_tally tally = {0};
    oversize_check_config(&cfg, buffer, CAPACITY, &tally, print_failure);
    oversize_run(20261129u, RANDOM_CONFIGS, buffer, CAPACITY, &tally, print_failure);
    printf("%d configurations: %d above SIZE_MAX (%d refused), %d initialised and fed\n", tally.tried,
           tally.oversized, tally.refused, tally.fitted);
    CHECK(tally.failures == 0);
    CHECK(tally.oversized >= RANDOM_CONFIGS / 10);
    CHECK(tally.refused == tally.oversized);
    CHECK(tally.fitted >= RANDOM_CONFIGS / 8);
    return target_summary("test_target_sizes");
}

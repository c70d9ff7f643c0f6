/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Exact decimation by lifting (okid/lifting.h): noise-free paper data decimated by K = 2..8
 * identify the exact modes (numpy/scipy, reference_data.h) to 1e-6 relative, where the built-in
 * anti-alias decimation (okid_config::decimation) is biased (printed for docs/refinement.md).
 */
#include "test_support.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { LIFTED_SAMPLES = 3001 };

/* Relative errors of the two frequencies and damping ratios against the exact ones (largest). */
static double modal_error(const okid_result *res)
{
    double worst = 0;
    int pairs = 0;
    for (int i = 0; i < res->num_modes && pairs < 2; ++i) {
        if (!res->modes[i].is_pair) continue;
        const double ef = fabs(res->modes[i].frequency_hz - REF_PAPER.freq_hz[pairs]) / REF_PAPER.freq_hz[pairs];
        const double ez =
            fabs(res->modes[i].damping_ratio - REF_PAPER.damping_ratio[pairs]) / REF_PAPER.damping_ratio[pairs];
        worst = fmax(worst, fmax(ef, ez));
        ++pairs;
    }
    return pairs == 2 ? worst : 1e9;
}

/* Identify r inputs, 2 outputs, count samples at dt, with decimation K and observer order p; the modal error. */
static double identify_error(int r, double dt, int decimation, int p, size_t count, const okid_real *u,
                             const okid_real *y)
{
    okid_config cfg;
    okid_config_default(&cfg, r, 2);
    cfg.dt = (okid_real)dt;
    cfg.observer_order = p;
    cfg.order = 4;
    cfg.hankel_rows = cfg.hankel_cols = 20;
    cfg.decimation = decimation;
    size_t bytes = 0;
    void *ws = test_workspace(&cfg, &bytes);
    okid_identifier id;
    okid_result res;
    assert_int_equal(okid_init(&id, &cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&id, count, u, (size_t)r, y, 2, NULL), OKID_OK);
    const double err = okid_identify(&id, &res) == OKID_OK ? modal_error(&res) : 1e9;
    free(ws);
    return err;
}

static void test_lifted_decimation_is_exact(void **state)
{
    (void)state;
    const double dt = 0.01;
    for (int k = 2; k <= 8; ++k) {
        const size_t count = (size_t)LIFTED_SAMPLES * (size_t)k + (size_t)k - 1; /* K - 1 left over */
        okid_real *u, *y;
        test_paper_record(dt, count, 40u + (uint64_t)k, 0, &u, &y);
        okid_real *ul = malloc(sizeof(okid_real) * count), *yl = malloc(sizeof(okid_real) * 2 * count);
        assert_non_null(ul);
        assert_non_null(yl);
        size_t lifted = 0;
        assert_int_equal(okid_lift(1, 2, k, count, u, 1, y, 2, ul, yl, &lifted), OKID_OK);
        assert_int_equal(lifted, LIFTED_SAMPLES);
        assert_true(ul[k] == u[k] && ul[2 * k + 1] == u[2 * k + 1] && yl[2] == y[2 * k] && yl[3] == y[2 * k + 1]);
        const double exact = identify_error(k, dt * k, 1, 4, lifted, ul, yl);
        /* the filter's two states per channel need a longer observer: p = 20 */
        const double filtered = identify_error(1, dt, k, 20, count, u, y);
        print_message("K = %d: modal error lifted %.2e, built-in anti-alias decimation %.2e\n", k, exact, filtered);
        assert_within(exact, TOL(1e-6, 2e-3));
        free(u);
        free(y);
        free(ul);
        free(yl);
    }
}

static void test_lift_refusals(void **state)
{
    (void)state;
    okid_real u[8] = {0}, y[16] = {0}, ul[8], yl[16];
    size_t lifted = 99;
    assert_int_equal(okid_lift(1, 2, 3, 8, NULL, 1, y, 2, ul, yl, &lifted), OKID_E_NULL_POINTER);
    assert_int_equal(okid_lift(1, 2, 0, 8, u, 1, y, 2, ul, yl, &lifted), OKID_E_BAD_SIZE);
    assert_int_equal(okid_lift(1, 2, OKID_MAX_DECIMATION + 1, 8, u, 1, y, 2, ul, yl, &lifted), OKID_E_BAD_SIZE);
    assert_int_equal(okid_lift(1, 2, 3, 8, u, 1, y, 1, ul, yl, &lifted), OKID_E_BAD_SIZE);
    assert_int_equal(lifted, 99);
    assert_int_equal(okid_lift(1, 2, 3, 8, u, 1, y, 2, ul, yl, &lifted), OKID_OK);
    assert_int_equal(lifted, 2);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_lifted_decimation_is_exact),
        cmocka_unit_test(test_lift_refusals),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

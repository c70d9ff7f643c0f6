/* SPDX-License-Identifier: Apache-2.0 */
/*
 * refine_model = auto's choice (host_tools/common/refine_choice.h) on hand-made refinement results:
 * every branch, and the 3-sigma agreement rule at differences of 2.83 and 3.54 combined standard
 * deviations (0.4 and 0.5 Hz against two stds of 0.1 Hz: sqrt(0.1^2 + 0.1^2) = 0.1414), and an
 * innovation form whose white residual is correlated with the input (output error stays).
 */
#include <math.h>
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>
#include <cmocka.h>

#include "okid/okid.h"
#include "refine_choice.h"

enum { M = 2 };

typedef struct fake {
    okid_refine_result r;
    okid_mode modes[2];
    okid_mode_std std[2];
    unsigned out_warn[M];
    okid_real whiteness[M];
    okid_real input_correlation[M]; /* one input: [i + M * 0] */
} fake;

/* A converged result with two pairs at f Hz (std sf) and 1.0 + f Hz, damping 0.02 (std 0.001). */
static void make(fake *f, okid_real freq, okid_real sf, unsigned warn_output2)
{
    memset(f, 0, sizeof *f);
    for (int k = 0; k < 2; ++k) {
        f->modes[k].is_pair = 1;
        f->modes[k].frequency_hz = freq + (okid_real)k;
        f->modes[k].damping_ratio = (okid_real)0.02;
        f->std[k].frequency_hz = sf;
        f->std[k].damping_ratio = (okid_real)0.001;
    }
    f->out_warn[1] = warn_output2;
    f->whiteness[0] = 10;
    f->whiteness[1] = warn_output2 ? 500 : 20;
    f->r.state = OKID_REFINE_CONVERGED;
    f->r.num_modes = 2;
    f->r.modes = f->modes;
    f->r.mode_std = f->std;
    f->r.output_warnings = f->out_warn;
    f->r.whiteness = f->whiteness;
    f->input_correlation[0] = 1;
    f->input_correlation[1] = (warn_output2 & OKID_W_RESIDUAL_INPUT_CORRELATED) ? 9 : 2;
    f->r.input_correlation = f->input_correlation;
    f->r.B.cols = 1;
    f->r.warnings = warn_output2;
}

static void test_branches(void **state)
{
    (void)state;
    fake oe, inn;
    refine_choice c;
    /* output error white: it stays, nothing else needed */
    make(&oe, 1, (okid_real)0.1, 0);
    assert_false(refine_choice_needs_innovation(&oe.r));
    refine_choose(&oe.r, NULL, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_OUTPUT_ERROR);
    assert_int_equal(c.reason, REFINE_CHOICE_WHITE);
    /* output error diverged: no test to choose from */
    oe.r.state = OKID_REFINE_DIVERGED;
    assert_false(refine_choice_needs_innovation(&oe.r));
    refine_choose(&oe.r, NULL, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_OE_DIVERGED);
    /* not white: the innovation form is needed; not run or not converged keeps output error */
    make(&oe, 1, (okid_real)0.1, OKID_W_RESIDUAL_NOT_WHITE);
    assert_true(refine_choice_needs_innovation(&oe.r));
    refine_choose(&oe.r, NULL, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_OUTPUT_ERROR);
    assert_int_equal(c.reason, REFINE_CHOICE_NOT_CONVERGED);
    make(&inn, (okid_real)1.4, (okid_real)0.1, 0);
    inn.r.state = OKID_REFINE_ITERATION_LIMIT;
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_NOT_CONVERGED);
    /* converged, agrees (2.83 sigma), but output 2 not white: a drift, output error stays */
    make(&inn, (okid_real)1.4, (okid_real)0.1, OKID_W_RESIDUAL_NOT_WHITE);
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_OUTPUT_ERROR);
    assert_int_equal(c.reason, REFINE_CHOICE_STILL_NOT_WHITE);
    assert_non_null(strstr(c.detail, "output 2"));
    /* white and 2.83 combined sigma apart: the innovation form */
    make(&inn, (okid_real)1.4, (okid_real)0.1, 0);
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_INNOVATION);
    assert_int_equal(c.reason, REFINE_CHOICE_INNOVATION);
    assert_non_null(strstr(c.detail, "2.83"));
    /* white, agrees, but output 2's residual correlated with the input (statistic 9 above 4.06):
       the innovation form misses dynamics that output error's would too; output error stays */
    make(&inn, (okid_real)1.4, (okid_real)0.1, OKID_W_RESIDUAL_INPUT_CORRELATED);
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_OUTPUT_ERROR);
    assert_int_equal(c.reason, REFINE_CHOICE_INPUT_CORRELATED);
    assert_non_null(strstr(c.detail, "output 2, input 1, statistic 9"));
    assert_string_equal(refine_choice_reason_name(REFINE_CHOICE_INPUT_CORRELATED), "innovation_input_correlated");
    /* output error white but correlated with the input: it stays (the innovation form has the same
       deterministic part), not run */
    make(&oe, 1, (okid_real)0.1, OKID_W_RESIDUAL_INPUT_CORRELATED);
    assert_false(refine_choice_needs_innovation(&oe.r));
    refine_choose(&oe.r, NULL, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_WHITE);
    make(&oe, 1, (okid_real)0.1, OKID_W_RESIDUAL_NOT_WHITE);
    /* 3.54 combined sigma apart: output error stays */
    make(&inn, (okid_real)1.5, (okid_real)0.1, 0);
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.chosen, OKID_REFINE_OUTPUT_ERROR);
    assert_int_equal(c.reason, REFINE_CHOICE_MODES_DIFFER);
    assert_non_null(strstr(c.detail, "3.54"));
    /* a damping ratio apart (0.02 against 0.0245: 3.18 sigma of sqrt(2) 0.001) is a difference too */
    make(&inn, 1, (okid_real)0.1, 0);
    inn.modes[1].damping_ratio = (okid_real)0.0245;
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_MODES_DIFFER);
    /* modes that do not correspond (a pair against a real pole) or a std missing: output error */
    make(&inn, 1, (okid_real)0.1, 0);
    inn.modes[0].is_pair = 0;
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_MODES_DIFFER);
    make(&inn, 1, (okid_real)0.1, 0);
    inn.std[1].frequency_hz = -1;
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_MODES_DIFFER);
    make(&inn, 1, (okid_real)0.1, 0);
    inn.r.num_modes = 1;
    refine_choose(&oe.r, &inn.r, M, &c);
    assert_int_equal(c.reason, REFINE_CHOICE_MODES_DIFFER);
    assert_string_equal(refine_choice_reason_name(REFINE_CHOICE_STILL_NOT_WHITE), "innovation_not_white");
}

int main(void)
{
    const struct CMUnitTest tests[] = {cmocka_unit_test(test_branches)};
    return cmocka_run_group_tests(tests, NULL, NULL);
}

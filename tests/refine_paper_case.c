/* SPDX-License-Identifier: Apache-2.0 */
/* The refinement tests' simulated case (refine_paper_case.h). */
#include "refine_paper_case.h"

#include <math.h>
#include <stdlib.h>

void paper_record(double dt, size_t count, uint64_t seed, double unmeasured, double noise, okid_real **u,
                  okid_real **y)
{
    const okid_real m2 = REF_PAPER.mass[3];
    const okid_real bc[8] = {REF_PAPER.bc[0], REF_PAPER.bc[1], REF_PAPER.bc[2], REF_PAPER.bc[3], 0, 0, 0, 1 / m2};
    const okid_real d[4] = {REF_PAPER.d[0], REF_PAPER.d[1], 0, 1 / m2};
    okid_real a[16], b[8], work[OKID_ZOH_WORK_REALS(4, 2)], state[4] = {0}, scratch[4];
    assert_int_equal(okid_discretize_zoh(PAPER_STATES, 2, REF_PAPER.ac, bc, (okid_real)dt, a, b, work,
                                         sizeof work / sizeof work[0]), OKID_OK);
    okid_simulator sim;
    assert_int_equal(okid_simulator_init(&sim, PAPER_STATES, 2, PAPER_OUTPUTS, a, b, REF_PAPER.c, d, state, scratch),
                     OKID_OK);
    okid_real *forces = test_white_noise(2, count, seed);
    *u = malloc(sizeof(okid_real) * count);
    *y = malloc(sizeof(okid_real) * PAPER_OUTPUTS * count);
    assert_non_null(*u);
    assert_non_null(*y);
    for (size_t k = 0; k < count; ++k) {
        (*u)[k] = forces[2 * k];
        forces[2 * k + 1] *= (okid_real)unmeasured;
    }
    assert_int_equal(okid_simulate(&sim, count, forces, 2, *y, PAPER_OUTPUTS), OKID_OK);
    free(forces);
    okid_real *e = test_white_noise(PAPER_OUTPUTS, count, seed ^ 0xA5A5u);
    for (int i = 0; i < PAPER_OUTPUTS; ++i) {
        double power = 0;
        for (size_t k = 0; k < count; ++k) power += (double)(*y)[PAPER_OUTPUTS * k + i] * (double)(*y)[PAPER_OUTPUTS * k + i];
        const double std = noise * sqrt(power / (double)count);
        for (size_t k = 0; k < count; ++k) (*y)[PAPER_OUTPUTS * k + i] += (okid_real)(std * e[PAPER_OUTPUTS * k + i]);
    }
    free(e);
}

okid_refine_state paper_identify_and_refine(refine_run *rn, double dt, size_t count, const okid_real *u,
                                            const okid_real *y, okid_refine_model model, int combined)
{
    return paper_identify_and_refine_with(rn, dt, count, u, y, model, combined, PAPER_STATES, 0, 1);
}

okid_refine_state paper_identify_and_refine_with(refine_run *rn, double dt, size_t count, const okid_real *u,
                                                 const okid_real *y, okid_refine_model model, int combined, int order,
                                                 int max_passes, double d_scale)
{
    okid_config cfg;
    okid_config_default(&cfg, 1, PAPER_OUTPUTS);
    cfg.dt = (okid_real)dt;
    cfg.observer_order = 20;
    cfg.order = order;
    cfg.hankel_rows = cfg.hankel_cols = 20;
    if (combined) {
        cfg.realization = OKID_REALIZATION_COMBINED;
    }
    size_t bytes = 0;
    rn->id_ws = test_workspace(&cfg, &bytes);
    assert_int_equal(okid_init(&rn->id, &cfg, rn->id_ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&rn->id, count, u, 1, y, PAPER_OUTPUTS, NULL), OKID_OK);
    assert_int_equal(okid_identify(&rn->id, &rn->start), OKID_OK);
    okid_refine_config rc;
    okid_refine_config_default(&rc);
    rc.refine_model = model;
    if (max_passes > 0) {
        rc.max_passes = max_passes;
    }
    for (int j = 0; j < PAPER_OUTPUTS; ++j) { /* the start's D scaled: a wrong D when d_scale != 1 */
        rn->d_start[j] = rn->start.D.data[j] * (okid_real)d_scale;
    }
    rn->start.D.data = rn->d_start;
    rn->start.D.ld = PAPER_OUTPUTS;
    /* the innovation form took 18-30 passes on these records (a non-convex start, then the tail
       of one-pass-late weights): the default max_passes (100) leaves room for round-off to add a few */
    assert_int_equal(okid_refine_model_workspace_size(model, order, 1, PAPER_OUTPUTS, &bytes), OKID_OK);
    assert_int_equal(bytes, OKID_REFINE_MODEL_WORKSPACE_BYTES(model, order, 1, PAPER_OUTPUTS));
    rn->rf_ws = aligned_alloc(OKID_WORKSPACE_ALIGN, bytes);
    assert_non_null(rn->rf_ws);
    assert_int_equal(okid_refine_init(&rn->rf, &rc, &rn->start, OKID_SENSING_ACCELERATION, rn->rf_ws, bytes, NULL),
                     OKID_OK);
    okid_refine_state st = OKID_REFINE_NEED_PASS;
    while (st == OKID_REFINE_NEED_PASS) {
        assert_int_equal(okid_refine_begin_pass(&rn->rf), OKID_OK);
        for (size_t k = 0; k < count; k += 333) {
            const size_t len = count - k < 333 ? count - k : 333;
            assert_int_equal(okid_refine_push_block(&rn->rf, len, u + k, 1, y + PAPER_OUTPUTS * k, PAPER_OUTPUTS),
                             OKID_OK);
        }
        assert_int_equal(okid_refine_end_pass(&rn->rf, &st), OKID_OK);
    }
    assert_int_equal(okid_refine_get_result(&rn->rf, &rn->out), OKID_OK);
    return st;
}

void refine_run_free(refine_run *rn)
{
    free(rn->id_ws);
    free(rn->rf_ws);
}

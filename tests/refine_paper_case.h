/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The refinement tests' simulated case (test_refine_residuals, test_refine_innovation; test_refine
 * shares refine_run): the paper's system with a measured white force on mass 1, optionally an
 * unmeasured one on mass 2 and white output noise; OKID/ERA and the refinement over the record.
 */
#ifndef OKID_TEST_REFINE_PAPER_CASE_H
#define OKID_TEST_REFINE_PAPER_CASE_H

#include "test_support.h"

enum { PAPER_STATES = 4, PAPER_OUTPUTS = 2 };

typedef struct refine_run {
    okid_identifier id;
    okid_result start;
    void *id_ws, *rf_ws;
    okid_refiner rf;
    okid_refine_result out;
    okid_status init_status; /* test_refine's okid_refine_init() */
    okid_real d_start[PAPER_OUTPUTS]; /* the start's D as refined (paper_identify_and_refine_with) */
} refine_run;

/*
 * A paper record at dt with a measured unit white force on mass 1 (u) and, when unmeasured > 0, an
 * unmeasured white force of that RMS on mass 2 (the "30 %"), then white output noise of
 * noise x each output's RMS. *u (count) and *y (2 x count) are malloc'd.
 */
void paper_record(double dt, size_t count, uint64_t seed, double unmeasured, double noise, okid_real **u,
                  okid_real **y);

/*
 * OKID/ERA (p = h = 20, n = 4; combined realization: an observer gain, when combined) and the
 * refinement of its model fitting model over the record, fed in blocks of 333.
 */
okid_refine_state paper_identify_and_refine(refine_run *rn, double dt, size_t count, const okid_real *u,
                                            const okid_real *y, okid_refine_model model, int combined);

/*
 * The same at another order, with max_passes (0: the default) and the start model's D multiplied
 * by d_scale before the refinement starts (1: as identified).
 */
okid_refine_state paper_identify_and_refine_with(refine_run *rn, double dt, size_t count, const okid_real *u,
                                                 const okid_real *y, okid_refine_model model, int combined, int order,
                                                 int max_passes, double d_scale);

void refine_run_free(refine_run *rn);

#endif

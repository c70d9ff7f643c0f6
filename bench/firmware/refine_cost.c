/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Cost of the prediction-error refinement (okid/refine.h) on the target, for docs/refinement.md:
 * the paper's plant at dt = 0.05 s, 1001 samples, 5 % output noise, OKID/ERA (p = 20,
 * alpha = beta = 20, n = 4) as the start; workspace bytes, instructions of the residual pass and
 * of a Jacobian pass per sample, of each end of pass (the step), passes, total, and the stack
 * used. Run under qemu-system-arm -icount shift=OKID_ICOUNT_SHIFT,align=off (see cost_report.c).
 * OKID_REFINE_COST_MODEL picks the predictor (okid_refine_innovation_cost: the innovation form).
 */
#include <stdint.h>
#include <stdio.h>

#include "board.h"
#include "okid/okid.h"
#include "plant_2dof.h"

#ifndef OKID_ICOUNT_SHIFT
#define OKID_ICOUNT_SHIFT 5
#endif
#ifndef OKID_REFINE_COST_MODEL
#define OKID_REFINE_COST_MODEL OKID_REFINE_OUTPUT_ERROR
#endif

enum { SAMPLES = 1001 };
#define DT ((okid_real)0.05)
#define NOISE ((okid_real)0.05)

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    id_workspace[OKID_WORKSPACE_BYTES(PLANT_INPUTS, PLANT_OUTPUTS, PLANT_OBSERVER_ORDER, PLANT_HANKEL_ROWS,
                                      PLANT_HANKEL_COLS, PLANT_STATES, 32, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    rf_workspace[OKID_REFINE_MODEL_WORKSPACE_BYTES(OKID_REFINE_COST_MODEL, PLANT_STATES, PLANT_INPUTS, PLANT_OUTPUTS)];
static okid_real force[SAMPLES], accelerations[PLANT_OUTPUTS * SAMPLES], noise[SAMPLES];
static okid_identifier identifier;
static okid_refiner refiner;

static uint64_t instructions(uint32_t ticks)
{
    return board_ticks_to_instructions(ticks, OKID_ICOUNT_SHIFT);
}

int main(void)
{
    board_counter_start();
    printf("real %s, refine_model %s\n", OKID_REAL_IS_FLOAT ? "float" : "double",
           okid_refine_model_str(OKID_REFINE_COST_MODEL));
    if (plant_2dof_noisy_record(DT, 7, NOISE, SAMPLES, force, accelerations, noise) != OKID_OK) return 2;
    okid_config cfg;
    plant_2dof_identifier_config(&cfg, DT, 32);
    okid_result start;
    size_t bytes = 0;
    if (okid_workspace_size(&cfg, &bytes) != OKID_OK || okid_init(&identifier, &cfg, id_workspace, bytes, NULL) != OKID_OK ||
        okid_push_block(&identifier, SAMPLES, force, 1, accelerations, PLANT_OUTPUTS, NULL) != OKID_OK ||
        okid_identify(&identifier, &start) != OKID_OK) {
        return 3;
    }
    okid_refine_config rc;
    okid_refine_config_default(&rc);
    rc.refine_model = OKID_REFINE_COST_MODEL;
    rc.max_passes = OKID_REFINE_COST_MODEL == OKID_REFINE_INNOVATION ? 100 : rc.max_passes; /* 18-45 passes */
    if (okid_refine_init(&refiner, &rc, &start, OKID_SENSING_ACCELERATION, rf_workspace, sizeof rf_workspace, NULL) !=
        OKID_OK) {
        return 4;
    }
    printf("refine.workspace_bytes %lu\n", (unsigned long)sizeof rf_workspace);
    printf("refine.refiner_struct_bytes %lu\n", (unsigned long)sizeof refiner);
    const uint32_t *sp = board_stack_pointer();
    board_paint_stack();
    uint64_t total = 0, worst_step = 0;
    okid_refine_state state = OKID_REFINE_NEED_PASS;
    for (int pass = 0; state == OKID_REFINE_NEED_PASS; ++pass) {
        uint32_t t0 = board_counter_ticks();
        if (okid_refine_begin_pass(&refiner) != OKID_OK ||
            okid_refine_push_block(&refiner, SAMPLES, force, 1, accelerations, PLANT_OUTPUTS) != OKID_OK) {
            return 5;
        }
        const uint64_t feed = instructions(board_counter_ticks() - t0);
        t0 = board_counter_ticks();
        if (okid_refine_end_pass(&refiner, &state) != OKID_OK) return 6;
        const uint64_t step = instructions(board_counter_ticks() - t0);
        if (pass <= 1) {
            printf("refine.%s_pass_instructions_per_sample %lu\n", pass == 0 ? "residual" : "jacobian",
                   (unsigned long)(feed / SAMPLES));
        }
        worst_step = step > worst_step ? step : worst_step;
        total += feed + step;
    }
    const unsigned long stack = board_stack_used(sp);
    okid_refine_result out;
    if (okid_refine_get_result(&refiner, &out) != OKID_OK) return 7;
    printf("refine.state %s\n", okid_refine_state_str(out.state));
    printf("refine.passes %d\n", out.passes);
    printf("refine.end_pass_instructions_worst %lu\n", (unsigned long)worst_step);
    printf("refine.total_instructions %lu\n", (unsigned long)total);
    printf("refine.stack_bytes %lu\n", stack);
    for (int i = 0; i < out.num_modes; ++i) {
        printf("refine.mode%d %.6f +- %.6f Hz, damping %.5f +- %.5f\n", i + 1, (double)out.modes[i].frequency_hz,
               (double)out.mode_std[i].frequency_hz, (double)out.modes[i].damping_ratio,
               (double)out.mode_std[i].damping_ratio);
    }
    return out.state == OKID_REFINE_CONVERGED ? 0 : 1;
}

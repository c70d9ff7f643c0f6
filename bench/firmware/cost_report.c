/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Cost of okid on the target, for scripts/footprint.sh: workspace bytes of the paper
 * configuration (r = 1, m = 2, p = 20, n = 4, alpha = beta = 20), instructions per pushed sample
 * (mean and worst) and per okid_identify(), and the stack those calls really used. Run it under
 * QEMU -icount shift=OKID_ICOUNT_SHIFT,align=off: each instruction then advances virtual time by
 * 2^shift ns and the board's counter (a timer, SysTick or minstret: board/) counts them (checked
 * first on a loop of known length). Prints "key value" lines; exit status 0 when every call succeeded.
 */
#include <stdint.h>
#include <stdio.h>

#include "board.h"
#include "okid/okid.h"
#include "plant_2dof.h"

#ifndef OKID_ICOUNT_SHIFT
#define OKID_ICOUNT_SHIFT 5
#endif

enum { SAMPLES = 1001, KNOWN_LOOP = 100000 };
#define DT ((okid_real)0.01)

/* Room for the larger of the two configurations measured (block_rows 1 and the default 32). */
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    workspace[OKID_WORKSPACE_BYTES(PLANT_INPUTS, PLANT_OUTPUTS, PLANT_OBSERVER_ORDER, PLANT_HANKEL_ROWS,
                                   PLANT_HANKEL_COLS, PLANT_STATES, 32, 0)];
static okid_real force[SAMPLES], accelerations[PLANT_OUTPUTS * SAMPLES];
static okid_identifier identifier;

static uint64_t instructions(uint32_t ticks)
{
    return board_ticks_to_instructions(ticks, OKID_ICOUNT_SHIFT);
}

static void make_data(void)
{
    okid_rng rng;
    okid_rng_seed(&rng, 2024);
    if (plant_2dof_record(DT, &rng, SAMPLES, force, accelerations) != OKID_OK) {
        board_exit(2);
    }
}

/* Push every sample, one call each as from an interrupt, then identify; print the costs. */
static int measure(int block_rows)
{
    okid_config cfg;
    plant_2dof_identifier_config(&cfg, DT, block_rows);
    size_t bytes = 0;
    if (okid_workspace_size(&cfg, &bytes) != OKID_OK || okid_init(&identifier, &cfg, workspace, bytes, NULL) != OKID_OK) {
        return 0;
    }
    uint64_t push_total = 0, push_worst = 0;
    const uint32_t *sp = board_stack_pointer();
    board_paint_stack();
    for (int k = 0; k < SAMPLES; ++k) {
        const uint32_t start = board_counter_ticks();
        const okid_status st = okid_push(&identifier, &force[k], &accelerations[PLANT_OUTPUTS * k]);
        const uint64_t cost = instructions(board_counter_ticks() - start);
        if (st != OKID_OK) {
            return 0;
        }
        push_total += cost;
        push_worst = cost > push_worst ? cost : push_worst;
    }
    const unsigned long push_stack = board_stack_used(sp);
    okid_result result;
    board_paint_stack();
    const uint32_t start = board_counter_ticks();
    const okid_status st = okid_identify(&identifier, &result);
    const uint64_t identify_cost = instructions(board_counter_ticks() - start);
    const unsigned long identify_stack = board_stack_used(sp);
    printf("block_rows_%d.workspace_bytes %lu\n", block_rows, (unsigned long)bytes);
    printf("block_rows_%d.push_instructions_mean %lu\n", block_rows, (unsigned long)(push_total / SAMPLES));
    printf("block_rows_%d.push_instructions_worst %lu\n", block_rows, (unsigned long)push_worst);
    printf("block_rows_%d.identify_instructions %lu\n", block_rows, (unsigned long)identify_cost);
    printf("block_rows_%d.push_stack_bytes %lu\n", block_rows, push_stack);
    printf("block_rows_%d.identify_stack_bytes %lu\n", block_rows, identify_stack);
    if (st == OKID_OK) {
        printf("block_rows_%d.regressor_rank %d of %d\n", block_rows, result.regressor_rank, result.regressor_columns);
        printf("block_rows_%d.modes_hz %.6f %.6f\n", block_rows, (double)result.modes[0].frequency_hz,
               (double)result.modes[1].frequency_hz);
    }
    return st == OKID_OK;
}

int main(void)
{
    board_counter_start();
    /* The counter against a loop of known length: the two must agree to a few instructions. */
    const uint32_t start = board_counter_ticks();
    board_known_loop(KNOWN_LOOP);
    const uint64_t loop = instructions(board_counter_ticks() - start);
    printf("real %s\n", OKID_REAL_IS_FLOAT ? "float" : "double");
    printf("calibration.loop_instructions_expected %lu\n", (unsigned long)(2 * KNOWN_LOOP));
    printf("calibration.loop_instructions_measured %lu\n", (unsigned long)loop);
    /* a few for the counter reads themselves (some 20 where SysTick is extended to 32 bits); the
       counters tick every 1 to 3 instructions */
    if (loop + 4 < 2 * KNOWN_LOOP || loop > 2 * KNOWN_LOOP + 32) {
        printf("the instruction counter is off: was QEMU run with -icount shift=%d?\n", OKID_ICOUNT_SHIFT);
        return 3;
    }
    make_data();
    const int ok = measure(1) && measure(32);
    return ok ? 0 : 1;
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Cost of the automatic mode selection on the target, for docs/firmware.md: the paper's plant at
 * dt = 0.05 s (the Hankel's 20 rows then span 1 s, half the slowest period: at dt = 0.01 s they
 * span 0.2 s, too short for any pole to pass EMAC), 1001 samples, 2 % output noise, identified
 * with the paper configuration (p = 20,
 * alpha = beta = 20, n = 4); then the stabilization table of the even orders 2..20 (the largest
 * the Hankel's 20 input columns allow) from its one SVD (okid_stabilization_compute) and the
 * physical modes of that table (okid_select_modes, default criteria). Prints the workspace bytes
 * of each, the instructions of each call and the stack they used, and the modes selected. Run
 * under qemu-system-arm -icount shift=OKID_ICOUNT_SHIFT,align=off (see cost_report.c).
 */
#include <stdint.h>
#include <stdio.h>

#include "board.h"
#include "okid/okid.h"
#include "plant_2dof.h"

#ifndef OKID_ICOUNT_SHIFT
#define OKID_ICOUNT_SHIFT 5
#endif

enum { SAMPLES = 1001, MAX_ORDER = 20, STEP = 2 };
#define DT ((okid_real)0.05)
#define NOISE ((okid_real)0.02)

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    id_workspace[OKID_WORKSPACE_BYTES(PLANT_INPUTS, PLANT_OUTPUTS, PLANT_OBSERVER_ORDER, PLANT_HANKEL_ROWS,
                                      PLANT_HANKEL_COLS, PLANT_STATES, 32, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    table_workspace[OKID_STABILIZATION_WORKSPACE_BYTES(PLANT_INPUTS, PLANT_OUTPUTS, PLANT_HANKEL_ROWS,
                                                       PLANT_HANKEL_COLS, MAX_ORDER, STEP, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char selection_workspace[OKID_MODE_SELECTION_WORKSPACE_BYTES(MAX_ORDER, STEP)];
static okid_real force[SAMPLES], accelerations[PLANT_OUTPUTS * SAMPLES], noise[SAMPLES];
static okid_identifier identifier;

static uint64_t instructions(uint32_t ticks)
{
    return board_ticks_to_instructions(ticks, OKID_ICOUNT_SHIFT);
}

int main(void)
{
    board_counter_start();
    printf("real %s\n", OKID_REAL_IS_FLOAT ? "float" : "double");
    if (plant_2dof_noisy_record(DT, 7, NOISE, SAMPLES, force, accelerations, noise) != OKID_OK) return 2;
    okid_config cfg;
    plant_2dof_identifier_config(&cfg, DT, 32);
    okid_result result;
    size_t bytes = 0;
    if (okid_workspace_size(&cfg, &bytes) != OKID_OK || okid_init(&identifier, &cfg, id_workspace, bytes, NULL) != OKID_OK ||
        okid_push_block(&identifier, SAMPLES, force, 1, accelerations, PLANT_OUTPUTS, NULL) != OKID_OK ||
        okid_identify(&identifier, &result) != OKID_OK) {
        return 3;
    }
    size_t table_bytes = 0, selection_bytes = 0;
    if (okid_stabilization_workspace_size(&identifier, MAX_ORDER, STEP, &table_bytes) != OKID_OK ||
        okid_mode_selection_workspace_size(MAX_ORDER, STEP, &selection_bytes) != OKID_OK ||
        table_bytes > sizeof table_workspace || selection_bytes > sizeof selection_workspace) {
        return 4;
    }
    const uint32_t *sp = board_stack_pointer();
    okid_stabilization table;
    board_paint_stack();
    uint32_t start = board_counter_ticks();
    okid_status st = okid_stabilization_compute(&identifier, MAX_ORDER, STEP, NULL, table_workspace, table_bytes, &table);
    const uint64_t table_cost = instructions(board_counter_ticks() - start);
    const unsigned long table_stack = board_stack_used(sp);
    if (st != OKID_OK) return 5;
    okid_mode_selection selection;
    board_paint_stack();
    start = board_counter_ticks();
    st = okid_select_modes(&table, PLANT_OUTPUTS, NULL, selection_workspace, selection_bytes, &selection, NULL);
    const uint64_t select_cost = instructions(board_counter_ticks() - start);
    const unsigned long select_stack = board_stack_used(sp);
    if (st != OKID_OK) return 6;
    printf("stabilization.orders %d (2..%d step %d, rank limit %d)\n", table.num_orders, MAX_ORDER, STEP, table.rank_limit);
    printf("stabilization.workspace_bytes %lu\n", (unsigned long)table_bytes);
    printf("stabilization.instructions %lu\n", (unsigned long)table_cost);
    printf("stabilization.stack_bytes %lu\n", table_stack);
    printf("selection.workspace_bytes %lu\n", (unsigned long)selection_bytes);
    printf("selection.instructions %lu\n", (unsigned long)select_cost);
    printf("selection.stack_bytes %lu\n", select_stack);
    printf("selection.candidates %d clusters %d min_orders %d\n", selection.num_candidates, selection.num_clusters,
           selection.min_orders);
    for (int k = 0; k < selection.num_modes; ++k) {
        const okid_selected_mode *s = &selection.modes[k];
        printf("selection.mode %d %.4f Hz damping %.4f orders %d\n", k + 1, (double)s->mode.frequency_hz,
               (double)s->mode.damping_ratio, s->num_orders);
    }
    return 0;
}

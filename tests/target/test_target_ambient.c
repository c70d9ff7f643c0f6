/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Output-only identification on the target (okid/ambient.h, docs/ambient.md): the paper's plant
 * driven by unmeasured white forces on both masses, its two accelerations with 5 % sensor noise,
 * simulated here sample by sample and pushed as they come (no record in memory), m = 2, L = 20,
 * order 4; then the stabilization table of orders 2..20 and the selection of its physical modes.
 * The modes against the paper's within tests/test_ambient.c's statistical bounds (4 times the rms
 * measured over 30 seeds; the float sums add about sqrt(N) u = 1e-5 relative, far below them).
 * Printed for docs/firmware.md (figures valid under QEMU -icount, as scripts/footprint.sh runs):
 * workspace bytes, instructions per push (worst) and per identify, table and selection, stack.
 */
#include <math.h>
#include <stdint.h>
#include <stdio.h>

#include "board.h"
#include "okid/okid.h"
#include "reference/reference_data.h"
#include "target_check.h"

#ifndef OKID_ICOUNT_SHIFT
#define OKID_ICOUNT_SHIFT 5
#endif

enum { SAMPLES = 40000, L = 20, ORDER = 4, TABLE_ORDER = 20, CHUNK = 500 };
#define DT 0.05
#define TWO_PI 6.283185307179586

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char workspace[OKID_AMBIENT_WORKSPACE_BYTES(2, 0, L, ORDER, 0)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    table_workspace[OKID_AMBIENT_STABILIZATION_WORKSPACE_BYTES(2, 0, L, TABLE_ORDER, 2)];
static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char selection_workspace[OKID_MODE_SELECTION_WORKSPACE_BYTES(TABLE_ORDER, 2)];
static okid_ambient amb;

static uint64_t instructions(uint32_t ticks)
{
    return board_ticks_to_instructions(ticks, OKID_ICOUNT_SHIFT);
}

/* The paper's plant, a force on each mass, exact ZOH at DT. */
static int plant(okid_real *a, okid_real *b, okid_real *c, okid_real *d)
{
    static const okid_real b2[4] = {1, 0, 0, 1};
    const okid_mechanical_model mm = {2, 2, 2, PAPER_MASS, PAPER_DAMPING, PAPER_STIFFNESS, b2, PAPER_CA, NULL, NULL};
    static okid_real ac[16], bc[8], work[OKID_STATE_SPACE_WORK_REALS(2, 2)], zw[OKID_ZOH_WORK_REALS(4, 2)];
    return okid_model_state_space(&mm, ac, bc, c, d, work, sizeof work / sizeof work[0]) == OKID_OK &&
           okid_discretize_zoh(4, 2, ac, bc, (okid_real)DT, a, b, zw, sizeof zw / sizeof zw[0]) == OKID_OK;
}

int main(void)
{
    board_counter_start();
    static okid_real a[16], b[8], c[8], d[4];
    CHECK(plant(a, b, c, d));
    okid_ambient_config cfg;
    CHECK(okid_ambient_config_default(&cfg, 2) == OKID_OK);
    cfg.dt = (okid_real)DT;
    cfg.hankel_rows = L;
    cfg.order = ORDER;
    size_t bytes = 0;
    CHECK(okid_ambient_workspace_size(&cfg, &bytes) == OKID_OK && bytes == sizeof workspace);
    CHECK(okid_ambient_init(&amb, &cfg, workspace, sizeof workspace, NULL) == OKID_OK);
    /* the forces for a chunk, then the sensor noise of each output (5 % of the RMS of a first chunk) */
    okid_rng rng;
    okid_rng_seed(&rng, 11);
    static okid_real u[2 * CHUNK], e[2 * CHUNK], y[2 * CHUNK];
    okid_real x[4] = {0, 0, 0, 0}, noise[2] = {0, 0};
    uint64_t worst_push = 0, push_total = 0;
    for (int first = 0; first < SAMPLES; first += CHUNK) {
        CHECK(okid_rng_normal(&rng, 1, 2 * CHUNK, u, 1) == OKID_OK);
        CHECK(okid_rng_normal(&rng, 1, 2 * CHUNK, e, 1) == OKID_OK);
        for (int k = 0; k < CHUNK; ++k) {
            okid_real xn[4];
            for (int i = 0; i < 2; ++i) {
                y[2 * k + i] = d[i] * u[2 * k] + d[2 + i] * u[2 * k + 1];
                for (int j = 0; j < 4; ++j) y[2 * k + i] += c[2 * j + i] * x[j];
            }
            for (int i = 0; i < 4; ++i) {
                xn[i] = b[i] * u[2 * k] + b[4 + i] * u[2 * k + 1];
                for (int j = 0; j < 4; ++j) xn[i] += a[4 * j + i] * x[j];
            }
            for (int i = 0; i < 4; ++i) x[i] = xn[i];
        }
        if (first == 0) {
            for (int i = 0; i < 2; ++i) {
                double power = 0;
                for (int k = 0; k < CHUNK; ++k) power += (double)y[2 * k + i] * (double)y[2 * k + i];
                noise[i] = (okid_real)(0.05 * sqrt(power / CHUNK));
            }
        }
        for (int k = 0; k < CHUNK; ++k) {
            for (int i = 0; i < 2; ++i) y[2 * k + i] += noise[i] * e[2 * k + i];
            const uint32_t t0 = board_counter_ticks();
            const okid_status st = okid_ambient_push(&amb, &y[2 * k]);
            const uint64_t cost = instructions(board_counter_ticks() - t0);
            CHECK(st == OKID_OK);
            push_total += cost;
            worst_push = cost > worst_push ? cost : worst_push;
        }
    }
    const uint32_t *sp = board_stack_pointer();
    board_paint_stack();
    okid_ambient_result res;
    uint32_t t0 = board_counter_ticks();
    CHECK(okid_ambient_identify(&amb, &res) == OKID_OK);
    const uint64_t identify_cost = instructions(board_counter_ticks() - t0);
    const unsigned long identify_stack = board_stack_used(sp);
    const double T = SAMPLES * DT;
    int pairs = 0;
    for (int i = 0; i < res.num_modes; ++i) {
        if (!res.modes[i].is_pair || pairs >= 2) continue;
        const double f = PAPER_FREQ_HZ[pairs], z = PAPER_DAMPING_RATIO[pairs], omega = TWO_PI * f;
        CHECK_CLOSE(res.modes[i].frequency_hz, f, 4 * 3.7 * sqrt(z / (omega * T)), f);
        CHECK_CLOSE(res.modes[i].damping_ratio, z, 4 * 4.2 / sqrt(z * omega * T), z);
        printf("ambient.mode%d %.5f Hz, damping %.4f\n", pairs + 1, (double)res.modes[i].frequency_hz,
               (double)res.modes[i].damping_ratio);
        ++pairs;
    }
    CHECK(pairs == 2);
    /* the table of orders 2..20 and its physical modes (default criteria: the 16 % mode only) */
    okid_stabilization table;
    okid_mode_selection selection;
    board_paint_stack();
    t0 = board_counter_ticks();
    CHECK(okid_ambient_stabilization_compute(&amb, TABLE_ORDER, 2, NULL, table_workspace, sizeof table_workspace,
                                             &table) == OKID_OK);
    const uint64_t table_cost = instructions(board_counter_ticks() - t0);
    t0 = board_counter_ticks();
    CHECK(okid_select_modes(&table, 2, NULL, selection_workspace, sizeof selection_workspace, &selection, NULL) ==
          OKID_OK);
    const uint64_t selection_cost = instructions(board_counter_ticks() - t0);
    const unsigned long table_stack = board_stack_used(sp);
    CHECK(table.num_orders == TABLE_ORDER / 2);
    CHECK(selection.num_modes == 1);
    if (selection.num_modes >= 1) {
        const double f = PAPER_FREQ_HZ[0], z = PAPER_DAMPING_RATIO[0], omega = TWO_PI * f;
        CHECK_CLOSE(selection.modes[0].mode.frequency_hz, f, 4 * 3.7 * sqrt(z / (omega * T)), f);
    }
    printf("ambient.workspace_bytes %lu\n", (unsigned long)sizeof workspace);
    printf("ambient.struct_bytes %lu\n", (unsigned long)sizeof amb);
    printf("ambient.push_instructions_worst %lu\n", (unsigned long)worst_push);
    printf("ambient.push_instructions_mean %lu\n", (unsigned long)(push_total / SAMPLES));
    printf("ambient.identify_instructions %lu\n", (unsigned long)identify_cost);
    printf("ambient.identify_stack_bytes %lu\n", identify_stack);
    printf("ambient.table_workspace_bytes %lu\n", (unsigned long)sizeof table_workspace);
    printf("ambient.selection_workspace_bytes %lu\n", (unsigned long)sizeof selection_workspace);
    printf("ambient.table_instructions %lu\n", (unsigned long)table_cost);
    printf("ambient.selection_instructions %lu\n", (unsigned long)selection_cost);
    printf("ambient.table_selection_stack_bytes %lu\n", table_stack);
    return target_summary("test_target_ambient");
}

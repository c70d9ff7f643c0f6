/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Instruction counting under QEMU on AN505 (Cortex-M33) and AN547 (Cortex-M55), whose CMSDK
 * timers sit behind the SSE's protection controllers: the core's own SysTick instead, clocked by
 * the processor clock (BOARD_COUNTER_HZ: 20 MHz on AN505, 32 MHz on AN547). With -icount shift=S
 * QEMU advances virtual time by exactly 2^S ns per instruction, so ticks measure instructions
 * deterministically. SysTick has 24 bits: the counter polls its COUNTFLAG and extends it to 32
 * bits, so two reads may be at most 2^24 ticks apart (16 M instructions at S = 5 on AN547,
 * 26 M on AN505; okid_identify takes about 4 M). No interrupt: nothing runs inside a measurement.
 */
#include "board.h"

#ifndef BOARD_COUNTER_HZ
#error "BOARD_COUNTER_HZ: the counter clock of the board (board/mps2/CMakeLists.txt)"
#endif

#define SYST_CSR (*(volatile uint32_t *)0xE000E010u)
#define SYST_RVR (*(volatile uint32_t *)0xE000E014u)
#define SYST_CVR (*(volatile uint32_t *)0xE000E018u)

enum { SYST_ENABLE = 1u << 0, SYST_PROCESSOR_CLOCK = 1u << 2, SYST_COUNTFLAG = 1u << 16, SYST_MAX = 0xFFFFFFu };

static uint32_t wraps; /* 2^24-tick periods seen so far */

void board_counter_start(void)
{
    SYST_CSR = 0;
    SYST_RVR = SYST_MAX;
    SYST_CVR = 0; /* any write clears the counter and COUNTFLAG */
    wraps = 0;
    SYST_CSR = SYST_ENABLE | SYST_PROCESSOR_CLOCK;
}

uint32_t board_counter_ticks(void)
{
    uint32_t value = SYST_CVR;
    /* Reading CSR clears COUNTFLAG: a wrap since the last read, maybe just after the read above. */
    if (SYST_CSR & SYST_COUNTFLAG) {
        ++wraps;
        value = SYST_CVR;
    }
    return (wraps << 24) + (SYST_MAX - value);
}

uint64_t board_ticks_to_instructions(uint32_t ticks, int icount_shift)
{
    return ((uint64_t)ticks * 1000000000u / BOARD_COUNTER_HZ) >> icount_shift;
}

void board_known_loop(uint32_t iterations)
{
    /* Two instructions per iteration (subs, bne): 2 * iterations in all. */
    __asm volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(iterations) : : "cc");
}

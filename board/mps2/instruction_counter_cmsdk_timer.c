/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Instruction counting under QEMU on AN386 and AN500: the boards' CMSDK APB timer 0 (0x40000000)
 * counts down at SYSCLK = 25 MHz of virtual time. With -icount shift=S, QEMU advances virtual time by exactly
 * 2^S ns per executed instruction, so timer ticks measure instructions deterministically
 * (DWT->CYCCNT is not emulated). The footprint report checks this on a loop of known length.
 */
#include "board.h"

#define TIMER0_CTRL (*(volatile uint32_t *)0x40000000u)
#define TIMER0_VALUE (*(volatile uint32_t *)0x40000004u)
#define TIMER0_RELOAD (*(volatile uint32_t *)0x40000008u)

enum { SYSCLK_PERIOD_NS = 40 }; /* 25 MHz */

void board_counter_start(void)
{
    TIMER0_CTRL = 0;
    TIMER0_RELOAD = 0xFFFFFFFFu;
    TIMER0_VALUE = 0xFFFFFFFFu;
    TIMER0_CTRL = 1u; /* enable, no interrupt */
}

uint32_t board_counter_ticks(void)
{
    return 0xFFFFFFFFu - TIMER0_VALUE;
}

uint64_t board_ticks_to_instructions(uint32_t ticks, int icount_shift)
{
    return ((uint64_t)ticks * SYSCLK_PERIOD_NS) >> icount_shift;
}

void board_known_loop(uint32_t iterations)
{
    /* Two instructions per iteration (subs, bne): 2 * iterations in all. */
    __asm volatile("1: subs %0, %0, #1\n\tbne 1b" : "+r"(iterations) : : "cc");
}

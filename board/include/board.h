/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Services of the board support to tests, benchmarks and the example, the same on every board:
 * board/mps2 (QEMU mps2-an386 Cortex-M4F, mps2-an500 Cortex-M7, mps2-an505 Cortex-M33,
 * mps3-an547 Cortex-M55) and board/riscv-virt (QEMU virt, rv32imafc).
 */
#ifndef OKID_BOARD_H
#define OKID_BOARD_H

#include <stdint.h>

/* End the program with this exit status at once (semihosting), flushing nothing. */
_Noreturn void board_exit(int status);

/* Start the free-running counter. */
void board_counter_start(void);

/* Counter ticks since board_counter_start(); differences are valid across one wrap (2^32 ticks). */
uint32_t board_counter_ticks(void);

/* Instructions executed during ticks when QEMU runs with -icount shift=icount_shift (2^shift ns each). */
uint64_t board_ticks_to_instructions(uint32_t ticks, int icount_shift);

/* A loop of exactly 2 * iterations instructions (iterations >= 1), to check the counter. */
void board_known_loop(uint32_t iterations);

/* Lowest address of the main stack (the linker script's), for stack painting. */
extern uint32_t __stack_limit__[];

/* The stack pointer of the caller. */
static inline uint32_t *board_stack_pointer(void)
{
    uint32_t *sp;
#if defined(__riscv)
    __asm volatile("mv %0, sp" : "=r"(sp));
#else
    __asm volatile("mov %0, sp" : "=r"(sp));
#endif
    return sp;
}

/* Stack painting, to measure what calls really use: board_paint_stack() fills the free stack below
   the caller's frame with a pattern, board_stack_used(sp) finds how far down the calls since then
   overwrote it (bytes below sp, the caller's board_stack_pointer() before painting). */
enum { BOARD_STACK_PAINT = 0x5AFE57ACu, BOARD_STACK_MARGIN_WORDS = 16 };

static __attribute__((noinline, unused)) void board_paint_stack(void)
{
    for (uint32_t *w = __stack_limit__; w < board_stack_pointer() - BOARD_STACK_MARGIN_WORDS; ++w) {
        *w = BOARD_STACK_PAINT;
    }
}

static inline unsigned long board_stack_used(const uint32_t *sp_at_call)
{
    const uint32_t *w = __stack_limit__;
    while (w < sp_at_call && *w == BOARD_STACK_PAINT) {
        ++w;
    }
    return (unsigned long)((const char *)sp_at_call - (const char *)w);
}

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Board services on QEMU's RISC-V virt machine: exit over semihosting (picolibc's libsemihost)
 * and instruction counting. In machine mode minstret is readable; under -icount shift=S QEMU
 * derives it from its instruction counter in ns of virtual time (2^S per instruction, checked by
 * the cost report on a loop of known length), so ticks >> S are instructions.
 */
#include <unistd.h>

#include "board.h"

_Noreturn void board_exit(int status)
{
    _exit(status);
}

static uint32_t counter_origin;

static uint32_t minstret(void)
{
    uint32_t value;
    __asm volatile("csrr %0, minstret" : "=r"(value));
    return value;
}

void board_counter_start(void)
{
    counter_origin = minstret();
}

uint32_t board_counter_ticks(void)
{
    return minstret() - counter_origin;
}

uint64_t board_ticks_to_instructions(uint32_t ticks, int icount_shift)
{
    return (uint64_t)ticks >> icount_shift;
}

void board_known_loop(uint32_t iterations)
{
    /* Two instructions per iteration (addi, bnez): 2 * iterations in all. */
    __asm volatile("1: addi %0, %0, -1\n\tbnez %0, 1b" : "+r"(iterations));
}

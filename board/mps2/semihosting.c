/* SPDX-License-Identifier: Apache-2.0 */
/* Semihosting calls the board support makes itself (newlib's rdimon does stdio and exit()). */
#include "board.h"

enum { SYS_EXIT_EXTENDED = 0x20, ADP_STOPPED_APPLICATION_EXIT = 0x20026 };

static int semihost_call(int op, void *arg)
{
    register int r0 __asm("r0") = op;
    register void *r1 __asm("r1") = arg;
    __asm volatile("bkpt 0xAB" : "+r"(r0) : "r"(r1) : "memory");
    return r0;
}

_Noreturn void board_exit(int status)
{
    /* The extended call carries the status on 32-bit ARM too (plain SYS_EXIT only says ok or not). */
    uint32_t block[2] = {ADP_STOPPED_APPLICATION_EXIT, (uint32_t)status};
    for (;;) {
        (void)semihost_call(SYS_EXIT_EXTENDED, block);
    }
}

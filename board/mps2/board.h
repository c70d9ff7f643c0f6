/* Services of the MPS2 board support (QEMU mps2-an386 / mps2-an500) to tests and the example. */
#ifndef OKID_BOARD_H
#define OKID_BOARD_H

#include <stdint.h>

/* End the program with this exit status at once (semihosting SYS_EXIT_EXTENDED), flushing nothing. */
_Noreturn void board_exit(int status);

/* Start the free-running counter (CMSDK timer 0 at 25 MHz of virtual time). */
void board_counter_start(void);

/* Counter ticks since board_counter_start(); differences are valid across one wrap (2^32 ticks). */
uint32_t board_counter_ticks(void);

/* Instructions executed during ticks when QEMU runs with -icount shift=icount_shift (2^shift ns each). */
uint64_t board_ticks_to_instructions(uint32_t ticks, int icount_shift);

/* A loop of exactly 2 * iterations instructions (iterations >= 1), to check the counter. */
void board_known_loop(uint32_t iterations);

#endif

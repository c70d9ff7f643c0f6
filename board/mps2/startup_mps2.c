/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Start-up code of the MPS2/MPS3 boards (AN386 Cortex-M4F, AN500 Cortex-M7, AN505 Cortex-M33,
 * AN547 Cortex-M55; the last two start in the Secure state and stay there) under QEMU: vector table,
 * FPU (and the M55's MVE) enable, .data copy and .bss clear, newlib's semihosting and constructors, then main().
 * main()'s return value leaves through exit() and newlib's rdimon _exit, which QEMU turns into
 * its own exit status (semihosting SYS_EXIT): the exit code is the test verdict.
 */
#include <stdint.h>
#include <stdlib.h>

#include "board.h"

extern uint32_t __data_load__[], __data_start__[], __data_end__[], __bss_start__[], __bss_end__[];
extern uint32_t __stack_top__[];

int main(void);
void initialise_monitor_handles(void); /* newlib rdimon: opens stdin/stdout/stderr over semihosting */
void __libc_init_array(void);          /* newlib: runs the constructors of .init_array */
void Reset_Handler(void);
void Fault_Handler(void);
void _init(void);
void _fini(void);

/* __libc_init_array() calls these (crti/crtn, which -nostartfiles leaves out): nothing to do. */
void _init(void) {}
void _fini(void) {}

#define SCB_CPACR (*(volatile uint32_t *)0xE000ED88u)
#define SCB_ICSR (*(volatile uint32_t *)0xE000ED04u)

/*
 * Runs before .data and .bss exist and before the FPU is on, so it touches no global and no
 * floating-point register; the loops stay loops (no memcpy/memset the compiler could pick).
 */
__attribute__((optimize("no-tree-loop-distribute-patterns"))) void Reset_Handler(void)
{
    /* CP10 and CP11 (the FPU) full access: any floating-point instruction faults until this. */
    SCB_CPACR |= (0xFu << 20);
    __asm volatile("dsb\n\tisb" ::: "memory");

    const uint32_t *src = __data_load__;
    for (uint32_t *dst = __data_start__; dst < __data_end__;) {
        *dst++ = *src++;
    }
    for (uint32_t *dst = __bss_start__; dst < __bss_end__;) {
        *dst++ = 0;
    }
    initialise_monitor_handles();
    __libc_init_array();
    exit(main());
}

/* Any fault or unexpected interrupt ends the run with 128 + the exception number (never hangs). */
void Fault_Handler(void)
{
    board_exit(128 + (int)(SCB_ICSR & 0x1FFu));
}

typedef void (*vector)(void);

/* Initial stack pointer, reset, then the 14 system exceptions and the 32 interrupts of the boards. */
__attribute__((section(".vectors"), used)) static const vector vector_table[16 + 32] = {
    (vector)(uintptr_t)__stack_top__, Reset_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, 0, 0, 0, 0, Fault_Handler, Fault_Handler, 0, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler,
    Fault_Handler, Fault_Handler, Fault_Handler, Fault_Handler};

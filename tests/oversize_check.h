/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Randomised configurations whose dimensions are each in range but whose workspace may exceed the
 * address space (4 GiB with a 32-bit size_t, the firmware targets'). Shared by the host test
 * (test_workspace_overflow, cmocka) and the target test (tests/target/test_target_sizes, QEMU).
 */
#ifndef OKID_OVERSIZE_CHECK_H
#define OKID_OVERSIZE_CHECK_H

#include <stddef.h>
#include <stdint.h>

#include "okid/okid.h"

typedef struct oversize_tally {
    int tried;     /* configurations generated */
    int oversized; /* whose independent lower bound exceeds SIZE_MAX */
    int refused;   /* of those, refused with OKID_E_BAD_SIZE by okid_workspace_size and okid_init */
    int fitted;    /* accepted and small enough to be initialised and fed in the buffer */
    int failures;  /* violations (each reported through fail) */
} oversize_tally;

/* Called once per violation with what went wrong and the configuration. */
typedef void (*oversize_fail_fn)(const char *what, const okid_config *cfg);

/*
 * A lower bound of the workspace of cfg, computed apart from the library in 64 bits: R (w x w), the
 * pending block (block_rows x w), the sample ring and the Markov parameters, in okid_real.
 */
uint64_t oversize_lower_bound(const okid_config *cfg);

/*
 * Check one configuration: refused with OKID_E_BAD_SIZE when its lower bound exceeds SIZE_MAX (and
 * OKID_WORKSPACE_BYTES_OPTIONS saturated at SIZE_MAX), else a size that is at least the lower
 * bound and equal to the macro; okid_init never writes outside [buf, buf + capacity), and with a
 * workspace that fits, init and 3 block_rows + p pushes leave the bytes after it untouched.
 * buf holds capacity + OVERSIZE_GUARD bytes, aligned to OKID_WORKSPACE_ALIGN.
 */
void oversize_check_config(const okid_config *cfg, unsigned char *buf, size_t capacity, oversize_tally *tally,
                           oversize_fail_fn fail);

/* count seeded random configurations (half small, half large) through oversize_check_config. */
void oversize_run(uint64_t seed, int count, unsigned char *buf, size_t capacity, oversize_tally *tally,
                  oversize_fail_fn fail);

#define OVERSIZE_GUARD 256u

#endif

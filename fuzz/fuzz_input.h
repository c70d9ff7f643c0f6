/* SPDX-License-Identifier: Apache-2.0 */
/* Reading a fuzzer's byte stream as numbers and choices (zeros once it runs out). */
#ifndef OKID_FUZZ_INPUT_H
#define OKID_FUZZ_INPUT_H

#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <string.h>

typedef struct fuzz_input {
    const uint8_t *data;
    size_t size, pos;
} fuzz_input;

static inline uint8_t fuzz_byte(fuzz_input *in)
{
    return in->pos < in->size ? in->data[in->pos++] : 0;
}

static inline int fuzz_int(fuzz_input *in, int lo, int hi)
{
    const unsigned span = (unsigned)(hi - lo) + 1u;
    const unsigned v = (unsigned)fuzz_byte(in) | ((unsigned)fuzz_byte(in) << 8);
    return lo + (int)(v % span);
}

/* Mostly ordinary values, sometimes the awkward ones: NaN, +-Inf, denormals, 1e+-300, zero. */
static inline double fuzz_real(fuzz_input *in)
{
    static const double specials[] = {(double)NAN, (double)INFINITY, -(double)INFINITY, 4.9e-324, -2.2e-308, 1e300, -1e300, 1e-300, 0.0, -0.0};
    const uint8_t kind = fuzz_byte(in);
    if (kind < 24) {
        return specials[kind % (sizeof specials / sizeof specials[0])];
    }
    if (kind < 40) {
        double d = 0;
        for (size_t i = 0; i < sizeof d; ++i) ((uint8_t *)&d)[i] = fuzz_byte(in);
        return d; /* any bit pattern */
    }
    return ((double)fuzz_int(in, 0, 65535) - 32768.0) / 4096.0;
}

#endif

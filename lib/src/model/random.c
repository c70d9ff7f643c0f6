/* SPDX-License-Identifier: Apache-2.0 */
/* xoshiro256** seeded by splitmix64 (Blackman and Vigna), normal deviates by Box-Muller. */
#include "okid/random.h"

#include "numerics/real_math.h"

static uint64_t splitmix64(uint64_t *x)
{
    uint64_t z = (*x += UINT64_C(0x9E3779B97F4A7C15));
    z = (z ^ (z >> 30)) * UINT64_C(0xBF58476D1CE4E5B9);
    z = (z ^ (z >> 27)) * UINT64_C(0x94D049BB133111EB);
    return z ^ (z >> 31);
}

static uint64_t rotl(uint64_t x, int k)
{
    return (x << k) | (x >> (64 - k));
}

static uint64_t next(okid_rng *rng)
{
    uint64_t *s = rng->s;
    const uint64_t result = rotl(s[1] * 5u, 7) * 9u;
    const uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

okid_status okid_rng_seed(okid_rng *rng, uint64_t seed)
{
    if (rng == NULL) {
        return OKID_E_NULL_POINTER;
    }
    uint64_t x = seed;
    for (int i = 0; i < 4; ++i) {
        rng->s[i] = splitmix64(&x);
    }
    return OKID_OK;
}

okid_real okid_rng_uniform(okid_rng *rng)
{
    if (rng == NULL) {
        return 0;
    }
#if OKID_REAL_IS_FLOAT
    return (okid_real)(next(rng) >> 40) * 0x1.0p-24f;
#else
    return (okid_real)(next(rng) >> 11) * 0x1.0p-53;
#endif
}

okid_status okid_rng_normal(okid_rng *rng, okid_real sigma, size_t count, okid_real *out, size_t stride)
{
    if (rng == NULL || (out == NULL && count > 0)) {
        return OKID_E_NULL_POINTER;
    }
    if (stride == 0) {
        return OKID_E_BAD_SIZE;
    }
    if (!okid_is_finite(sigma) || sigma < 0) {
        return OKID_E_BAD_PARAMETER;
    }
    for (size_t k = 0; k < count; k += 2) {
        const okid_real u1 = 1 - okid_rng_uniform(rng); /* in (0, 1]: log is finite */
        const okid_real u2 = okid_rng_uniform(rng);
        const okid_real radius = okid_sqrt(-2 * okid_log(u1));
        const okid_real angle = 2 * OKID_PI * u2;
        out[k * stride] = sigma * radius * okid_cos(angle);
        if (k + 1 < count) {
            out[(k + 1) * stride] = sigma * radius * okid_sin(angle);
        }
    }
    return OKID_OK;
}

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file random.h
 * \brief A small deterministic random generator (xoshiro256**), state owned by the caller, for
 *        white-noise excitation and measurement noise in simulations and tests.
 */
#ifndef OKID_RANDOM_H
#define OKID_RANDOM_H

#include <stddef.h>
#include <stdint.h>

#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct okid_rng {
    uint64_t s[4];
} okid_rng;

/** Seed the generator (any seed, 0 included). \return OKID_OK, OKID_E_NULL_POINTER */
okid_status okid_rng_seed(okid_rng *rng, uint64_t seed);

/**
 * Fill count values spaced by stride with independent normal deviates of mean 0 and standard
 * deviation sigma (Box-Muller). \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (stride 0),
 * OKID_E_BAD_PARAMETER (sigma < 0 or not finite)
 */
okid_status okid_rng_normal(okid_rng *rng, okid_real sigma, size_t count, okid_real *out, size_t stride);

/** A uniform deviate in [0, 1) with 53 (double) or 24 (float) random bits; 0 when rng is NULL. */
okid_real okid_rng_uniform(okid_rng *rng);

#ifdef __cplusplus
}
#endif

#endif

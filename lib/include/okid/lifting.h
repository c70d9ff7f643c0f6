/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file lifting.h
 * \brief Exact decimation by lifting: K consecutive samples become one sample of a system with
 *        K r inputs at the interval K dt.
 *
 * With a zero-order hold, x((k+1)K) = A^K x(kK) + sum_j A^(K-1-j) B u(kK+j) and
 * y(kK) = C x(kK) + D u(kK): the lifted record [u(kK); ...; u(kK+K-1)], y(kK) is an exact
 * n-state LTI system at K dt with the same continuous poles, whatever the input's spectrum. An
 * identifier configured with num_inputs = K r, dt = K dt and decimation 1 therefore identifies
 * the modes of decimated noise-free data to round-off (okid_config::decimation's anti-alias filter
 * cannot: a held input is not band-limited, so its decimated model is biased, docs/refinement.md).
 * Modes must lie below the decimated Nyquist frequency 1 / (2 K dt).
 */
#ifndef OKID_LIFTING_H
#define OKID_LIFTING_H

#include <stddef.h>

#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Lift count samples: lifted sample i has inputs u(iK), u(iK+1), ..., u(iK+K-1) (K r values,
 * sample by sample) and outputs y(iK). count / K samples are written; the last count % K samples
 * are left for the caller to pass again with the next block.
 * \param[in]  r, m     inputs and outputs of the original samples, 1..64
 * \param[in]  factor   K, 1..64
 * \param[in]  count    samples in u and y
 * \param[in]  u, ldu   r x count, leading dimension ldu >= r
 * \param[in]  y, ldy   m x count, leading dimension ldy >= m
 * \param[out] u_lifted (K r) x (count / K), leading dimension K r
 * \param[out] y_lifted m x (count / K), leading dimension m
 * \param[out] lifted   count / K
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE
 */
okid_status okid_lift(int r, int m, int factor, size_t count, const okid_real *u, size_t ldu, const okid_real *y,
                      size_t ldy, okid_real *u_lifted, okid_real *y_lifted, size_t *lifted);

#ifdef __cplusplus
}
#endif

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/* Exact decimation by lifting (okid/lifting.h): a copy, K samples of inputs side by side. */
#include "okid/lifting.h"

#include "okid/limits.h"

okid_status okid_lift(int r, int m, int factor, size_t count, const okid_real *u, size_t ldu, const okid_real *y,
                      size_t ldy, okid_real *u_lifted, okid_real *y_lifted, size_t *lifted)
{
    if (u == NULL || y == NULL || u_lifted == NULL || y_lifted == NULL || lifted == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (r < 1 || r > OKID_MAX_DIMENSION || m < 1 || m > OKID_MAX_DIMENSION || factor < 1 ||
        factor > OKID_MAX_DECIMATION || ldu < (size_t)r || ldy < (size_t)m) {
        return OKID_E_BAD_SIZE;
    }
    const size_t k_count = (size_t)factor, wide = k_count * (size_t)r, out = count / k_count;
    for (size_t i = 0; i < out; ++i) {
        for (size_t j = 0; j < k_count; ++j) {
            const okid_real *uj = u + (i * k_count + j) * ldu;
            for (int c = 0; c < r; ++c) {
                u_lifted[i * wide + j * (size_t)r + (size_t)c] = uj[c];
            }
        }
        for (int c = 0; c < m; ++c) {
            y_lifted[i * (size_t)m + (size_t)c] = y[i * k_count * ldy + (size_t)c];
        }
    }
    *lifted = out;
    return OKID_OK;
}

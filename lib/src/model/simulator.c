/* SPDX-License-Identifier: Apache-2.0 */
/* Discrete state-space simulator: y(k) = C x(k) + D u(k), x(k+1) = A x(k) + B u(k). */
#include "okid/model.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "okid/limits.h"

okid_status okid_simulator_init(okid_simulator *sim, int n, int r, int m, const okid_real *a,
                                const okid_real *b, const okid_real *c, const okid_real *d, okid_real *state,
                                okid_real *scratch)
{
    if (sim == NULL || a == NULL || c == NULL || state == NULL || scratch == NULL ||
        (r > 0 && (b == NULL || d == NULL))) {
        return OKID_E_NULL_POINTER;
    }
    if (n < 1 || n > OKID_MAX_ORDER || r < 0 || r > OKID_MAX_DIMENSION || m < 1 || m > OKID_MAX_DIMENSION) {
        return OKID_E_BAD_SIZE;
    }
    sim->n = n;
    sim->r = r;
    sim->m = m;
    sim->a = a;
    sim->b = b;
    sim->c = c;
    sim->d = d;
    sim->x = state;
    sim->tmp = scratch;
    for (int i = 0; i < n; ++i) {
        state[i] = 0;
    }
    return OKID_OK;
}

okid_status okid_simulate(okid_simulator *sim, size_t count, const okid_real *u, size_t ldu, okid_real *y,
                          size_t ldy)
{
    if (sim == NULL || sim->x == NULL || (count > 0 && (y == NULL || (sim->r > 0 && u == NULL)))) {
        return OKID_E_NULL_POINTER;
    }
    if (sim->n < 1 || sim->m < 1 || sim->r < 0 || ldy < (size_t)sim->m || (sim->r > 0 && ldu < (size_t)sim->r)) {
        return OKID_E_BAD_SIZE;
    }
    const int n = sim->n, r = sim->r, m = sim->m;
    for (size_t k = 0; k < count && r > 0; ++k) {
        if (!okid_all_finite(r, 1, u + k * ldu, r)) {
            return OKID_E_NONFINITE_SAMPLE;
        }
    }
    for (size_t k = 0; k < count; ++k) {
        const okid_real *uk = (r > 0) ? u + k * ldu : NULL;
        okid_real *yk = y + k * ldy;
        okid_gemm('N', 'N', m, 1, n, 1, sim->c, m, sim->x, n, 0, yk, m);
        if (r > 0) {
            okid_gemm('N', 'N', m, 1, r, 1, sim->d, m, uk, r, 1, yk, m);
        }
        okid_gemm('N', 'N', n, 1, n, 1, sim->a, n, sim->x, n, 0, sim->tmp, n);
        if (r > 0) {
            okid_gemm('N', 'N', n, 1, r, 1, sim->b, n, uk, r, 1, sim->tmp, n);
        }
        for (int i = 0; i < n; ++i) {
            sim->x[i] = sim->tmp[i];
        }
    }
    return OKID_OK;
}

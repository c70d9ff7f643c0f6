/* SPDX-License-Identifier: Apache-2.0 */
/* Randomised oversized configurations: see oversize_check.h. */
#include "oversize_check.h"

#include <string.h>

#define GUARD_BYTE 0xA5u

/* splitmix64: a generator of its own, so the configurations do not depend on the library's. */
static uint64_t next_random(uint64_t *state)
{
    uint64_t z = (*state += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
}

static int uniform(uint64_t *state, int lo, int hi)
{
    return lo + (int)(next_random(state) % (uint64_t)(hi - lo + 1));
}

uint64_t oversize_lower_bound(const okid_config *cfg)
{
    const uint64_t r = (uint64_t)cfg->num_inputs, m = (uint64_t)cfg->num_outputs, p = (uint64_t)cfg->observer_order;
    const uint64_t w = r + (r + m) * p + m, nb = cfg->block_rows > 0 ? (uint64_t)cfg->block_rows : 32u;
    const uint64_t markov = m * r * ((uint64_t)cfg->hankel_rows + (uint64_t)cfg->hankel_cols + 1u);
    return sizeof(okid_real) * (w * w + nb * w + p * (r + m) + markov);
}

static int untouched(const unsigned char *bytes, size_t count)
{
    for (size_t i = 0; i < count; ++i) {
        if (bytes[i] != GUARD_BYTE) {
            return 0;
        }
    }
    return 1;
}

static size_t macro_bytes(const okid_config *c)
{
    return OKID_WORKSPACE_BYTES_OPTIONS(c->num_inputs, c->num_outputs, c->observer_order, c->hankel_rows,
                                        c->hankel_cols, c->order, c->block_rows,
                                        c->realization == OKID_REALIZATION_COMBINED, c->decimation, c->scaling,
                                        c->estimator, c->instrument_lags);
}

static void report(oversize_tally *t, oversize_fail_fn fail, const char *what, const okid_config *cfg)
{
    ++t->failures;
    fail(what, cfg);
}

/* Init over an exact-size workspace and push 3 blocks plus a window of samples. */
static void feed(const okid_config *cfg, size_t bytes, unsigned char *buf, oversize_tally *t, oversize_fail_fn fail)
{
    okid_identifier id;
    if (okid_init(&id, cfg, buf, bytes, NULL) != OKID_OK) {
        report(t, fail, "okid_init refused a workspace of the size okid_workspace_size gave", cfg);
        return;
    }
    okid_real u[OKID_MAX_DIMENSION], y[OKID_MAX_DIMENSION];
    uint64_t state = 7;
    const int nb = cfg->block_rows > 0 ? cfg->block_rows : 32;
    const int pushes = (3 * nb + cfg->observer_order + 1) * (cfg->decimation > 1 ? cfg->decimation : 1);
    for (int k = 0; k < pushes; ++k) {
        for (int i = 0; i < OKID_MAX_DIMENSION; ++i) {
            u[i] = (okid_real)uniform(&state, -1000, 1000) / 1000;
            y[i] = (okid_real)uniform(&state, -1000, 1000) / 1000;
        }
        if (okid_push(&id, u, y) != OKID_OK) {
            report(t, fail, "okid_push failed on finite samples", cfg);
            return;
        }
    }
    ++t->fitted;
}

void oversize_check_config(const okid_config *cfg, unsigned char *buf, size_t capacity, oversize_tally *t,
                           oversize_fail_fn fail)
{
    ++t->tried;
    memset(buf, GUARD_BYTE, capacity + OVERSIZE_GUARD);
    const uint64_t bound = oversize_lower_bound(cfg);
    size_t bytes = 0;
    const okid_status st = okid_workspace_size(cfg, &bytes);
    okid_identifier id;
    if (bound > (uint64_t)SIZE_MAX) {
        ++t->oversized;
        const int refused = st == OKID_E_BAD_SIZE && okid_init(&id, cfg, buf, capacity, NULL) == OKID_E_BAD_SIZE;
        if (!refused) {
            report(t, fail, "a workspace above SIZE_MAX was not refused with OKID_E_BAD_SIZE", cfg);
        } else if (macro_bytes(cfg) != (size_t)-1) {
            report(t, fail, "OKID_WORKSPACE_BYTES_OPTIONS did not saturate at SIZE_MAX", cfg);
        } else {
            ++t->refused;
        }
        if (!untouched(buf, capacity + OVERSIZE_GUARD)) {
            report(t, fail, "a refused okid_init wrote into the buffer", cfg);
        }
        return;
    }
    if (st != OKID_OK) {
        return; /* refused for another reason (a product above INT_MAX for the backend, lags) */
    }
    if (bytes < bound) {
        report(t, fail, "okid_workspace_size is below the lower bound (wrapped around)", cfg);
        return;
    }
    if (bytes != macro_bytes(cfg)) {
        report(t, fail, "OKID_WORKSPACE_BYTES_OPTIONS differs from okid_workspace_size", cfg);
    }
    if (bytes > capacity) {
        if (okid_init(&id, cfg, buf, capacity, NULL) != OKID_E_WORKSPACE_TOO_SMALL ||
            !untouched(buf, capacity + OVERSIZE_GUARD)) {
            report(t, fail, "okid_init over a too small buffer was not refused untouched", cfg);
        }
        return;
    }
    feed(cfg, bytes, buf, t, fail);
    if (!untouched(buf + bytes, OVERSIZE_GUARD)) {
        report(t, fail, "okid_init or okid_push wrote past the workspace", cfg);
    }
}

/* Dimensions each in range; the order valid for them (1 .. the Hankel and observer limits). */
static void random_config(uint64_t *state, int large, okid_config *cfg)
{
    const int r = large ? uniform(state, 1, OKID_MAX_DIMENSION) : uniform(state, 1, 4);
    const int m = large ? uniform(state, 1, OKID_MAX_DIMENSION) : uniform(state, 1, 4);
    (void)okid_config_default(cfg, r, m);
    cfg->observer_order = large ? uniform(state, 1, OKID_MAX_HORIZON) : uniform(state, 1, 12);
    cfg->hankel_rows = large ? uniform(state, 1, OKID_MAX_HORIZON) : uniform(state, 1, 20);
    cfg->hankel_cols = large ? uniform(state, 1, OKID_MAX_HORIZON) : uniform(state, 1, 20);
    cfg->block_rows = uniform(state, 0, 3) == 0 ? 0 : uniform(state, 1, large ? 4096 : 16);
    cfg->realization = uniform(state, 0, 1) ? OKID_REALIZATION_COMBINED : OKID_REALIZATION_SYSTEM;
    cfg->scaling = uniform(state, 0, 1) ? OKID_SCALING_AUTO : OKID_SCALING_NONE;
    cfg->decimation = uniform(state, 0, 3) == 0 ? uniform(state, 2, 8) : 1;
    cfg->estimator = uniform(state, 0, 4) == 0 ? OKID_ESTIMATOR_INSTRUMENTAL : OKID_ESTIMATOR_LEAST_SQUARES;
    const int ncols = cfg->realization == OKID_REALIZATION_COMBINED ? r + m : r;
    int limit = m * cfg->observer_order;
    limit = limit < m * cfg->hankel_rows ? limit : m * cfg->hankel_rows;
    limit = limit < ncols * cfg->hankel_cols ? limit : ncols * cfg->hankel_cols;
    limit = limit < OKID_MAX_ORDER ? limit : OKID_MAX_ORDER;
    cfg->order = uniform(state, 1, limit < 12 ? limit : 12);
}

void oversize_run(uint64_t seed, int count, unsigned char *buf, size_t capacity, oversize_tally *tally,
                  oversize_fail_fn fail)
{
    uint64_t state = seed;
    for (int i = 0; i < count; ++i) {
        okid_config cfg;
        random_config(&state, i % 2, &cfg);
        oversize_check_config(&cfg, buf, capacity, tally, fail);
    }
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * libFuzzer target: the public C API driven by a byte stream. Random (also absurd) configurations,
 * workspace sizes around the required one inside canary bytes, random interleavings of init,
 * push, push_block, identify, predict, reset and progress with NaN, Inf, denormal and huge samples.
 * Invariants: no crash or sanitizer report; canaries intact; every status one of the documented
 * values; no heap allocation inside the library; and a shadow identifier that gets only the calls
 * the library accepted (plus the non-finite samples, whose documented effect is a window restart)
 * and only the identifications that succeeded identifies exactly the same: a rejected call, a failed
 * identification and an identification with rows pending change nothing (after a failed one the
 * two also predict the same, from the last good model).
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fuzz_input.h"
#include "okid/okid.h"

enum { CANARY = 64, MAX_SAMPLES = 64 };

static int in_library; /* set around library calls; the malloc hook fails the run if it fires */

#ifdef OKID_FUZZ_MALLOC_HOOK /* libFuzzer builds: the sanitizer runtime reports every allocation */
#include <sanitizer/allocator_interface.h>

static void malloc_hook(const volatile void *ptr, size_t size)
{
    (void)ptr;
    (void)size;
    if (in_library) {
        fprintf(stderr, "heap allocation inside the okid library\n");
        abort();
    }
}
#endif

static void check_status(okid_status st)
{
    if (st > OKID_OK || st < OKID_E_DATA_RANGE) { /* OKID_E_DATA_RANGE: the lowest status (status.h) */
        fprintf(stderr, "undocumented status %d\n", (int)st);
        abort();
    }
}

static okid_status checked(okid_status st)
{
    in_library = 0;
    check_status(st);
    return st;
}

/* A library call: allocations inside it fail the run, its status must be a documented one. */
#define CALL(expr) (in_library = 1, checked(expr))

static void check_canaries(const unsigned char *buf, size_t bytes)
{
    for (size_t i = 0; i < CANARY; ++i) {
        if (buf[i] != 0xA5 || buf[CANARY + bytes + i] != 0x5A) {
            fprintf(stderr, "write outside the workspace\n");
            abort();
        }
    }
}

static void same_results(const okid_result *a, const okid_result *b)
{
    if (a->order != b->order || a->num_modes != b->num_modes || a->rows != b->rows ||
        memcmp(a->A.data, b->A.data, sizeof(okid_real) * (size_t)a->order * (size_t)a->order) != 0) {
        fprintf(stderr, "a rejected call changed the identification\n");
        abort();
    }
}

/* The stabilization diagram of an identified model into its own workspace (any orders, valid or not). */
static void stabilize(okid_identifier *id, int max_order, int step)
{
    size_t bytes = 0;
    if (CALL(okid_stabilization_workspace_size(id, max_order, step, &bytes)) != OKID_OK || bytes > (1u << 22)) {
        return;
    }
    void *ws = aligned_alloc(16, (bytes + 15) / 16 * 16);
    okid_stabilization table;
    if (CALL(okid_stabilization_compute(id, max_order, step, NULL, ws, bytes, &table)) == OKID_OK) {
        for (int i = 0; i < table.num_orders; ++i) {
            if (table.orders[i].num_modes > table.orders[i].order) abort();
        }
    }
    free(ws);
}

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size);

int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size)
{
#ifdef OKID_FUZZ_MALLOC_HOOK
    static int hooked;
    if (!hooked) {
        __sanitizer_install_malloc_and_free_hooks(malloc_hook, NULL);
        hooked = 1;
    }
#endif
    fuzz_input in = {data, size, 0};
    okid_config cfg;
    okid_config_default(&cfg, fuzz_int(&in, -1, 3), fuzz_int(&in, -1, 3));
    cfg.observer_order = fuzz_int(&in, -1, 12);
    cfg.order = fuzz_int(&in, -1, 8);
    cfg.hankel_rows = fuzz_int(&in, -1, 14);
    cfg.hankel_cols = fuzz_int(&in, -1, 14);
    cfg.block_rows = fuzz_int(&in, -1, 9);
    cfg.realization = (okid_realization)fuzz_int(&in, 0, 2);
    cfg.sensing = (okid_sensing)fuzz_int(&in, -1, 3);
    cfg.zero_initial_state = fuzz_int(&in, 0, 1);
    cfg.dt = fuzz_byte(&in) < 240 ? 0.01 : fuzz_real(&in);
    cfg.forgetting_factor = fuzz_byte(&in) < 200 ? 0 : fuzz_real(&in);
    cfg.rank_tolerance = fuzz_byte(&in) < 200 ? 0 : fuzz_real(&in);
    /* the quality options: decimation, scaling, instrumental variables (automatic or given lags) */
    cfg.decimation = fuzz_byte(&in) < 160 ? 1 : fuzz_int(&in, -1, 5);
    cfg.scaling = (okid_scaling)fuzz_int(&in, 0, 2);
    cfg.estimator = (okid_estimator)fuzz_int(&in, 0, 2);
    cfg.instrument_lags = fuzz_byte(&in) < 160 ? 0 : fuzz_int(&in, -1, 60);

    okid_status st;
    size_t needed = 0;
    if (CALL(okid_workspace_size(&cfg, &needed)) != OKID_OK) {
        okid_identifier id;
        unsigned char small[64];
        CALL(okid_init(&id, &cfg, small, sizeof small, NULL)); /* must refuse the same way, no write */
        return 0;
    }
    if (needed > (1u << 22)) return 0;
    const long delta = (long)fuzz_int(&in, -64, 64) * (fuzz_byte(&in) < 64 ? 1 : 0);
    const size_t bytes = (size_t)((long)needed + delta > 0 ? (long)needed + delta : 0);
    unsigned char *buf = aligned_alloc(16, (2 * CANARY + bytes + needed + 15) / 16 * 16 + 16);
    unsigned char *shadow_ws = aligned_alloc(16, (needed + 15) / 16 * 16);
    memset(buf, 0xA5, CANARY);
    memset(buf + CANARY + bytes, 0x5A, CANARY);
    okid_identifier id, shadow;
    size_t reported = 0;
    st = CALL(okid_init(&id, &cfg, buf + CANARY, bytes, &reported));
    if (reported != needed) abort();
    if (st != OKID_OK) {
        if (bytes >= needed) abort(); /* a valid configuration with enough room must initialise */
        check_canaries(buf, bytes);
        free(buf);
        free(shadow_ws);
        return 0;
    }
    CALL(okid_init(&shadow, &cfg, shadow_ws, needed, NULL));
    const int r = cfg.num_inputs, m = cfg.num_outputs;
    okid_real u[MAX_SAMPLES * 3], y[MAX_SAMPLES * 3], y_hat[3];
    okid_result res, shadow_res;
    okid_progress progress;
    for (int op = 0; op < 200 && in.pos < in.size; ++op) {
        switch (fuzz_byte(&in) % 8) {
        case 0: case 1: case 2: { /* push one sample */
            for (int i = 0; i < r; ++i) u[i] = fuzz_real(&in);
            for (int i = 0; i < m; ++i) y[i] = fuzz_real(&in);
            st = CALL(okid_push(&id, u, y));
            if (st == OKID_OK || st == OKID_E_NONFINITE_SAMPLE) CALL(okid_push(&shadow, u, y));
            break;
        }
        case 3: { /* a block, sometimes with a too-small leading dimension */
            const int count = fuzz_int(&in, 0, MAX_SAMPLES);
            const size_t ldu = (size_t)fuzz_int(&in, r - 1, 3), ldy = (size_t)fuzz_int(&in, m - 1, 3);
            for (int i = 0; i < count * 3; ++i) {
                u[i] = fuzz_byte(&in) < 250 ? ((double)fuzz_int(&in, 0, 200) - 100) / 50 : fuzz_real(&in);
                y[i] = fuzz_byte(&in) < 250 ? ((double)fuzz_int(&in, 0, 200) - 100) / 50 : fuzz_real(&in);
            }
            size_t accepted = 0;
            st = CALL(okid_push_block(&id, (size_t)count, u, ldu, y, ldy, &accepted));
            if (st == OKID_OK || st == OKID_E_NONFINITE_SAMPLE) {
                CALL(okid_push_block(&shadow, (size_t)count, u, ldu, y, ldy, NULL));
            }
            break;
        }
        case 4: { /* identify; the shadow only when it succeeds: same model, or the same last one */
            const okid_status a = CALL(okid_identify(&id, &res));
            if (a == OKID_OK) {
                if (CALL(okid_identify(&shadow, &shadow_res)) != OKID_OK) abort();
                same_results(&res, &shadow_res);
            } else {
                okid_progress pa, pb;
                okid_real y_shadow[3];
                CALL(okid_get_progress(&id, &pa));
                CALL(okid_get_progress(&shadow, &pb));
                if (pa.samples != pb.samples || pa.rejected != pb.rejected || pa.rows != pb.rows) abort();
                for (int i = 0; i < r; ++i) u[i] = 0.5;
                const okid_status pa_st = CALL(okid_predict(&id, u, y_hat));
                if (pa_st != CALL(okid_predict(&shadow, u, y_shadow))) abort();
                if (pa_st == OKID_OK && memcmp(y_hat, y_shadow, sizeof(okid_real) * (size_t)m) != 0) {
                    fprintf(stderr, "a failed identification changed the prediction\n");
                    abort();
                }
            }
            if (a == OKID_OK && fuzz_byte(&in) < 64) {
                stabilize(&id, fuzz_int(&in, -1, 10), fuzz_int(&in, 0, 3));
                same_results(&res, &shadow_res); /* the diagram leaves the last result alone */
            }
            break;
        }
        case 5:
            for (int i = 0; i < r; ++i) u[i] = fuzz_real(&in);
            CALL(okid_predict(&id, u, y_hat));
            break;
        case 6:
            if (fuzz_byte(&in) < 32) {
                CALL(okid_reset(&id));
                CALL(okid_reset(&shadow));
            } else if (fuzz_byte(&in) < 64) { /* caller's scales: the same answer for both */
                for (int i = 0; i < r; ++i) u[i] = fuzz_real(&in);
                for (int i = 0; i < m; ++i) y[i] = fuzz_real(&in);
                const okid_status a = CALL(okid_set_scales(&id, u, y));
                if (a != CALL(okid_set_scales(&shadow, u, y))) abort();
            } else {
                CALL(okid_get_progress(&id, &progress));
            }
            break;
        default: /* calls with bad arguments must change nothing */
            CALL(okid_push(&id, NULL, y));
            CALL(okid_push_block(&id, 3, u, 0, y, (size_t)m, NULL));
            CALL(okid_identify(&id, NULL));
            break;
        }
        check_canaries(buf, bytes);
    }
    free(buf);
    free(shadow_ws);
    return 0;
}

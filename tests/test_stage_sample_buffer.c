/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The sample window and its regressor rows on their own (pipeline/sample_buffer.h, the
 * instruments' rows of pipeline/instrumental.h): the row layout the header documents, written out
 * by hand here, the prediction as the row times X, and the restart rules.
 */
#include "test_support.h"

#include <string.h>

#include "pipeline/instrumental.h"
#include "pipeline/sample_buffer.h"

enum { R = 2, M = 3, P = 3, W = R + M, Q = R + (R + M) * P, LD = 4, LAGS = 4 };

/* Sample k of a made-up record: u_i(k) = 10 k + i, y_a(k) = -(10 k + a) - 0.5. */
static okid_real u_of(int k, int i) { return (okid_real)(10 * k + i); }
static okid_real y_of(int k, int a) { return (okid_real)(-(10 * k + a) - 0.5); }

static void push(okid_ring_ *ring, int k)
{
    okid_real u[R], y[M];
    for (int i = 0; i < R; ++i) u[i] = u_of(k, i);
    for (int a = 0; a < M; ++a) y[a] = y_of(k, a);
    okid_ring_append(ring, u, R, y, M);
}

static void test_regressor_row_layout(void **state)
{
    (void)state;
    okid_real data[W * P], row[LD * (Q + M)];
    okid_ring_ window = {data, W, P, 0, 0};
    okid_ring_restart(&window, 0);
    const int k = 7; /* the ring wraps: samples 2 .. 6 pushed, 4 .. 6 kept */
    for (int j = 2; j < k; ++j) {
        assert_int_equal(okid_ring_full(&window), j >= 2 + P);
        push(&window, j);
    }
    assert_true(okid_ring_full(&window));
    okid_real u[R], y[M];
    for (int i = 0; i < R; ++i) u[i] = u_of(k, i);
    for (int a = 0; a < M; ++a) y[a] = y_of(k, a);
    memset(row, 0, sizeof row);
    okid_buffer_write_row(&window, R, u, y, row + 1, LD); /* row 1 of a block with leading dimension 4 */
    /* [ u(k) | u(k-1) .. u(k-p) | y(k-1) .. y(k-p) | y(k) ] */
    okid_real want[Q + M];
    int col = 0;
    for (int i = 0; i < R; ++i) want[col++] = u_of(k, i);
    for (int j = 1; j <= P; ++j) for (int i = 0; i < R; ++i) want[col++] = u_of(k - j, i);
    for (int j = 1; j <= P; ++j) for (int a = 0; a < M; ++a) want[col++] = y_of(k - j, a);
    for (int a = 0; a < M; ++a) want[col++] = y_of(k, a);
    for (int c = 0; c < Q + M; ++c) {
        assert_true(row[1 + c * LD] == want[c]);
        assert_true(row[0 + c * LD] == 0 && row[2 + c * LD] == 0); /* nothing outside the row */
    }

    /* the prediction is that row's first q columns times X */
    okid_real x[(Q + 1) * M], y_hat[M];
    for (int i = 0; i < (Q + 1) * M; ++i) x[i] = (okid_real)(0.125 * (i % 9) - 0.5);
    okid_buffer_predict(&window, R, u, x, Q + 1, y_hat);
    for (int a = 0; a < M; ++a) {
        okid_real s = 0;
        for (int c = 0; c < Q; ++c) s += want[c] * x[c + a * (Q + 1)];
        assert_true(y_hat[a] == s); /* the same sum in the same order */
    }
}

/* A record that starts at rest: the window is full at once and holds zeros. */
/*
 * The block path (okid_push_block's, okid_buffer_write_rows()): `count` rows at once, column by
 * column, equal to count calls of okid_buffer_write_row() with the window appended between them,
 * bit for bit (both copy the same values). Runs shorter than p (every lagged column partly from the
 * window), equal to it and longer, with the window's ring wrapped at any head.
 */
static void test_rows_at_once_equal_row_by_row(void **state)
{
    (void)state;
    enum { MOST = 9, LDB = 11, LDU = R + 1, LDY = M + 2 };
    const int counts[] = {1, 2, P, P + 1, MOST};
    for (int start = P; start < P + 4; ++start) {
        for (size_t c = 0; c < sizeof counts / sizeof counts[0]; ++c) {
            const int count = counts[c];
            okid_real data[W * P], one[LDB * (Q + M)], block[LDB * (Q + M)];
            okid_real u[MOST * LDU], y[MOST * LDY];
            okid_ring_ window = {data, W, P, 0, 0};
            okid_ring_restart(&window, 0);
            for (int k = 0; k < start; ++k) push(&window, k); /* heads at every slot */
            for (int t = 0; t < count; ++t) {
                for (int i = 0; i < R; ++i) u[t * LDU + i] = u_of(start + t, i);
                for (int a = 0; a < M; ++a) y[t * LDY + a] = y_of(start + t, a);
            }
            for (int e = 0; e < LDB * (Q + M); ++e) one[e] = block[e] = (okid_real)-999;
            okid_buffer_write_rows(&window, R, count, u, LDU, y, LDY, block, LDB);
            for (int t = 0; t < count; ++t) {
                okid_buffer_write_row(&window, R, u + t * LDU, y + t * LDY, one + t, LDB);
                okid_ring_append(&window, u + t * LDU, R, y + t * LDY, M);
            }
            assert_memory_equal(block, one, sizeof block); /* the rows below count untouched in both */
        }
    }
}

static void test_zero_history(void **state)
{
    (void)state;
    okid_real data[W * P], row[Q + M];
    for (int i = 0; i < W * P; ++i) data[i] = 99;
    okid_ring_ window = {data, W, P, 0, 0};
    okid_ring_restart(&window, 1);
    assert_true(okid_ring_full(&window));
    const okid_real u[R] = {1, 2}, y[M] = {3, 4, 5};
    okid_buffer_write_row(&window, R, u, y, row, 1);
    for (int c = R; c < Q; ++c) assert_true(row[c] == 0);
    okid_ring_restart(&window, 0);
    assert_false(okid_ring_full(&window));
}

/* The instruments' row: z(k) = [u(k); u(k-1); ...; u(k-L)] from the ring of past inputs. */
static void test_instrument_row(void **state)
{
    (void)state;
    okid_real data[R * LAGS], row[R * (LAGS + 1)];
    okid_ring_ inputs = {data, R, LAGS, 0, 0};
    okid_ring_restart(&inputs, 0);
    const int k = 9;
    for (int j = 0; j < k; ++j) {
        okid_real u[R];
        for (int i = 0; i < R; ++i) u[i] = u_of(j, i);
        okid_ring_append(&inputs, u, R, NULL, 0);
    }
    okid_real u[R];
    for (int i = 0; i < R; ++i) u[i] = u_of(k, i);
    okid_iv_write_row(&inputs, u, row, 1);
    for (int j = 0; j <= LAGS; ++j) {
        for (int i = 0; i < R; ++i) assert_true(row[j * R + i] == u_of(k - j, i));
    }
    okid_ring_ none = {NULL, R, 0, 0, 0}; /* least squares: no ring, always ready */
    okid_ring_restart(&none, 0);
    okid_ring_append(&none, u, R, NULL, 0);
    assert_true(okid_ring_full(&none));
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_regressor_row_layout),
        cmocka_unit_test(test_rows_at_once_equal_row_by_row),
        cmocka_unit_test(test_zero_history),
        cmocka_unit_test(test_instrument_row),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

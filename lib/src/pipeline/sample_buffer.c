/* SPDX-License-Identifier: Apache-2.0 */
/* Recursive buffering: see sample_buffer.h for the row layout. */
#include "pipeline/sample_buffer.h"

#include "numerics/dense.h"

void okid_ring_restart(okid_ring_ *ring, int zero_history)
{
    if (ring->depth > 0) {
        okid_zero_matrix(ring->width, ring->depth, ring->data, ring->width);
    }
    ring->head = ring->depth > 0 ? ring->depth - 1 : 0;
    ring->fill = zero_history ? ring->depth : 0;
}

int okid_ring_full(const okid_ring_ *ring)
{
    return ring->fill >= ring->depth;
}

void okid_ring_append(okid_ring_ *ring, const okid_real *a, int na, const okid_real *b, int nb)
{
    if (ring->depth == 0) {
        return;
    }
    ring->head = (ring->head + 1) % ring->depth;
    okid_real *slot = ring->data + (size_t)ring->head * (size_t)ring->width;
    for (int i = 0; i < na; ++i) {
        slot[i] = a[i];
    }
    for (int i = 0; i < nb; ++i) {
        slot[na + i] = b[i];
    }
    if (ring->fill < ring->depth) {
        ++ring->fill;
    }
}

const okid_real *okid_ring_past(const okid_ring_ *ring, int j)
{
    const int slot = (ring->head - (j - 1) + ring->depth) % ring->depth;
    return ring->data + (size_t)slot * (size_t)ring->width;
}

/* Channel ch of the window, newest first (v(k-1) .. v(k-p)), to dst with stride step. Called for
   every pushed sample: two plain strided copies, slots head down to 0, then p - 1 down to head + 1. */
static void copy_channel_history(const okid_ring_ *window, int ch, okid_real *dst, size_t step)
{
    const int p = window->depth, width = window->width, head = window->head;
    const okid_real *ring = window->data + ch;
    for (int slot = head; slot >= 0; --slot, dst += step) {
        *dst = ring[(size_t)slot * (size_t)width];
    }
    for (int slot = p - 1; slot > head; --slot, dst += step) {
        *dst = ring[(size_t)slot * (size_t)width];
    }
}

void okid_buffer_write_row(const okid_ring_ *window, int r, const okid_real *u, const okid_real *y, okid_real *row,
                           size_t ld)
{
    const int m = window->width - r, p = window->depth;
    okid_real *past_y = row + (size_t)r * (size_t)(p + 1) * ld;
    for (int i = 0; i < r; ++i) {
        row[(size_t)i * ld] = u[i];
        copy_channel_history(window, i, row + (size_t)(r + i) * ld, (size_t)r * ld);
    }
    for (int a = 0; a < m; ++a) {
        copy_channel_history(window, r + a, past_y + (size_t)a * ld, (size_t)m * ld);
        past_y[(size_t)(p * m + a) * ld] = y[a];
    }
}

/* Column of channel ch at lag j (0: the current sample) for `count` rows: the window's p samples
   before the block for the first j rows, then the block's own (x: its first sample's channel ch,
   stride ldx between samples). */
static void copy_lagged_column(const okid_ring_ *window, int ch, int j, int count, const okid_real *x, size_t ldx,
                               okid_real *dst)
{
    const int from_window = j < count ? j : count;
    for (int t = 0; t < from_window; ++t) {
        dst[t] = okid_ring_past(window, j - t)[ch];
    }
    for (int t = from_window; t < count; ++t) {
        dst[t] = x[(size_t)(t - j) * ldx];
    }
}

void okid_buffer_write_rows(const okid_ring_ *window, int r, int count, const okid_real *u, size_t ldu,
                            const okid_real *y, size_t ldy, okid_real *block, size_t ld)
{
    const int m = window->width - r, p = window->depth;
    const size_t past_y = (size_t)r * (size_t)(p + 1);
    for (int i = 0; i < r; ++i) {
        copy_lagged_column(window, i, 0, count, u + i, ldu, block + (size_t)i * ld);
        for (int j = 1; j <= p; ++j) {
            copy_lagged_column(window, i, j, count, u + i, ldu, block + (size_t)(r + (j - 1) * r + i) * ld);
        }
    }
    for (int a = 0; a < m; ++a) {
        for (int j = 1; j <= p; ++j) {
            copy_lagged_column(window, r + a, j, count, y + a, ldy, block + (past_y + (size_t)((j - 1) * m + a)) * ld);
        }
        copy_lagged_column(window, r + a, 0, count, y + a, ldy, block + (past_y + (size_t)(p * m + a)) * ld);
    }
}

void okid_buffer_predict(const okid_ring_ *window, int r, const okid_real *u, const okid_real *x, int ldx,
                         okid_real *y_hat)
{
    const int m = window->width - r, p = window->depth;
    for (int a = 0; a < m; ++a) {
        const okid_real *xa = x + (size_t)a * (size_t)ldx; /* column a of X, in row-layout order */
        okid_real s = 0;
        int col = 0;
        for (int i = 0; i < r; ++i) {
            s += xa[col++] * u[i];
        }
        for (int j = 1; j <= p; ++j) {
            const okid_real *v = okid_ring_past(window, j);
            for (int i = 0; i < r; ++i) {
                s += xa[col++] * v[i];
            }
        }
        for (int j = 1; j <= p; ++j) {
            const okid_real *v = okid_ring_past(window, j) + r;
            for (int i = 0; i < m; ++i) {
                s += xa[col++] * v[i];
            }
        }
        y_hat[a] = s;
    }
}

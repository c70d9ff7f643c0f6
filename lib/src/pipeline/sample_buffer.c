/* Recursive buffering: see sample_buffer.h for the row layout. */
#include "sample_buffer.h"

#include "dense.h"

/* The slot of v(k - j), j = 1..p; ring_head_ is the slot of v(k - 1). */
static const okid_real *past(const okid_identifier *id, int j)
{
    const int p = id->dims_.p, width = id->dims_.r + id->dims_.m;
    const int slot = (id->ring_head_ - (j - 1) + p) % p;
    return id->at_.ring + (size_t)slot * (size_t)width;
}

void okid_buffer_restart(okid_identifier *id, int zero_history)
{
    const int p = id->dims_.p, width = id->dims_.r + id->dims_.m;
    okid_zero_matrix(width, p, id->at_.ring, width);
    id->ring_head_ = p - 1;
    id->window_fill_ = zero_history ? p : 0;
}

int okid_buffer_window_full(const okid_identifier *id)
{
    return id->window_fill_ >= id->dims_.p;
}

/* Channel ch of the window, newest first (v(k-1) .. v(k-p)), to dst with stride step. Called for
   every pushed sample: two plain strided copies, slots head down to 0, then p - 1 down to head + 1. */
static void copy_channel_history(const okid_identifier *id, int ch, okid_real *dst, size_t step)
{
    const int p = id->dims_.p, width = id->dims_.r + id->dims_.m, head = id->ring_head_;
    const okid_real *ring = id->at_.ring + ch;
    for (int slot = head; slot >= 0; --slot, dst += step) {
        *dst = ring[(size_t)slot * (size_t)width];
    }
    for (int slot = p - 1; slot > head; --slot, dst += step) {
        *dst = ring[(size_t)slot * (size_t)width];
    }
}

void okid_buffer_write_row(const okid_identifier *id, const okid_real *u, const okid_real *y, int row)
{
    const int r = id->dims_.r, m = id->dims_.m, p = id->dims_.p;
    const size_t ld = (size_t)id->dims_.block_rows;
    okid_real *out = id->at_.block + row;
    okid_real *past_y = out + (size_t)r * (size_t)(p + 1) * ld;
    for (int i = 0; i < r; ++i) {
        out[(size_t)i * ld] = u[i];
        copy_channel_history(id, i, out + (size_t)(r + i) * ld, (size_t)r * ld);
    }
    for (int a = 0; a < m; ++a) {
        copy_channel_history(id, r + a, past_y + (size_t)a * ld, (size_t)m * ld);
        past_y[(size_t)(p * m + a) * ld] = y[a];
    }
}

void okid_buffer_predict(const okid_identifier *id, const okid_real *u, const okid_real *x, okid_real *y_hat)
{
    const int r = id->dims_.r, m = id->dims_.m, p = id->dims_.p, q = id->dims_.q;
    for (int a = 0; a < m; ++a) {
        const okid_real *xa = x + (size_t)a * (size_t)q; /* column a of X, in row-layout order */
        okid_real s = 0;
        int col = 0;
        for (int i = 0; i < r; ++i) {
            s += xa[col++] * u[i];
        }
        for (int j = 1; j <= p; ++j) {
            const okid_real *v = past(id, j);
            for (int i = 0; i < r; ++i) {
                s += xa[col++] * v[i];
            }
        }
        for (int j = 1; j <= p; ++j) {
            const okid_real *v = past(id, j) + r;
            for (int i = 0; i < m; ++i) {
                s += xa[col++] * v[i];
            }
        }
        y_hat[a] = s;
    }
}

void okid_buffer_append(okid_identifier *id, const okid_real *u, const okid_real *y)
{
    const int r = id->dims_.r, m = id->dims_.m, p = id->dims_.p;
    id->ring_head_ = (id->ring_head_ + 1) % p;
    okid_real *slot = id->at_.ring + (size_t)id->ring_head_ * (size_t)(r + m);
    for (int i = 0; i < r; ++i) {
        slot[i] = u[i];
    }
    for (int i = 0; i < m; ++i) {
        slot[r + i] = y[i];
    }
    if (id->window_fill_ < p) {
        ++id->window_fill_;
    }
}

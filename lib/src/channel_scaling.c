/* Per-channel scaling: see channel_scaling.h; column order of the rows in sample_buffer.h. */
#include "channel_scaling.h"

#include "dense.h"
#include "real_math.h"

okid_real okid_channel_scale(const okid_identifier *id, int channel)
{
    return (id->at_.scales != NULL && id->scales_known_) ? id->at_.scales[channel] : 1;
}

/* The channel (input i, or r + output a) of regressor column col. */
static int regressor_channel(const okid_dims_ *d, int col)
{
    const int r = d->r, m = d->m, past_inputs_end = r * (d->p + 1);
    if (col < past_inputs_end) {
        return col % r; /* u(k), then u(k-1) .. u(k-p) */
    }
    if (col < d->q) {
        return r + (col - past_inputs_end) % m; /* y(k-1) .. y(k-p) */
    }
    return r + (col - d->q); /* y(k) */
}

/*
 * RMS of column col of the pending rows; 1 when it is zero there (the channel keeps its units).
 * Channels far from 1 (1e155, 1e-160) are what scaling is for, but their squares overflow or
 * underflow: the sum is then taken over v / max|v|. Within the range where the plain squares are
 * exact to rounding, the plain sum is kept (the same bits as before for ordinary data).
 */
static okid_real pending_rms(const okid_identifier *id, int col)
{
    const int rows = id->block_fill_, ld = id->dims_.block_rows;
    okid_real amax = 0;
    for (int i = 0; i < rows; ++i) {
        const okid_real v = okid_fabs(OKID_AT(id->at_.block, ld, i, col));
        amax = v > amax ? v : amax;
    }
    if (amax == 0) {
        return 1;
    }
    const int plain = amax >= okid_sqrt(OKID_REAL_MIN) / OKID_EPSILON && amax <= okid_sqrt(OKID_REAL_MAX / (okid_real)rows);
    const okid_real unit = plain ? 1 : amax;
    okid_real s = 0;
    for (int i = 0; i < rows; ++i) {
        const okid_real v = OKID_AT(id->at_.block, ld, i, col) / unit;
        s += v * v;
    }
    return unit * okid_sqrt(s / (okid_real)rows);
}

void okid_scaling_apply_pending(okid_identifier *id)
{
    const okid_dims_ *d = &id->dims_;
    okid_views_ *v = &id->at_;
    const int rows = id->block_fill_, ld = d->block_rows;
    if (v->scales == NULL || rows == 0) {
        return;
    }
    if (!id->scales_known_) {
        for (int i = 0; i < d->r; ++i) {
            v->scales[i] = pending_rms(id, i); /* u(k) */
        }
        for (int a = 0; a < d->m; ++a) {
            v->scales[d->r + a] = pending_rms(id, d->q + a); /* y(k) */
        }
        id->scales_known_ = 1;
    }
    for (int col = 0; col < d->w; ++col) {
        const okid_real inv = 1 / v->scales[regressor_channel(d, col)];
        for (int i = 0; i < rows; ++i) {
            OKID_AT(v->block, ld, i, col) *= inv;
        }
    }
    for (int col = 0; col < d->nz; ++col) { /* instruments: u(k - j), input col % r */
        const okid_real inv = 1 / v->scales[col % d->r];
        for (int i = 0; i < rows; ++i) {
            OKID_AT(v->iv_block, ld, i, col) *= inv;
        }
    }
}

void okid_scaling_unscale_solution(okid_identifier *id)
{
    const okid_dims_ *d = &id->dims_;
    if (id->at_.scales == NULL || !id->scales_known_) {
        return;
    }
    for (int a = 0; a < d->m; ++a) {
        const okid_real out = id->at_.scales[d->r + a];
        for (int i = 0; i < d->q; ++i) {
            OKID_AT(id->at_.x, d->q, i, a) *= out / id->at_.scales[regressor_channel(d, i)];
        }
    }
}

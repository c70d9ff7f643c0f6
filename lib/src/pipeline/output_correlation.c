/* SPDX-License-Identifier: Apache-2.0 */
/* Streaming output correlations: see output_correlation.h. */
#include "pipeline/output_correlation.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "pipeline/sample_buffer.h"

/* Reals of one segment's S(0..lags). */
static size_t segment_reals(const okid_correlation_sums_ *s)
{
    return (size_t)s->m * (size_t)s->nref * (size_t)(s->lags + 1);
}

void okid_corr_clear(okid_correlation_sums_ *s)
{
    for (int j = 0; j < s->segments; ++j) {
        okid_zero_matrix(s->m, s->nref * (s->lags + 1), s->sums + (size_t)j * segment_reals(s), s->m);
    }
    for (int a = 0; a < s->m; ++a) {
        s->squares[a] = 0;
    }
    for (int k = 0; k < s->segments * (s->lags + 1); ++k) {
        s->pairs[k] = 0;
    }
    s->added = 0;
    okid_ring_restart(&s->past, 0);
}

void okid_corr_gap(okid_correlation_sums_ *s)
{
    okid_ring_restart(&s->past, 0);
}

/* S(k) += y ref' for one block k (m x nref at column k nref) of the sums at base. */
static void add_outer(const okid_correlation_sums_ *s, okid_real *base, int k, const okid_real *y, const okid_real *ref)
{
    const int m = s->m, nref = s->nref;
    okid_real *block = base + (size_t)k * (size_t)nref * (size_t)m;
    for (int l = 0; l < nref; ++l) {
        const okid_real rl = ref[l];
        okid_real *col = block + (size_t)l * (size_t)m;
        for (int a = 0; a < m; ++a) {
            col[a] += y[a] * rl;
        }
    }
}

void okid_corr_add(okid_correlation_sums_ *s, const okid_real *y)
{
    okid_real ref[OKID_MAX_DIMENSION];
    for (int l = 0; l < s->nref; ++l) {
        ref[l] = y[s->refs[l]];
    }
    const int segment = (int)((s->added / (uint64_t)s->block) % (uint64_t)s->segments);
    okid_real *base = s->sums + (size_t)segment * segment_reals(s);
    uint64_t *pairs = s->pairs + (size_t)segment * (size_t)(s->lags + 1);
    add_outer(s, base, 0, y, ref);
    for (int a = 0; a < s->m; ++a) {
        s->squares[a] += y[a] * y[a];
    }
    ++pairs[0];
    /* lag k is ring slot head - (k - 1): walked down from head, then from the top, without the
       modulo okid_ring_past() takes per lag (the same products in the same order) */
    const okid_ring_ *ring = &s->past;
    int k = 1;
    for (int slot = ring->head; slot >= 0 && k <= ring->fill; --slot, ++k) {
        add_outer(s, base, k, y, ring->data + (size_t)slot * (size_t)ring->width);
        ++pairs[k];
    }
    for (int slot = ring->depth - 1; k <= ring->fill; --slot, ++k) {
        add_outer(s, base, k, y, ring->data + (size_t)slot * (size_t)ring->width);
        ++pairs[k];
    }
    ++s->added;
    okid_ring_append(&s->past, ref, s->nref, NULL, 0);
}

uint64_t okid_corr_pairs(const okid_correlation_sums_ *s, int segment, int k)
{
    if (segment >= 0) {
        return s->pairs[(size_t)segment * (size_t)(s->lags + 1) + (size_t)k];
    }
    uint64_t total = 0;
    for (int j = 0; j < s->segments; ++j) {
        total += s->pairs[(size_t)j * (size_t)(s->lags + 1) + (size_t)k];
    }
    return total;
}

void okid_corr_estimate(const okid_correlation_sums_ *s, int segment, okid_real *r)
{
    const size_t block = (size_t)s->nref * (size_t)s->m, reals = segment_reals(s);
    const int first = segment >= 0 ? segment : 0, last = segment >= 0 ? segment : s->segments - 1;
    for (int k = 0; k <= s->lags; ++k) {
        const uint64_t pairs = okid_corr_pairs(s, segment, k);
        const okid_real inv = pairs > 0 ? 1 / (okid_real)pairs : 0;
        for (size_t i = (size_t)k * block; i < (size_t)(k + 1) * block; ++i) {
            okid_real sum = s->sums[(size_t)first * reals + i];
            for (int j = first + 1; j <= last; ++j) {
                sum += s->sums[(size_t)j * reals + i];
            }
            r[i] = sum * inv;
        }
    }
}

void okid_corr_rms(const okid_correlation_sums_ *s, okid_real *rms)
{
    const uint64_t samples = okid_corr_pairs(s, -1, 0);
    const okid_real inv = samples > 0 ? 1 / (okid_real)samples : 0;
    for (int a = 0; a < s->m; ++a) {
        rms[a] = okid_sqrt(s->squares[a] * inv);
    }
}

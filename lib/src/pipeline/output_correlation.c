/* SPDX-License-Identifier: Apache-2.0 */
/* Streaming output correlations: see output_correlation.h. */
#include "pipeline/output_correlation.h"

#include "numerics/dense.h"
#include "numerics/real_math.h"
#include "pipeline/sample_buffer.h"

void okid_corr_clear(okid_correlation_sums_ *s)
{
    okid_zero_matrix(s->m, s->nref * (s->lags + 1), s->sums, s->m);
    for (int a = 0; a < s->m; ++a) {
        s->squares[a] = 0;
    }
    for (int k = 0; k <= s->lags; ++k) {
        s->pairs[k] = 0;
    }
    okid_ring_restart(&s->past, 0);
}

void okid_corr_gap(okid_correlation_sums_ *s)
{
    okid_ring_restart(&s->past, 0);
}

/* S(k) += y ref' for one block k (m x nref at column k nref). */
static void add_outer(okid_correlation_sums_ *s, int k, const okid_real *y, const okid_real *ref)
{
    const int m = s->m, nref = s->nref;
    okid_real *block = s->sums + (size_t)k * (size_t)nref * (size_t)m;
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
    add_outer(s, 0, y, ref);
    for (int a = 0; a < s->m; ++a) {
        s->squares[a] += y[a] * y[a];
    }
    ++s->pairs[0];
    for (int k = 1; k <= s->past.fill; ++k) {
        add_outer(s, k, y, okid_ring_past(&s->past, k));
        ++s->pairs[k];
    }
    okid_ring_append(&s->past, ref, s->nref, NULL, 0);
}

void okid_corr_estimate(const okid_correlation_sums_ *s, okid_real *r, okid_real *rms)
{
    const int m = s->m, nref = s->nref;
    for (int k = 0; k <= s->lags; ++k) {
        const okid_real inv = s->pairs[k] > 0 ? 1 / (okid_real)s->pairs[k] : 0;
        const size_t first = (size_t)k * (size_t)nref * (size_t)m;
        for (size_t i = 0; i < (size_t)nref * (size_t)m; ++i) {
            r[first + i] = s->sums[first + i] * inv;
        }
    }
    const okid_real inv0 = s->pairs[0] > 0 ? 1 / (okid_real)s->pairs[0] : 0;
    for (int a = 0; a < m; ++a) {
        rms[a] = okid_sqrt(s->squares[a] * inv0);
    }
}

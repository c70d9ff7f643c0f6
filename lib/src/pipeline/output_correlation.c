/* SPDX-License-Identifier: Apache-2.0 */
/* Streaming output correlations: see output_correlation.h. */
#include "pipeline/output_correlation.h"

#include <string.h> /* memcpy */

#include "okid/sizes.h" /* OKID__AMB_BATCH */

#include "numerics/dense.h"
#include "numerics/linalg.h"
#include "numerics/real_math.h"
#include "pipeline/sample_buffer.h"

/* From this many products per lag (m r_ref) a batch goes to xGEMM (LAPACK backend); below, the
   register-tiled loop was as fast or faster (docs/design.md, "Batched correlation sums"). */
#define OKID__CORR_GEMM_MIN 16

/* Samples of okid_corr_add()'s run: each of its sums adds at most this many products before it
   joins the record's. In float, products added one by one to a sum N times their size lose about
   log2(N) of the 24 bits, all of them from N = 2^24 (R(0) of 3e7 samples was 7 % low); in runs,
   about log2(RUN) + log2(N / RUN) in the worst case, the host batches' accuracy (docs/ambient.md,
   "Limits"). */
#define OKID__CORR_RUN 256

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
    for (size_t i = 0; i < segment_reals(s) + (size_t)s->m; ++i) {
        s->partial[i] = 0;
    }
    s->partial_count = s->partial_segment = 0;
    s->added = 0;
    s->batching = s->pending = s->held = 0;
    s->batch_segment = 0;
    okid_ring_restart(&s->past, 0);
}

/* Add okid_corr_add()'s run to its segment's sums and squares, and start a new one. */
static void partial_flush(okid_correlation_sums_ *s)
{
    if (s->partial_count == 0) {
        return;
    }
    const size_t reals = segment_reals(s);
    okid_real *base = s->sums + (size_t)s->partial_segment * reals;
    for (size_t i = 0; i < reals; ++i) {
        base[i] += s->partial[i];
        s->partial[i] = 0;
    }
    for (int a = 0; a < s->m; ++a) {
        s->squares[a] += s->partial[reals + (size_t)a];
        s->partial[reals + (size_t)a] = 0;
    }
    s->partial_count = 0;
}

void okid_corr_gap(okid_correlation_sums_ *s)
{
    okid_ring_restart(&s->past, 0);
}

/* ---- Batches (okid_corr_batch_*; compiled with the LAPACK backend only: OKID__AMB_BATCH) ---- */
#if OKID__AMB_BATCH > 1

/* The batch's output a: its own row, or the history's when every output is a reference. */
static const okid_real *batch_output(const okid_correlation_sums_ *s, int a)
{
    return s->yblock != NULL ? s->yblock + (size_t)a * (size_t)s->batch
                             : s->hist + (size_t)a * (size_t)s->ldh + (size_t)s->lags;
}

enum { LAG_TILE = 8 }; /* narrow_products() spells its eight sums out */

/*
 * On x86-64 with GCC or Clang (ELF: the loader's ifunc picks the clone) the loop is also compiled
 * for AVX2, which holds the eight sums of a lag tile in two registers: 0.74 ms instead of 1.48 ms
 * for the paper's 40 000 samples when it was measured (docs/design.md; from 23 lags the wide tiles
 * below run instead). Each sum still adds its products one by one in sample order (no FMA: ISO C
 * contracts nothing), so both clones give the same bits.
 */
#if defined(__x86_64__) && defined(__GNUC__) && defined(__ELF__)
#define OKID__CORR_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define OKID__CORR_CLONES
#endif

/*
 * out(a, k nref + l) += sum_{i < p} y_a(i) r_l(i - k), k = 0 .. lags, for two outputs y0, y1 (y1
 * NULL: one) against the reference row rl (rl[i - k], i.e. the history's row at the batch): the
 * lags in tiles of LAG_TILE held in registers, each a dot product over the batch.
 */
OKID__CORR_CLONES static void narrow_products(int m, int nref, int lags, int p, const okid_real *y0, const okid_real *y1,
                                              const okid_real *rl, okid_real *out)
{
    const size_t block = (size_t)m * (size_t)nref;
    int k0 = 0;
    for (; k0 + LAG_TILE <= lags + 1; k0 += LAG_TILE) {
        /* c[j] sums lag k0 + LAG_TILE - 1 - j: its factor rl[i - k0 - LAG_TILE + 1 + j] */
        const okid_real *q = rl - k0 - (LAG_TILE - 1);
        okid_real c0[LAG_TILE] = {0}, c1[LAG_TILE] = {0};
        if (y1 != NULL) { /* sixteen scalars: the compilers keep them in registers (an array they did not) */
            okid_real a0 = 0, a1 = 0, a2 = 0, a3 = 0, a4 = 0, a5 = 0, a6 = 0, a7 = 0;
            okid_real b0 = 0, b1 = 0, b2 = 0, b3 = 0, b4 = 0, b5 = 0, b6 = 0, b7 = 0;
            for (int i = 0; i < p; ++i) {
                const okid_real v0 = y0[i], v1 = y1[i], *qi = q + i;
                a0 += v0 * qi[0], a1 += v0 * qi[1], a2 += v0 * qi[2], a3 += v0 * qi[3];
                a4 += v0 * qi[4], a5 += v0 * qi[5], a6 += v0 * qi[6], a7 += v0 * qi[7];
                b0 += v1 * qi[0], b1 += v1 * qi[1], b2 += v1 * qi[2], b3 += v1 * qi[3];
                b4 += v1 * qi[4], b5 += v1 * qi[5], b6 += v1 * qi[6], b7 += v1 * qi[7];
            }
            c0[0] = a0, c0[1] = a1, c0[2] = a2, c0[3] = a3, c0[4] = a4, c0[5] = a5, c0[6] = a6, c0[7] = a7;
            c1[0] = b0, c1[1] = b1, c1[2] = b2, c1[3] = b3, c1[4] = b4, c1[5] = b5, c1[6] = b6, c1[7] = b7;
        } else {
            for (int i = 0; i < p; ++i) {
                const okid_real v0 = y0[i], *qi = q + i;
                for (int j = 0; j < LAG_TILE; ++j) {
                    c0[j] += v0 * qi[j];
                }
            }
        }
        for (int j = 0; j < LAG_TILE; ++j) {
            okid_real *o = out + (size_t)(k0 + LAG_TILE - 1 - j) * block;
            o[0] += c0[j];
            if (y1 != NULL) {
                o[1] += c1[j];
            }
        }
    }
    for (; k0 <= lags; ++k0) {
        const okid_real *q = rl - k0;
        okid_real c0 = 0, c1 = 0;
        for (int i = 0; i < p; ++i) {
            c0 += y0[i] * q[i];
            if (y1 != NULL) {
                c1 += y1[i] * q[i];
            }
        }
        okid_real *o = out + (size_t)k0 * block;
        o[0] += c0;
        if (y1 != NULL) {
            o[1] += c1;
        }
    }
}


#if defined(__x86_64__) && defined(__GNUC__)
#define OKID__CORR_WIDE 1
enum { WIDE_TILE = 24 };

/* Four reals, one AVX2 register for double. The sums are named vectors stored one by one at the
   end: as an array (or copied through one) GCC 12 kept them in memory, a store and a load per
   sum and sample, at half the speed. */
typedef okid_real okid__corr_v4 __attribute__((vector_size(4 * sizeof(okid_real))));

__attribute__((target("avx2"))) static okid__corr_v4 load4(const okid_real *x)
{
    okid__corr_v4 v;
    memcpy(&v, x, sizeof v); /* unaligned */
    return v;
}

__attribute__((target("avx2"))) static void store4(okid_real *x, okid__corr_v4 v)
{
    memcpy(x, &v, sizeof v);
}

/*
 * With AVX2, twenty-four lags of two outputs: 48 sums in twelve registers, enough independent
 * chains to hide the adder's latency (the narrow loop's eight lags in four registers wait on it):
 * okid_ambient_push_block() of the paper's 40 000 samples (41 lags) 0.94 -> 0.67 ms on an
 * AVX-512 Intel core (docs/design.md, "Batched correlation sums"). c0[j], c1[j] = sum_{i < p}
 * y0(i) q(i + j), each in sample order from zero as the narrow loop sums them, and AVX2 has no FMA
 * to contract into: the same bits (test_ambient's test_batches_sum_in_sample_order).
 */
__attribute__((target("avx2"))) static void wide_tile2(int p, const okid_real *y0, const okid_real *y1,
                                                        const okid_real *q, okid_real *c0, okid_real *c1)
{
    okid__corr_v4 a0 = {0}, a1 = {0}, a2 = {0}, a3 = {0}, a4 = {0}, a5 = {0};
    okid__corr_v4 b0 = {0}, b1 = {0}, b2 = {0}, b3 = {0}, b4 = {0}, b5 = {0};
    for (int i = 0; i < p; ++i) {
        const okid__corr_v4 v = {y0[i], y0[i], y0[i], y0[i]}, w = {y1[i], y1[i], y1[i], y1[i]};
        const okid_real *qi = q + i;
        okid__corr_v4 x = load4(qi);
        a0 += v * x, b0 += w * x, x = load4(qi + 4);
        a1 += v * x, b1 += w * x, x = load4(qi + 8);
        a2 += v * x, b2 += w * x, x = load4(qi + 12);
        a3 += v * x, b3 += w * x, x = load4(qi + 16);
        a4 += v * x, b4 += w * x, x = load4(qi + 20);
        a5 += v * x, b5 += w * x;
    }
    store4(c0, a0), store4(c0 + 4, a1), store4(c0 + 8, a2), store4(c0 + 12, a3), store4(c0 + 16, a4);
    store4(c0 + 20, a5);
    store4(c1, b0), store4(c1 + 4, b1), store4(c1 + 8, b2), store4(c1 + 12, b3), store4(c1 + 16, b4);
    store4(c1 + 20, b5);
}

/* wide_tile2() for one output. */
__attribute__((target("avx2"))) static void wide_tile1(int p, const okid_real *y0, const okid_real *q, okid_real *c0)
{
    okid__corr_v4 a0 = {0}, a1 = {0}, a2 = {0}, a3 = {0}, a4 = {0}, a5 = {0};
    for (int i = 0; i < p; ++i) {
        const okid__corr_v4 v = {y0[i], y0[i], y0[i], y0[i]};
        const okid_real *qi = q + i;
        a0 += v * load4(qi), a1 += v * load4(qi + 4), a2 += v * load4(qi + 8);
        a3 += v * load4(qi + 12), a4 += v * load4(qi + 16), a5 += v * load4(qi + 20);
    }
    store4(c0, a0), store4(c0 + 4, a1), store4(c0 + 8, a2), store4(c0 + 12, a3), store4(c0 + 16, a4);
    store4(c0 + 20, a5);
}

/* narrow_products() in tiles of WIDE_TILE lags (lags + 1 >= WIDE_TILE): the last tile ends at lag
   `lags` and overlaps the one before, whose lags it does not add again. */
static void wide_products(int m, int nref, int lags, int p, const okid_real *y0, const okid_real *y1,
                          const okid_real *rl, okid_real *out)
{
    const size_t block = (size_t)m * (size_t)nref;
    for (int k0 = 0; k0 <= lags; k0 += WIDE_TILE) {
        const int start = k0 + WIDE_TILE <= lags + 1 ? k0 : lags + 1 - WIDE_TILE;
        /* c[j] sums lag start + WIDE_TILE - 1 - j: its factor rl[i - start - WIDE_TILE + 1 + j] */
        const okid_real *q = rl - start - (WIDE_TILE - 1);
        okid_real c0[WIDE_TILE], c1[WIDE_TILE];
        if (y1 != NULL) {
            wide_tile2(p, y0, y1, q, c0, c1);
        } else {
            wide_tile1(p, y0, q, c0);
        }
        for (int j = 0; j < WIDE_TILE; ++j) {
            const int k = start + WIDE_TILE - 1 - j;
            if (k >= k0) {
                okid_real *o = out + (size_t)k * block;
                o[0] += c0[j];
                if (y1 != NULL) {
                    o[1] += c1[j];
                }
            }
        }
    }
}
#else
#define OKID__CORR_WIDE 0
#endif

/* out(a, k nref + l) += sum_{i < p} y_a(i) r_l(i - k), k = 0 .. lags, for two outputs y0, y1 (y1
   NULL: one): the wide tiles where the CPU has AVX2 and the lags fill one, else the narrow loop. */
static void tiled_products(int m, int nref, int lags, int p, const okid_real *y0, const okid_real *y1,
                           const okid_real *rl, okid_real *out)
{
#if OKID__CORR_WIDE
    if (lags + 1 >= WIDE_TILE && __builtin_cpu_supports("avx2")) {
        wide_products(m, nref, lags, p, y0, y1, rl, out);
        return;
    }
#endif
    narrow_products(m, nref, lags, p, y0, y1, rl, out);
}

/* out(:, k nref .. k nref + nref - 1) += Y R_k' for the p pending samples, k = 0 .. lags <= s->lags
   (out: m x nref (lags + 1), leading dimension m); each lag's sum alone, in sample order, so the
   same bits for any lags. The history's zeros stand for lags held by no sample. */
static void batch_products(const okid_correlation_sums_ *s, int p, int lags, okid_real *out)
{
    const int m = s->m, nref = s->nref;
#if !OKID_LINALG_EIGEN
    if (m * nref > OKID__CORR_GEMM_MIN) {
        const int ldy = s->yblock != NULL ? s->batch : s->ldh;
        for (int k = 0; k <= lags; ++k) {
            (void)okid_la_add_product_tn(m, nref, p, batch_output(s, 0), ldy, s->hist + s->lags - k, s->ldh,
                                         out + (size_t)k * (size_t)m * (size_t)nref, m);
        }
        return;
    }
#endif
    for (int l = 0; l < nref; ++l) {
        const okid_real *rl = s->hist + (size_t)l * (size_t)s->ldh + (size_t)s->lags;
        int a = 0;
        for (; a + 2 <= m; a += 2) {
            tiled_products(m, nref, lags, p, batch_output(s, a), batch_output(s, a + 1), rl, out + (size_t)l * (size_t)m + (size_t)a);
        }
        if (a < m) {
            tiled_products(m, nref, lags, p, batch_output(s, a), NULL, rl, out + (size_t)l * (size_t)m + (size_t)a);
        }
    }
}

/* Sum the pending samples into their segment, count their pairs, move the history on. */
static void batch_flush(okid_correlation_sums_ *s)
{
    const int p = s->pending, lags = s->lags;
    if (p == 0) {
        return;
    }
    batch_products(s, p, lags, s->sums + (size_t)s->batch_segment * segment_reals(s));
    uint64_t *pairs = s->pairs + (size_t)s->batch_segment * (size_t)(lags + 1);
    for (int k = 0; k <= lags; ++k) { /* sample i of the batch pairs at lag k when k <= held + i */
        const int first = k > s->held ? k - s->held : 0;
        pairs[k] += p > first ? (uint64_t)(p - first) : 0u;
    }
    for (int l = 0; l < s->nref; ++l) { /* the last lags samples become the history */
        okid_real *row = s->hist + (size_t)l * (size_t)s->ldh;
        for (int j = 0; j < lags; ++j) {
            row[j] = row[j + p];
        }
    }
    s->held = s->held + p < lags ? s->held + p : lags;
    s->pending = 0;
}

void okid_corr_batch_begin(okid_correlation_sums_ *s)
{
    const okid_ring_ *ring = &s->past;
    if (s->batching) {
        return; /* the pending samples stay: the batches do not depend on how the record was cut */
    }
    partial_flush(s); /* the samples pushed one by one before */
    s->batching = 1;
    s->pending = 0;
    s->held = ring->fill;
    for (int l = 0; l < s->nref; ++l) {
        okid_real *row = s->hist + (size_t)l * (size_t)s->ldh;
        for (int j = 0; j < s->lags; ++j) {
            row[j] = 0;
        }
    }
    for (int k = 1; k <= ring->fill; ++k) { /* v(t - k) into column lags - k */
        const okid_real *v = okid_ring_past(ring, k);
        for (int l = 0; l < s->nref; ++l) {
            s->hist[(size_t)l * (size_t)s->ldh + (size_t)(s->lags - k)] = v[l];
        }
    }
}

void okid_corr_batch_add_rows(okid_correlation_sums_ *s, size_t count, const okid_real *y, size_t ldy)
{
    size_t t = 0;
    while (t < count) {
        /* no 64-bit divisions per sample without segments */
        const int segment = s->segments > 1 ? (int)((s->added / (uint64_t)s->block) % (uint64_t)s->segments) : 0;
        if (s->pending > 0 && segment != s->batch_segment) {
            batch_flush(s);
        }
        s->batch_segment = segment;
        /* the rows up to the batch's end and, with segments, the segment's */
        size_t take = (size_t)(s->batch - s->pending);
        if (s->segments > 1) {
            const uint64_t left = (uint64_t)s->block - s->added % (uint64_t)s->block;
            take = left < (uint64_t)take ? (size_t)left : take;
        }
        take = count - t < take ? count - t : take;
        const okid_real *rows = y + t * ldy;
        const size_t first = (size_t)s->pending;
        for (int l = 0; l < s->nref; ++l) {
            okid_real *h = s->hist + (size_t)l * (size_t)s->ldh + (size_t)s->lags + first;
            const okid_real *v = rows + s->refs[l];
            for (size_t i = 0; i < take; ++i) {
                h[i] = v[i * ldy];
            }
        }
        if (s->yblock != NULL) {
            for (int a = 0; a < s->m; ++a) {
                okid_real *o = s->yblock + (size_t)a * (size_t)s->batch + first;
                for (size_t i = 0; i < take; ++i) {
                    o[i] = rows[i * ldy + (size_t)a];
                }
            }
        }
        /* each channel's squares in sample order, as one sample at a time */
        int a = 0;
        for (; a + 2 <= s->m; a += 2) { /* two channels' sums side by side: their latencies overlap */
            okid_real q0 = s->squares[a], q1 = s->squares[a + 1];
            for (size_t i = 0; i < take; ++i) {
                const okid_real *row = rows + i * ldy + a;
                q0 += row[0] * row[0];
                q1 += row[1] * row[1];
            }
            s->squares[a] = q0, s->squares[a + 1] = q1;
        }
        if (a < s->m) {
            okid_real q = s->squares[a];
            for (size_t i = 0; i < take; ++i) {
                q += rows[i * ldy + (size_t)a] * rows[i * ldy + (size_t)a];
            }
            s->squares[a] = q;
        }
        s->added += take;
        s->pending += (int)take;
        t += take;
        if (s->pending == s->batch) {
            batch_flush(s);
        }
    }
}

void okid_corr_batch_gap(okid_correlation_sums_ *s)
{
    batch_flush(s);
    for (int l = 0; l < s->nref; ++l) {
        okid_real *row = s->hist + (size_t)l * (size_t)s->ldh;
        for (int j = 0; j < s->lags; ++j) {
            row[j] = 0;
        }
    }
    s->held = 0;
}

void okid_corr_batch_end(okid_correlation_sums_ *s)
{
    if (!s->batching) {
        return;
    }
    s->batching = 0;
    batch_flush(s);
    okid_ring_restart(&s->past, 0);
    okid_real ref[OKID_MAX_DIMENSION];
    for (int j = s->lags - s->held; j < s->lags; ++j) { /* oldest first, as okid_corr_add() appended them */
        for (int l = 0; l < s->nref; ++l) {
            ref[l] = s->hist[(size_t)l * (size_t)s->ldh + (size_t)j];
        }
        okid_ring_append(&s->past, ref, s->nref, NULL, 0);
    }
}

#endif /* OKID__AMB_BATCH > 1 */

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
    if (s->partial_count > 0 && segment != s->partial_segment) {
        partial_flush(s);
    }
    s->partial_segment = segment;
    okid_real *base = s->partial, *squares = s->partial + segment_reals(s);
    uint64_t *pairs = s->pairs + (size_t)segment * (size_t)(s->lags + 1);
    add_outer(s, base, 0, y, ref);
    for (int a = 0; a < s->m; ++a) {
        squares[a] += y[a] * y[a];
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
    if (++s->partial_count == OKID__CORR_RUN) {
        partial_flush(s);
    }
}

/* Pairs of the pending samples at lag k (none unless segment is theirs or -1). */
static uint64_t pending_pairs(const okid_correlation_sums_ *s, int segment, int k)
{
#if OKID__AMB_BATCH > 1
    if (s->pending == 0 || (segment >= 0 && segment != s->batch_segment)) {
        return 0;
    }
    const int first = k > s->held ? k - s->held : 0;
    return s->pending > first ? (uint64_t)(s->pending - first) : 0u;
#else
    (void)s, (void)segment, (void)k; /* no batch: nothing pending (the firmware's code as before) */
    return 0;
#endif
}

uint64_t okid_corr_pairs(const okid_correlation_sums_ *s, int segment, int k)
{
    if (segment >= 0) {
        return s->pairs[(size_t)segment * (size_t)(s->lags + 1) + (size_t)k] + pending_pairs(s, segment, k);
    }
    uint64_t total = pending_pairs(s, -1, k);
    for (int j = 0; j < s->segments; ++j) {
        total += s->pairs[(size_t)j * (size_t)(s->lags + 1) + (size_t)k];
    }
    return total;
}

void okid_corr_estimate(const okid_correlation_sums_ *s, int segment, int lags, okid_real *r)
{
    const size_t block = (size_t)s->nref * (size_t)s->m, reals = segment_reals(s);
    const int first = segment >= 0 ? segment : 0, last = segment >= 0 ? segment : s->segments - 1;
    /* the pending samples' products first, into r (the sums are not changed) */
    const int pending = pending_pairs(s, segment, 0) > 0;
    /* and okid_corr_add()'s run, when it adds to these segments (not into the sums either) */
    const int run = s->partial_count > 0 && (segment < 0 || segment == s->partial_segment);
#if OKID__AMB_BATCH > 1
    if (pending) {
        okid_zero_matrix(s->m, s->nref * (lags + 1), r, s->m);
        batch_products(s, s->pending, lags, r);
    }
#endif
    for (int k = 0; k <= lags; ++k) {
        const uint64_t pairs = okid_corr_pairs(s, segment, k);
        const okid_real inv = pairs > 0 ? 1 / (okid_real)pairs : 0;
        for (size_t i = (size_t)k * block; i < (size_t)(k + 1) * block; ++i) {
            okid_real sum = pending ? r[i] + s->sums[(size_t)first * reals + i] : s->sums[(size_t)first * reals + i];
            for (int j = first + 1; j <= last; ++j) {
                sum += s->sums[(size_t)j * reals + i];
            }
            if (run) {
                sum += s->partial[i];
            }
            r[i] = sum * inv;
        }
    }
}

void okid_corr_rms(const okid_correlation_sums_ *s, okid_real *rms)
{
    const uint64_t samples = okid_corr_pairs(s, -1, 0);
    const okid_real inv = samples > 0 ? 1 / (okid_real)samples : 0;
    const okid_real *run = s->partial + segment_reals(s); /* zeros without a run */
    for (int a = 0; a < s->m; ++a) {
        rms[a] = okid_sqrt((s->squares[a] + run[a]) * inv);
    }
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Streaming sums of the output correlations (okid/ambient.h):
 *   S(k) = sum_t y(t+k) y_ref(t)',  k = 0 .. lags,
 * from a ring of the last `lags` reference vectors, and the unbiased estimates R(k) = S(k) / pairs(k).
 * A gap (okid_corr_gap) empties the ring: no product spans it. With segments > 1 the sums of
 * sample t go to segment (t / block) mod segments, so that identify can also realize each
 * segment's correlations (the spread of their modes); the record's sums are their total.
 */
#ifndef OKID_OUTPUT_CORRELATION_H
#define OKID_OUTPUT_CORRELATION_H

#include "okid/correlation_storage.h" /* okid_correlation_sums_ */

/* Zero the sums and the counts and empty the ring. */
void okid_corr_clear(okid_correlation_sums_ *s);

/* A gap in the record: the next sample pairs with nothing before it. */
void okid_corr_gap(okid_correlation_sums_ *s);

/* Add the products of y(t) (m finite values) with itself and the ring's references, then ring it. */
void okid_corr_add(okid_correlation_sums_ *s, const okid_real *y);

/*
 * Batches (okid_ambient_push_block(), s->batch > 1): begin copies the ring into the history (once:
 * while batching, pending samples wait for the next call); add_rows takes count finite samples, row
 * t at y + t ldy (each one's square, count and segment as okid_corr_add()) and sums the products of a full batch, or of the
 * pending samples before the segment changes, as one matrix product per lag (xGEMM with the LAPACK
 * backend when m r_ref > OKID__CORR_GEMM_MIN, else a register-tiled loop); gap sums the pending
 * samples and empties the history; end (okid_ambient_push(), before its sample) sums them and
 * leaves the ring as okid_corr_add() would have. okid_corr_pairs() and okid_corr_estimate() count
 * the pending samples without summing them into the state. The same pairs as okid_corr_add()
 * sample by sample; the sums equal theirs to round-off (docs/ambient.md, "Batched sums").
 */
void okid_corr_batch_begin(okid_correlation_sums_ *s);
void okid_corr_batch_add_rows(okid_correlation_sums_ *s, size_t count, const okid_real *y, size_t ldy);
void okid_corr_batch_gap(okid_correlation_sums_ *s);
void okid_corr_batch_end(okid_correlation_sums_ *s);

/* R(k) = S(k) / pairs(k), k = 0 .. lags (lags <= s->lags: each lag's sum does not depend on how
   many are kept), of one segment (0 .. segments - 1) or, with segment -1, of the whole record, into
   r (m x nref (lags + 1), leading dimension m); 0 where a lag has no pair. */
void okid_corr_estimate(const okid_correlation_sums_ *s, int segment, int lags, okid_real *r);

/* Products summed at lag k, over every segment (segment -1) or in one. */
uint64_t okid_corr_pairs(const okid_correlation_sums_ *s, int segment, int k);

/* RMS of each output (m values) over the record into rms. */
void okid_corr_rms(const okid_correlation_sums_ *s, okid_real *rms);

#endif

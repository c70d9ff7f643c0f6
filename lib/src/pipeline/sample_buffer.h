/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Recursive buffering (eq. 35, 49): a ring of the last p samples v = [u; y] and the regressor
 * row built from it. Row layout (internal column order, inputs first so that the leading block of
 * the triangular factor is the input-only regressor, whose rank tells persistence of excitation):
 *   [ u(k) | u(k-1) ... u(k-p) | y(k-1) ... y(k-p) | y(k) ]
 *     r      r p                 m p                 m      (q = r + (r + m) p columns, then m)
 * The ring itself (okid_ring_, okid/ring_storage.h) also holds the instruments' past inputs.
 */
#ifndef OKID_SAMPLE_BUFFER_H
#define OKID_SAMPLE_BUFFER_H

#include "okid/ring_storage.h" /* okid_ring_ */

/* Empty the ring (zero_history: fill it with zeros, as a record that starts at rest). */
void okid_ring_restart(okid_ring_ *ring, int zero_history);

/* 1 when the ring holds depth vectors (always with depth 0). */
int okid_ring_full(const okid_ring_ *ring);

/* Append [a (na values); b (nb values)], na + nb = width, as the newest vector (no-op with depth 0). */
void okid_ring_append(okid_ring_ *ring, const okid_real *a, int na, const okid_real *b, int nb);

/* The newest-but-(j - 1) vector, j = 1 .. depth: v(k - j) when sample k is the next one. */
const okid_real *okid_ring_past(const okid_ring_ *ring, int j);

/* Write the regressor row of sample k (u: r values, y: m values; the window holds v(k-1) .. v(k-p),
   width r + m) to row (stride ld between columns). */
void okid_buffer_write_row(const okid_ring_ *window, int r, const okid_real *u, const okid_real *y, okid_real *row,
                           size_t ld);

/* okid_buffer_write_row() of `count` consecutive samples at once: u (count x r, sample k at u + k ldu)
   and y (count x m, at y + k ldy) hold samples k .. k + count - 1, the window their p predecessors;
   rows 0 .. count - 1 of block (stride ld between columns) get the same values, written column by
   column (one contiguous run per column instead of one strided store per column and sample). */
void okid_buffer_write_rows(const okid_ring_ *window, int r, int count, const okid_real *u, size_t ldu,
                            const okid_real *y, size_t ldy, okid_real *block, size_t ld);

/* y_hat = X' phi(k): the regressor row of (u, window) times the q x m solution x (leading dimension ldx). */
void okid_buffer_predict(const okid_ring_ *window, int r, const okid_real *u, const okid_real *x, int ldx,
                         okid_real *y_hat);

#endif

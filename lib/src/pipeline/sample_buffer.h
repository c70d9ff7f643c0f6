/*
 * Recursive buffering (eq. 35, 49): a ring of the last p samples v = [u; y] and the regressor
 * row built from it. Row layout (internal column order, inputs first so that the leading block of
 * the triangular factor is the input-only regressor, whose rank tells persistence of excitation):
 *   [ u(k) | u(k-1) ... u(k-p) | y(k-1) ... y(k-p) | y(k) ]
 *     r      r p                 m p                 m      (q = r + (r + m) p columns, then m)
 */
#ifndef OKID_SAMPLE_BUFFER_H
#define OKID_SAMPLE_BUFFER_H

#include "okid/identifier.h"

/* Empty the window (zero_history: fill it with zeros, as a record that starts at rest). */
void okid_buffer_restart(okid_identifier *id, int zero_history);

/* 1 when the window holds p past samples, so that sample k gives a regressor row. */
int okid_buffer_window_full(const okid_identifier *id);

/* Write the regressor row of sample k (u, y) into row `row` of the pending block (leading dimension block_rows). */
void okid_buffer_write_row(const okid_identifier *id, const okid_real *u, const okid_real *y, int row);

/* y_hat = X' phi(k): the regressor row of (u, window) times the q x m solution x (leading dimension q). */
void okid_buffer_predict(const okid_identifier *id, const okid_real *u, const okid_real *x, okid_real *y_hat);

/* Append v(k) = [u; y] to the window. */
void okid_buffer_append(okid_identifier *id, const okid_real *u, const okid_real *y);

#endif

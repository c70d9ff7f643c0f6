/* SPDX-License-Identifier: Apache-2.0 */
/* Folding one regressor row into the triangular factor by Givens rotations (okid_push's cost). */
#ifndef OKID_GIVENS_FOLD_H
#define OKID_GIVENS_FOLD_H

#include "okid/types.h"

/*
 * Fold one row (n values, stride inc) into the n x n upper-triangular r (column-major, leading
 * dimension ldr) with Givens rotations, each applied as three shears (givens_fold.c says why):
 * afterwards r' r = r' r + row row', and r's diagonal keeps its signs. The row is only read; t
 * and s (n reals each) take the rotations. About 3 n^2 flops: for a single row much cheaper than
 * a blocked Householder update. The bits are those of the textbook loop (rotation j sweeps row j
 * of r), in which an exactly zero row element makes no rotation; here it makes the identity,
 * which gives the same numbers (a zero of r may change its sign).
 */
void okid_givens_fold_row(int n, okid_real *r, int ldr, const okid_real *row, int inc, okid_real *t, okid_real *s);

#endif

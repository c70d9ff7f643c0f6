/* SPDX-License-Identifier: Apache-2.0 */
/* The Toeplitz block Gram of consecutive regressor rows: see toeplitz_gram.h. */
#include "pipeline/toeplitz_gram.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"

/* The row column holding channel s (inputs 0..r-1, then outputs) at lag l, sample_buffer.h's order:
   [u(k) | u(k-1) .. u(k-p) | y(k-1) .. y(k-p) | y(k)]. */
static int column(int r, int m, int p, int s, int l)
{
    if (s < r) {
        return l * r + s;
    }
    const int past_y = r * (p + 1);
    return l == 0 ? past_y + p * m + (s - r) : past_y + (l - 1) * m + (s - r);
}

/* The end of the run of rows from start in which each row is the one before shifted by a sample:
   exact comparisons, one column pair at a time (contiguous in the column-major block). */
static int run_end(int r, int m, int p, int start, int nrows, const okid_real *rows, size_t ld)
{
    int end = nrows;
    for (int s = 0; s < r + m; ++s) {
        for (int l = 0; l < p; ++l) {
            const okid_real *now = rows + (size_t)column(r, m, p, s, l) * ld;
            const okid_real *older = rows + (size_t)column(r, m, p, s, l + 1) * ld;
            for (int t = start; t + 1 < end; ++t) {
                if (older[t + 1] != now[t]) {
                    end = t + 1;
                    break;
                }
            }
        }
    }
    return end;
}

/* c += the Gram of the consecutive rows first..last: the first block row G_0j = Z0' [rows] by two
   products (Z0's inputs are the row's first r columns, its outputs the last m), then each block
   diagonal's G_(i+1)(j+1) from its G_ij in place with the two edge terms, block column by block
   column so that the additions to C stay in the few columns of one lag. work: g ((r + m) x w),
   then the first and the last row by (channel, lag), w reals each. */
static okid_status add_run(int r, int m, int p, int first, int last, const okid_real *rows, size_t ld, okid_real *c,
                           int ldc, okid_real *work)
{
    const int n = r + m, w = n * (p + 1), count = last - first + 1;
    okid_real *g = work, *head = work + (size_t)n * (size_t)w, *tail = head + w; /* z(k0 - l), z(k1 - l) at s + n l */
    const okid_real *block = rows + first;
    okid_zero_matrix(n, w, g, n);
    okid_status st = okid_la_add_product_tn(r, w, count, block, (int)ld, block, (int)ld, g, n);
    if (st == OKID_OK) {
        st = okid_la_add_product_tn(m, w, count, block + (size_t)(w - m) * ld, (int)ld, block, (int)ld, g + r, n);
    }
    if (st != OKID_OK) {
        return st;
    }
    for (int l = 0; l <= p; ++l) {
        for (int s = 0; s < n; ++s) {
            head[s + n * l] = rows[(size_t)first + (size_t)column(r, m, p, s, l) * ld];
            tail[s + n * l] = rows[(size_t)last + (size_t)column(r, m, p, s, l) * ld];
        }
    }
    for (int j = 0; j <= p; ++j) {
        for (int d = 0; d <= j; ++d) { /* diagonal d is at its block (j - d, j): it steps once per j */
            const int i = j - d, step = j < p;
            const okid_real *h1 = head + n * (i + 1), *t1 = tail + n * i;
            for (int s2 = 0; s2 < n; ++s2) {
                const int c2 = column(r, m, p, s2, j), s1_end = d == 0 ? s2 + 1 : n; /* G_ii: its upper half */
                okid_real *gs2 = g + (size_t)column(r, m, p, s2, d) * (size_t)n;       /* G_ij(:, s2) */
                const okid_real h2 = step ? head[s2 + n * (j + 1)] : 0, t2 = tail[s2 + n * j];
                /* inputs at lag i: rows i r .. of C's column c2, always above the diagonal */
                okid_real *to = &OKID_AT(c, ldc, column(r, m, p, 0, i), c2);
                const int inputs = s1_end < r ? s1_end : r;
                for (int s1 = 0; s1 < inputs; ++s1) {
                    to[s1] += gs2[s1];
                    if (step) {
                        gs2[s1] += h1[s1] * h2 - t1[s1] * t2;
                    }
                }
                /* outputs at lag i: below c2 (so row c2 of their columns) beside an input or y(k) beside a past y */
                const int c1 = column(r, m, p, r, i), below = s2 < r || (i == 0 && j > 0);
                const size_t stride = below ? (size_t)ldc : 1;
                to = below ? &OKID_AT(c, ldc, c2, c1) : &OKID_AT(c, ldc, c1, c2);
                for (int s1 = r; s1 < s1_end; ++s1) {
                    to[(size_t)(s1 - r) * stride] += gs2[s1];
                    if (step) {
                        gs2[s1] += h1[s1] * h2 - t1[s1] * t2;
                    }
                }
            }
        }
    }
    return OKID_OK;
}

okid_status okid_toeplitz_gram(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *c,
                               int ldc, okid_real *work)
{
    const int w = (r + m) * (p + 1);
    if (r < 0 || m < 0 || p < 0 || nrows < 0 || ldrows < (nrows > 1 ? nrows : 1) || ldc < (w > 1 ? w : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    for (int start = 0; start < nrows;) {
        const int end = run_end(r, m, p, start, nrows, rows, (size_t)ldrows);
        const okid_status st = add_run(r, m, p, start, end - 1, rows, (size_t)ldrows, c, ldc, work);
        if (st != OKID_OK) {
            return st;
        }
        start = end;
    }
    return OKID_OK;
}

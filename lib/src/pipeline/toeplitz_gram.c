/* SPDX-License-Identifier: Apache-2.0 */
/* The Toeplitz Gram of consecutive regressor rows: see toeplitz_gram.h. */
#include "pipeline/toeplitz_gram.h"

#include "numerics/dense.h"
#include "numerics/linalg.h"

#if !OKID_LINALG_EIGEN /* xGEMM: the LAPACK backend only (the firmware archive stays as it was) */

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

/* The run's parts: first block row g (n x w), first row head and last row tail (s + n l), open flag. */
typedef struct run_view {
    okid_real *g, *head, *tail, *open;
} run_view;

static run_view view_run(int r, int m, int p, okid_real *run)
{
    const size_t n = (size_t)(r + m), w = n * (size_t)(p + 1);
    const run_view v = {run, run + n * w, run + n * w + w, run + n * w + 2 * w};
    return v;
}

/* Row t of the rows by (channel, lag). */
static void gather(int r, int m, int p, const okid_real *rows, size_t ld, int t, okid_real *to)
{
    const int n = r + m;
    for (int l = 0; l <= p; ++l) {
        for (int s = 0; s < n; ++s) {
            to[s + n * l] = rows[(size_t)t + (size_t)column(r, m, p, s, l) * ld];
        }
    }
}

/* Row t is the row prev (by (channel, lag)) shifted by a sample. */
static int shifted(int r, int m, int p, const okid_real *rows, size_t ld, int t, const okid_real *prev)
{
    const int n = r + m;
    for (int l = 0; l < p; ++l) {
        for (int s = 0; s < n; ++s) {
            if (rows[(size_t)t + (size_t)column(r, m, p, s, l + 1) * ld] != prev[s + n * l]) {
                return 0;
            }
        }
    }
    return 1;
}

/* The end of the run of rows from start: exact comparisons, one column pair at a time (contiguous
   in the column-major block). */
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

/* g += Z0' rows(first .. first + count - 1): Z0's inputs are the row's first r columns, its outputs the last m. */
static okid_status add_first_block_row(int r, int m, int p, int first, int count, const okid_real *rows, size_t ld,
                                       okid_real *g)
{
    const int n = r + m, w = n * (p + 1);
    const okid_real *block = rows + first;
    const okid_status st = okid_la_add_product_tn(r, w, count, block, (int)ld, block, (int)ld, g, n);
    return st != OKID_OK ? st
                         : okid_la_add_product_tn(m, w, count, block + (size_t)(w - m) * ld, (int)ld, block, (int)ld,
                                                  g + r, n);
}

/* c += the run's Gram from its first block row g (overwritten): each block diagonal's
   G_(i+1)(j+1) from its G_ij in place with the two edge terms, block column by block column so
   that the additions to c stay in the few columns of one lag. */
static void assemble(int r, int m, int p, okid_real *g, const okid_real *head, const okid_real *tail, okid_real *c,
                     int ldc)
{
    const int n = r + m;
    for (int j = 0; j <= p; ++j) {
        for (int d = 0; d <= j; ++d) { /* diagonal d is at its block (j - d, j): it steps once per j */
            const int i = j - d, step = j < p;
            const okid_real *h1 = head + n * (i + 1), *t1 = tail + n * i;
            for (int s2 = 0; s2 < n; ++s2) {
                const int c2 = column(r, m, p, s2, j), s1_end = d == 0 ? s2 + 1 : n; /* G_ii: its upper half */
                okid_real *gs2 = g + (size_t)column(r, m, p, s2, d) * (size_t)n;       /* G_ij(:, s2) */
                const okid_real h2 = step ? head[s2 + n * (j + 1)] : 0, t2 = tail[s2 + n * j];
                /* inputs at lag i: rows i r .. of c's column c2, always above the diagonal */
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
}

void okid_toeplitz_restart(int r, int m, int p, okid_real *run)
{
    const run_view v = view_run(r, m, p, run);
    okid_zero_matrix(r + m, (r + m) * (p + 1), v.g, r + m);
    *v.open = 0;
}

okid_status okid_toeplitz_fold(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *run,
                               okid_real *c, int ldc)
{
    const int n = r + m, w = n * (p + 1);
    if (r < 0 || m < 0 || p < 0 || nrows < 0 || ldrows < (nrows > 1 ? nrows : 1) || ldc < (w > 1 ? w : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    const run_view v = view_run(r, m, p, run);
    const size_t ld = (size_t)ldrows;
    for (int start = 0; start < nrows;) {
        const int end = run_end(r, m, p, start, nrows, rows, ld);
        if (*v.open == 0 || start > 0 || !shifted(r, m, p, rows, ld, 0, v.tail)) { /* a new run */
            if (*v.open != 0) {
                assemble(r, m, p, v.g, v.head, v.tail, c, ldc);
                okid_zero_matrix(n, w, v.g, n);
            }
            gather(r, m, p, rows, ld, start, v.head);
            *v.open = 1;
        }
        const okid_status st = add_first_block_row(r, m, p, start, end - start, rows, ld, v.g);
        if (st != OKID_OK) {
            return st;
        }
        gather(r, m, p, rows, ld, end - 1, v.tail);
        start = end;
    }
    return OKID_OK;
}

void okid_toeplitz_close(int r, int m, int p, const okid_real *run, okid_real *c, int ldc, okid_real *work)
{
    const int n = r + m, w = n * (p + 1);
    const run_view v = view_run(r, m, p, (okid_real *)run);
    if (*v.open != 0) {
        okid_copy_matrix(n, w, v.g, n, work, n);
        assemble(r, m, p, work, v.head, v.tail, c, ldc);
    }
}

okid_status okid_toeplitz_gram(int r, int m, int p, int nrows, const okid_real *rows, int ldrows, okid_real *c,
                               int ldc, okid_real *work)
{
    okid_toeplitz_restart(r, m, p, work);
    const okid_status st = okid_toeplitz_fold(r, m, p, nrows, rows, ldrows, work, c, ldc);
    if (st == OKID_OK) {
        const run_view v = view_run(r, m, p, work);
        if (*v.open != 0) {
            assemble(r, m, p, v.g, v.head, v.tail, c, ldc);
        }
    }
    return st;
}
#endif

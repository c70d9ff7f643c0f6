/*
 * Givens fold of one row: see givens_fold.h. It is the whole cost of okid_push with block_rows 1
 * (3 n^2 flops against O(n) for the rest), hence the loop shape below, measured in instructions
 * per sample on a Cortex-M4F by bench/firmware/cost_report.c.
 */
#include "givens_fold.h"

#include "real_math.h"

/* The rotations must be inlined into the unrolled loop even at -Os, where a call costs more than
   the rotation itself. */
#if defined(__GNUC__)
#define OKID_INLINE_ALWAYS inline __attribute__((always_inline))
#else
#define OKID_INLINE_ALWAYS inline
#endif

/* The rotation (c, s) = (diag, x) / hypot that zeroes x against *diag, which becomes the hypot; for
   x == 0 the identity, which leaves *diag as it is. */
static void make_rotation(okid_real *diag, okid_real x, okid_real *c, okid_real *s)
{
    if (x == 0) {
        *c = 1;
        *s = 0;
        return;
    }
    const okid_real h = okid_hypot(*diag, x);
    *c = *diag / h;
    *s = x / h;
    *diag = h;
}

/* (a, x) <- (c a + s x, c x - s a): the operations of the textbook loop, in its order. */
static OKID_INLINE_ALWAYS void rotate(okid_real c, okid_real s, okid_real *a, okid_real *x)
{
    const okid_real a0 = *a, x0 = *x;
    *a = c * a0 + s * x0;
    *x = c * x0 - s * a0;
}

/* Rotation (c, s) on an element of each of the two columns, a and b, and their row elements. */
static OKID_INLINE_ALWAYS void rotate_two(okid_real c, okid_real s, okid_real *a, okid_real *b, okid_real *xa, okid_real *xb)
{
    rotate(c, s, a, xa);
    rotate(c, s, b, xb);
}

/*
 * Column by column, two at a time: columns k and k + 1 of r meet the rotations 0..k-1 made for
 * the columns before them, their row elements travelling along in registers; then they make
 * rotations k and k + 1. Every element sees the operations of the textbook loop in the same
 * order, so the bits are the same, but a column of r is contiguous, the row elements are not
 * loaded and stored at every step, and each (c, s) serves two columns, four rotations a pass:
 * 8.3 instructions per element on a Cortex-M4F at -Os against 14 for the textbook loop. (On an
 * out-of-order host it is some 15 % slower: a row element's rotations form a dependent chain.)
 */
void okid_givens_fold_row(int n, okid_real *r, int ldr, const okid_real *row, int inc, okid_real *c, okid_real *s)
{
    int k = n & 1; /* an odd n starts with column 0 alone: it meets no rotation */
    if (k == 1) {
        make_rotation(r, row[0], c, s);
    }
    const size_t pair_r = 2 * (size_t)ldr, pair_row = 2 * (size_t)inc;
    okid_real *col = r + (size_t)k * (size_t)ldr;
    const okid_real *x = row + (size_t)k * (size_t)inc;
    for (; k < n; k += 2, col += pair_r, x += pair_row) {
        okid_real *ca = col, *cb = col + ldr;
        okid_real xa = x[0], xb = x[inc];
        const okid_real *cj = c, *sj = s;
        /* k & 3 rotations, then k / 4 passes of four; the pass tests at its end (a branch less
           than a for loop at -Os) */
        if (k & 1) {
            rotate_two(*cj++, *sj++, ca++, cb++, &xa, &xb);
        }
        if (k & 2) {
            rotate_two(cj[0], sj[0], &ca[0], &cb[0], &xa, &xb);
            rotate_two(cj[1], sj[1], &ca[1], &cb[1], &xa, &xb);
            cj += 2;
            sj += 2;
            ca += 2;
            cb += 2;
        }
        const okid_real *const end = c + k;
        if (cj != end) {
            do {
                rotate_two(cj[0], sj[0], &ca[0], &cb[0], &xa, &xb);
                rotate_two(cj[1], sj[1], &ca[1], &cb[1], &xa, &xb);
                rotate_two(cj[2], sj[2], &ca[2], &cb[2], &xa, &xb);
                rotate_two(cj[3], sj[3], &ca[3], &cb[3], &xa, &xb);
                cj += 4;
                sj += 4;
                ca += 4;
                cb += 4;
            } while (cj != end);
        }
        /* ca and cb are at row k now */
        okid_real *ck = c + k, *sk = s + k;
        make_rotation(ca, xa, ck, sk);
        rotate(*ck, *sk, cb, &xb);
        make_rotation(cb + 1, xb, ck + 1, sk + 1);
    }
}

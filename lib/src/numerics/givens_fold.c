/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Givens fold of one row: see givens_fold.h. It is the whole cost of okid_push with block_rows 1
 * (3 n^2 flops against O(n) for the rest), hence the loop shape below, measured in instructions
 * per sample on a Cortex-M4F by bench/firmware/cost_report.c.
 */
#include "numerics/givens_fold.h"

#include "numerics/real_math.h"

/* The rotations must be inlined into the unrolled loop even at -Os, where a call costs more than
   the rotation itself. */
#if defined(__GNUC__)
#define OKID_INLINE_ALWAYS inline __attribute__((always_inline))
#else
#define OKID_INLINE_ALWAYS inline
#endif

/*
 * Why shears. Over a long record R's entries grow like sqrt(k) while sample k changes them by
 * about 1/k of their size: after 10^6 samples some ten units in the last place of a float. In the
 * textbook form a' = c a + s x, c = 1 - O(1/k) lies on the grid of floats just below 1, which
 * keeps only a few bits of 1 - c, the rotation's real content; those errors do not average out
 * over the record, and they made the float build's slow-mode frequency and damping errors 9 and
 * 19 times the double build's after 10^6 noisy samples (docs/accuracy.md). The same rotation as
 * three shears with t = tan(theta / 2) = s / (1 + c),
 *   x1 = x - t a,   a' = a + s x1,   x' = x1 - t a',
 * changes R's element by one small increment s x1, computed to full relative precision and
 * rounded once, and costs three multiply-adds where the textbook form takes four.
 */

/* The rotation that zeroes x against *diag: *diag becomes sign(*diag) hypot(*diag, x), with s and
   t = s / (1 + c) for the shears (c = |*diag| / hypot >= 0, so |t| <= 1); for x == 0 the
   identity. The hypot is *diag's magnitude plus the increment x^2 / (|*diag| + hypot), which
   depends on the first hypot's rounding only to second order: correctly rounded but for a few
   eps of the increment. It stores -t, *minus_t: each shear is then a plain multiply-add,
   x + (-t) a (negation is exact: the same bits as x - t a), where t itself costs RV32F an fneg
   per rotation and column pair. The identity's -0 keeps x - 0 a's sign of zero. */
static void make_rotation(okid_real *diag, okid_real x, okid_real *minus_t, okid_real *s)
{
    if (x == 0) {
        *minus_t = -(okid_real)0;
        *s = 0;
        return;
    }
    const okid_real d = okid_fabs(*diag), x_abs = okid_fabs(x);
    const okid_real h = d + x_abs * (x_abs / (d + okid_hypot(d, x_abs)));
    const okid_real sign = *diag < 0 ? -1 : 1;
    *s = x / (sign * h);
    *minus_t = x / (-sign * (d + h));
    *diag = sign * h;
}

/*
 * (a, x) <- (c a + s x, c x - s a) as three shears (see above). RV32F has no unfused multiply-add:
 * each shear is an fmul and an fadd there, six instructions an element where the Arm cores'
 * VMLA takes three. With OKID_FUSED_FOLD (CMake option; the riscv32 preset turns it on) the
 * shears are fmaf/fma, which C defines as correctly rounded: one fmadd.s on RV32F (VFMA on the
 * Arm FPUs), and the same bits from the host's libm, so the host twin still matches the target
 * bit for bit (-ffp-contract=fast fuses where the compiler chooses, which no host build
 * reproduces).
 */
static OKID_INLINE_ALWAYS void rotate(okid_real minus_t, okid_real s, okid_real *a, okid_real *x)
{
#if OKID_FUSED_FOLD
    const okid_real x1 = okid_fma(minus_t, *a, *x);
    *a = okid_fma(s, x1, *a);
    *x = okid_fma(minus_t, *a, x1);
#else
    const okid_real x1 = *x + minus_t * *a;
    *a += s * x1;
    *x = x1 + minus_t * *a;
#endif
}

/* Rotation (-t, s) on an element of each of the two columns, a and b, and their row elements. */
static OKID_INLINE_ALWAYS void rotate_two(okid_real minus_t, okid_real s, okid_real *a, okid_real *b, okid_real *xa, okid_real *xb)
{
    rotate(minus_t, s, a, xa);
    rotate(minus_t, s, b, xb);
}

/*
 * Column by column, two at a time: columns k and k + 1 of r meet the rotations 0..k-1 made for
 * the columns before them, their row elements travelling along in registers; then they make
 * rotations k and k + 1. Every element sees the operations of the textbook loop in the same
 * order, so the bits are the same, but a column of r is contiguous, the row elements are not
 * loaded and stored at every step, and each (t, s) serves two columns, four rotations a pass:
 * 52 instructions for its 8 elements on a Cortex-M4F at -Os (each a load and a store of r and
 * three VMLA, and a load of t or s for every other), against 14 an element for the textbook
 * loop. (On an out-of-order host it is some 15 % slower: a row element's rotations form a
 * dependent chain.)
 */
void okid_givens_fold_row(int n, okid_real *r, int ldr, const okid_real *row, int inc, okid_real *t, okid_real *s)
{
    /* rotation j: t[j] holds its -t (make_rotation), s[j] its s */
    int k = n & 1; /* an odd n starts with column 0 alone: it meets no rotation */
    if (k == 1) {
        make_rotation(r, row[0], t, s);
    }
    const size_t pair_r = 2 * (size_t)ldr, pair_row = 2 * (size_t)inc;
    okid_real *col = r + (size_t)k * (size_t)ldr;
    const okid_real *x = row + (size_t)k * (size_t)inc;
    for (; k < n; k += 2, col += pair_r, x += pair_row) {
        okid_real *ca = col, *cb = col + ldr;
        okid_real xa = x[0], xb = x[inc];
        const okid_real *tj = t, *sj = s;
        /* k & 3 rotations, then k / 4 passes of four; the pass tests at its end (a branch less
           than a for loop at -Os) */
        if (k & 1) {
            rotate_two(*tj++, *sj++, ca++, cb++, &xa, &xb);
        }
        if (k & 2) {
            rotate_two(tj[0], sj[0], &ca[0], &cb[0], &xa, &xb);
            rotate_two(tj[1], sj[1], &ca[1], &cb[1], &xa, &xb);
            tj += 2;
            sj += 2;
            ca += 2;
            cb += 2;
        }
        const okid_real *const end = t + k;
        if (tj != end) {
            do {
                rotate_two(tj[0], sj[0], &ca[0], &cb[0], &xa, &xb);
                rotate_two(tj[1], sj[1], &ca[1], &cb[1], &xa, &xb);
                rotate_two(tj[2], sj[2], &ca[2], &cb[2], &xa, &xb);
                rotate_two(tj[3], sj[3], &ca[3], &cb[3], &xa, &xb);
                tj += 4;
                sj += 4;
                ca += 4;
                cb += 4;
            } while (tj != end);
        }
        /* ca and cb are at row k now */
        okid_real *tk = t + k, *sk = s + k;
        make_rotation(ca, xa, tk, sk);
        rotate(*tk, *sk, cb, &xb);
        make_rotation(cb + 1, xb, tk + 1, sk + 1);
    }
}

/* Rank-revealing least squares on a triangular matrix by Givens rotations: see triangular_lstsq.h. */
#include "triangular_lstsq.h"

#include "real_math.h"

/* a(i, j) of the row-stored triangle */
#define T_AT(a, lda, i, j) ((a)[(size_t)(i) * (size_t)(lda) + (size_t)(j)])

/* Relative machine precision as LAPACK's xLAMCH('E') reports it (round to nearest). */
#define ICE_EPS (OKID_EPSILON / 2)

static okid_real max_real(okid_real a, okid_real b)
{
    return a > b ? a : b;
}

/* ---- incremental condition estimation (Bischof 1990): the cases and formulas of LAPACK's xLAIC1
   (modified BSD licence), as the Eigen backend's port of it ---- */

typedef struct ice_step {
    okid_real sest, s, c;
} ice_step;

static ice_step ice(okid_real sest, okid_real s, okid_real c)
{
    const ice_step step = {sest, s, c};
    return step;
}

/* x (unit norm) has |R' x| = sest, the largest singular value's estimate for the j x j triangle R;
   the estimate for R extended by the column [w; gamma] (alpha = x' w) and the sine/cosine that extend x. */
static ice_step ice_largest(okid_real sest, okid_real alpha, okid_real gamma)
{
    const okid_real absalp = okid_fabs(alpha), absgam = okid_fabs(gamma), absest = okid_fabs(sest);
    if (sest == 0) {
        const okid_real s1 = max_real(absgam, absalp);
        if (s1 == 0) {
            return ice(0, 0, 1);
        }
        const okid_real s = alpha / s1, c = gamma / s1, tmp = okid_sqrt(s * s + c * c);
        return ice(s1 * tmp, s / tmp, c / tmp);
    }
    if (absgam <= ICE_EPS * absest) {
        const okid_real tmp = max_real(absest, absalp), s1 = absest / tmp, s2 = absalp / tmp;
        return ice(tmp * okid_sqrt(s1 * s1 + s2 * s2), 1, 0);
    }
    if (absalp <= ICE_EPS * absest) {
        return absgam <= absest ? ice(absest, 1, 0) : ice(absgam, 0, 1);
    }
    if (absest <= ICE_EPS * absalp || absest <= ICE_EPS * absgam) {
        if (absgam <= absalp) {
            const okid_real tmp = absgam / absalp, s = okid_sqrt(1 + tmp * tmp);
            return ice(absalp * s, okid_copysign(1, alpha) / s, (gamma / absalp) / s);
        }
        const okid_real tmp = absalp / absgam, c = okid_sqrt(1 + tmp * tmp);
        return ice(absgam * c, (alpha / absgam) / c, okid_copysign(1, gamma) / c);
    }
    const okid_real zeta1 = alpha / absest, zeta2 = gamma / absest;
    const okid_real b = (1 - zeta1 * zeta1 - zeta2 * zeta2) / 2, c = zeta1 * zeta1;
    const okid_real t = b > 0 ? c / (b + okid_sqrt(b * b + c)) : okid_sqrt(b * b + c) - b;
    const okid_real sine = -zeta1 / t, cosine = -zeta2 / (1 + t), tmp = okid_sqrt(sine * sine + cosine * cosine);
    return ice(okid_sqrt(t + 1) * absest, sine / tmp, cosine / tmp);
}

/* The same for the smallest singular value. */
static ice_step ice_smallest(okid_real sest, okid_real alpha, okid_real gamma)
{
    const okid_real absalp = okid_fabs(alpha), absgam = okid_fabs(gamma), absest = okid_fabs(sest);
    if (sest == 0) {
        okid_real sine = 1, cosine = 0;
        if (max_real(absgam, absalp) != 0) {
            sine = -gamma;
            cosine = alpha;
        }
        const okid_real s1 = max_real(okid_fabs(sine), okid_fabs(cosine)), s = sine / s1, c = cosine / s1;
        const okid_real tmp = okid_sqrt(s * s + c * c);
        return ice(0, s / tmp, c / tmp);
    }
    if (absgam <= ICE_EPS * absest) {
        return ice(absgam, 0, 1);
    }
    if (absalp <= ICE_EPS * absest) {
        return absgam <= absest ? ice(absgam, 0, 1) : ice(absest, 1, 0);
    }
    if (absest <= ICE_EPS * absalp || absest <= ICE_EPS * absgam) {
        if (absgam <= absalp) {
            const okid_real tmp = absgam / absalp, c = okid_sqrt(1 + tmp * tmp);
            return ice(absest * (tmp / c), -(gamma / absalp) / c, okid_copysign(1, alpha) / c);
        }
        const okid_real tmp = absalp / absgam, s = okid_sqrt(1 + tmp * tmp);
        return ice(absest / s, -okid_copysign(1, gamma) / s, (alpha / absgam) / s);
    }
    const okid_real zeta1 = alpha / absest, zeta2 = gamma / absest;
    const okid_real norma =
        max_real(1 + zeta1 * zeta1 + okid_fabs(zeta1 * zeta2), okid_fabs(zeta1 * zeta2) + zeta2 * zeta2);
    const okid_real floor = 4 * ICE_EPS * ICE_EPS * norma;
    okid_real sine, cosine, sestpr;
    if (1 + 2 * (zeta1 - zeta2) * (zeta1 + zeta2) >= 0) { /* root close to zero */
        const okid_real b = (zeta1 * zeta1 + zeta2 * zeta2 + 1) / 2, c = zeta2 * zeta2;
        const okid_real t = c / (b + okid_sqrt(okid_fabs(b * b - c)));
        sine = zeta1 / (1 - t);
        cosine = -zeta2 / t;
        sestpr = okid_sqrt(t + floor) * absest;
    } else { /* root closer to one: shift by it */
        const okid_real b = (zeta2 * zeta2 + zeta1 * zeta1 - 1) / 2, c = zeta1 * zeta1;
        const okid_real t = b >= 0 ? -c / (b + okid_sqrt(b * b + c)) : b - okid_sqrt(b * b + c);
        sine = -zeta1 / t;
        cosine = -zeta2 / (1 + t);
        sestpr = okid_sqrt(1 + t + floor) * absest;
    }
    const okid_real tmp = okid_sqrt(sine * sine + cosine * cosine);
    return ice(sestpr, sine / tmp, cosine / tmp);
}

/* ---- pivoting inside the triangle ---- */

/*
 * Swap columns t - 1 and t of the triangle and restore it by the rotation of rows t - 1 and t that
 * zeroes the one element the swap puts below the diagonal; b gets the same rotation (Q' b).
 */
static void swap_adjacent(int n, okid_real *a, int lda, int t, int nrhs, okid_real *b, int ldb)
{
    for (int i = 0; i < t - 1; ++i) {
        const okid_real tmp = T_AT(a, lda, i, t - 1);
        T_AT(a, lda, i, t - 1) = T_AT(a, lda, i, t);
        T_AT(a, lda, i, t) = tmp;
    }
    const okid_real x = T_AT(a, lda, t - 1, t), y = T_AT(a, lda, t, t), left = T_AT(a, lda, t - 1, t - 1);
    const okid_real h = okid_hypot(x, y);
    const okid_real c = h > 0 ? x / h : 1, s = h > 0 ? y / h : 0;
    T_AT(a, lda, t - 1, t - 1) = h;
    T_AT(a, lda, t - 1, t) = c * left;
    T_AT(a, lda, t, t) = -s * left;
    for (int j = t + 1; j < n; ++j) {
        const okid_real u = T_AT(a, lda, t - 1, j), v = T_AT(a, lda, t, j);
        T_AT(a, lda, t - 1, j) = c * u + s * v;
        T_AT(a, lda, t, j) = c * v - s * u;
    }
    for (int k = 0; k < nrhs; ++k) {
        okid_real *col = b + (size_t)k * (size_t)ldb;
        const okid_real u = col[t - 1], v = col[t];
        col[t - 1] = c * u + s * v;
        col[t] = c * v - s * u;
    }
}

/* Squared norm of column j below row i - 1 (rows i..j). */
static okid_real trailing_norm2(const okid_real *a, int lda, int i, int j)
{
    okid_real s = 0;
    for (int l = i; l <= j; ++l) {
        s += T_AT(a, lda, l, j) * T_AT(a, lda, l, j);
    }
    return s;
}

/*
 * Pivoted triangular QR (xLAQP2's order: the column of largest remaining norm next) and its
 * numerical rank by incremental condition estimation (xGELSY), column by column, stopping at the
 * first column the estimate rejects: rows 0..rank-1 of the factor and of Q' b are then final.
 */
static int pivoted_rank(int n, okid_real *a, int lda, int nrhs, okid_real *b, int ldb, okid_real rcond, int *perm,
                        okid_real *xmin, okid_real *xmax)
{
    okid_real smin = 0, smax = 0;
    for (int i = 0; i < n; ++i) {
        int pvt = i;
        okid_real best = trailing_norm2(a, lda, i, i);
        for (int j = i + 1; j < n; ++j) {
            const okid_real norm2 = trailing_norm2(a, lda, i, j);
            if (norm2 > best) {
                best = norm2;
                pvt = j;
            }
        }
        for (int t = pvt; t > i; --t) { /* move column pvt to i, the columns between one back */
            swap_adjacent(n, a, lda, t, nrhs, b, ldb);
            const int moved = perm[t - 1];
            perm[t - 1] = perm[t];
            perm[t] = moved;
        }
        if (i == 0) { /* the estimate starts from |r00| */
            smax = smin = okid_fabs(T_AT(a, lda, 0, 0));
            if (smax == 0) {
                return 0;
            }
            xmin[0] = xmax[0] = 1;
            continue;
        }
        okid_real alpha_min = 0, alpha_max = 0; /* does column i keep the condition below 1 / rcond? */
        for (int l = 0; l < i; ++l) {
            alpha_min += xmin[l] * T_AT(a, lda, l, i);
            alpha_max += xmax[l] * T_AT(a, lda, l, i);
        }
        const ice_step lo = ice_smallest(smin, alpha_min, T_AT(a, lda, i, i));
        const ice_step hi = ice_largest(smax, alpha_max, T_AT(a, lda, i, i));
        if (hi.sest * rcond > lo.sest) {
            return i;
        }
        for (int l = 0; l < i; ++l) {
            xmin[l] *= lo.s;
            xmax[l] *= hi.s;
        }
        xmin[i] = lo.c;
        xmax[i] = hi.c;
        smin = lo.sest;
        smax = hi.sest;
    }
    return n;
}

/*
 * The elementary reflector of xLARFG on [alpha; x] (x: len contiguous reals): alpha becomes beta,
 * x the vector v of H = I - tau [1; v] [1; v]'. Returns tau (0: H = I).
 */
static okid_real make_reflector(okid_real *alpha, okid_real *x, int len)
{
    okid_real xnorm = 0;
    for (int l = 0; l < len; ++l) {
        xnorm += x[l] * x[l];
    }
    xnorm = okid_sqrt(xnorm);
    if (xnorm == 0) {
        return 0;
    }
    const okid_real beta = -okid_copysign(okid_hypot(*alpha, xnorm), *alpha);
    const okid_real tau = (beta - *alpha) / beta, scale = 1 / (*alpha - beta);
    for (int l = 0; l < len; ++l) {
        x[l] *= scale;
    }
    *alpha = beta;
    return tau;
}

/* [head; tail] -= tau [1; v] ([1; v]' [head; tail]); tail with stride inc. */
static void apply_reflector(okid_real tau, const okid_real *v, int len, okid_real *head, okid_real *tail, int inc)
{
    okid_real w = *head;
    for (int l = 0; l < len; ++l) {
        w += v[l] * tail[(size_t)l * (size_t)inc];
    }
    w *= tau;
    *head -= w;
    for (int l = 0; l < len; ++l) {
        tail[(size_t)l * (size_t)inc] -= w * v[l];
    }
}

int okid_triangular_lstsq(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb, okid_real rcond, int *perm,
                          okid_real *work)
{
    okid_real *xmin = work, *xmax = work + n, *ztau = work + 2 * n, *column = work + 3 * n;
    for (int j = 0; j < n; ++j) {
        perm[j] = j;
    }
    const int rank = pivoted_rank(n, a, lda, nrhs, b, ldb, rcond, perm, xmin, xmax);
    const int tail = n - rank;
    /* [T11 T12] = [T 0] Z with Z = Z(0) ... Z(rank-1) (xTZRZF): z vectors into T12's rows. */
    for (int i = rank - 1; i >= 0 && tail > 0; --i) {
        okid_real *z = &T_AT(a, lda, i, rank);
        ztau[i] = make_reflector(&T_AT(a, lda, i, i), z, tail);
        for (int k = 0; k < i; ++k) {
            apply_reflector(ztau[i], z, tail, &T_AT(a, lda, k, i), &T_AT(a, lda, k, rank), 1);
        }
    }
    for (int c = 0; c < nrhs; ++c) {
        okid_real *x = b + (size_t)c * (size_t)ldb;
        for (int i = rank - 1; i >= 0; --i) { /* T y = (Q' b)(0:rank) */
            if (x[i] != 0) {
                x[i] /= T_AT(a, lda, i, i);
                for (int l = 0; l < i; ++l) {
                    x[l] -= x[i] * T_AT(a, lda, l, i);
                }
            }
        }
        for (int i = rank; i < n; ++i) {
            x[i] = 0;
        }
        for (int i = 0; i < rank && tail > 0; ++i) { /* Z' [y; 0] */
            apply_reflector(ztau[i], &T_AT(a, lda, i, rank), tail, &x[i], &x[rank], 1);
        }
        for (int i = 0; i < n; ++i) { /* undo the column permutation */
            column[perm[i]] = x[i];
        }
        for (int i = 0; i < n; ++i) {
            x[i] = column[i];
        }
    }
    return rank;
}

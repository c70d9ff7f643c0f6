// SPDX-License-Identifier: Apache-2.0
/*
 * The Eigen backend of linalg.h, for targets without LAPACK (bare-metal Cortex-M). Heap-free and
 * re-entrant: every matrix is an Eigen::Map over the caller's memory (the identifier's workspace);
 * the QR update, the rank-revealing least squares and the SVD run in place in it, and the one
 * decomposition object, Eigen's RealSchur of a fixed maximum order (OKID__EIGEN_SCHUR_ORDER: 8 for
 * up to 8 states, else OKID_EIGEN_MAX_ORDER), is built in the caller's work array. No statics, no exceptions, no RTTI; EIGEN_NO_MALLOC makes any
 * allocation an assertion failure in builds with assertions. Work sizes: OKID__LWORK_* in the
 * public headers, under OKID_LINALG_EIGEN.
 *
 * The least squares follows LAPACK's xGELSY step by step (xLARFG reflectors, xLAQP2 pivoting and
 * norm downdating, xLAIC1 condition estimation, xTZRZF), so that both backends take the same rank
 * decisions; the SVD is a one-sided Jacobi SVD after a QR (as xGEJSV), the eigenproblem Eigen's
 * real Schur form after a Hessenberg reduction, with eigenvectors in xGEEV's layout.
 */
#define EIGEN_NO_MALLOC
#define EIGEN_MPL2_ONLY
#define EIGEN_NO_IO
/* Scalar code in one fixed order on every target, so that the host twin and the Cortex-M agree
   bit for bit (tests/target); the sizes here are tens, SIMD would gain little. */
#define EIGEN_DONT_VECTORIZE
/* Eigen's matrix-vector products take a temporary from alloca when an operand is not directly
   addressable; with the fixed-maximum-size operands here they never do (they use a fixed-size
   local). A trap instead of alloca keeps every stack frame static (.su) and a missed case loud. */
#include <cstddef>
[[noreturn]] static inline void *okid_eigen_no_alloca(std::size_t)
{
    __builtin_trap();
}
#define EIGEN_ALLOCA(bytes) okid_eigen_no_alloca(bytes)

#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <Eigen/Jacobi>

#include <cmath>
#include <complex>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <memory>
#include <new>
#include <type_traits>

extern "C" {
#include "numerics/linalg.h"

#include "numerics/condition_estimate.h"
#include "numerics/dense.h"
#include "numerics/givens_fold.h"
}
#include "numerics/real_math.h"
#include "okid/sizes.h"

namespace {

using Real = okid_real;
using Matrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic>;
using MatrixMap = Eigen::Map<Matrix, Eigen::Unaligned, Eigen::OuterStride<>>;
using VectorMap = Eigen::Map<Eigen::Matrix<Real, Eigen::Dynamic, 1>>;
/* Real Schur decompositions with their results inline: one of order up to the small order (the
   usual few modes: its work array is a small fraction of the largest's) and one of the largest
   order the build supports (okid/modal.h, OKID__EIGEN_SCHUR_ORDER). */
template <int N>
using EigMatrix = Eigen::Matrix<Real, Eigen::Dynamic, Eigen::Dynamic, Eigen::ColMajor, N, N>;
template <int N>
using Schur = Eigen::RealSchur<EigMatrix<N>>;
template <int N>
constexpr std::size_t kSchurBytes = (sizeof(Schur<N>) + 15u) / 16u * 16u;

template <int N>
constexpr bool schur_fits()
{
    return kSchurBytes<N> + alignof(Schur<N>) + 2 * sizeof(Real) * N <= sizeof(Real) * OKID__LWORK_GEEV(N);
}
static_assert(schur_fits<OKID__EIGEN_SMALL_ORDER>() && schur_fits<OKID_EIGEN_MAX_ORDER>(),
              "OKID__LWORK_GEEV (okid/modal.h) must hold the RealSchur of its order and a complex vector");

/* Relative machine precision as LAPACK's xLAMCH('E') reports it (round to nearest). */
constexpr Real kEps = std::numeric_limits<Real>::epsilon() / 2;

MatrixMap map(Real *p, int rows, int cols, int ld)
{
    return MatrixMap(p, rows, cols, Eigen::OuterStride<>(ld));
}

bool bad_matrix(int rows, int cols, int ld)
{
    return rows < 0 || cols < 0 || ld < (rows > 1 ? rows : 1);
}

/*
 * The elementary reflector of xLARFG: H [alpha; x] = [beta; 0] with H = I - tau [1; v] [1; v]'.
 * On return alpha holds beta and x holds v; tau = 0 (H = I) when x is already zero.
 */
template <typename Vec>
Real make_reflector(Real &alpha, Vec &&x)
{
    const Real xnorm = x.norm();
    if (xnorm == 0) {
        return 0;
    }
    const Real beta = -std::copysign(okid_hypot(alpha, xnorm), alpha);
    const Real tau = (beta - alpha) / beta;
    x *= 1 / (alpha - beta);
    alpha = beta;
    return tau;
}

/* [head; tail] -= tau [1; v] ([1; v]' [head; tail]): a reflector applied to one column. */
template <typename Vec, typename Tail>
void apply_reflector(Real tau, const Vec &v, Real &head, Tail &&tail)
{
    const Real w = tau * (head + v.dot(tail));
    head -= w;
    tail -= w * v;
}

/* ---- the pieces of the rank-revealing solve (xGEQP3, xLAIC1 loop, xTZRZF, xORMQR, xORMRZ) ---- */

/*
 * Householder QR with column pivoting of the n x n a (xLAQP2) and its numerical rank by incremental
 * condition estimation (xGELSY: the largest leading block whose estimated condition stays below
 * 1 / rcond), column by column: the factorisation stops at the first column the estimate rejects.
 * Rows 0..rank-1 of R, the first rank reflectors and the first rank pivots are then final and
 * the same as from the whole factorisation, which is all the solve uses. Returns the rank.
 */
struct PivotedQr {
    Real *tau, *vn1, *vn2, *xmin, *xmax; /* n reals each */
    int *perm;                           /* 0-based column permutation */
};

int qr_rank(MatrixMap &a, Real rcond, const PivotedQr &w)
{
    const int n = static_cast<int>(a.cols());
    const Real tol3z = std::sqrt(kEps);
    for (int j = 0; j < n; ++j) {
        w.perm[j] = j;
        w.vn1[j] = w.vn2[j] = a.col(j).norm();
    }
    Real smin = 0, smax = 0;
    for (int i = 0; i < n; ++i) {
        int pvt = i;
        for (int j = i + 1; j < n; ++j) {
            if (w.vn1[j] > w.vn1[pvt]) {
                pvt = j;
            }
        }
        if (pvt != i) {
            a.col(pvt).swap(a.col(i));
            std::swap(w.perm[pvt], w.perm[i]);
            w.vn1[pvt] = w.vn1[i];
            w.vn2[pvt] = w.vn2[i];
        }
        auto v = a.col(i).tail(n - i - 1);
        w.tau[i] = make_reflector(a(i, i), v);
        if (i == 0) { /* the estimate starts from |r00| */
            smax = smin = std::abs(a(0, 0));
            if (smax == 0) {
                return 0;
            }
            w.xmin[0] = w.xmax[0] = 1;
        } else { /* does column i keep the condition below 1 / rcond? */
            const auto col = a.col(i).head(i);
            const okid_ice_step lo = okid_ice_smallest(smin, VectorMap(w.xmin, i).dot(col), a(i, i));
            const okid_ice_step hi = okid_ice_largest(smax, VectorMap(w.xmax, i).dot(col), a(i, i));
            if (hi.sest * rcond > lo.sest) {
                return i;
            }
            VectorMap(w.xmin, i) *= lo.s;
            VectorMap(w.xmax, i) *= hi.s;
            w.xmin[i] = lo.c;
            w.xmax[i] = hi.c;
            smin = lo.sest;
            smax = hi.sest;
        }
        for (int j = i + 1; j < n; ++j) {
            apply_reflector(w.tau[i], v, a(i, j), a.col(j).tail(n - i - 1));
            if (w.vn1[j] != 0) { /* downdate the norm of the rest of column j, recompute when it cancels */
                const Real ratio = std::abs(a(i, j)) / w.vn1[j];
                const Real temp = std::max(Real(0), 1 - ratio * ratio);
                const Real temp2 = temp * (w.vn1[j] / w.vn2[j]) * (w.vn1[j] / w.vn2[j]);
                if (temp2 <= tol3z) {
                    w.vn1[j] = w.vn2[j] = a.col(j).tail(n - i - 1).norm();
                } else {
                    w.vn1[j] *= std::sqrt(temp);
                }
            }
        }
    }
    return n;
}

/* [R11 R12] (rank x n) = [T 0] Z with Z = Z(0) ... Z(rank-1) (xTZRZF): z vectors into R12's rows. */
void rz_factor(MatrixMap &a, int rank, Real *ztau)
{
    const int n = static_cast<int>(a.cols()), l = n - rank;
    for (int i = rank - 1; i >= 0; --i) {
        auto z = a.row(i).tail(l);
        ztau[i] = make_reflector(a(i, i), z);
        for (int k = 0; k < i; ++k) {
            apply_reflector(ztau[i], z, a(k, i), a.row(k).tail(l));
        }
    }
}

} // namespace

extern "C" okid_status okid_la_fold_rows(int n, okid_real *r, int ldr, int nrows, okid_real *rows, int ldb,
                                         int nbt, okid_real *t, okid_real *work)
{
    (void)nbt; /* column-by-column Householder: no block reflector; t and work serve the Givens fold */
    if (n < 0 || nrows < 0 || ldr < (n > 1 ? n : 1) || ldb < (nrows > 1 ? nrows : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (nrows == 0 || n == 0) {
        return OKID_OK;
    }
    if (nrows == 1) { /* one row: the Givens fold the LAPACK backend uses too */
        okid_givens_fold_row(n, r, ldr, rows, ldb, t, work);
        return OKID_OK;
    }
    MatrixMap rf = map(r, n, n, ldr), b = map(rows, nrows, n, ldb);
    for (int j = 0; j < n; ++j) { /* the reflector of [r(j,j); rows(:,j)] meets columns j+1.. (xTPQRT2) */
        auto v = b.col(j);
        const Real tau = make_reflector(rf(j, j), v);
        if (tau == 0) {
            continue;
        }
        for (int c = j + 1; c < n; ++c) {
            apply_reflector(tau, v, rf(j, c), b.col(c));
        }
    }
    return OKID_OK;
}

extern "C" okid_status okid_la_accumulate_rows(int n, okid_real *c, int ldc, int nrows, const okid_real *rows,
                                               int ldb)
{
    if (n < 0 || nrows < 0 || ldc < (n > 1 ? n : 1) || ldb < (nrows > 1 ? nrows : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    MatrixMap cm = map(c, n, n, ldc);
    const MatrixMap b = map(const_cast<okid_real *>(rows), nrows, n, ldb);
    for (int j = 0; j < n; ++j) { /* the upper triangle, column by column (xSYRK's 'U', 'T') */
        for (int i = 0; i <= j; ++i) {
            cm(i, j) += b.col(i).dot(b.col(j));
        }
    }
    return OKID_OK;
}

extern "C" okid_status okid_la_cholesky_rows(int q, int n, okid_real *c, int ldc)
{
    if (q < 0 || n < q || ldc < (n > 1 ? n : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    MatrixMap cm = map(c, n, n, ldc);
    for (int j = 0; j < q; ++j) { /* xPOTF2's upper loop: row j of R from the rows above it */
        const Real d = cm(j, j) - cm.col(j).head(j).squaredNorm();
        if (!(d > 0)) {
            return OKID_E_DECOMPOSITION_FAILED;
        }
        cm(j, j) = std::sqrt(d);
        for (int k = j + 1; k < n; ++k) { /* R11 and R12 alike: R(j, k) = (C(j, k) - R(0:j, j)' R(0:j, k)) / R(j, j) */
            cm(j, k) = (cm(j, k) - cm.col(j).head(j).dot(cm.col(k).head(j))) / cm(j, j);
        }
    }
    return OKID_OK;
}

extern "C" okid_status okid_la_lstsq_rank(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb,
                                          okid_real rcond, int *rank, int *jpvt, okid_real *work)
{
    if (bad_matrix(n, n, lda) || bad_matrix(n, nrhs, ldb) || !(rcond >= 0)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    *rank = 0;
    if (n == 0 || nrhs == 0) { /* as xGELSY: nothing to solve, rank 0 */
        return OKID_OK;
    }
    /* work: tau, vn1, vn2, xmin, xmax, ztau (n each) and one column of the permutation (n) */
    const PivotedQr w = {work, work + n, work + 2 * n, work + 3 * n, work + 4 * n, jpvt};
    Real *ztau = work + 5 * n, *column = work + 6 * n;
    MatrixMap am = map(a, n, n, lda), bm = map(b, n, nrhs, ldb);
    const int k = am.cwiseAbs().maxCoeff() == 0 ? 0 : qr_rank(am, rcond, w);
    *rank = k;
    if (k == 0) {
        bm.setZero();
    } else {
        if (k < n) {
            rz_factor(am, k, ztau);
        }
        for (int c = 0; c < nrhs; ++c) {
            auto x = bm.col(c);
            for (int i = 0; i < k; ++i) { /* (Q' b)(0:k): the later reflectors leave these rows alone */
                apply_reflector(w.tau[i], am.col(i).tail(n - i - 1), x(i), x.tail(n - i - 1));
            }
            for (int i = k - 1; i >= 0; --i) { /* T y = (Q' b)(0:k), column-oriented as xTRSM */
                if (x(i) != 0) {
                    x(i) /= am(i, i);
                    x.head(i) -= x(i) * am.col(i).head(i);
                }
            }
            x.tail(n - k).setZero();
            for (int i = 0; i < k && k < n; ++i) { /* Z' [y; 0] */
                apply_reflector(ztau[i], am.row(i).tail(n - k).transpose(), x(i), x.tail(n - k));
            }
            for (int i = 0; i < n; ++i) { /* undo the column permutation */
                column[jpvt[i]] = x(i);
            }
            x = VectorMap(column, n);
        }
    }
    for (int j = 0; j < n; ++j) {
        jpvt[j] += 1; /* LAPACK's 1-based permutation, as the other backend leaves it */
    }
    return OKID_OK;
}

namespace {

/*
 * One-sided Jacobi (Hestenes): rotate pairs of columns of x until they are mutually orthogonal,
 * applying the same rotations to the columns of y (none when Y is std::nullptr_t). Then x = U S,
 * and y accumulates V. norms holds x's squared column norms (k reals): refreshed every sweep,
 * updated by each rotation in between. With de_rijk, each sweep first brings the largest
 * remaining column to position p before pairing it (de Rijk's pivoting: fewer sweeps, and the
 * columns come out nearly sorted).
 */
template <typename X, typename Y>
bool orthogonalize_columns(X &&x, Y &&y, Real *norms, bool de_rijk = false)
{
    constexpr bool accumulate = !std::is_same<std::decay_t<Y>, std::nullptr_t>::value;
    const Eigen::Index k = x.cols();
    const Real tol = std::numeric_limits<Real>::epsilon() * std::sqrt(static_cast<Real>(x.rows()));
    for (int sweep = 0; sweep < 60; ++sweep) {
        for (Eigen::Index j = 0; j < k; ++j) {
            norms[j] = x.col(j).squaredNorm();
        }
        bool rotated = false;
        for (Eigen::Index p = 0; p + 1 < k; ++p) {
            if (de_rijk) {
                Eigen::Index best = p;
                for (Eigen::Index i = p + 1; i < k; ++i) {
                    if (norms[i] > norms[best]) {
                        best = i;
                    }
                }
                if (best != p) {
                    x.col(best).swap(x.col(p));
                    if constexpr (accumulate) {
                        y.col(best).swap(y.col(p));
                    }
                    std::swap(norms[best], norms[p]);
                }
            }
            for (Eigen::Index q = p + 1; q < k; ++q) {
                const Real alpha = norms[p], beta = norms[q], gamma = x.col(p).dot(x.col(q));
                if (alpha == 0 || beta == 0 || std::abs(gamma) <= tol * std::sqrt(alpha) * std::sqrt(beta)) {
                    continue;
                }
                Eigen::JacobiRotation<Real> rot;
                rot.makeJacobi(alpha, gamma, beta);
                x.applyOnTheRight(p, q, rot);
                if constexpr (accumulate) {
                    y.applyOnTheRight(p, q, rot);
                }
                Eigen::Matrix<Real, 2, 2> gram; /* J' [alpha gamma; gamma beta] J: the new squared norms */
                gram << alpha, gamma, gamma, beta;
                gram.applyOnTheRight(0, 1, rot);
                gram.applyOnTheLeft(0, 1, rot.adjoint());
                norms[p] = std::max(Real(0), gram(0, 0));
                norms[q] = std::max(Real(0), gram(1, 1));
                rotated = true;
            }
        }
        if (!rotated) {
            return true;
        }
    }
    return false;
}

/* s = column norms of x in decreasing order (columns of x and y swapped alike), x's columns unit. */
template <typename X, typename Y>
void sort_and_normalize(X &&x, Y &&y, Real *s)
{
    const Eigen::Index k = x.cols();
    for (Eigen::Index j = 0; j < k; ++j) {
        s[j] = x.col(j).norm();
    }
    for (Eigen::Index j = 0; j < k; ++j) {
        Eigen::Index best = j;
        for (Eigen::Index i = j + 1; i < k; ++i) {
            if (s[i] > s[best]) {
                best = i;
            }
        }
        if (best != j) {
            std::swap(s[best], s[j]);
            x.col(best).swap(x.col(j));
            y.col(best).swap(y.col(j));
        }
        if (s[j] > 0) {
            x.col(j) /= s[j];
        }
    }
}

/*
 * a (m x n, m >= n) = Q R P' by Householder QR with column pivoting (xGEQP2 with xLAQP2's norm
 * downdating): R in the upper triangle, the reflectors below it, tau (n), perm the 0-based
 * permutation (column j of a P is column perm[j] of a). vn1 and vn2 hold n reals each.
 */
void pivoted_qr(MatrixMap &a, Real *tau, int *perm, Real *vn1, Real *vn2)
{
    const int m = static_cast<int>(a.rows()), n = static_cast<int>(a.cols());
    const Real tol3z = std::sqrt(kEps);
    for (int j = 0; j < n; ++j) {
        perm[j] = j;
        vn1[j] = vn2[j] = a.col(j).norm();
    }
    for (int i = 0; i < n; ++i) {
        int pvt = i;
        for (int j = i + 1; j < n; ++j) {
            if (vn1[j] > vn1[pvt]) {
                pvt = j;
            }
        }
        if (pvt != i) {
            a.col(pvt).swap(a.col(i));
            std::swap(perm[pvt], perm[i]);
            vn1[pvt] = vn1[i];
            vn2[pvt] = vn2[i];
        }
        auto v = a.col(i).tail(m - i - 1);
        tau[i] = make_reflector(a(i, i), v);
        for (int j = i + 1; j < n; ++j) {
            apply_reflector(tau[i], v, a(i, j), a.col(j).tail(m - i - 1));
            if (vn1[j] != 0) {
                const Real ratio = std::abs(a(i, j)) / vn1[j];
                const Real temp = std::max(Real(0), 1 - ratio * ratio);
                const Real temp2 = temp * (vn1[j] / vn2[j]) * (vn1[j] / vn2[j]);
                if (temp2 <= tol3z) {
                    vn1[j] = vn2[j] = a.col(j).tail(m - i - 1).norm();
                } else {
                    vn1[j] *= std::sqrt(temp);
                }
            }
        }
    }
}

/* The first n columns of Q in place of a's reflectors (xORG2R); R is lost. */
void form_q(MatrixMap &a, const Real *tau)
{
    const int m = static_cast<int>(a.rows()), n = static_cast<int>(a.cols());
    for (int j = n - 1; j >= 0; --j) {
        auto v = a.col(j).tail(m - j - 1);
        for (int c = j + 1; c < n; ++c) {
            apply_reflector(tau[j], v, a(j, c), a.col(c).tail(m - j - 1));
        }
        v *= -tau[j];
        a(j, j) = 1 - tau[j];
        a.col(j).head(j).setZero();
    }
}

/*
 * The leading nvec singular triplets of a (m >= n) and all n singular values, after xGEJSV's
 * preconditioning: a P = Q R with column pivoting, then one-sided Jacobi with de Rijk's pivoting
 * on the columns of X = R' (rows of R), which rotates nothing else: X W = V_R S gives V_R by
 * normalising its columns, and U_R for the nvec wanted only, as R V_R orthonormalised in the
 * order of decreasing s (S^-1 R V_R is its first guess). Then U = Q U_R (a's
 * first nvec columns), V' = (P V_R)' (vt's first nvec rows). work: tau (n), X (n x n), the
 * column norms (n), the permutation (n ints in n reals: sizeof(int) <= a real's).
 */
okid_status svd_leading(MatrixMap &am, int nvec, okid_real *s, okid_real *vt, int ldvt, okid_real *work)
{
    const int m = static_cast<int>(am.rows()), n = static_cast<int>(am.cols());
    Real *tau = work, *norms = work + n + n * n;
    int *perm = reinterpret_cast<int *>(norms + n);
    MatrixMap x = map(work + n, n, n, n);
    pivoted_qr(am, tau, perm, x.data(), x.data() + n); /* X's memory holds the pivoting norms meanwhile */
    x = am.topRows(n).triangularView<Eigen::Upper>().transpose();
    if (!orthogonalize_columns(x, nullptr, norms, true)) {
        return OKID_E_DECOMPOSITION_FAILED;
    }
    for (int j = 0; j < n; ++j) {
        s[j] = x.col(j).norm();
    }
    for (int j = 0; j < n; ++j) { /* decreasing (de Rijk leaves them nearly so) */
        int best = j;
        for (int i = j + 1; i < n; ++i) {
            if (s[i] > s[best]) {
                best = i;
            }
        }
        if (best != j) {
            std::swap(s[best], s[j]);
            x.col(best).swap(x.col(j));
        }
    }
    MatrixMap vtm = map(vt, nvec, n, ldvt);
    for (int j = 0; j < nvec; ++j) {
        auto v = x.col(j);
        if (s[j] > 0) {
            v /= s[j];
        }
        for (int i = 0; i < n; ++i) {
            vtm(j, perm[i]) = v(i);
        }
        Real *u = norms; /* R v = s u, back over X's column j */
        for (int i = 0; i < n; ++i) {
            u[i] = am.row(i).tail(n - i).dot(v.tail(n - i));
        }
        v = VectorMap(u, n);
        /* R v_j carries v_j's error times s_i / s_j along each u_i of a larger s_i: taking out its
           components along u_0 .. u_j-1 (twice: Gram-Schmidt's second pass restores orthogonality
           to round-off) leaves U_R as accurate as V_R, whatever s_j / s_0 */
        for (int pass = 0; pass < 2; ++pass) {
            for (int i = 0; i < j; ++i) {
                v -= x.col(i).dot(v) * x.col(i);
            }
        }
        const Real norm = v.norm();
        if (norm > 0) {
            v /= norm;
        }
    }
    form_q(am, tau);
    Real *row = norms;
    for (int i = 0; i < m; ++i) { /* U = Q U_R, row by row */
        for (int c = 0; c < nvec; ++c) {
            row[c] = am.row(i).dot(x.col(c));
        }
        am.row(i).head(nvec) = VectorMap(row, nvec).transpose();
    }
    return OKID_OK;
}

} // namespace

extern "C" okid_status okid_la_svd(int m, int n, int nvec, okid_real *a, int lda, okid_real *s, okid_real *vt,
                                   int ldvt, okid_real *work)
{
    const int k = m < n ? m : n;
    if (nvec < 0 || nvec > k) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    const bool leading = m >= n && nvec < k;
    if (bad_matrix(m, n, lda) || bad_matrix(leading ? nvec : k, n, ldvt)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (k == 0) {
        return OKID_OK;
    }
    MatrixMap am = map(a, m, n, lda);
    if (leading) {
        return svd_leading(am, nvec, s, vt, ldvt, work);
    }
    MatrixMap vtm = map(vt, k, n, ldvt);
    if (m >= n) {
        /* a = Q R first (as xGEJSV): Jacobi then rotates the n x n R instead of the m x n a, and
           U = Q U_R. work (OKID__LWORK_GESVD): tau, R (n x n), one row, the column norms. */
        Real *tau = work, *row = work + n + n * n, *norms = row + n;
        MatrixMap r = map(work + n, n, n, n);
        for (int j = 0; j < n; ++j) {
            auto v = am.col(j).tail(m - j - 1);
            tau[j] = make_reflector(am(j, j), v);
            for (int c = j + 1; c < n; ++c) {
                apply_reflector(tau[j], v, am(j, c), am.col(c).tail(m - j - 1));
            }
        }
        r = am.topRows(n).triangularView<Eigen::Upper>();
        vtm.setIdentity();
        if (!orthogonalize_columns(r, vtm.transpose(), norms)) {
            return OKID_E_DECOMPOSITION_FAILED;
        }
        sort_and_normalize(r, vtm.transpose(), s);
        form_q(am, tau);
        for (int i = 0; i < m; ++i) { /* U = Q U_R, row by row */
            for (int c = 0; c < n; ++c) {
                row[c] = am.row(i).dot(r.col(c));
            }
            am.row(i) = VectorMap(row, n).transpose();
        }
    } else { /* the rows of a (copied into vt) become S V'; a = U collects the rotations */
        vtm = am;
        auto u = am.leftCols(m);
        u.setIdentity();
        if (!orthogonalize_columns(vtm.transpose(), u, work)) {
            return OKID_E_DECOMPOSITION_FAILED;
        }
        sort_and_normalize(vtm.transpose(), u, s);
    }
    return OKID_OK;
}

namespace {

using Complex = std::complex<Real>;

/* a = Q H Q' in place (xGEHD2): H upper Hessenberg in a, Q (n x n) formed in q. */
void hessenberg(MatrixMap &a, MatrixMap &q, Real *tau)
{
    const int n = static_cast<int>(a.cols());
    for (int i = 0; i + 2 < n; ++i) {
        const int len = n - i - 2;
        auto v = a.col(i).tail(len);
        tau[i] = make_reflector(a(i + 1, i), v);
        for (int k = 0; k < n; ++k) { /* from the right on columns i+1.. */
            apply_reflector(tau[i], v.transpose(), a(k, i + 1), a.row(k).tail(len));
        }
        for (int c = i + 1; c < n; ++c) { /* from the left on rows i+1.. */
            apply_reflector(tau[i], v, a(i + 1, c), a.col(c).tail(len));
        }
    }
    q.setIdentity();
    for (int i = n - 3; i >= 0; --i) { /* Q = H(0) ... H(n-3), accumulated backwards (xORGHR) */
        const int len = n - i - 2;
        for (int c = i + 1; c < n; ++c) {
            apply_reflector(tau[i], a.col(i).tail(len), q(i + 1, c), q.col(c).tail(len));
        }
        a.col(i).tail(len).setZero();
    }
}

/* The eigenvalue of T's diagonal block at k (1 x 1, or 2 x 2 with a complex pair: the one with Im > 0). */
template <typename T>
Complex block_eigenvalue(const T &t, int k, bool pair)
{
    if (!pair) {
        return Complex(t(k, k), 0);
    }
    /* as Eigen's EigenSolver: p +- sqrt(p^2 + t10 t01) about t11, scaled against overflow */
    const Real p = (t(k, k) - t(k + 1, k + 1)) / 2, t0 = t(k + 1, k), t1 = t(k, k + 1);
    const Real big = std::max(std::abs(p), std::max(std::abs(t0), std::abs(t1)));
    const Real p0 = p / big, s0 = t0 / big, s1 = t1 / big;
    return Complex(t(k + 1, k + 1) + p, big * std::sqrt(std::abs(p0 * p0 + s0 * s1)));
}

/* A divisor kept off zero (a repeated eigenvalue), as xTREVC perturbs it by eps |T|. */
Complex guarded(Complex d, Real smin)
{
    return std::abs(d) < smin ? Complex(smin, 0) : d;
}

/*
 * Eigenvector x of the quasi-triangular T for its eigenvalue lambda at block k (size 1 or 2):
 * x is zero below the block, fixed in the block, and solved upwards block by block.
 */
template <typename T>
void schur_vector(const T &t, int k, bool pair, Complex lambda, Real smin, Complex *x)
{
    const int n = static_cast<int>(t.cols());
    for (int i = 0; i < n; ++i) {
        x[i] = 0;
    }
    int top = k;
    if (!pair) {
        x[k] = 1;
    } else { /* (t00 - lambda) x0 + t01 x1 = 0: x = [t01; lambda - t00] (t01 != 0 in a complex block) */
        x[k] = t(k, k + 1);
        x[k + 1] = lambda - t(k, k);
    }
    for (int i = top - 1; i >= 0; --i) {
        const bool block2 = i > 0 && t(i, i - 1) != 0;
        auto rhs = [&](int row) {
            Complex sum = 0;
            for (int j = i + 1; j < n; ++j) {
                sum += t(row, j) * x[j];
            }
            return -sum;
        };
        if (!block2) {
            x[i] = rhs(i) / guarded(Complex(t(i, i), 0) - lambda, smin);
            continue;
        }
        /* rows i-1, i together: [a b; c d] [x_{i-1}; x_i] = [r0; r1] (Cramer) */
        const Complex r0 = rhs(i - 1), r1 = rhs(i);
        const Complex a = t(i - 1, i - 1) - lambda, b = t(i - 1, i), c = t(i, i - 1), d = t(i, i) - lambda;
        const Complex det = guarded(a * d - b * c, smin);
        x[i - 1] = (r0 * d - b * r1) / det;
        x[i] = (a * r1 - c * r0) / det;
        --i;
    }
}

/* okid_la_eig with the Schur form of maximum order N >= n. */
template <int N>
okid_status eig_fixed(int n, okid_real *a, int lda, okid_real *wr, okid_real *wi, okid_real *vr, int ldvr,
                      okid_real *work)
{
    /* The Schur object (results inline, fixed maximum size) lives in the caller's work array,
       followed by one complex vector. */
    void *place = work;
    std::size_t room = sizeof(Real) * OKID__LWORK_GEEV(n);
    if (std::align(alignof(Schur<N>), sizeof(Schur<N>), place, room) == nullptr) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    Schur<N> *schur = new (place) Schur<N>(n);
    Complex *x = reinterpret_cast<Complex *>(static_cast<unsigned char *>(place) + kSchurBytes<N>);
    MatrixMap am = map(a, n, n, lda), v = map(vr, n, n, ldvr);
    hessenberg(am, v, reinterpret_cast<Real *>(x));
    schur->computeFromHessenberg(am, v, true);
    const bool ok = schur->info() == Eigen::Success;
    if (ok) {
        const EigMatrix<N> &t = schur->matrixT();
        const EigMatrix<N> &u = schur->matrixU();
        const Real smin = std::max(kEps * t.cwiseAbs().maxCoeff(), std::numeric_limits<Real>::min());
        for (int k = 0; k < n; ++k) {
            const bool pair = k + 1 < n && t(k + 1, k) != 0;
            const Complex lambda = block_eigenvalue(t, k, pair);
            schur_vector(t, k, pair, lambda, smin, x);
            wr[k] = lambda.real();
            wi[k] = lambda.imag();
            for (int i = 0; i < n; ++i) { /* back to A's basis: U x, LAPACK's Re / Im columns */
                Complex ux = 0;
                for (int j = 0; j < n; ++j) {
                    ux += u(i, j) * x[j];
                }
                v(i, k) = ux.real();
                if (pair) {
                    v(i, k + 1) = ux.imag();
                }
            }
            if (!pair) { /* normalise as xGEEV: unit norm, a pair's largest component real */
                v.col(k).normalize();
                continue;
            }
            wr[k + 1] = lambda.real();
            wi[k + 1] = -lambda.imag();
            const Real scale = okid_hypot(v.col(k).norm(), v.col(k + 1).norm());
            v.col(k) /= scale;
            v.col(k + 1) /= scale;
            Eigen::Index big = 0;
            (v.col(k).cwiseAbs2() + v.col(k + 1).cwiseAbs2()).maxCoeff(&big);
            const Real f = v(big, k), g = v(big, k + 1), h = std::copysign(okid_hypot(f, g), f);
            for (int i = 0; i < n; ++i) { /* times conj(f + i g) / |f + i g| */
                const Real re = v(i, k), im = v(i, k + 1);
                v(i, k) = (f * re + g * im) / h;
                v(i, k + 1) = (f * im - g * re) / h;
            }
            v(big, k + 1) = 0;
            ++k;
        }
    }
    std::destroy_at(schur);
    return ok ? OKID_OK : OKID_E_DECOMPOSITION_FAILED;
}

} // namespace

extern "C" okid_status okid_la_eig(int n, okid_real *a, int lda, okid_real *wr, okid_real *wi, okid_real *vr,
                                   int ldvr, okid_real *work)
{
    if (bad_matrix(n, n, lda) || bad_matrix(n, n, ldvr)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (n > OKID_EIGEN_MAX_ORDER) {
        return OKID_E_BAD_ORDER; /* the build's fixed maximum (CMake OKID_EIGEN_MAX_ORDER) */
    }
    if (n == 0) {
        return OKID_OK;
    }
    return n <= OKID__EIGEN_SMALL_ORDER ? eig_fixed<OKID__EIGEN_SMALL_ORDER>(n, a, lda, wr, wi, vr, ldvr, work)
                                        : eig_fixed<OKID_EIGEN_MAX_ORDER>(n, a, lda, wr, wi, vr, ldvr, work);
}

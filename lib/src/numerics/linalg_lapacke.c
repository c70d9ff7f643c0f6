/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The LAPACK backend of linalg.h. Only column-major LAPACKE_*_work calls: LAPACKE's high-level
 * wrappers and its row-major paths allocate, the column-major _work path goes straight to the
 * Fortran routine. Work arrays come from the caller (sized by the OKID__LWORK_* formulas).
 */
#include "numerics/linalg.h"

#include <lapacke.h>
#include <stddef.h>

#include "numerics/givens_fold.h"
#include "okid/sizes.h"

_Static_assert(sizeof(lapack_int) == sizeof(int), "okid passes int arrays as lapack_int (LP64 LAPACK)");

/* OKID_LAPACKE_PREFIX: the symbol prefix of a renamed LAPACKE (scipy_ for the Python package's
   scipy-openblas32, whose lapacke.h declares scipy_LAPACKE_*); empty for the system's. */
#ifndef OKID_LAPACKE_PREFIX
#define OKID_LAPACKE_PREFIX
#endif
#define LA_NAME(prefix, type, name) prefix##LAPACKE_##type##name##_work
#define LA_EXPAND(prefix, type, name) LA_NAME(prefix, type, name)
#if OKID_REAL_IS_FLOAT
#define LA(name) LA_EXPAND(OKID_LAPACKE_PREFIX, s, name)
#else
#define LA(name) LA_EXPAND(OKID_LAPACKE_PREFIX, d, name)
#endif

/* The BLAS routines called directly (Fortran interface, hidden string lengths last), with the
   LAPACKE's prefix: the scipy-openblas32 build renames every symbol alike. */
#define BLAS_NAME(prefix, type, name) prefix##type##name##_
#define BLAS_EXPAND(prefix, type, name) BLAS_NAME(prefix, type, name)
#if OKID_REAL_IS_FLOAT
#define BLAS(name) BLAS_EXPAND(OKID_LAPACKE_PREFIX, s, name)
#else
#define BLAS(name) BLAS_EXPAND(OKID_LAPACKE_PREFIX, d, name)
#endif
void BLAS(syrk)(const char *uplo, const char *trans, const int *n, const int *k, const okid_real *alpha,
                const okid_real *a, const int *lda, const okid_real *beta, okid_real *c, const int *ldc,
                size_t uplo_len, size_t trans_len);
void BLAS(gemm)(const char *transa, const char *transb, const int *m, const int *n, const int *k, const okid_real *alpha,
                const okid_real *a, const int *lda, const okid_real *b, const int *ldb, const okid_real *beta,
                okid_real *c, const int *ldc, size_t transa_len, size_t transb_len);
void BLAS(trmm)(const char *side, const char *uplo, const char *transa, const char *diag, const int *m, const int *n,
                const okid_real *alpha, const okid_real *a, const int *lda, okid_real *b, const int *ldb,
                size_t side_len, size_t uplo_len, size_t transa_len, size_t diag_len);

static okid_status from_info(lapack_int info)
{
    if (info == 0) {
        return OKID_OK;
    }
    return info < 0 ? OKID_E_BACKEND_ARGUMENT : OKID_E_DECOMPOSITION_FAILED;
}

/*
 * One panel of the recursive fold: the n x n upper triangle a on the m x n block b becomes its
 * QR factor (R in a, the reflectors' lower part V in b, the n x n triangular factor T of the
 * compact WY form in t), Elmroth and Gustavson's recursive QR (LAPACK's xGEQRT3) on xTPQRT's
 * triangle-on-block structure: the left half, its reflectors on the right half (xTPRFB, two GEMMs),
 * the right half, then T12 = -T11 (V1' V2) T22. V's upper part is the identity in the rows of a,
 * which the halves do not share, so V1' V2 is b1' b2. Columns of at most OKID__FOLD_PANEL_BASE go
 * to LAPACK's level-2 xTPQRT2. Depth log2(OKID__FOLD_PANEL_TILE / OKID__FOLD_PANEL_BASE).
 */
static lapack_int fold_panel(int m, int n, okid_real *a, int lda, okid_real *b, int ldb, okid_real *t, int ldt,
                             okid_real *work)
{
    if (n <= OKID__FOLD_PANEL_BASE) {
        return LA(tpqrt2)(LAPACK_COL_MAJOR, m, n, 0, a, lda, b, ldb, t, ldt);
    }
    const int n1 = n / 2, n2 = n - n1;
    okid_real *a12 = a + (size_t)n1 * (size_t)lda, *a22 = a12 + n1, *b2 = b + (size_t)n1 * (size_t)ldb;
    okid_real *t12 = t + (size_t)n1 * (size_t)ldt, *t22 = t12 + n1;
    lapack_int info = fold_panel(m, n1, a, lda, b, ldb, t, ldt, work);
    if (info == 0) {
        info = LA(tprfb)(LAPACK_COL_MAJOR, 'L', 'T', 'F', 'C', m, n2, n1, 0, b, ldb, t, ldt, a12, lda, b2, ldb, work, n1);
    }
    if (info == 0) {
        info = fold_panel(m, n2, a22, lda, b2, ldb, t22, ldt, work);
    }
    if (info == 0) {
        const okid_real one = 1, zero = 0, minus_one = -1;
        BLAS(gemm)("T", "N", &n1, &n2, &m, &one, b, &ldb, b2, &ldb, &zero, t12, &ldt, 1, 1);
        BLAS(trmm)("L", "U", "N", "N", &n1, &n2, &minus_one, t, &ldt, t12, &ldt, 1, 1, 1, 1);
        BLAS(trmm)("R", "U", "N", "N", &n1, &n2, &one, t22, &ldt, t12, &ldt, 1, 1, 1, 1);
    }
    return info;
}

/* xTPQRT's blocked loop with the recursive panel: each panel of nbt columns, then its block
   reflector on the columns right of it (xTPRFB: GEMMs of inner dimension nrows and nbt). */
static lapack_int fold_recursive(int n, okid_real *r, int ldr, int nrows, okid_real *rows, int ldb, int nbt,
                                 okid_real *t, okid_real *work)
{
    lapack_int info = 0;
    for (int j = 0; j < n && info == 0; j += nbt) {
        const int nb = n - j < nbt ? n - j : nbt, right = n - j - nb;
        okid_real *rjj = r + j + (size_t)j * (size_t)ldr, *vj = rows + (size_t)j * (size_t)ldb;
        info = fold_panel(nrows, nb, rjj, ldr, vj, ldb, t, nbt, work);
        if (info == 0 && right > 0) {
            info = LA(tprfb)(LAPACK_COL_MAJOR, 'L', 'T', 'F', 'C', nrows, right, nb, 0, vj, ldb, t, nbt,
                             rjj + (size_t)nb * (size_t)ldr, ldr, vj + (size_t)nb * (size_t)ldb, ldb, work, nb);
        }
    }
    return info;
}

okid_status okid_la_fold_rows(int n, okid_real *r, int ldr, int nrows, okid_real *rows, int ldb, int nbt,
                              okid_real *t, okid_real *work)
{
    if (nrows == 0) {
        return OKID_OK;
    }
    if (nrows == 1) { /* one row: Givens rotations beat a blocked Householder update by far */
        okid_givens_fold_row(n, r, ldr, rows, ldb, t, work);
        return OKID_OK;
    }
    if (nbt >= OKID__FOLD_PANEL_TILE) {
        return from_info(fold_recursive(n, r, ldr, nrows, rows, ldb, nbt, t, work));
    }
    return from_info(LA(tpqrt)(LAPACK_COL_MAJOR, nrows, n, 0, nbt, r, ldr, rows, ldb, t, nbt, work));
}

okid_status okid_la_accumulate_rows(int n, okid_real *c, int ldc, int nrows, const okid_real *rows, int ldb)
{
    if (n < 0 || nrows < 0 || ldc < (n > 1 ? n : 1) || ldb < (nrows > 1 ? nrows : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (n == 0 || nrows == 0) {
        return OKID_OK;
    }
    const okid_real one = 1;
    BLAS(syrk)("U", "T", &n, &nrows, &one, rows, &ldb, &one, c, &ldc, 1, 1);
    return OKID_OK;
}

okid_status okid_la_add_product_tn(int m, int n, int k, const okid_real *a, int lda, const okid_real *b, int ldb,
                                   okid_real *c, int ldc)
{
    if (m < 0 || n < 0 || k < 0 || lda < (k > 1 ? k : 1) || ldb < (k > 1 ? k : 1) || ldc < (m > 1 ? m : 1)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (m == 0 || n == 0 || k == 0) {
        return OKID_OK;
    }
    const okid_real one = 1;
    BLAS(gemm)("T", "N", &m, &n, &k, &one, a, &lda, b, &ldb, &one, c, &ldc, 1, 1);
    return OKID_OK;
}

okid_status okid_la_cholesky_rows(int q, int n, okid_real *c, int ldc)
{
    okid_status st = from_info(LA(potrf)(LAPACK_COL_MAJOR, 'U', q, c, ldc));
    if (st == OKID_OK && n > q) {
        st = from_info(LA(trtrs)(LAPACK_COL_MAJOR, 'U', 'T', 'N', q, n - q, c, ldc, c + (size_t)q * (size_t)ldc, ldc));
    }
    return st;
}

okid_status okid_la_solve_conditioned(int n, int nrhs, const okid_real *l, int ldl, okid_real *b, int ldb,
                                      okid_real min_rcond, int *solved, okid_real *work, int *iwork)
{
    *solved = 0;
    okid_real rcond = 0;
    okid_status st = from_info(LA(trcon)(LAPACK_COL_MAJOR, '1', 'L', 'N', n, l, ldl, &rcond, work, iwork));
    if (st != OKID_OK || !(rcond >= min_rcond)) {
        return st;
    }
    if (nrhs > 0) {
        st = from_info(LA(trtrs)(LAPACK_COL_MAJOR, 'L', 'T', 'N', n, nrhs, l, ldl, b, ldb));
    }
    *solved = st == OKID_OK;
    return st;
}

okid_status okid_la_lstsq_rank(int n, int nrhs, okid_real *a, int lda, okid_real *b, int ldb, okid_real rcond,
                               int *rank, int *jpvt, okid_real *work)
{
    for (int j = 0; j < n; ++j) {
        jpvt[j] = 0; /* every column is free to move */
    }
    lapack_int got_rank = 0;
    const lapack_int lwork = (lapack_int)OKID__LWORK_GELSY(n, nrhs);
    const lapack_int info =
        LA(gelsy)(LAPACK_COL_MAJOR, n, n, nrhs, a, lda, b, ldb, jpvt, rcond, &got_rank, work, lwork);
    *rank = (int)got_rank;
    return from_info(info);
}

okid_status okid_la_svd(int m, int n, int nvec, okid_real *a, int lda, okid_real *s, okid_real *vt, int ldvt,
                        okid_real *work)
{
    if (nvec < 0 || nvec > (m < n ? m : n)) {
        return OKID_E_BACKEND_ARGUMENT;
    }
    if (OKID__SVD_DC(m, n)) { /* U over a, V' (n x n) in vt, as xGESVD's 'O', 'S' below */
        const lapack_int lwork = (lapack_int)OKID__LWORK_GESDD(m, n);
        lapack_int *iwork = (lapack_int *)(void *)(work + lwork);
        return from_info(LA(gesdd)(LAPACK_COL_MAJOR, 'O', m, n, a, lda, s, NULL, 1, vt, ldvt, work, lwork, iwork));
    }
    const lapack_int lwork = (lapack_int)OKID__LWORK_GESVD_QR(m, n);
    return from_info(LA(gesvd)(LAPACK_COL_MAJOR, 'O', 'S', m, n, a, lda, s, NULL, 1, vt, ldvt, work, lwork));
}

okid_status okid_la_eig(int n, okid_real *a, int lda, okid_real *wr, okid_real *wi, okid_real *vr, int ldvr,
                        okid_real *work)
{
    const lapack_int lwork = (lapack_int)OKID__LWORK_GEEV(n);
    return from_info(LA(geev)(LAPACK_COL_MAJOR, 'N', 'V', n, a, lda, wr, wi, NULL, 1, vr, ldvr, work, lwork));
}

/*
 * LAPACK reports a bad argument by setting INFO < 0 and calling XERBLA. The stock XERBLA prints
 * and stops the process (with status 0 in the static reference LAPACK); this one returns, so the
 * routine returns its INFO and okid turns it into OKID_E_BACKEND_ARGUMENT. It lives in this file
 * so that linking libokid.a always pulls it in before the LAPACK archive is searched.
 */
void xerbla_(const char *srname, const int *info, size_t srname_len);

void xerbla_(const char *srname, const int *info, size_t srname_len)
{
    (void)srname;
    (void)info;
    (void)srname_len;
}

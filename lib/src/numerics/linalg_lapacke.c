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

/* The one BLAS routine called directly (Fortran interface, hidden string lengths last), with the
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

static okid_status from_info(lapack_int info)
{
    if (info == 0) {
        return OKID_OK;
    }
    return info < 0 ? OKID_E_BACKEND_ARGUMENT : OKID_E_DECOMPOSITION_FAILED;
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

okid_status okid_la_cholesky_rows(int q, int n, okid_real *c, int ldc)
{
    okid_status st = from_info(LA(potrf)(LAPACK_COL_MAJOR, 'U', q, c, ldc));
    if (st == OKID_OK && n > q) {
        st = from_info(LA(trtrs)(LAPACK_COL_MAJOR, 'U', 'T', 'N', q, n - q, c, ldc, c + (size_t)q * (size_t)ldc, ldc));
    }
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

okid_status okid_la_svd(int m, int n, okid_real *a, int lda, okid_real *s, okid_real *vt, int ldvt,
                        okid_real *work)
{
    const lapack_int lwork = (lapack_int)OKID__LWORK_GESVD(m, n);
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

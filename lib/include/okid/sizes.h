/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file sizes.h
 * \brief NOT API: every internal size formula of the library, in one place.
 *
 * The public entry macros (OKID_WORKSPACE_BYTES, OKID_WORKSPACE_BYTES_OPTIONS,
 * OKID_MODAL_WORKSPACE_BYTES, OKID_REFINE_WORKSPACE_BYTES, OKID_STABILIZATION_WORKSPACE_BYTES)
 * stay in their API headers and expand to the formulas below; the workspace carvings of lib/src
 * and the backends' work arrays use the same formulas. Do not use these names yourself: they
 * change without notice. The formulas name sizeof(okid_mode) and the like only where they are
 * expanded, so this header needs nothing but the scalar types.
 */
#ifndef OKID_SIZES_H
#define OKID_SIZES_H

#include <stddef.h>

#include "okid/limits.h"
#include "okid/types.h"

/**
 * Round a byte count up to a multiple of OKID_WORKSPACE_ALIGN (helper of the size macros). The size
 * macros compute in unsigned long long (64 bits at least) whatever size_t is, and OKID__SIZE
 * saturates their result at SIZE_MAX: on a 32-bit target a sum that exceeds 4 GiB gives SIZE_MAX
 * (a static array that large does not compile, and the functions refuse the configuration with
 * OKID_E_BAD_SIZE) instead of wrapping around to a small number.
 */
#define OKID__ALIGN16(bytes) ((((unsigned long long)(bytes)) + 15u) / 16u * 16u)
#define OKID__SIZE(bytes64) ((bytes64) > (unsigned long long)(size_t)-1 ? (size_t)-1 : (size_t)(bytes64))

/* ---- The identifier (okid/identifier.h): equal to okid_workspace_size(), checked by the tests ---- */

/* Every size macro computes in unsigned long long (OKID__ALIGN16); the public ones
   saturate at SIZE_MAX through OKID__SIZE. */
#define OKID__Z(x) ((unsigned long long)(x))
#define OKID__MAX(a, b) ((a) > (b) ? (a) : (b))
#define OKID__MIN(a, b) ((a) < (b) ? (a) : (b))
#define OKID__RB(count) OKID__ALIGN16(sizeof(okid_real) * OKID__Z(count))
#if OKID_LINALG_EIGEN
/* The Eigen backend works in place: 7 vectors for the rank-revealing solve, the n x n factor of
   the QR-preconditioned Jacobi SVD and three vectors (linalg_eigen.cpp). */
#define OKID__LWORK_GELSY(n, nrhs) (OKID__Z(n) * 7u + OKID__Z(nrhs) * 0u + 1u)
#define OKID__LWORK_GESVD(m, n) \
    (OKID__MIN(OKID__Z(m), OKID__Z(n)) * (OKID__MIN(OKID__Z(m), OKID__Z(n)) + 3u) + 1u)
/* Rows of V' the SVD writes when nvec pairs of singular vectors are asked for (linalg.h): only
   those when m >= n (the Eigen backend's leading-vector route), else min(m, n). */
#define OKID__SVD_VT_ROWS(m, n, nvec) \
    (OKID__Z(m) >= OKID__Z(n) ? OKID__Z(nvec) : OKID__MIN(OKID__Z(m), OKID__Z(n)))
#else
/* LAPACK's xGESVD / xGESDD write every right singular vector. */
#define OKID__SVD_VT_ROWS(m, n, nvec) (OKID__MIN(OKID__Z(m), OKID__Z(n)) + 0u * OKID__Z(nvec))
#define OKID__LWORK_GELSY(n, nrhs) (OKID__Z(n) * 37u + OKID__Z(nrhs) * 33u + 33u)
/*
 * The thin SVD: xGESVD, or for a Hankel matrix with m >= n >= OKID__SVD_DC_MIN columns the
 * divide-and-conquer xGESDD (JOBZ = 'O': U over a, the same layout; 3-7x faster from n = 200,
 * docs/design.md "Divide-and-conquer SVD"), whose work is its documented minimum 3 n + max(m, 5 n^2
 * + 4 n), m n more for the unchunked U, and its 8 n ints (counted as reals, sizeof(int) <= a real's).
 */
#define OKID__SVD_DC_MIN 150u
#define OKID__SVD_DC(m, n) (OKID__Z(m) >= OKID__Z(n) && OKID__Z(n) >= OKID__SVD_DC_MIN)
#define OKID__LWORK_GESVD_QR(m, n)                                                             \
    (OKID__MAX(3u * OKID__MIN(OKID__Z(m), OKID__Z(n)) + OKID__MAX(OKID__Z(m), OKID__Z(n)),     \
               5u * OKID__MIN(OKID__Z(m), OKID__Z(n)))                                          \
     + 32u * (OKID__Z(m) + OKID__Z(n)))
#define OKID__LWORK_GESDD_INTS(n) (8u * OKID__Z(n))
#define OKID__LWORK_GESDD(m, n)                                                                       \
    (3u * OKID__Z(n) + OKID__MAX(OKID__Z(m), 5u * OKID__Z(n) * OKID__Z(n) + 4u * OKID__Z(n))          \
     + OKID__Z(m) * OKID__Z(n) + 32u * (OKID__Z(m) + OKID__Z(n)))
#define OKID__LWORK_GESVD(m, n) \
    (OKID__SVD_DC(m, n) ? OKID__LWORK_GESDD(m, n) + OKID__LWORK_GESDD_INTS(n) : OKID__LWORK_GESVD_QR(m, n))
#endif
/* Work array of the general eigenproblem with right eigenvectors, in reals. */
#if OKID_LINALG_EIGEN
/* Eigen backend: its RealSchur for N = OKID__EIGEN_SCHUR_ORDER(n) states (3 N^2 + 3 N reals and
   the object's bookkeeping) and one complex N-vector are built in the work array. N is 8 for up to
   8 states (a few modes: 1 KB in float instead of 13 KB for N = 32), else OKID_EIGEN_MAX_ORDER. */
#define OKID__EIGEN_SMALL_ORDER (OKID_EIGEN_MAX_ORDER < 8 ? OKID_EIGEN_MAX_ORDER : 8)
#define OKID__EIGEN_SCHUR_ORDER(n) \
    ((size_t)(n) <= (size_t)OKID__EIGEN_SMALL_ORDER ? (size_t)OKID__EIGEN_SMALL_ORDER : (size_t)OKID_EIGEN_MAX_ORDER)
#define OKID__LWORK_GEEV(n)                                                                       \
    (3u * OKID__EIGEN_SCHUR_ORDER(n) * OKID__EIGEN_SCHUR_ORDER(n) + 5u * OKID__EIGEN_SCHUR_ORDER(n) + 32u)
#else
#define OKID__LWORK_GEEV(n) ((size_t)(n) * 36u + 16u)
#endif
#define OKID__Q(r, m, p) (OKID__Z(r) + (OKID__Z(r) + OKID__Z(m)) * OKID__Z(p))
#define OKID__W(r, m, p) (OKID__Q(r, m, p) + OKID__Z(m))
#define OKID__NCOLS(r, m, combined) ((combined) ? OKID__Z(r) + OKID__Z(m) : OKID__Z(r))
#define OKID__HR(m, alpha) (OKID__Z(alpha) * OKID__Z(m))
#define OKID__HC(r, m, beta, combined) (OKID__Z(beta) * OKID__NCOLS(r, m, combined))
#define OKID__K(r, m, alpha, beta, combined) OKID__MIN(OKID__HR(m, alpha), OKID__HC(r, m, beta, combined))
#define OKID__N(r, m, p, alpha, beta, order, combined) \
    ((order) > 0 ? OKID__Z(order) : OKID__MIN(OKID__K(r, m, alpha, beta, combined), OKID__Z(m) * OKID__Z(p)))
/*
 * Regressor rows per fold when block_rows is 0. LAPACK backend: the largest of 256, 128, 64 whose
 * block of rows (rows x w reals) fits OKID__FOLD_CACHE_BYTES, a core's L2 (2 MiB on the AMD EPYC
 * of docs/benchmarks.md; half or a quarter of it elsewhere only costs a few percent): xTPQRT then
 * streams the block from the cache, and 256 rows were at least 90 % of the fastest block size
 * measured for w = 61, 231 and 521 (docs/design.md, "Fold block size"). The block and identify's
 * copy of the pending rows take 2 x rows x w reals. Eigen backend: 32, as before (its fold is
 * unblocked and the firmware's memory budget counts every row).
 */
#define OKID__FOLD_CACHE_BYTES 2097152u
#if OKID_LINALG_EIGEN
#define OKID__AUTO_BLOCK_ROWS(w) (0u * OKID__Z(w) + 32u)
#else
#define OKID__AUTO_BLOCK_ROWS(w)                                                          \
    (256u * sizeof(okid_real) * OKID__Z(w) <= OKID__FOLD_CACHE_BYTES   ? 256u              \
     : 128u * sizeof(okid_real) * OKID__Z(w) <= OKID__FOLD_CACHE_BYTES ? 128u              \
                                                                       : 64u)
#endif
#define OKID__NB(r, m, p, block_rows) \
    ((block_rows) > 0 ? OKID__Z(block_rows) : OKID__AUTO_BLOCK_ROWS(OKID__W(r, m, p)))
/*
 * The fold's tile (xTPQRT's nb): 8 columns for w <= 128, else 16; with block_rows 0 and w > 128
 * on the LAPACK backend a panel of OKID__FOLD_PANEL_TILE columns factored recursively down to
 * OKID__FOLD_PANEL_BASE (linalg_lapacke.c: GEMM-rich updates, docs/design.md "Recursive fold
 * panel"); the T tile and the update's work are nbt x w reals each either way.
 */
#define OKID__FOLD_PANEL_TILE 64
#define OKID__FOLD_PANEL_BASE 8
#if OKID_LINALG_EIGEN
#define OKID__TILE(w, block_rows) (OKID__Z(w) <= 128u ? 8u : 16u + 0u * OKID__Z(block_rows))
#else
#define OKID__TILE(w, block_rows) \
    (OKID__Z(w) <= 128u ? 8u : OKID__Z(block_rows) == 0u ? OKID__Z(OKID__FOLD_PANEL_TILE) : 16u)
#endif
#define OKID__NBT(r, m, p, block_rows) \
    OKID__MIN(OKID__MIN(OKID__NB(r, m, p, block_rows), OKID__W(r, m, p)), OKID__TILE(OKID__W(r, m, p), block_rows))

#define OKID__PERSISTENT_BYTES(r, m, p, block_rows)                                                \
    (OKID__RB(OKID__Z(p) * (OKID__Z(r) + OKID__Z(m))) + OKID__RB(OKID__NB(r, m, p, block_rows) * OKID__W(r, m, p)) \
     + OKID__RB(OKID__W(r, m, p) * OKID__W(r, m, p)))

#define OKID__ONE_RESULT_BYTES(r, m, p, alpha, beta, n, k, combined)                               \
    (OKID__RB(OKID__Q(r, m, p) * OKID__Z(m)) + OKID__RB(OKID__Z(m) * OKID__Z(r) * (OKID__Z(alpha) + OKID__Z(beta) + 1u)) \
     + ((combined) ? OKID__RB(OKID__Z(m) * OKID__Z(m) * (OKID__Z(alpha) + OKID__Z(beta))) : 0u)        \
     + OKID__RB(k) + OKID__RB(OKID__Z(n) * OKID__Z(n)) + OKID__RB(OKID__Z(n) * OKID__Z(r))              \
     + OKID__RB(OKID__Z(m) * OKID__Z(n)) + OKID__RB(OKID__Z(m) * OKID__Z(r))                           \
     + ((combined) ? OKID__RB(OKID__Z(n) * OKID__Z(m)) : 0u)                                           \
     + OKID__RB(OKID__Z(m) * OKID__Z(n)) + OKID__RB(OKID__Z(n) * OKID__Z(r))                           \
     + OKID__ALIGN16(sizeof(okid_mode) * OKID__Z(n))                                                   \
     + OKID__ALIGN16(sizeof(okid_complex) * OKID__Z(n) * 3u * OKID__Z(m)))
/* Two results: the last good one and the one okid_identify() writes (a failed call keeps the first). */
#define OKID__RESULT_BYTES(r, m, p, alpha, beta, n, k, combined) (2u * OKID__ONE_RESULT_BYTES(r, m, p, alpha, beta, n, k, combined))

/* The folds: push's tiles, and identify's copy of the pending rows (block_rows > 1). */
#define OKID__PHASE_FOLD_BYTES(r, m, p, block_rows)                                                 \
    (2u * OKID__RB(OKID__NBT(r, m, p, block_rows) * OKID__W(r, m, p))                                 \
     + (OKID__NB(r, m, p, block_rows) > 1u ? OKID__RB(OKID__NB(r, m, p, block_rows) * OKID__W(r, m, p)) : 0u))
/* From this many regressor columns the solve tries a condition estimate before the rank-revealing
   solve (least_squares.c); below it every solve keeps its bits. */
#define OKID__FAST_SOLVE_MIN 200
/* Work of the core's rank-revealing solve on a triangle (triangular_lstsq.h), in reals. */
#define OKID__LWORK_TRIANGULAR_LSTSQ(n) (4u * OKID__Z(n))
/* The rank-revealing solves (least squares, the diagnostics' noise-free test) run in R's unused
   lower triangle: column scales, a column, the permutation and the solve's work. */
#define OKID__PHASE_SOLVE_BYTES(r, m, p)                                                           \
    (2u * OKID__RB(OKID__Q(r, m, p)) + OKID__ALIGN16(sizeof(int) * OKID__Q(r, m, p))                \
     + OKID__RB(OKID__LWORK_TRIANGULAR_LSTSQ(OKID__Q(r, m, p))))
/* The Hankel matrix (hr x hc) and V' (k x hc) go into R's unused strict lower triangle when they
   fit (columns stepping down the diagonal, leading dimension w + 1): hr + hc <= w, 2 hc + k <= w. */
#define OKID__ERA_IN_R(r, m, p, alpha, beta, k, combined)                                           \
    (OKID__HR(m, alpha) + OKID__HC(r, m, beta, combined) <= OKID__W(r, m, p)                          \
     && 2u * OKID__HC(r, m, beta, combined) + OKID__Z(k) <= OKID__W(r, m, p))
#define OKID__PHASE_ERA_BYTES(r, m, p, alpha, beta, n, k, combined)                                \
    ((OKID__ERA_IN_R(r, m, p, alpha, beta, k, combined)                                              \
          ? 0u                                                                                      \
          : OKID__RB(OKID__HR(m, alpha) * OKID__HC(r, m, beta, combined))                            \
                + OKID__RB(OKID__Z(k) * OKID__HC(r, m, beta, combined)))                             \
     + OKID__RB(OKID__HR(m, alpha) * OKID__Z(n)) + OKID__RB(OKID__NCOLS(r, m, combined))             \
     + OKID__RB(OKID__LWORK_GESVD(OKID__HR(m, alpha), OKID__HC(r, m, beta, combined))))
#define OKID__PHASE_MODAL_BYTES(n) \
    (2u * OKID__RB(OKID__Z(n) * OKID__Z(n)) + 2u * OKID__RB(n) + OKID__RB(OKID__LWORK_GEEV(n)))
/* The modal indicators run on the eigenvectors the modal phase leaves, in memory after it. */
#define OKID__PHASE_INDICATOR_BYTES(n, r)                                                          \
    (OKID__RB(OKID__Z(n) * 2u * OKID__Z(r)) + OKID__RB(OKID__LWORK_GELSY(n, 2u * OKID__Z(r)))        \
     + OKID__ALIGN16(sizeof(int) * OKID__Z(n)))
/* With block_rows > 1, identify folds the pending rows into a copy of R (w x w), which its later
   phases use as they would use R: the accumulation stays as it was, bit for bit. */
#define OKID__IDENTIFY_FOLD_BYTES(r, m, p, block_rows) \
    (OKID__NB(r, m, p, block_rows) > 1u ? OKID__RB(OKID__W(r, m, p) * OKID__W(r, m, p)) : 0u)
#define OKID__SCRATCH_BYTES(r, m, p, alpha, beta, n, k, block_rows, combined)                        \
    (OKID__IDENTIFY_FOLD_BYTES(r, m, p, block_rows)                                                  \
     + OKID__MAX(OKID__MAX(OKID__PHASE_FOLD_BYTES(r, m, p, block_rows), OKID__PHASE_SOLVE_BYTES(r, m, p)),   \
                 OKID__MAX(OKID__PHASE_ERA_BYTES(r, m, p, alpha, beta, n, k, combined),                         \
                           OKID__PHASE_MODAL_BYTES(n) + OKID__PHASE_INDICATOR_BYTES(n, r))))

/* Options (okid_config decimation, scaling, estimator, instrument_lags): persistent memory on top. */
#define OKID__DEC_BYTES(r, m, decimation) \
    ((decimation) > 1 ? OKID__RB(5u) + OKID__RB(2u * (OKID__Z(r) + OKID__Z(m))) + OKID__RB(OKID__Z(r) + OKID__Z(m)) : 0u)
/* the scales, and a copy in each result */
#define OKID__SCALE_BYTES(r, m, scaling) ((scaling) ? 3u * OKID__RB(OKID__Z(r) + OKID__Z(m)) : 0u)
#define OKID__IV_LAGS(r, m, p, lags) \
    ((lags) > 0 ? OKID__Z(lags) : (OKID__Q(r, m, p) + OKID__Z(r) - 1u) / OKID__Z(r) + 2u * OKID__Z(p))
#define OKID__IV_BYTES(r, m, p, block_rows, estimator, lags)                                                  \
    ((estimator) == 1 ? OKID__RB(OKID__Z(r) * OKID__IV_LAGS(r, m, p, lags))                                        \
                       + OKID__RB(OKID__NB(r, m, p, block_rows) * OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u))    \
                       + OKID__RB(OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u) * OKID__W(r, m, p))        \
                       + (OKID__NB(r, m, p, block_rows) > 1u                                                            \
                              ? OKID__RB(OKID__NB(r, m, p, block_rows) * OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u)) \
                                    + OKID__RB(OKID__NB(r, m, p, block_rows) * OKID__W(r, m, p))                        \
                              : 0u)                                                                            \
                 : 0u)

/* The correlation form factors a copy of [Phi Y]'[Phi Y] at identify: the copy of R that
   block_rows > 1 has anyway, else w x w more. LAPACK backend: the Toeplitz Gram's open run and a
   scratch run for identify's pending rows, OKID__TOEPLITZ_RUN_REALS each (toeplitz_gram.h; the
   Eigen backend sums the Gram by dot products). */
#if OKID_LINALG_EIGEN
#define OKID__TOEPLITZ_RUN_REALS(r, m, p) (0u * OKID__W(r, m, p))
#else
#define OKID__TOEPLITZ_RUN_REALS(r, m, p) ((OKID__Z(r) + OKID__Z(m) + 2u) * OKID__W(r, m, p) + 1u)
#endif
#define OKID__CORRELATION_BYTES(r, m, p, block_rows, estimator)                                                   \
    ((estimator) == 2 ? (OKID__NB(r, m, p, block_rows) <= 1u ? OKID__RB(OKID__W(r, m, p) * OKID__W(r, m, p)) : 0u) \
                            + OKID__RB(2u * OKID__TOEPLITZ_RUN_REALS(r, m, p))                                    \
                      : 0u)

/* OKID_WORKSPACE_BYTES before the saturation. */
#define OKID__WORKSPACE_BYTES64(r, m, p, alpha, beta, order, block_rows, combined)                         \
    (OKID__PERSISTENT_BYTES(r, m, p, block_rows)                                                         \
     + OKID__RESULT_BYTES(r, m, p, alpha, beta, OKID__N(r, m, p, alpha, beta, order, combined),                \
                          OKID__K(r, m, alpha, beta, combined), combined)                                 \
     + OKID__SCRATCH_BYTES(r, m, p, alpha, beta, OKID__N(r, m, p, alpha, beta, order, combined),              \
                           OKID__K(r, m, alpha, beta, combined), block_rows, combined))

/* OKID_WORKSPACE_BYTES_OPTIONS before the saturation. */
#define OKID__WORKSPACE_OPTIONS_BYTES64(r, m, p, alpha, beta, order, block_rows, combined, decimation, scaling, \
                                        estimator, lags)                                                        \
    (OKID__WORKSPACE_BYTES64(r, m, p, alpha, beta, order, block_rows, combined)                     \
               + OKID__DEC_BYTES(r, m, decimation) + OKID__SCALE_BYTES(r, m, scaling)                           \
               + OKID__IV_BYTES(r, m, p, block_rows, estimator, lags) + OKID__CORRELATION_BYTES(r, m, p, block_rows, estimator))

/* ---- Modal analysis (okid/modal.h) ---- */

/* OKID_MODAL_WORKSPACE_BYTES before the saturation. */
#define OKID__MODAL_WORKSPACE_BYTES64(n, m)                                                        \
    (OKID__ALIGN16(sizeof(okid_real) * (size_t)(n) * (size_t)(n)) * 2u                               \
     + OKID__ALIGN16(sizeof(okid_real) * (size_t)(n)) * 2u                                             \
     + OKID__ALIGN16(sizeof(okid_complex) * (size_t)(n) * 3u * (size_t)(m))                            \
     + OKID__ALIGN16(sizeof(okid_real) * OKID__LWORK_GEEV(n)))

/* ---- Refinement (okid/refine.h) ---- */

/* The same in 64 bits (at most 512 x 129 + 64 x 64 = 70144, but its square does not fit 32 bits). */
#define OKID__REFINE_PARAMETERS64(n, r, m) (OKID__Z(n) * (OKID__Z(r) + OKID__Z(m) + 1u) + OKID__Z(m) * OKID__Z(r))

/* Lags of the refinement's residual whiteness test (OKID_REFINE_LAGS). */
#define OKID__REFINE_LAGS 20u

/* Reals of each of the two normal-matrix buffers (internal; the eigenvalue scratch shares them). */
#define OKID__REFINE_SCRATCH(n, np)                                                                  \
    OKID__MAX(2u * OKID__Z(n) * OKID__Z(n) + 2u * OKID__Z(n) + OKID__Z(OKID__LWORK_GEEV(n)), OKID__Z(np) * OKID__Z(np))

/* Parameters of the output-error (inn 0) or innovation (inn 1) refinement: the latter adds K, n x m. */
#define OKID__REFINE_NP64(inn, n, r, m) (OKID__REFINE_PARAMETERS64(n, r, m) + OKID__Z(inn) * OKID__Z(n) * OKID__Z(m))

/* OKID_REFINE_MODEL_WORKSPACE_BYTES before the saturation (inn: 1 for the innovation form). */
#define OKID__REFINE_MODEL_WORKSPACE_BYTES64(inn, n, r, m)                                                                        \
    (OKID__ALIGN16(sizeof(int) * 4u * OKID__REFINE_NP64(inn, n, r, m)) + OKID__ALIGN16(sizeof(int) * 4u * OKID__Z(n)) \
     + 2u * OKID__RB(OKID__REFINE_NP64(inn, n, r, m)) + 2u * OKID__RB(n) + OKID__RB(OKID__Z(n) * OKID__Z(r))         \
     + OKID__RB(OKID__Z(m) * OKID__Z(n)) + OKID__RB(OKID__Z(m) * OKID__Z(r)) + 2u * OKID__RB(n)                        \
     + OKID__RB((OKID__Z(inn) ? OKID__Z(n) : 2u) * OKID__REFINE_NP64(inn, n, r, m)) + OKID__RB(OKID__Z(m) * OKID__REFINE_NP64(inn, n, r, m))    \
     + 2u * OKID__RB(OKID__REFINE_SCRATCH(n, OKID__REFINE_NP64(inn, n, r, m)))                                     \
     + OKID__RB(OKID__Z(m) * OKID__REFINE_NP64(inn, n, r, m)) + 3u * OKID__RB(OKID__REFINE_NP64(inn, n, r, m))    \
     + 7u * OKID__RB(m) + OKID__RB(OKID__Z(n) * OKID__Z(n)) + OKID__ALIGN16(sizeof(okid_mode) * OKID__Z(n))             \
     + OKID__ALIGN16(sizeof(okid_mode_std) * OKID__Z(n)) + OKID__ALIGN16(sizeof(okid_complex) * OKID__Z(n) * 3u * OKID__Z(m)) \
     + OKID__ALIGN16(sizeof(okid_complex) * OKID__Z(n) * OKID__Z(m))                                    \
     + 3u * OKID__RB(OKID__Z(m) * OKID__REFINE_LAGS) + 4u * OKID__RB(m) + OKID__ALIGN16(sizeof(unsigned) * OKID__Z(m)) \
     + OKID__RB(OKID__Z(m) * OKID__REFINE_NP64(inn, n, r, m))                                               \
     + 2u * OKID__RB(OKID__REFINE_NP64(inn, n, r, m) * OKID__REFINE_NP64(inn, n, r, m))                  \
     + OKID__RB(OKID__REFINE_NP64(inn, n, r, m))                                                                        \
     + 2u * OKID__RB(OKID__Z(r) * OKID__REFINE_LAGS) + 2u * OKID__RB(OKID__Z(m) * OKID__Z(r) * OKID__REFINE_LAGS)        \
     + OKID__RB(r) + 2u * OKID__RB(m) + 3u * OKID__RB(OKID__Z(m) * OKID__Z(r))                                          \
     + (OKID__Z(inn) ? OKID__RB(OKID__Z(n) * OKID__Z(m)) : 0u))

/* OKID_REFINE_WORKSPACE_BYTES before the saturation: the output-error one. */
#define OKID__REFINE_WORKSPACE_BYTES64(n, r, m) OKID__REFINE_MODEL_WORKSPACE_BYTES64(0u, n, r, m)

/* ---- Stabilization diagram (okid/stabilization.h) ---- */

/* Sizes of the table (internal helpers of the macro below). */
#define OKID__STAB_ORDERS(nmax, step) (OKID__Z(nmax) / OKID__Z(step))
#define OKID__STAB_MODES(nmax, step) \
    (OKID__Z(step) * OKID__STAB_ORDERS(nmax, step) * (OKID__STAB_ORDERS(nmax, step) + 1u) / 2u)

/* OKID_STABILIZATION_WORKSPACE_BYTES before the saturation. */
#define OKID__STABILIZATION_WORKSPACE_BYTES64(r, m, alpha, beta, nmax, step, combined) \
    (OKID__RB(OKID__K(r, m, alpha, beta, combined)) + OKID__RB(OKID__HR(m, alpha) * OKID__Z(nmax))           \
     + OKID__RB(OKID__Z(nmax) * OKID__Z(nmax)) + 2u * OKID__RB(OKID__Z(nmax) * OKID__Z(r))                   \
     + 2u * OKID__RB(OKID__Z(m) * OKID__Z(nmax)) + OKID__RB(OKID__Z(m) * OKID__Z(r))                         \
     + ((combined) ? OKID__RB(OKID__Z(nmax) * OKID__Z(m)) : 0u) + OKID__PHASE_MODAL_BYTES(nmax)              \
     + OKID__PHASE_INDICATOR_BYTES(nmax, r) + OKID__ALIGN16(sizeof(okid_stabilization_order) * OKID__STAB_ORDERS(nmax, step)) \
     + OKID__ALIGN16(sizeof(okid_mode) * OKID__STAB_MODES(nmax, step))                                      \
     + OKID__ALIGN16(sizeof(okid_complex) * 3u * OKID__Z(m) * OKID__STAB_MODES(nmax, step))                  \
     + OKID__ALIGN16(sizeof(unsigned) * OKID__STAB_MODES(nmax, step)))

/* ---- Mode selection (okid/mode_selection.h) ---- */

/* Bytes for a table of `total` modes whose largest order is nmax (internal helper of
   OKID_MODE_SELECTION_WORKSPACE_BYTES; expanded where okid_selected_mode is declared). */
#define OKID__MODESEL_BYTES(total, nmax)                                                     \
    (5u * OKID__ALIGN16(sizeof(int) * OKID__Z(total)) + OKID__ALIGN16(sizeof(okid_selected_mode) * OKID__Z(nmax)))

/* ---- Output-only identification (okid/ambient.h) ---- */

/* References (0 = every output), correlation blocks 2L + 1, Hankel rank limit k and sized order n. */
#define OKID__AMB_NREF(m, nref) ((nref) > 0 ? OKID__Z(nref) : OKID__Z(m))
#define OKID__AMB_BLOCKS(L) (2u * OKID__Z(L) + 1u)
#define OKID__AMB_K(m, nref, L) (OKID__Z(L) * OKID__MIN(OKID__Z(m), OKID__Z(nref)))
#define OKID__AMB_N(m, nref, L, order) \
    ((order) > 0 ? OKID__Z(order) : OKID__MIN(OKID__AMB_K(m, nref, L), (unsigned long long)OKID_MAX_ORDER))
/* Segments kept apart (okid_ambient_config::segments: 0 and 1 are one). */
#define OKID__AMB_SEGS(segments) ((segments) > 1 ? OKID__Z(segments) : 1u)
/*
 * Samples whose correlation products okid_ambient_push_block() sums as one matrix product per lag
 * (docs/ambient.md, "Batched sums"). LAPACK backend: 256 (the kernels' rate was flat from 64 to
 * 1024 samples: docs/design.md); Eigen backend (the firmware's): 1, push_block is then push
 * sample by sample and its workspace holds no batch.
 */
#if OKID_LINALG_EIGEN
#define OKID__AMB_BATCH 1u
#else
#define OKID__AMB_BATCH 256u
#endif
/* The batch's history (nref x (2L + batch)) and, when some output is no reference, its outputs
   (m x batch); nothing with a batch of 1. */
#define OKID__AMB_BATCH_BYTES(m, nref, L)                                                                  \
    (OKID__AMB_BATCH > 1u ? OKID__RB(OKID__Z(nref) * (2u * OKID__Z(L) + OKID__AMB_BATCH))                   \
                                + (OKID__Z(nref) < OKID__Z(m) ? OKID__RB(OKID__Z(m) * OKID__AMB_BATCH) : 0u) \
                          : 0u)
/* The sums: ring of the last 2L references, S(0..2L) and the pairs per lag of each segment, each
   output's sum of squares, the run of okid_ambient_push() (its S(0..2L) and squares), the batch. */
#define OKID__AMB_PERSISTENT_BYTES(m, nref, L, segments)                                                \
    (OKID__RB(OKID__Z(nref) * 2u * OKID__Z(L))                                                          \
     + OKID__RB(OKID__AMB_SEGS(segments) * OKID__Z(m) * OKID__Z(nref) * OKID__AMB_BLOCKS(L)) + OKID__RB(m) \
     + OKID__ALIGN16(8u * OKID__AMB_SEGS(segments) * OKID__AMB_BLOCKS(L))                                   \
     + OKID__RB(OKID__Z(m) * OKID__Z(nref) * OKID__AMB_BLOCKS(L) + OKID__Z(m)) + OKID__AMB_BATCH_BYTES(m, nref, L))
/* One result set: R(0..2L), singular values, A, G, C, D = R(0), modes and their shapes, the modes'
   two standard deviations. */
#define OKID__AMB_RESULT_BYTES(m, nref, L, n, mode_bytes)                                                 \
    (OKID__RB(OKID__Z(m) * OKID__Z(nref) * OKID__AMB_BLOCKS(L)) + OKID__RB(OKID__AMB_K(m, nref, L))          \
     + OKID__RB(OKID__Z(n) * OKID__Z(n)) + OKID__RB(OKID__Z(n) * OKID__Z(nref)) + OKID__RB(OKID__Z(m) * OKID__Z(n)) \
     + OKID__RB(OKID__Z(m) * OKID__Z(nref)) + OKID__ALIGN16((mode_bytes) * OKID__Z(n))                         \
     + OKID__ALIGN16(sizeof(okid_complex) * OKID__Z(n) * 3u * OKID__Z(m)) + 2u * OKID__RB(n))
/* With segments, identify's scratch for one segment's realization (R, singular values, A, G, C, D,
   modes, shapes) and every segment's matched frequency and damping of each mode. */
#define OKID__AMB_SEGMENT_BYTES(m, nref, L, n, segments, mode_bytes)                                     \
    ((segments) > 1 ? OKID__AMB_RESULT_BYTES(m, nref, L, n, mode_bytes) - 2u * OKID__RB(n)               \
                          + 2u * OKID__RB(OKID__Z(segments) * OKID__Z(n))                                  \
                    : 0u)
/* Identify's scratch: scales, the indicators' blocks, then one region for the phases in turn:
   ERA (H, V' of the n rows the SVD writes, H(1) V_n, column scales, SVD work), then the modal
   analysis and the indicators' solve. */
#define OKID__AMB_ERA_BYTES(m, nref, L, n)                                                                      \
    (OKID__RB(OKID__HR(m, L) * OKID__HR(nref, L))                                                                \
     + OKID__RB(OKID__SVD_VT_ROWS(OKID__HR(m, L), OKID__HR(nref, L), n) * OKID__HR(nref, L))                    \
     + OKID__RB(OKID__HR(m, L) * OKID__Z(n)) + OKID__RB(nref)                                                   \
     + OKID__RB(OKID__LWORK_GESVD(OKID__HR(m, L), OKID__HR(nref, L))))
#define OKID__AMB_SCRATCH_BYTES(m, nref, L, n)                                                                  \
    (OKID__RB(OKID__Z(nref) + OKID__Z(m)) + OKID__RB(OKID__Z(m) * OKID__Z(n)) + OKID__RB(OKID__Z(n) * OKID__Z(nref)) \
     + OKID__MAX(OKID__AMB_ERA_BYTES(m, nref, L, n), OKID__PHASE_MODAL_BYTES(n) + OKID__PHASE_INDICATOR_BYTES(n, nref)))
/* okid_ambient_stabilization_compute()'s workspace before the saturation (nref resolved): R(0..2L),
   the scales, the singular values, H(1) V_N, V' (the rows the SVD writes for N), A, G and its last
   block column, C and its last block row, D, the modal and indicator phases at N, and the table of
   OKID__STABILIZATION_WORKSPACE_BYTES64. */
#define OKID__AMBIENT_STABILIZATION_BYTES64(m, nref, L, nmax, step)                                              \
    (OKID__RB(OKID__Z(m) * OKID__Z(nref) * OKID__AMB_BLOCKS(L)) + OKID__RB(OKID__Z(nref) + OKID__Z(m))            \
     + OKID__RB(OKID__AMB_K(m, nref, L)) + OKID__RB(OKID__HR(m, L) * OKID__Z(nmax))                                \
     + OKID__RB(OKID__SVD_VT_ROWS(OKID__HR(m, L), OKID__HR(nref, L), nmax) * OKID__HR(nref, L))                    \
     + OKID__RB(OKID__Z(nmax) * OKID__Z(nmax)) + 2u * OKID__RB(OKID__Z(nmax) * OKID__Z(nref))                      \
     + 2u * OKID__RB(OKID__Z(m) * OKID__Z(nmax)) + OKID__RB(OKID__Z(m) * OKID__Z(nref)) + OKID__PHASE_MODAL_BYTES(nmax) \
     + OKID__PHASE_INDICATOR_BYTES(nmax, nref)                                                                     \
     + OKID__ALIGN16(sizeof(okid_stabilization_order) * OKID__STAB_ORDERS(nmax, step))                             \
     + OKID__ALIGN16(sizeof(okid_mode) * OKID__STAB_MODES(nmax, step))                                            \
     + OKID__ALIGN16(sizeof(okid_complex) * 3u * OKID__Z(m) * OKID__STAB_MODES(nmax, step))                        \
     + OKID__ALIGN16(sizeof(unsigned) * OKID__STAB_MODES(nmax, step)))
/* OKID_AMBIENT_WORKSPACE_BYTES before the saturation (nref resolved). */
#define OKID__AMBIENT_WORKSPACE_BYTES64(m, nref, L, order, segments, mode_bytes)                         \
    (OKID__AMB_PERSISTENT_BYTES(m, nref, L, segments)                                                   \
     + 2u * OKID__AMB_RESULT_BYTES(m, nref, L, OKID__AMB_N(m, nref, L, order), mode_bytes)               \
     + OKID__AMB_SCRATCH_BYTES(m, nref, L, OKID__AMB_N(m, nref, L, order))                               \
     + OKID__AMB_SEGMENT_BYTES(m, nref, L, OKID__AMB_N(m, nref, L, order), segments, mode_bytes))

#endif

/**
 * \file identifier_storage.h
 * \brief NOT API: the storage of an okid_identifier and the workspace size formulas.
 *
 * okid/identifier.h includes this header; do not include it yourself. The struct is complete here
 * only so that an identifier can be allocated statically (firmware); its members are private to
 * the library and change without notice. Read an identifier through the functions of
 * okid/identifier.h and size a workspace with okid_workspace_size() or OKID_WORKSPACE_BYTES().
 */
#ifndef OKID_IDENTIFIER_STORAGE_H
#define OKID_IDENTIFIER_STORAGE_H

#include <stddef.h>
#include <stdint.h>

#include "okid/modal.h"
#include "okid/types.h"

/* One identification's output, in the workspace. There are two: the last good one, which
   okid_predict(), okid_result's views and the stabilization diagram read, and the one the next
   okid_identify() writes; a successful identify swaps them, a failed one changes neither. */
typedef struct okid_result_views_ {
    okid_real *x;                    /* q x m observer solution [D, observer Markov parameters]' */
    okid_real *markov, *markov_obs, *sv, *a, *b, *c, *d, *g;
    okid_real *obs_last, *ctrl_last; /* last block row of U_n S^1/2, last block column of S^1/2 V_n' (indicators) */
    okid_real *scales;               /* the r + m channel scales it used (OKID_SCALING_AUTO), else NULL */
    okid_mode *modes;
    okid_complex *shapes;
} okid_result_views_;

/* Views into the workspace (workspace_layout.c carves them). */
typedef struct okid_views_ {
    /* persistent accumulation */
    okid_real *ring, *block, *r;
    okid_result_views_ result[2];
    /* scratch shared by the phases of okid_push() and okid_identify() */
    okid_real *factor;  /* identify's copy of R with the pending rows folded in (block_rows > 1), else NULL */
    okid_real *pending; /* those rows, scaled and weighted (block_rows > 1) */
    okid_real *iv_pending, *iv_chunk; /* the instrument rows likewise, and a block of rows of M (instruments) */
    okid_real *fold_t, *fold_work;
    okid_real *lsq_scale, *lsq_column, *lsq_work; /* the solves of okid_lsq_solve() and the diagnostics */
    int *lsq_perm;
    okid_real *era_h, *era_vt, *era_t, *era_scale, *era_work; /* era_h, era_vt: NULL when in the factor's triangle */
    okid_real *modal_a, *modal_vr, *modal_wr, *modal_wi, *modal_work;
    okid_real *ind_rhs, *ind_work;
    int *ind_jpvt;
    /* options: NULL when not configured */
    okid_real *dec_coef, *dec_state, *dec_out; /* anti-alias biquads, their state per channel, the kept sample */
    okid_real *scales;                         /* r input then m output scales */
    okid_real *iv_ring, *iv_block, *iv_m;      /* past inputs, pending instrument rows, Z'[Phi y] */
} okid_views_;

/* A ring of the last `depth` vectors of `width` values: the sample window (r + m, p) and the
   instruments' past inputs (r, L; depth 0 without instruments). */
typedef struct okid_ring_ {
    okid_real *data;   /* width x depth, in the workspace */
    int width, depth;
    int head;          /* slot of the newest vector */
    int fill;          /* vectors held, up to depth */
} okid_ring_;

/* Sizes derived from the configuration. */
typedef struct okid_dims_ {
    int r, m, p, q, w;        /* inputs, outputs, observer order, regressor columns, q + m */
    int ncols;                /* columns of one Hankel block: r, or r + m when combined */
    int hankel_rows, hankel_cols, svd_size, max_order, markov_count;
    int block_rows, block_tile;
    int era_in_r;             /* the Hankel matrix and V' in R's unused triangle (OKID__ERA_IN_R) */
    int era_ldh, era_ldvt;    /* their leading dimensions: w + 1 there, else hankel_rows and svd_size */
    int decimation, instrument_lags, nz; /* K; L and nz = r (L + 1) (0 for least squares) */
} okid_dims_;

/* The identifier (typedef in okid/identifier.h): every member is private. */
struct okid_identifier {
    uint32_t magic_;
    okid_config cfg_;            /* as given, except dt: the model's interval, K times the pushed one */
    okid_dims_ dims_;
    okid_real forgetting_, rank_tolerance_;
    okid_ring_ window_;          /* v(k-1) .. v(k-p) */
    okid_ring_ inputs_;          /* u(k-1) .. u(k-L) for the instruments */
    int block_fill_;
    int has_model_;              /* 1 after a successful okid_identify(), until init/reset */
    int result_;                 /* at_.result[result_] is the last good result */
    int dec_phase_;              /* pushed samples since the last kept one (decimation) */
    int scales_known_;           /* 1 once the scales are set (OKID_SCALING_AUTO: at the first fold, or okid_set_scales()) */
    uint64_t samples_, rejected_, rows_;
    okid_views_ at_;
};

/* ---- Compile-time workspace size (equal to okid_workspace_size(); checked by the tests) ---- */

/* Every size macro computes in unsigned long long (types.h, OKID__ALIGN16); the public ones
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
#else
#define OKID__LWORK_GELSY(n, nrhs) (OKID__Z(n) * 37u + OKID__Z(nrhs) * 33u + 33u)
#define OKID__LWORK_GESVD(m, n)                                                                \
    (OKID__MAX(3u * OKID__MIN(OKID__Z(m), OKID__Z(n)) + OKID__MAX(OKID__Z(m), OKID__Z(n)),     \
               5u * OKID__MIN(OKID__Z(m), OKID__Z(n)))                                          \
     + 32u * (OKID__Z(m) + OKID__Z(n)))
#endif
#define OKID__Q(r, m, p) (OKID__Z(r) + (OKID__Z(r) + OKID__Z(m)) * OKID__Z(p))
#define OKID__W(r, m, p) (OKID__Q(r, m, p) + OKID__Z(m))
#define OKID__NCOLS(r, m, combined) ((combined) ? OKID__Z(r) + OKID__Z(m) : OKID__Z(r))
#define OKID__HR(m, alpha) (OKID__Z(alpha) * OKID__Z(m))
#define OKID__HC(r, m, beta, combined) (OKID__Z(beta) * OKID__NCOLS(r, m, combined))
#define OKID__K(r, m, alpha, beta, combined) OKID__MIN(OKID__HR(m, alpha), OKID__HC(r, m, beta, combined))
#define OKID__N(r, m, p, alpha, beta, order, combined) \
    ((order) > 0 ? OKID__Z(order) : OKID__MIN(OKID__K(r, m, alpha, beta, combined), OKID__Z(m) * OKID__Z(p)))
#define OKID__NB(block_rows) ((block_rows) > 0 ? OKID__Z(block_rows) : 32u)
#define OKID__NBT(r, m, p, block_rows) \
    OKID__MIN(OKID__MIN(OKID__NB(block_rows), OKID__W(r, m, p)), OKID__W(r, m, p) <= 128u ? 8u : 16u)

#define OKID__PERSISTENT_BYTES(r, m, p, block_rows)                                                \
    (OKID__RB(OKID__Z(p) * (OKID__Z(r) + OKID__Z(m))) + OKID__RB(OKID__NB(block_rows) * OKID__W(r, m, p)) \
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
     + (OKID__NB(block_rows) > 1u ? OKID__RB(OKID__NB(block_rows) * OKID__W(r, m, p)) : 0u))
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
    (OKID__NB(block_rows) > 1u ? OKID__RB(OKID__W(r, m, p) * OKID__W(r, m, p)) : 0u)
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
    ((estimator) ? OKID__RB(OKID__Z(r) * OKID__IV_LAGS(r, m, p, lags))                                        \
                       + OKID__RB(OKID__NB(block_rows) * OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u))    \
                       + OKID__RB(OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u) * OKID__W(r, m, p))        \
                       + (OKID__NB(block_rows) > 1u                                                            \
                              ? OKID__RB(OKID__NB(block_rows) * OKID__Z(r) * (OKID__IV_LAGS(r, m, p, lags) + 1u)) \
                                    + OKID__RB(OKID__NB(block_rows) * OKID__W(r, m, p))                        \
                              : 0u)                                                                            \
                 : 0u)

#endif

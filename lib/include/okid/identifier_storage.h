/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file identifier_storage.h
 * \brief NOT API: the storage of an okid_identifier (its size formulas are in okid/sizes.h).
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
#include "okid/ring_storage.h"
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
    okid_real *factor;  /* identify's copy of R with the pending rows folded in (block_rows > 1; with the
                           correlation form always: its Cholesky factor), else NULL */
    okid_real *pending; /* those rows, scaled and weighted (block_rows > 1) */
    okid_real *iv_pending, *iv_chunk; /* the instrument rows likewise, and a block of rows of M (instruments) */
    okid_real *fold_t, *fold_work; /* the QR fold's T tile and work; with the correlation form (LAPACK)
                                      fold_t: the Toeplitz Gram's open run, then identify's scratch run */
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

/* Sizes derived from the configuration. */
typedef struct okid_dims_ {
    int r, m, p, q, w;        /* inputs, outputs, observer order, regressor columns, q + m */
    int ncols;                /* columns of one Hankel block: r, or r + m when combined */
    int hankel_rows, hankel_cols, svd_size, max_order, markov_count;
    int block_rows, block_tile;
    int era_in_r;             /* the Hankel matrix and V' in R's unused triangle (OKID__ERA_IN_R) */
    int era_ldh, era_ldvt;    /* their leading dimensions: w + 1 there, else hankel_rows and svd_size */
    int decimation, instrument_lags, nz; /* K; L and nz = r (L + 1) (0 for least squares) */
    int correlation;          /* OKID_ESTIMATOR_CORRELATION: r holds [Phi Y]'[Phi Y], not its factor */
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

#endif

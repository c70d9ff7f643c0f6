/* SPDX-License-Identifier: Apache-2.0 */
/* The refinement's parametrisation, shared by refine.c, refine_modal_form.c and refine_uncertainty.c. */
#ifndef OKID_REFINE_INTERNAL_H
#define OKID_REFINE_INTERNAL_H

#include "okid/refine.h"

/* Kinds of parameter (okid_refiner::ptab_[4 p]); the state-moving ones come first in theta. */
enum {
    OKID_RP_LAMBDA_RE = 0, /* Re of the block's eigenvalue */
    OKID_RP_LAMBDA_IM = 1, /* Im of a pair's eigenvalue */
    OKID_RP_B = 2,         /* B(row, col), row an absolute state index */
    OKID_RP_X0 = 3,        /* x0(row) */
    OKID_RP_C = 4,         /* C(row, col), row an output, col a state */
    OKID_RP_D = 5,         /* D(row, col) */
    OKID_RP_K = 6          /* K(row, col) of the innovation form, row a state, col an output */
};

/* 1 when the refiner fits the innovation form. */
#define OKID_REFINE_IS_INNOVATION(rf) ((rf)->cfg_.refine_model == OKID_REFINE_INNOVATION)

/* Block table okid_refiner::blk_[OKID_RB_INTS b + field]. */
#define OKID_RB_INTS 4
#define OKID_RB_FIRST 0  /* first state */
#define OKID_RB_SIZE 1   /* 1 (real eigenvalue) or 2 (complex pair) */
#define OKID_RB_LAMBDA 2 /* index of its OKID_RP_LAMBDA_RE parameter */
#define OKID_RB_FIXED 3  /* the input whose B column is fixed to [1; 0] (or 1) */

/*
 * Real modal form of the start model: blocks, parameter table, theta, B, C, D; x0 = 0. Uses
 * rf->nrm_[1] (OKID__REFINE_SCRATCH reals) as scratch. Unstable eigenvalues are reflected into
 * the unit circle.
 */
okid_status okid_refine_modal_form(okid_refiner *rf, const okid_result *start);

/* Write theta into the model arrays (lam_re_, lam_im_, b_, c_, d_, x0_). */
void okid_refine_apply(okid_refiner *rf, const okid_real *theta);

/*
 * 1 when every eigenvalue of the model in the arrays lies strictly inside the unit circle, and
 * for the innovation form every eigenvalue of A - K C as well (the predictor's; its eigenvalue
 * scratch is the spare normal-matrix buffer nrm_[1 - best_]).
 */
int okid_refine_stable(okid_refiner *rf);

/*
 * Covariance of theta_best_ (the inverse of the accepted normal matrix, into nrm_[best_]), the
 * modes of the model and their standard deviations, scaled by noise_scale_. with_covariance 0:
 * stds are -1. Sets std_status_ (okid_refine_result::std_status).
 */
okid_status okid_refine_modes_and_std(okid_refiner *rf, int with_covariance);

/* OKID_W_MODE_SPLIT and split_[] of the modes and stds okid_refine_modes_and_std() left (refine_split.c). */
void okid_refine_find_split(okid_refiner *rf);

/*
 * Solve (N + mu diag(N)) x = g for symmetric positive semi-definite N (upper triangle used,
 * np x np), through the Cholesky factor of its unit-diagonal scaling written to f (np x np) and
 * the scales sqrt(diag N) written to d (np). Returns 0 when the damped matrix is not positive definite.
 */
int okid_refine_damped_solve(int np, const okid_real *nrm, okid_real mu, const okid_real *g, okid_real *f,
                             okid_real *d, okid_real *x);

/* The residual tests (refine_residual_tests.c): zero this pass's sums (begin_pass); add one used
   sample's residual e, output y and input u; close a block of the score (every block_len_ used samples and
   at the pass's end); keep this pass's sums as the accepted ones; the figures, the output warnings
   and the covariance choice at the end (diverged: no figures, -1). */
void okid_refine_tests_begin_pass(okid_refiner *rf);
void okid_refine_tests_sample(okid_refiner *rf, const okid_real *e, const okid_real *y, const okid_real *u);
void okid_refine_tests_close_block(okid_refiner *rf);
void okid_refine_tests_accept(okid_refiner *rf);
void okid_refine_tests_finish(okid_refiner *rf, int diverged);

#endif

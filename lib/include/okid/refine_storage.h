/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file refine_storage.h
 * \brief NOT API: the storage of an okid_refiner.
 *
 * okid/refine.h includes this header; do not include it yourself. The struct is complete here
 * only so that a refiner can be allocated statically (firmware); its members are private to the
 * library and change without notice. Size its workspace with okid_refine_workspace_size() or
 * OKID_REFINE_WORKSPACE_BYTES().
 */
#ifndef OKID_REFINE_STORAGE_H
#define OKID_REFINE_STORAGE_H

#include <stdint.h>

#include "okid/modal.h"
#include "okid/types.h"

/* The refiner (typedef in okid/refine.h): every member is private. */
struct okid_refiner {
    uint32_t magic_;
    okid_refine_config cfg_;
    int n_, r_, m_, np_, nblocks_;
    okid_sensing sensing_;
    okid_real dt_;
    okid_refine_state state_;
    int passes_, iterations_, in_pass_, finished_, noise_fixed_;
    int best_;                  /* which of the two normal-matrix buffers holds the accepted one */
    okid_real mu_, cost_best_;
    okid_real decrement_;       /* okid_refine_result::decrement */
    okid_real noise_scale_;     /* a power of two: weight_ are those of noise_std / noise_scale_ */
    okid_status std_status_;    /* okid_refine_result::std_status */
    uint64_t samples_, pass_samples_, samples_used_;
    unsigned warnings_;
    int num_modes_;
    int split_[2];              /* okid_refine_result::split_modes */
    /* workspace views */
    int *ptab_;                 /* 4 ints per parameter: kind, block, row, col */
    int *blk_;                  /* 4 ints per block: first state, size, eigenvalue parameter, fixed input */
    okid_real *theta_best_, *theta_, *lam_re_, *lam_im_, *b_, *c_, *d_, *x0_;
    okid_real *x_, *sens_, *jrow_, *nrm_[2], *grad_, *grad_best_, *step_, *diag_;
    okid_real *ss_, *yy_, *weight_, *rms_start_, *rms_, *e_, *wj_; /* e_, wj_: one sample's residual, weighted row */
    okid_real *a_full_;
    /* residual tests: past residuals (ring of OKID_REFINE_LAGS per output, lag_pos_ the newest),
       lagged products of this pass and of the accepted one, sum of y, the tests' figures */
    okid_real *lag_ring_, *acf_, *acf_best_, *ysum_, *whiteness_, *max_acf_, *fit_;
    unsigned *out_warn_, test_warnings_;
    int lag_pos_;
    /* the input-residual cross-correlation test: ring of the last OKID_REFINE_LAGS inputs (u_pos_ the
       newest, u(k) once the sample is in), sum_k e_i(k) u_j(k - l) of this pass and of the accepted
       one (m x r x lags, [(i + m j) lags + l]), sum_k u_j(k) u_j(k - l) (r x lags, lag 0 first),
       sum u, sum e (this pass, accepted), and the test's figures (m x r each, [i + m j]) */
    okid_real *u_ring_, *ccf_, *ccf_best_, *uacf_, *usum_, *esum_, *esum_best_;
    okid_real *xcorr_, *max_xcorr_, *xcorr_band_;
    int u_pos_;
    okid_refine_covariance covariance_;
    /* sandwich: the score's block sums (grad_ at the block's start) and their outer products of
       this pass and of the accepted one (score_[best_]); score_ok_[b]: that buffer was summed */
    okid_real *grad_mark_, *score_[2], *score_sum_;
    int score_ok_[2];
    uint64_t block_len_;
    okid_mode *modes_;
    okid_mode_std *mode_std_;
    okid_complex *shapes_, *shape_std_;
    /* innovation form (cfg_.refine_model): the gain K (n x m, modal form; NULL for output error); sens_
       then holds n reals per parameter (the full state sensitivity), not 2 */
    okid_real *k_;
};

#endif

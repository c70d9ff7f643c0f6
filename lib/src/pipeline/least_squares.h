/*
 * Least squares for the observer Markov parameters (eq. 50) in fixed memory: regressor rows are
 * folded into the upper-triangular factor R of [Phi | Y] (w x w, w = q + m) by blocks, so any
 * number of samples fits in O(w^2) memory. R = [R11 R12; 0 R22]: R11 (q x q) is the factor of
 * the regressor, R12 (q x m) of its correlation with the outputs.
 */
#ifndef OKID_LEAST_SQUARES_H
#define OKID_LEAST_SQUARES_H

#include "okid/identifier.h"

/* Fold the pending rows of the block into R (with the channel scales and the forgetting weights),
   or into the instruments' cross-product (OKID_ESTIMATOR_INSTRUMENTAL), and empty the block. */
okid_status okid_lsq_fold_pending(okid_identifier *id);

/*
 * Solve R11 X = R12 rank-revealingly into the x view (q x m, internal column order of
 * sample_buffer.h): X' = [D, observer Markov parameters]. Reports the numerical rank of the
 * regressor and of its input part. OKID_E_RANK_DEFICIENT when the input is not persistently
 * exciting (input rank < r (p + 1)).
 */
okid_status okid_lsq_solve(okid_identifier *id, int *regressor_rank, int *input_rank);

/* Column norms of the leading n columns of the triangular factor r (the regressor's); 1 for a zero column. */
void okid_lsq_column_norms(const okid_real *r, int ldr, int n, okid_real *scale);

/*
 * s = R(0:n, 0:n) diag(1 / scale), equilibrated so that units do not decide rank or condition,
 * written transposed into R's unused strict lower triangle (s(i, j) = s[i w + j], the layout of
 * okid_triangular_lstsq with lda = w): the solves need no copy beside R and leave R intact.
 * Returns s.
 */
okid_real *okid_lsq_equilibrated_copy(okid_identifier *id, int n, const okid_real *scale);

#endif

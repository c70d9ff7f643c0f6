/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Recovery of the system Markov parameters Y_k (eq. 51) and of the observer-gain Markov
 * parameters Y°_k (eq. 53) from the observer Markov parameters solved by least_squares.h.
 */
#ifndef OKID_MARKOV_H
#define OKID_MARKOV_H

#include "okid/types.h"

/*
 * From x (q x m, leading dimension ldx, q = r + (r + m) p, the column order of sample_buffer.h)
 * fill markov (m x r (L + 1), leading dimension m) with [Y_0 .. Y_L] and, when markov_obs is not
 * NULL, markov_obs (m x m L, leading dimension m) with [Y°_1 .. Y°_L].
 */
void okid_markov_recover(int r, int m, int p, int L, const okid_real *x, int ldx, okid_real *markov,
                         okid_real *markov_obs);

#endif

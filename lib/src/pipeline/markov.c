/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Eq. 51 and 53. With X the least-squares solution (q x m, sample_buffer.h column order), the
 * observer Markov parameters are
 *   D = Ybar_0 = X(0:r, :)',  Ybar1_j = X(r + (j-1) r : r + j r, :)',
 *   Ybar2_j = -X(r (p+1) + (j-1) m : r (p+1) + j m, :)'   (the model has -Ybar2_j y(k-j)).
 * Then Y_k = Ybar1_k - sum_{i=1}^{min(k,p)} Ybar2_i Y_(k-i)   (Ybar1_k = 0 for k > p)
 * and  Y°_k = Ybar2_k - sum_{i=1}^{min(k-1,p)} Ybar2_i Y°_(k-i) (Ybar2_k = 0 for k > p).
 */
#include "pipeline/markov.h"

#include "numerics/dense.h"

/* The solution x and its shape, read in place. */
typedef struct observer_solution {
    int r, m, p, ldx;
    const okid_real *x;
} observer_solution;

/* Ybar1_j(a, b) and Ybar2_j(a, b), read in place from X. */
static okid_real ybar1(const observer_solution *o, int j, int a, int b)
{
    return OKID_AT(o->x, o->ldx, o->r + (j - 1) * o->r + b, a);
}

static okid_real ybar2(const observer_solution *o, int j, int a, int b)
{
    return -OKID_AT(o->x, o->ldx, o->r * (o->p + 1) + (j - 1) * o->m + b, a);
}

void okid_markov_recover(int r, int m, int p, int L, const okid_real *x, int ldx, okid_real *markov,
                         okid_real *markov_obs)
{
    const observer_solution o = {r, m, p, ldx, x};
    okid_real *y = markov; /* m x r(L+1): block k at column k r */
    for (int b = 0; b < r; ++b) {
        for (int a = 0; a < m; ++a) {
            OKID_AT(y, m, a, b) = OKID_AT(x, ldx, b, a);
        }
    }
    for (int k = 1; k <= L; ++k) {
        for (int b = 0; b < r; ++b) {
            for (int a = 0; a < m; ++a) {
                okid_real s = (k <= p) ? ybar1(&o, k, a, b) : 0;
                for (int i = 1; i <= k && i <= p; ++i) {
                    for (int l = 0; l < m; ++l) {
                        s -= ybar2(&o, i, a, l) * OKID_AT(y, m, l, (k - i) * r + b);
                    }
                }
                OKID_AT(y, m, a, k * r + b) = s;
            }
        }
    }
    okid_real *yo = markov_obs; /* m x mL: Y°_k at column (k-1) m */
    if (yo == NULL) {
        return;
    }
    for (int k = 1; k <= L; ++k) {
        for (int b = 0; b < m; ++b) {
            for (int a = 0; a < m; ++a) {
                okid_real s = (k <= p) ? ybar2(&o, k, a, b) : 0;
                for (int i = 1; i <= k - 1 && i <= p; ++i) {
                    for (int l = 0; l < m; ++l) {
                        s -= ybar2(&o, i, a, l) * OKID_AT(yo, m, l, (k - i - 1) * m + b);
                    }
                }
                OKID_AT(yo, m, a, (k - 1) * m + b) = s;
            }
        }
    }
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Eigensystem realization (eq. 57-61) from the recovered Markov parameters: Hankel matrix H(0),
 * its SVD, the order, and the realization A, B, C, D (and G for the combined realization).
 */
#ifndef OKID_ERA_H
#define OKID_ERA_H

#include "okid/status.h"
#include "okid/types.h"

/* What ERA realizes. */
typedef struct okid_era_problem {
    int r, m, ncols;               /* inputs, outputs, columns of a Hankel block: r, or r + m (combined) */
    int alpha, beta;               /* Hankel block rows and columns */
    int order;                     /* n, or 0: the largest gap among the leading singular values */
    int order_limit;               /* the automatic order's largest value (m p) */
    const okid_real *markov;       /* [Y_0 .. Y_L], m x r (L + 1), leading dimension m, L = alpha + beta */
    const okid_real *markov_obs;   /* [Y°_1 .. Y°_L], m x m L, leading dimension m; NULL (system realization) */
    const okid_real *scales;       /* r input then m output scales of OKID_SCALING_AUTO; NULL = 1 */
} okid_era_problem;

/* Scratch (OKID__PHASE_ERA_BYTES); hr = alpha m, hc = beta ncols, k = min(hr, hc). */
typedef struct okid_era_scratch {
    okid_real *h; int ldh;         /* hr x hc: H(0), then U; the indicators read U afterwards */
    okid_real *vt; int ldvt;       /* k x hc: V'; with leading, OKID__SVD_VT_ROWS(hr, hc, n) x hc */
    okid_real *t;                  /* hr x n: H(1) V_n */
    okid_real *col_scale;          /* ncols */
    okid_real *work;               /* OKID__LWORK_GESVD(hr, hc) */
    /* 0: every singular vector (the input-output identifier's, whose float results keep their bits);
       1: those of the order n only (the given order, or the automatic rule's limit): okid_la_svd's
       leading-vector route on the Eigen backend (the output-only identifier's) */
    int leading;
} okid_era_scratch;

/* The realization: leading dimensions n (a, b, g) and m (c, d), n the realized order. */
typedef struct okid_era_output {
    okid_real *sv;                 /* k Hankel singular values, decreasing */
    okid_real *a, *b, *c, *d;
    okid_real *g;                  /* NULL unless markov_obs is given */
} okid_era_output;

/*
 * Realize into out; *order is the realized order (problem order or the automatic rule, which sets
 * OKID_W_ORDER_AT_LIMIT in *warnings when it picks the limit). OKID_E_RANK_DEFICIENT when sigma_n
 * is zero to working precision; the backend's status when the SVD fails.
 */
okid_status okid_era_realize(const okid_era_problem *problem, const okid_era_scratch *scratch,
                             const okid_era_output *out, int *order, unsigned *warnings);

#endif

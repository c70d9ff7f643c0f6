/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Identifiability diagnostics of an identification (warning bits of status.h and the condition
 * numbers of okid_result): regressor rank against r (p + 1) + n, persistence of excitation,
 * observer order above the minimum on (near) noise-free data, Hankel span against the slowest
 * period, conditioning of the least squares and of the realization.
 */
#ifndef OKID_DIAGNOSTICS_H
#define OKID_DIAGNOSTICS_H

#include "okid/modal.h"
#include "pipeline/least_squares.h"

typedef struct okid_regressor_diagnostics {
    int expected_rank;         /* min(q, r (p + 1) + n) */
    okid_real lsq_condition;   /* 1-norm condition of the equilibrated R11 (+inf when singular) */
    okid_real input_condition; /* the same for its leading r (p + 1) columns */
} okid_regressor_diagnostics;

/*
 * Conditioning of the column-equilibrated regressor factor: r is the w-column factor of the
 * solve (leading dimension ldr > q, its strict lower triangle scratch as in okid_lsq_solve()), q
 * its regressor columns, nu = r (p + 1) the inputs', tol the rank tolerance, n the realized order,
 * regressor_rank the numerical rank the solve found. Sets OKID_W_RANK_BELOW_MODEL,
 * OKID_W_WEAK_EXCITATION and OKID_W_OBSERVER_ORDER_ABOVE_MINIMUM in *warnings.
 */
okid_status okid_diagnose_regressor(int q, int nu, okid_real *r, int ldr, okid_real tol, int n, int regressor_rank,
                                    const okid_lsq_scratch *scratch, okid_regressor_diagnostics *out,
                                    unsigned *warnings);

/*
 * sigma_1 / sigma_n of H(0) (sv, decreasing) into *condition; sets OKID_W_REALIZATION_ILL_CONDITIONED
 * and OKID_W_HANKEL_SPAN_SHORT (modes with their indicators; span = (alpha + beta) dt seconds).
 */
void okid_diagnose_realization(const okid_real *sv, int n, okid_real span, const okid_mode *modes, int num_modes,
                               okid_real *condition, unsigned *warnings);

#endif

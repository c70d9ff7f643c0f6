/* SPDX-License-Identifier: Apache-2.0 */
/*
 * Per-mode accuracy indicators (EMAC, MPC, MSV, CMI; okid/modal_indicators.h) of a realization,
 * on caller-provided scratch, shared by okid_identify() and the stabilization diagram.
 */
#ifndef OKID_MODAL_INDICATORS_INTERNAL_H
#define OKID_MODAL_INDICATORS_INTERNAL_H

#include "numerics/carve.h"
#include "okid/modal.h"
#include "okid/modal_indicators.h"
#include "pipeline/era.h"
#include "pipeline/modal_internal.h"

/* What the indicators compare: the realization and the last blocks of P = U_n S^1/2, Q = S^1/2 V_n'. */
typedef struct okid_indicator_inputs {
    int n, m, r;
    int alpha, beta;                        /* Hankel block rows and columns */
    const okid_real *b; int ldb;            /* n x r */
    const okid_real *c; int ldc;            /* m x n */
    const okid_real *obs_last; int ldo;     /* m x n: block row alpha - 1 of P */
    const okid_real *ctrl_last; int ldq;    /* n x r: input columns of block column beta - 1 of Q */
} okid_indicator_inputs;

/* Scratch for an n-state model with r inputs (see OKID__PHASE_INDICATOR_BYTES). */
typedef struct okid_indicator_scratch {
    okid_real *vr_copy; /* n x n */
    okid_real *rhs;     /* n x 2r */
    int *jpvt;          /* n */
    okid_real *work;    /* OKID__LWORK_GELSY(n, 2r) */
} okid_indicator_scratch;

/*
 * Carve the modal analysis's scratch of an n-state model (OKID__PHASE_MODAL_BYTES) and the
 * indicators' for r inputs after it (OKID__PHASE_INDICATOR_BYTES; their copy of the eigenvectors
 * reuses the modal analysis's copy of A): the standalone consumers' layout (stabilization, ambient).
 */
void okid_carve_modal_phase(okid_carver *c, uint64_t n, uint64_t r, okid_modal_scratch *modal,
                            okid_indicator_scratch *ind);

/*
 * Fill emac_output, emac_input, emac, msv and cmi of modes[0..num_modes) (mpc is already set by the
 * modal analysis) from the eigen-decomposition wr + i wi, vr (LAPACK layout, ld n) of the realized A.
 * Modes are matched to eigenvalues by value (the modal analysis copies them verbatim).
 */
okid_status okid_modal_indicators(const okid_indicator_inputs *in, const okid_real *vr, const okid_real *wr,
                                  const okid_real *wi, const okid_indicator_scratch *scratch, okid_mode *modes,
                                  int num_modes);

/*
 * After okid_era_realize() at order n (the scratch still holds U, V' and the column scales):
 * obs_last (m x n, ld m) = block row alpha - 1 of U_n S^1/2, ctrl_last (n x r, ld n) = the input
 * columns of block column beta - 1 of S^1/2 V_n', unscaled as B.
 */
void okid_indicators_capture(const okid_era_problem *problem, const okid_era_scratch *scratch, const okid_real *sv,
                             int n, okid_real *obs_last, okid_real *ctrl_last);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file modal_indicators.h
 * \brief Modal accuracy indicators of an ERA realization (Juang 1994, ch. 5 and 7; Pappa, Elliott,
 *        Schenk 1992): EMAC, MPC, MSV and CMI, as okid_identify() fills them into okid_mode.
 *
 * Notation: H(0) = U S V' (alpha block rows of m outputs, beta block columns), n states,
 * A = Psi Lambda Psi^-1 (Psi the right eigenvectors of the identified A), P = U_n S_n^1/2 the
 * identified observability matrix, Q = S_n^1/2 V_n' the identified controllability matrix (input
 * columns only, unscaled as B is). For mode i with eigenvalue lambda_i:
 *
 * - modal output row c_i = C psi_i (m values), modal input row b_i = (Psi^-1 B)_i (r values);
 * - identified output history o_i = (last block row of P) psi_i: what the data says the modal
 *   amplitudes are alpha - 1 steps later; the model predicts c_i lambda_i^(alpha-1);
 * - identified input history g_i = (Psi^-1 (last block column of Q))_i; the model predicts
 *   b_i lambda_i^(beta-1).
 *
 * Coherence of a predicted p and an identified q amplitude (Pappa et al. 1992):
 *   e(p, q) = min(|p|, |q|) / max(|p|, |q|) * w(|arg(q conj(p))|),
 *   w(phi) = 1 - phi / (pi/4) for phi <= pi/4, 0 beyond (0 when p = q = 0).
 *
 * - EMAC_output_i = sum_a |c_ia|^2 e(c_ia lambda_i^(alpha-1), o_ia) / sum_a |c_ia|^2
 * - EMAC_input_i  = sum_l |b_il|^2 e(b_il lambda_i^(beta-1), g_il) / sum_l |b_il|^2
 * - EMAC_i = EMAC_output_i * EMAC_input_i                      in [0, 1]
 * - MPC_i = |phi^T phi|^2 / (phi^H phi)^2, phi = c_i (the sensor shape): the squared spread
 *   ((l1 - l2) / (l1 + l2))^2 of the eigenvalues l1 >= l2 of the 2 x 2 matrix
 *   [Re phi, Im phi]' [Re phi, Im phi]; 1 when all components share one phase (a real mode)
 * - MSV_i = sqrt(|c_i|_2 |b_i|_2 (1 + |lambda_i| + ... + |lambda_i|^(l - 1))), l = alpha + beta - 1
 *   Markov parameters in H(0) (Juang 1994, sec. 7.4): the size of the mode in the pulse response
 * - CMI_i = EMAC_i * MPC_i                                     in [0, 1]
 *
 * Noise-free data realized at its true order gives EMAC = 1 (the shift structure of P and Q holds
 * exactly); computational modes of an overstated order have inconsistent histories and a low CMI.
 * All indicators are independent of the scale of psi_i. A conjugate pair is reported once.
 */
#ifndef OKID_MODAL_INDICATORS_H
#define OKID_MODAL_INDICATORS_H

#include "okid/modal.h" /* okid_mpc(), beside okid_mac() */
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * Amplitude coherence e(predicted, identified) of one component, as defined above, in [0, 1].
 * \return min/max of the magnitudes times the linear phase weight (0 at or beyond 45 degrees)
 */
okid_real okid_amplitude_coherence(okid_complex predicted, okid_complex identified);

#ifdef __cplusplus
}
#endif

#endif

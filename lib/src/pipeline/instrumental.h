/*
 * Instrumental-variable estimation of the observer Markov parameters (OKID_ESTIMATOR_INSTRUMENTAL).
 * Instead of the factor of [Phi y], the fixed-memory state is the cross-product
 * M = sum_k z(k) [phi(k)' y(k)'] (nz x w, nz = r (L + 1)), z(k) = [u(k); u(k-1); ...; u(k-L)].
 * At identify, M is reduced by Householder QR to the w x w triangular factor of the same layout as
 * the least squares keeps, so the rank-revealing solve and the diagnostics run unchanged on it:
 * the solve then minimises |M_phi X - M_y|, the extended IV estimate (Soederstroem and Stoica 1989).
 */
#ifndef OKID_INSTRUMENTAL_H
#define OKID_INSTRUMENTAL_H

#include "okid/identifier.h"

/* Empty the ring of past inputs (zero_history: zeros, as a record that starts at rest). */
void okid_iv_restart(okid_identifier *id, int zero_history);

/* 1 when the ring holds L past inputs (always 1 without instruments). */
int okid_iv_ready(const okid_identifier *id);

/* Write z(k) of input u into row `row` of the pending instrument block. */
void okid_iv_write_row(const okid_identifier *id, const okid_real *u, int row);

/* Append u(k) to the ring (no-op without instruments). */
void okid_iv_append(okid_identifier *id, const okid_real *u);

/* M = decay M + Z' B over the pending rows (already weighted and scaled). */
void okid_iv_accumulate(okid_identifier *id, okid_real decay);

/* The triangular factor R (w x w) of M, through the pending block (which must be empty). */
okid_status okid_iv_factor(okid_identifier *id);

#endif

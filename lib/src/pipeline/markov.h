/*
 * Recovery of the system Markov parameters Y_k (eq. 51) and of the observer-gain Markov
 * parameters Y°_k (eq. 53) from the observer Markov parameters solved by least_squares.h.
 */
#ifndef OKID_MARKOV_H
#define OKID_MARKOV_H

#include "okid/identifier.h"

/* Fill the markov view with [Y_0 .. Y_L] and, when markov_obs is not NULL, [Y°_1 .. Y°_L], L = alpha + beta. */
void okid_markov_recover(okid_identifier *id);

#endif

/*
 * Eigensystem realization (eq. 57-61) from the recovered Markov parameters: Hankel matrix H(0),
 * its SVD, the order, and the realization A, B, C, D (and G for the combined realization).
 */
#ifndef OKID_ERA_H
#define OKID_ERA_H

#include "okid/identifier.h"

/*
 * Realize into the a, b, c, d, g and sv views; *order is the realized order (cfg order or the
 * automatic rule). OKID_E_RANK_DEFICIENT when sigma_n is zero to working precision.
 */
okid_status okid_era_realize(okid_identifier *id, int *order, unsigned *warnings);

#endif

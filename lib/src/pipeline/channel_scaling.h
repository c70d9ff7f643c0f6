/*
 * Per-channel scaling (OKID_SCALING_AUTO): the scales are the RMS of each input and output over
 * the first block of regressor rows. The least squares and the instruments see the data divided
 * by them; the observer solution is unscaled right after the solve, and ERA balances its Hankel
 * with the same scales (era.c), so every returned quantity is in the units of the data.
 */
#ifndef OKID_CHANNEL_SCALING_H
#define OKID_CHANNEL_SCALING_H

#include "okid/identifier.h"

/* Scale of input i (0 <= i < r) or output a (index r + a); 1 without scaling. */
okid_real okid_channel_scale(const okid_identifier *id, int channel);

/* Before a fold: fix the scales from the pending rows if not yet known, then divide every column of
   the pending regressor rows (and instrument rows) by the scale of its channel. */
void okid_scaling_apply_pending(okid_identifier *id);

/* X (q x m) of the scaled data to X of the data: X(i, a) * s(output a) / s(channel of column i). */
void okid_scaling_unscale_solution(okid_identifier *id);

#endif

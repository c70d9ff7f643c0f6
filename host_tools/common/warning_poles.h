/* SPDX-License-Identifier: Apache-2.0 */
/* The poles a result's warning is about (issue 23: "an identified pole lies on or outside the unit
 * circle" did not say which). The rules are the library's own (lib/src/pipeline/modal.c), applied
 * to the modes it returned. */
#ifndef OKID_HOST_WARNING_POLES_H
#define OKID_HOST_WARNING_POLES_H

#include <stddef.h>

#include "okid/okid.h"

/* The indices (into modes) of the poles that OKID_W_UNSTABLE_POLE (|z| >= 1) or
 * OKID_W_NONPHYSICAL_POLE (z real and <= 0) is about, at most max of them; the number found (0 for
 * any other warning bit). */
int warning_poles(const okid_mode *modes, int num_modes, unsigned bit, int *which, int max);

/* The key of such a warning in the JSON "warning_poles" object, or NULL for a warning about no pole. */
const char *warning_poles_key(unsigned bit);

/* ": 3.6800 Hz (|z| 1.00021), 0.0712 Hz (|z| 1.00310)" for the table (frequencies name the poles in
 * both the model's and the physical listing); "" when the warning is about no pole. Truncated at size. */
void warning_poles_text(const okid_mode *modes, int num_modes, unsigned bit, char *text, size_t size);

#endif

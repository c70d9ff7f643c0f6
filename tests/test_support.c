/* SPDX-License-Identifier: Apache-2.0 */
/* See test_support.h. */
#include "test_support.h"

#include <float.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "reference/reference_data.h"

#define REF_CASE(P, SENSING, CA, CV, CD)                                                                \
    {#P, P##_DOFS, P##_R, P##_M, P##_MODES, P##_MARKOV_COUNT, P##_DT, SENSING, P##_MASS, P##_DAMPING,   \
     P##_STIFFNESS, P##_B2, CA, CV, CD, P##_AC, P##_BC, P##_C, P##_D, P##_A, P##_B, P##_EIG_RE,        \
     P##_EIG_IM, P##_POLE_RE, P##_POLE_IM, P##_FREQ_HZ, P##_DAMPING_RATIO, P##_SHAPE_RE, P##_SHAPE_IM, \
     P##_MARKOV, P##_HANKEL_SV}

const ref_case REF_PAPER = REF_CASE(PAPER, OKID_SENSING_ACCELERATION, PAPER_CA, NULL, NULL);
const ref_case REF_STIFFER = REF_CASE(STIFFER, OKID_SENSING_ACCELERATION, STIFFER_CA, NULL, NULL);
const ref_case REF_MIMO = REF_CASE(MIMO, OKID_SENSING_DISPLACEMENT, NULL, NULL, MIMO_CD);
const ref_case REF_CHAIN3 = REF_CASE(CHAIN3, OKID_SENSING_VELOCITY, NULL, CHAIN3_CV, NULL);

void test_simulate(const ref_case *rc, size_t count, const okid_real *u, okid_real *y, okid_real *state)
{
    const int n = 2 * rc->dofs, r = rc->r, m = rc->m;
    double x[TEST_MAX_STATES] = {0}, next[TEST_MAX_STATES]; /* in double also in a float build */
    if (state != NULL) {
        for (int i = 0; i < n; ++i) x[i] = state[i];
    }
    for (size_t k = 0; k < count; ++k) {
        const okid_real *uk = u + k * (size_t)r;
        for (int i = 0; i < m; ++i) {
            double s = 0;
            for (int j = 0; j < n; ++j) s += rc->c[i + j * m] * x[j];
            for (int j = 0; j < r; ++j) s += rc->d[i + j * m] * uk[j];
            y[k * (size_t)m + (size_t)i] = (okid_real)s;
        }
        for (int i = 0; i < n; ++i) {
            double s = 0;
            for (int j = 0; j < n; ++j) s += rc->a[i + j * n] * x[j];
            for (int j = 0; j < r; ++j) s += rc->b[i + j * n] * uk[j];
            next[i] = s;
        }
        memcpy(x, next, sizeof x);
    }
    if (state != NULL) {
        for (int i = 0; i < n; ++i) state[i] = (okid_real)x[i];
    }
}

okid_real *test_white_noise(int r, size_t count, uint64_t seed)
{
    okid_real *u = malloc(sizeof(okid_real) * (size_t)r * count);
    assert_non_null(u);
    okid_rng rng;
    okid_rng_seed(&rng, seed);
    assert_int_equal(okid_rng_normal(&rng, 1, (size_t)r * count, u, 1), OKID_OK);
    return u;
}

void *test_workspace(const okid_config *cfg, size_t *bytes)
{
    assert_int_equal(okid_workspace_size(cfg, bytes), OKID_OK);
    void *ws = aligned_alloc(OKID_WORKSPACE_ALIGN, (*bytes + 15u) / 16u * 16u);
    assert_non_null(ws);
    return ws;
}

void test_config(const ref_case *rc, okid_config *cfg)
{
    assert_int_equal(okid_config_default(cfg, rc->r, rc->m), OKID_OK);
    cfg->dt = rc->dt;
    cfg->observer_order = 20;
    cfg->order = 2 * rc->dofs;
    cfg->hankel_rows = 20;
    cfg->hankel_cols = 20;
    cfg->sensing = rc->sensing;
    cfg->zero_initial_state = 1;
}

okid_status test_identify_case(const ref_case *rc, const okid_config *cfg, size_t samples, uint64_t seed,
                               okid_identifier *id, void **workspace, okid_result *result)
{
    return test_identify_noisy(rc, cfg, samples, seed, 0, id, workspace, result);
}

/* Adds white noise of std noise * RMS(output a) to each output a (seeded apart from the input). */
static void add_output_noise(int m, size_t samples, okid_real *y, double noise, uint64_t seed)
{
    okid_real *e = test_white_noise(m, samples, seed ^ 0x5EEDu);
    for (int a = 0; a < m; ++a) {
        double power = 0;
        for (size_t k = 0; k < samples; ++k) power += y[k * (size_t)m + (size_t)a] * y[k * (size_t)m + (size_t)a];
        const double std = noise * sqrt(power / (double)samples);
        for (size_t k = 0; k < samples; ++k) y[k * (size_t)m + (size_t)a] += (okid_real)(std * e[k * (size_t)m + (size_t)a]);
    }
    free(e);
}

okid_status test_identify_noisy(const ref_case *rc, const okid_config *cfg, size_t samples, uint64_t seed,
                                double noise, okid_identifier *id, void **workspace, okid_result *result)
{
    size_t bytes = 0;
    *workspace = test_workspace(cfg, &bytes);
    assert_int_equal(okid_init(id, cfg, *workspace, bytes, NULL), OKID_OK);
    okid_real *u = test_white_noise(rc->r, samples, seed);
    okid_real *y = malloc(sizeof(okid_real) * (size_t)rc->m * samples);
    assert_non_null(y);
    test_simulate(rc, samples, u, y, NULL);
    if (noise > 0) add_output_noise(rc->m, samples, y, noise, seed);
    size_t accepted = 0;
    assert_int_equal(okid_push_block(id, samples, u, (size_t)rc->r, y, (size_t)rc->m, &accepted), OKID_OK);
    assert_int_equal(accepted, samples);
    free(u);
    free(y);
    return okid_identify(id, result);
}

double identify_tol(const ref_case *rc)
{
#if OKID_REAL_IS_FLOAT
    const int n = 2 * rc->dofs;
    return 2 * FLT_EPSILON * rc->hankel_sv[0] / rc->hankel_sv[n - 1];
#else
    (void)rc;
    return 1e-9;
#endif
}

/* The tolerance log: each check site's worst err / tol, written when the test program exits. */
enum { TOLERANCE_SITES = 1024 };
typedef struct tolerance_site {
    const char *file, *what; /* string literals or __FILE__: they live as long as the program */
    int line;
    double worst_ratio, err, tol;
} tolerance_site;
static tolerance_site tolerance_sites[TOLERANCE_SITES];
static int tolerance_site_count;

static void write_tolerance_log(void)
{
    FILE *log = fopen(getenv("OKID_TOLERANCE_LOG"), "a");
    if (!log) return;
    for (int i = 0; i < tolerance_site_count; ++i) {
        const tolerance_site *s = &tolerance_sites[i];
        const char *base = strrchr(s->file, '/');
        fprintf(log, "%s:%d\t%s\t%.3e\t%.3e\t%.3e\n", base ? base + 1 : s->file, s->line, s->what, s->worst_ratio,
                s->err, s->tol);
    }
    fclose(log);
}

static void log_tolerance(const char *file, int line, const char *what, double err, double tol)
{
    static int enabled = -1;
    if (enabled < 0) {
        const char *path = getenv("OKID_TOLERANCE_LOG");
        enabled = path && *path;
        if (enabled) atexit(write_tolerance_log);
    }
    if (!enabled) return;
    const double ratio = (tol > 0) ? err / tol : (err == 0 ? 0 : HUGE_VAL);
    for (int i = 0; i < tolerance_site_count; ++i) {
        tolerance_site *s = &tolerance_sites[i];
        if (s->line == line && strcmp(s->file, file) == 0 && strcmp(s->what, what) == 0) {
            if (ratio > s->worst_ratio) { s->worst_ratio = ratio; s->err = err; s->tol = tol; }
            return;
        }
    }
    if (tolerance_site_count < TOLERANCE_SITES) {
        tolerance_sites[tolerance_site_count++] = (tolerance_site){file, what, line, ratio, err, tol};
    }
}

void check_within_at(const char *file, int line, const char *what, int index, double err, double tol)
{
    log_tolerance(file, line, what, err, tol);
    if (!(err <= tol)) {
        fail_msg("%s:%d: %s[%d] = %.17g exceeds its tolerance %.3g", file, line, what, index, err, tol);
    }
}

void assert_relative_at(const char *file, int line, double got, double want, double tol, const char *what, int index)
{
    const double scale = (want != 0) ? fabs(want) : 1;
    const double err = fabs(got - want) / scale;
    log_tolerance(file, line, what, err, tol);
    if (!(err <= tol)) {
        fail_msg("%s:%d: %s[%d]: got %.17g, want %.17g (relative error %.3g > %.3g)", file, line, what, index, got, want,
                 err, tol);
    }
}

/* MAC and the phase-aligned relative difference of two complex vectors (b is the reference). */
static void compare_shapes(const okid_complex *a, const okid_real *b_re, const okid_real *b_im, int len, double *mac,
                           double *diff)
{
    double ab_re = 0, ab_im = 0, aa = 0, bb = 0;
    for (int i = 0; i < len; ++i) {
        ab_re += a[i].re * b_re[i] + a[i].im * b_im[i]; /* conj(a) b */
        ab_im += a[i].re * b_im[i] - a[i].im * b_re[i];
        aa += a[i].re * a[i].re + a[i].im * a[i].im;
        bb += b_re[i] * b_re[i] + b_im[i] * b_im[i];
    }
    *mac = (ab_re * ab_re + ab_im * ab_im) / (aa * bb);
    /* a scaled by (a^H b) / (a^H a) is the closest multiple of a to b. */
    const double s_re = ab_re / aa, s_im = ab_im / aa;
    double worst = 0;
    for (int i = 0; i < len; ++i) {
        const double re = a[i].re * s_re - a[i].im * s_im - b_re[i];
        const double im = a[i].re * s_im + a[i].im * s_re - b_im[i];
        worst = fmax(worst, hypot(re, im));
    }
    *diff = worst / sqrt(bb);
}

void assert_modes_match_at(const char *file, int line, const ref_case *rc, const okid_mode *modes, int num_modes,
                           double tol, double mac_min)
{
    assert_int_equal(num_modes, rc->num_modes);
    const int len = 2 * rc->dofs;
    for (int i = 0; i < num_modes; ++i) {
        const double lambda_err = hypot(modes[i].eigenvalue.re - rc->eig_re[i], modes[i].eigenvalue.im - rc->eig_im[i]) /
                                  hypot(rc->eig_re[i], rc->eig_im[i]);
        assert_relative_at(file, line, lambda_err, 0, tol, "eigenvalue", i);
        assert_int_equal(modes[i].is_pair, 1);
#if OKID_REAL_IS_FLOAT
        /* s = ln(lambda) / dt magnifies lambda's relative error by 1 / (|s| dt) (oversampling), and
           zeta = -Re(s) / |s| by up to 2 / zeta more; in double one tolerance covers all of them. */
        const double s_tol = tol / (hypot(rc->pole_re[i], rc->pole_im[i]) * rc->dt);
        const double zeta_tol = 2 * s_tol / rc->damping_ratio[i];
#else
        const double s_tol = tol, zeta_tol = tol;
#endif
        assert_relative_at(file, line, modes[i].pole.re, rc->pole_re[i], zeta_tol, "pole re", i);
        assert_relative_at(file, line, modes[i].pole.im, rc->pole_im[i], s_tol, "pole im", i);
        assert_relative_at(file, line, modes[i].frequency_hz, rc->freq_hz[i], s_tol, "frequency", i);
        assert_relative_at(file, line, modes[i].damping_ratio, rc->damping_ratio[i], zeta_tol, "damping ratio", i);
        double mac = 0, diff = 0;
        compare_shapes(modes[i].shape, rc->shape_re + (size_t)i * (size_t)len, rc->shape_im + (size_t)i * (size_t)len,
                       len, &mac, &diff);
        /* 1 - MAC = sin^2 of the angle <= |a' - b|^2 / |b|^2 <= len diff^2 (diff: the largest component's
           difference over |b|), so a shape within s_tol has 1 - MAC <= len s_tol^2; mac_min is the floor */
        check_within_at(file, line, "1 - shape MAC", i, 1 - mac, fmax(1 - mac_min, len * s_tol * s_tol));
        check_within_at(file, line, "shape difference", i, diff, s_tol); /* the eq. 64 basis scales by powers of s */
    }
}

double max_relative_difference(const okid_real *a, const okid_real *b, size_t count)
{
    double diff = 0, scale = 0;
    for (size_t i = 0; i < count; ++i) {
        diff = fmax(diff, fabs(a[i] - b[i]));
        scale = fmax(scale, fabs(b[i]));
    }
    return (scale > 0) ? diff / scale : diff;
}

void test_paper_record(double dt, size_t count, uint64_t seed, double noise, okid_real **u, okid_real **y)
{
    const ref_case *rc = &REF_PAPER;
    const int n = 2 * rc->dofs;
    okid_real a[16], b[4], work[OKID_ZOH_WORK_REALS(4, 1)], state[4] = {0}, scratch[4];
    assert_int_equal(okid_discretize_zoh(n, rc->r, rc->ac, rc->bc, (okid_real)dt, a, b, work,
                                         sizeof work / sizeof work[0]), OKID_OK);
    okid_simulator sim;
    assert_int_equal(okid_simulator_init(&sim, n, rc->r, rc->m, a, b, rc->c, rc->d, state, scratch), OKID_OK);
    *u = test_white_noise(rc->r, count, seed);
    *y = malloc(sizeof(okid_real) * (size_t)rc->m * count);
    assert_non_null(*y);
    assert_int_equal(okid_simulate(&sim, count, *u, (size_t)rc->r, *y, (size_t)rc->m), OKID_OK);
    if (noise > 0) add_output_noise(rc->m, count, *y, noise, seed);
}

double test_paper_frequency_error(const okid_result *res)
{
    double got[2];
    int pairs = 0;
    for (int i = 0; i < res->num_modes && pairs < 2; ++i) {
        if (res->modes[i].is_pair) got[pairs++] = res->modes[i].frequency_hz;
    }
    if (pairs < 2) return 1e9;
    double worst = 0;
    for (int i = 0; i < 2; ++i) {
        const double e = fabs(got[i] - REF_PAPER.freq_hz[i]) / REF_PAPER.freq_hz[i];
        worst = e > worst ? e : worst;
    }
    return worst;
}

double test_paper_record_error(const okid_config *cfg, size_t count, uint64_t seed, double noise,
                               okid_result *res_out)
{
    okid_real *u = NULL, *y = NULL;
    test_paper_record((double)cfg->dt, count, seed, noise, &u, &y);
    size_t bytes = 0;
    void *ws = test_workspace(cfg, &bytes);
    okid_identifier id;
    okid_result res;
    assert_int_equal(okid_init(&id, cfg, ws, bytes, NULL), OKID_OK);
    assert_int_equal(okid_push_block(&id, count, u, 1, y, 2, NULL), OKID_OK);
    const okid_status st = okid_identify(&id, &res);
    const double err = st == OKID_OK ? test_paper_frequency_error(&res) : 1e9;
    if (res_out != NULL) {
        assert_int_equal(st, OKID_OK);
        *res_out = res;
        res_out->modes = NULL; /* every view points into the workspace freed below */
    }
    free(ws);
    free(u);
    free(y);
    return err;
}

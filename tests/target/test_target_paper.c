/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The paper case on the target (and, built by the host compiler, on the host: see host_twin/):
 * 1001 samples of white noise through the reference plant of tests/reference, identified with
 * p = 20, alpha = beta = 20, n = 4. The modes must match the reference within the tolerances the
 * docs/accuracy.md states (the host tests' ones). Every stage's numbers are also printed as IEEE bit
 * patterns ("bits <stage> <index> <hex>") so compare_bits.cmake can hold the target's run
 * against the host's bit for bit. The excitation is uniform noise scaled to unit variance, made
 * by integer arithmetic alone, so libm enters only where the library itself calls it.
 */
#include <stdint.h>
#include <string.h>

#include "okid/okid.h"
#include "plant_2dof.h"
#include "reference/reference_data.h"
#include "target_check.h"

enum { SAMPLES = 1001, N = PLANT_STATES };

#if OKID_REAL_IS_FLOAT
static const double LAMBDA_TOL = 3e-4, MARKOV_TOL = 2e-6; /* docs/accuracy.md: accuracy in float */
#else
static const double LAMBDA_TOL = 1e-9, MARKOV_TOL = 1e-9;
#endif

static _Alignas(OKID_WORKSPACE_ALIGN) unsigned char
    workspace[OKID_WORKSPACE_BYTES(PAPER_R, PAPER_M, PLANT_OBSERVER_ORDER, PLANT_HANKEL_ROWS, PLANT_HANKEL_COLS, N, 0, 0)];
static okid_real force[SAMPLES], accelerations[PAPER_M * SAMPLES];
static okid_identifier identifier;

static void print_bits(const char *stage, int index, okid_real x)
{
#if OKID_REAL_IS_FLOAT
    uint32_t b;
    memcpy(&b, &x, sizeof b);
    printf("bits %s %d %08lx\n", stage, index, (unsigned long)b);
#else
    uint64_t b;
    memcpy(&b, &x, sizeof b);
    printf("bits %s %d %016llx\n", stage, index, (unsigned long long)b);
#endif
}

/* One line for a long array: FNV-1a over its bytes. */
static void print_hash(const char *stage, const okid_real *x, int count)
{
    uint32_t h = 2166136261u;
    const unsigned char *bytes = (const unsigned char *)x;
    for (size_t i = 0; i < sizeof(okid_real) * (size_t)count; ++i) {
        h = (h ^ bytes[i]) * 16777619u;
    }
    printf("bits %s hash %08lx\n", stage, (unsigned long)h);
}

/* u: uniform on [-sqrt 3, sqrt 3); y: the reference model from rest, accumulated in double. */
static void make_data(void)
{
    okid_rng rng;
    okid_rng_seed(&rng, 2024);
    double x[4] = {0}, next[4];
    for (int k = 0; k < SAMPLES; ++k) {
        force[k] = (2 * okid_rng_uniform(&rng) - 1) * (okid_real)1.7320508075688772;
        for (int i = 0; i < PAPER_M; ++i) {
            double s = (double)PAPER_D[i] * (double)force[k];
            for (int j = 0; j < 4; ++j) s += (double)PAPER_C[i + j * PAPER_M] * x[j];
            accelerations[PAPER_M * k + i] = (okid_real)s;
        }
        for (int i = 0; i < 4; ++i) {
            double s = (double)PAPER_B[i] * (double)force[k];
            for (int j = 0; j < 4; ++j) s += (double)PAPER_A[i + j * 4] * x[j];
            next[i] = s;
        }
        memcpy(x, next, sizeof x);
    }
}

/* Modes against the reference; poles and damping inherit lambda's error magnified as in the
   host tests (1 / (|s| dt), then 2 / zeta). */
static void check_modes(const okid_result *res)
{
    CHECK(res->num_modes == PAPER_MODES);
    for (int i = 0; i < res->num_modes && i < PAPER_MODES; ++i) {
        const okid_mode *mode = &res->modes[i];
        const double lambda = hypot((double)PAPER_EIG_RE[i], (double)PAPER_EIG_IM[i]);
        const double s_abs = hypot((double)PAPER_POLE_RE[i], (double)PAPER_POLE_IM[i]);
        const double s_tol = OKID_REAL_IS_FLOAT ? LAMBDA_TOL / (s_abs * PAPER_DT) : LAMBDA_TOL;
        const double zeta_tol = OKID_REAL_IS_FLOAT ? 2 * s_tol / (double)PAPER_DAMPING_RATIO[i] : LAMBDA_TOL;
        CHECK_CLOSE(mode->eigenvalue.re, PAPER_EIG_RE[i], LAMBDA_TOL, lambda);
        CHECK_CLOSE(mode->eigenvalue.im, PAPER_EIG_IM[i], LAMBDA_TOL, lambda);
        CHECK_CLOSE(mode->frequency_hz, PAPER_FREQ_HZ[i], s_tol, (double)PAPER_FREQ_HZ[i]);
        CHECK_CLOSE(mode->damping_ratio, PAPER_DAMPING_RATIO[i], zeta_tol, (double)PAPER_DAMPING_RATIO[i]);
    }
}

static void check_markov(const okid_result *res)
{
    const int count = PAPER_M * PAPER_R * (PAPER_MARKOV_COUNT + 1);
    double scale = 0;
    for (int i = 0; i < count; ++i) {
        scale = fmax(scale, fabs((double)PAPER_MARKOV[i]));
    }
    CHECK(res->markov.cols * res->markov.rows == count);
    for (int i = 0; i < count; ++i) {
        CHECK_CLOSE(res->markov.data[i], PAPER_MARKOV[i], MARKOV_TOL, scale);
    }
}

static void print_stages(const okid_result *res)
{
    print_hash("force", force, SAMPLES);
    print_hash("accelerations", accelerations, PAPER_M * SAMPLES);
    for (int i = 0; i < res->markov.rows * res->markov.cols; ++i) print_bits("markov", i, res->markov.data[i]);
    for (int i = 0; i < res->num_singular_values; ++i) print_bits("singular_value", i, res->singular_values[i]);
    for (int i = 0; i < N * N; ++i) print_bits("A", i, res->A.data[i]);
    for (int i = 0; i < res->num_modes; ++i) {
        print_bits("eigenvalue_re", i, res->modes[i].eigenvalue.re);
        print_bits("eigenvalue_im", i, res->modes[i].eigenvalue.im);
        print_bits("frequency_hz", i, res->modes[i].frequency_hz);
        print_bits("damping_ratio", i, res->modes[i].damping_ratio);
    }
}

int main(void)
{
    okid_config cfg;
    plant_2dof_identifier_config(&cfg, (okid_real)PAPER_DT, 0); /* the paper's configuration, blocks of 32 rows */
    make_data();
    okid_result res;
    CHECK(okid_init(&identifier, &cfg, workspace, sizeof workspace, NULL) == OKID_OK);
    for (int k = 0; k < SAMPLES; ++k) {
        CHECK(okid_push(&identifier, &force[k], &accelerations[PAPER_M * k]) == OKID_OK);
    }
    const okid_status st = okid_identify(&identifier, &res);
    CHECK(st == OKID_OK);
    if (st == OKID_OK) {
        check_modes(&res);
        check_markov(&res);
        print_stages(&res);
        printf("modes: %.9g Hz (zeta %.6g), %.9g Hz (zeta %.6g)\n", (double)res.modes[0].frequency_hz,
               (double)res.modes[0].damping_ratio, (double)res.modes[1].frequency_hz, (double)res.modes[1].damping_ratio);
    }
    return target_summary("test_target_paper");
}

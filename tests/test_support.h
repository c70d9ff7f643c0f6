/* SPDX-License-Identifier: Apache-2.0 */
/* Shared helpers of the C tests: the reference cases of reference_data.h, a plain simulator
   over the reference (numpy) matrices, identification runs, and tolerant comparisons. */
#ifndef OKID_TEST_SUPPORT_H
#define OKID_TEST_SUPPORT_H

#include <stdarg.h>
#include <stddef.h>
#include <setjmp.h>
#include <stdint.h>
#include <cmocka.h>

#include "okid/okid.h"

/*
 * The tolerance of a check: the first in double, the second when okid_real is float
 * (docs/accuracy.md explains the float figures: eps 6e-8 times the conditioning of each step).
 */
#if OKID_REAL_IS_FLOAT
#define TOL(double_tol, float_tol) (float_tol)
#else
#define TOL(double_tol, float_tol) (double_tol)
#endif

/* Noise-free identification of the reference cases: shapes' MAC above this minimum. */
#define IDENTIFY_MAC_MIN TOL(0.999999, 0.9999)

/* One reference system: matrices, exact modes and Markov parameters from make_reference.py. */
typedef struct ref_case {
    const char *name;
    int dofs, r, m, num_modes, markov_count;
    okid_real dt;
    okid_sensing sensing;
    const okid_real *mass, *damping, *stiffness, *b2, *ca, *cv, *cd;
    const okid_real *ac, *bc, *c, *d, *a, *b;
    const okid_real *eig_re, *eig_im, *pole_re, *pole_im, *freq_hz, *damping_ratio, *shape_re, *shape_im;
    const okid_real *markov, *hankel_sv;
} ref_case;

extern const ref_case REF_PAPER, REF_STIFFER, REF_MIMO, REF_CHAIN3;

/* Enough room for every reference case. */
enum { TEST_MAX_STATES = 8, TEST_MAX_IO = 4 };

/* y(:,k) = C x + D u(:,k); x = A x + B u(:,k), from x = 0 unless state is given (n values, updated). */
void test_simulate(const ref_case *rc, size_t count, const okid_real *u, okid_real *y, okid_real *state);

/* Unit-variance white noise for every input, count samples (column-major r x count); caller frees. */
okid_real *test_white_noise(int r, size_t count, uint64_t seed);

/* A heap workspace of okid_workspace_size() bytes (tests only; lib/ never allocates). */
void *test_workspace(const okid_config *cfg, size_t *bytes);

/* The configuration the paper case uses: p = 20, n = 2 * dofs, Hankel 20 x 20, from rest. */
void test_config(const ref_case *rc, okid_config *cfg);

/* Runs init + pushes + identify on noise-free data of rc; returns the status of okid_identify. */
okid_status test_identify_case(const ref_case *rc, const okid_config *cfg, size_t samples, uint64_t seed,
                               okid_identifier *id, void **workspace, okid_result *result);

/* Like test_identify_case, with white output noise of std noise * RMS of each output (0: none). */
okid_status test_identify_noisy(const ref_case *rc, const okid_config *cfg, size_t samples, uint64_t seed,
                                double noise, okid_identifier *id, void **workspace, okid_result *result);

/*
 * The paper's 2-DOF plant at sample interval dt through the library's own simulator (exact ZOH of
 * REF_PAPER's continuous model), from rest, unit white-noise force (seed), output noise as in
 * test_identify_noisy; *u (count) and *y (2 x count) are the caller's to free.
 */
void test_paper_record(double dt, size_t count, uint64_t seed, double noise, okid_real **u, okid_real **y);

/* Largest relative error of the two identified paper frequencies (sorted); 1e9 with fewer than two pairs. */
double test_paper_frequency_error(const okid_result *res);

/*
 * Identify test_paper_record(cfg->dt, count, seed, noise) with cfg (r = 1, m = 2) and return
 * test_paper_frequency_error (1e9 when okid_identify fails). res_out (may be NULL: then identify
 * must succeed) gets the result's scalars; its views are gone with the workspace (modes is NULL).
 */
double test_paper_record_error(const okid_config *cfg, size_t count, uint64_t seed, double noise,
                               okid_result *res_out);

/*
 * Every tolerance check of the suite goes through check_within_at(): it fails unless err <= tol, and
 * with OKID_TOLERANCE_LOG=FILE set it appends, at exit, each check site's worst err / tol (over all its
 * calls) to FILE, so that scripts/blas_kernels.sh can report each tolerance against the worst error
 * that the reference BLAS and every OpenBLAS kernel produced (docs/testing.md, "Tolerances").
 */
void check_within_at(const char *file, int line, const char *what, int index, double err, double tol);

/* err <= tol, err and tol any real expressions; the check is named by err's text. */
#define assert_within(err, tol) check_within_at(__FILE__, __LINE__, #err, 0, (double)(err), (double)(tol))

/* |got - want| <= tol * |want| (or tol when want = 0), with a message naming what. */
void assert_relative_at(const char *file, int line, double got, double want, double tol, const char *what, int index);
#define assert_relative(got, want, tol, what, index) \
    assert_relative_at(__FILE__, __LINE__, (double)(got), (double)(want), (double)(tol), what, index)

/*
 * The relative eigenvalue error noise-free identification of rc must meet (poles, damping and shapes
 * to it magnified as assert_modes_match() says): 1e-9 in double; in float 4u sigma_1 / sigma_n of
 * rc's exact Hankel matrix (u = 6e-8): the first-order effect of H's round-off, u sigma_1, on the
 * realization (docs/accuracy.md). It is an estimate, not a bound: over reference BLAS and four
 * OpenBLAS kernels the worst error reached 2.1u sigma_1 / sigma_n (scripts/blas_kernels.sh), so 4u.
 */
double identify_tol(const ref_case *rc);

/* Modes of result against the exact ones: eigenvalues, poles, frequencies, damping (relative tol),
   shapes phase-aligned (relative to their norm) and MAC above mac_min. */
void assert_modes_match_at(const char *file, int line, const ref_case *rc, const okid_mode *modes, int num_modes,
                           double tol, double mac_min);
#define assert_modes_match(rc, modes, num_modes, tol, mac_min) \
    assert_modes_match_at(__FILE__, __LINE__, rc, modes, num_modes, tol, mac_min)

/* Largest |a_i - b_i| over max |b_i|. */
double max_relative_difference(const okid_real *a, const okid_real *b, size_t count);

#endif

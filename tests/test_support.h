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

/* One reference system: matrices, exact modes and Markov parameters from make_reference.py. */
typedef struct ref_case {
    const char *name;
    int dofs, r, m, num_modes, markov_count;
    double dt;
    okid_sensing sensing;
    const double *mass, *damping, *stiffness, *b2, *ca, *cv, *cd;
    const double *ac, *bc, *c, *d, *a, *b;
    const double *eig_re, *eig_im, *pole_re, *pole_im, *freq_hz, *damping_ratio, *shape_re, *shape_im;
    const double *markov, *hankel_sv;
} ref_case;

extern const ref_case REF_PAPER, REF_STIFFER, REF_MIMO, REF_CHAIN3;

/* Enough room for every reference case. */
enum { TEST_MAX_STATES = 8, TEST_MAX_IO = 4 };

/* y(:,k) = C x + D u(:,k); x = A x + B u(:,k), from x = 0 unless state is given (n values, updated). */
void test_simulate(const ref_case *rc, size_t count, const double *u, double *y, double *state);

/* Unit-variance white noise for every input, count samples (column-major r x count); caller frees. */
double *test_white_noise(int r, size_t count, uint64_t seed);

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

/* |got - want| <= tol * |want| (or tol when want = 0), with a message naming what. */
void assert_relative(double got, double want, double tol, const char *what, int index);

/* Modes of result against the exact ones: eigenvalues, poles, frequencies, damping (relative tol),
   shapes phase-aligned (relative to their norm) and MAC above mac_min. */
void assert_modes_match(const ref_case *rc, const okid_mode *modes, int num_modes, double tol, double mac_min);

/* Largest |a_i - b_i| over max |b_i|. */
double max_relative_difference(const double *a, const double *b, size_t count);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * On the target, without linear algebra: the example's plant (chain model, state space, zero-order
 * hold) against the numpy/scipy reference of tests/reference, its impulse response through the
 * simulator against the reference Markov parameters C A^(k-1) B, and the white-noise generator's
 * statistics. Tolerances are normwise (relative to the largest reference entry).
 */
#include "okid/okid.h"
#include "plant_2dof.h"
#include "reference/reference_data.h"
#include "target_check.h"

#if OKID_REAL_IS_FLOAT
/* float: eps 6e-8; the hold's matrix exponential (scaling and squaring) loses a few hundred eps. */
static const double MODEL_TOL = 2e-6, MARKOV_TOL = 2e-5;
#else
static const double MODEL_TOL = 1e-12, MARKOV_TOL = 1e-11;
#endif

static double max_abs(const okid_real *x, int count)
{
    double m = 0;
    for (int i = 0; i < count; ++i) {
        m = fmax(m, fabs((double)x[i]));
    }
    return m;
}

static void check_matrix(const okid_real *got, const okid_real *want, int count, double tol)
{
    const double scale = max_abs(want, count);
    for (int i = 0; i < count; ++i) {
        CHECK_CLOSE(got[i], want[i], tol, scale);
    }
}

static void test_plant_matches_reference(const plant_2dof *plant)
{
    check_matrix(plant->a, PAPER_A, PLANT_STATES * PLANT_STATES, MODEL_TOL);
    check_matrix(plant->b, PAPER_B, PLANT_STATES * PLANT_INPUTS, MODEL_TOL);
    check_matrix(plant->c, PAPER_C, PLANT_OUTPUTS * PLANT_STATES, MODEL_TOL);
    check_matrix(plant->d, PAPER_D, PLANT_OUTPUTS * PLANT_INPUTS, MODEL_TOL);
}

/* A unit impulse at k = 0 from rest: y(k) is the Markov parameter Y_k (Y_0 = D). */
static void test_impulse_response(const plant_2dof *plant)
{
    enum { STEPS = 41 };
    static okid_real u[STEPS], y[PLANT_OUTPUTS * STEPS];
    okid_real state[PLANT_STATES] = {0}, scratch[PLANT_STATES];
    okid_simulator sim;
    u[0] = 1;
    CHECK(okid_simulator_init(&sim, PLANT_STATES, PLANT_INPUTS, PLANT_OUTPUTS, plant->a, plant->b, plant->c,
                              plant->d, state, scratch) == OKID_OK);
    CHECK(okid_simulate(&sim, STEPS, u, PLANT_INPUTS, y, PLANT_OUTPUTS) == OKID_OK);
    check_matrix(y, PAPER_MARKOV, PLANT_OUTPUTS * STEPS, MARKOV_TOL);
}

/* Mean and variance of 20000 deviates within 4 standard errors of 0 and 1. */
static void test_white_noise_statistics(void)
{
    enum { COUNT = 20000 };
    static okid_real noise[COUNT];
    okid_rng rng;
    CHECK(okid_rng_seed(&rng, 7) == OKID_OK);
    CHECK(okid_rng_normal(&rng, 1, COUNT, noise, 1) == OKID_OK);
    double sum = 0, sum2 = 0;
    for (int i = 0; i < COUNT; ++i) {
        sum += (double)noise[i];
        sum2 += (double)noise[i] * (double)noise[i];
    }
    const double mean = sum / COUNT, variance = sum2 / COUNT - mean * mean;
    CHECK_CLOSE(mean, 0, 4.0 / sqrt(COUNT), 1);
    CHECK_CLOSE(variance, 1, 4.0 * sqrt(2.0 / COUNT), 1);
}

int main(void)
{
    plant_2dof plant;
    CHECK(plant_2dof_build(&plant, (okid_real)PAPER_DT) == OKID_OK);
    test_plant_matches_reference(&plant);
    test_impulse_response(&plant);
    test_white_noise_statistics();
    return target_summary("test_target_model");
}

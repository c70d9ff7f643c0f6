/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file model.h
 * \brief The mechanical model of the paper (eq. 1-14): M, R, K, B2, Ca, Cv, Cd to a continuous
 *        state-space model, its exact zero-order-hold discretisation, and a discrete simulator,
 *        so the library can generate the paper's experiment itself.
 */
#ifndef OKID_MODEL_H
#define OKID_MODEL_H

#include <stddef.h>

#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/**
 * M x'' + R x' + K x = B2 u, y = Ca x'' + Cv x' + Cd x, with n2 degrees of freedom, r inputs and
 * m outputs. Matrices are column-major with leading dimension equal to their row count.
 * Ca, Cv and Cd may each be NULL (zero).
 */
typedef struct okid_mechanical_model {
    int dofs;                 /**< n2 */
    int num_inputs;           /**< r */
    int num_outputs;          /**< m */
    const okid_real *mass;      /**< M, n2 x n2, invertible */
    const okid_real *damping;   /**< R, n2 x n2 */
    const okid_real *stiffness; /**< K, n2 x n2 */
    const okid_real *input;     /**< B2, n2 x r */
    const okid_real *out_acc;   /**< Ca, m x n2, or NULL */
    const okid_real *out_vel;   /**< Cv, m x n2, or NULL */
    const okid_real *out_disp;  /**< Cd, m x n2, or NULL */
} okid_mechanical_model;

/**
 * Mass, damping and stiffness matrices of a chain of n2 masses between two walls (the paper's
 * 2-DOF system for n2 = 2): spring k_i and damper r_i join mass i-1 and mass i, where mass 0 and
 * mass n2+1 are the walls. A zero k or r leaves that link out (a free end).
 * \param[in]  dofs      n2, 1..OKID_MAX_ORDER / 2
 * \param[in]  masses    n2 masses, finite and > 0
 * \param[in]  dampers   n2 + 1 damping coefficients r_1 .. r_(n2+1), finite and >= 0
 * \param[in]  springs   n2 + 1 stiffnesses k_1 .. k_(n2+1), finite and >= 0
 * \param[out] mass, damping, stiffness  n2 x n2 each, column-major, leading dimension n2
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER
 */
okid_status okid_chain_model(int dofs, const okid_real *masses, const okid_real *dampers,
                             const okid_real *springs, okid_real *mass, okid_real *damping,
                             okid_real *stiffness);

/** Work reals okid_model_state_space() needs for n2 degrees of freedom and r inputs. */
#define OKID_STATE_SPACE_WORK_REALS(dofs, r) ((size_t)(dofs) * ((size_t)(dofs) * 3u + (size_t)(r) + 1u))

/**
 * Continuous state space of eq. 6-9 with state z = [x; x']:
 * Ac = [0 I; -M^-1 K  -M^-1 R], Bc = [0; M^-1 B2], C = [Cd - Ca M^-1 K, Cv - Ca M^-1 R], D = Ca M^-1 B2.
 * \param[in]  model  the mechanical model
 * \param[out] ac     2n2 x 2n2, leading dimension 2n2
 * \param[out] bc     2n2 x r, leading dimension 2n2
 * \param[out] c      m x 2n2, leading dimension m
 * \param[out] d      m x r, leading dimension m
 * \param[out] work   OKID_STATE_SPACE_WORK_REALS(n2, r) reals
 * \param[in]  work_len number of reals in work
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER (non-finite entry, or M singular)
 */
okid_status okid_model_state_space(const okid_mechanical_model *model, okid_real *ac, okid_real *bc,
                                   okid_real *c, okid_real *d, okid_real *work, size_t work_len);

/** Work reals okid_discretize_zoh() needs for n states and r inputs. */
#define OKID_ZOH_WORK_REALS(n, r) (((size_t)(n) + (size_t)(r)) * ((size_t)(n) + (size_t)(r)) * 8u)

/**
 * Exact zero-order-hold discretisation (eq. 13-14): A = e^(Ac dt), B = int_0^dt e^(Ac tau) dtau Bc,
 * from the exponential of the augmented matrix [Ac Bc; 0 0] dt (scaling and squaring with a
 * degree-13 Pade approximant, Higham 2005).
 * \param[in]  n, r    states and inputs (1..OKID_MAX_ORDER, 0..OKID_MAX_DIMENSION)
 * \param[in]  ac, bc  n x n and n x r, leading dimension n
 * \param[in]  dt      sample interval, finite and > 0
 * \param[out] a, b    n x n and n x r, leading dimension n
 * \param[out] work    OKID_ZOH_WORK_REALS(n, r) reals
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER (dt, non-finite entry),
 *         OKID_E_DECOMPOSITION_FAILED (the Pade denominator is singular)
 */
okid_status okid_discretize_zoh(int n, int r, const okid_real *ac, const okid_real *bc, okid_real dt,
                                okid_real *a, okid_real *b, okid_real *work, size_t work_len);

/**
 * A discrete state-space model x(k+1) = A x(k) + B u(k), y(k) = C x(k) + D u(k) with its state,
 * all storage owned by the caller (matrices column-major, leading dimension = rows).
 */
typedef struct okid_simulator {
    int n, r, m;
    const okid_real *a, *b, *c, *d;
    okid_real *x;   /**< state, n values: set it for a non-zero initial condition */
    okid_real *tmp; /**< n reals of scratch */
} okid_simulator;

/**
 * Set up a simulator with zero state.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE
 */
okid_status okid_simulator_init(okid_simulator *sim, int n, int r, int m, const okid_real *a,
                                const okid_real *b, const okid_real *c, const okid_real *d, okid_real *state,
                                okid_real *scratch);

/**
 * Advance count steps: for each k, y(:,k) = C x + D u(:,k), then x = A x + B u(:,k).
 * u is r x count with leading dimension ldu >= r; y is m x count with leading dimension ldy >= m.
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_NONFINITE_SAMPLE (an input is not finite: nothing is advanced)
 */
okid_status okid_simulate(okid_simulator *sim, size_t count, const okid_real *u, size_t ldu, okid_real *y,
                          size_t ldy);

#ifdef __cplusplus
}
#endif

#endif

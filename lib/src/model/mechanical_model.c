/* SPDX-License-Identifier: Apache-2.0 */
/* The mechanical model of eq. 1-10 turned into the continuous state space of eq. 6-9. */
#include "okid/model.h"

#include "numerics/dense.h"
#include "okid/limits.h"

static int dims_ok(const okid_mechanical_model *model)
{
    return model->dofs >= 1 && model->dofs <= OKID_MAX_ORDER / 2 && model->num_inputs >= 0 &&
           model->num_inputs <= OKID_MAX_DIMENSION && model->num_outputs >= 1 &&
           model->num_outputs <= OKID_MAX_DIMENSION;
}

static int optional_finite(int rows, int cols, const okid_real *a)
{
    return a == NULL || okid_all_finite(rows, cols, a, rows);
}

okid_status okid_model_state_space(const okid_mechanical_model *model, okid_real *ac, okid_real *bc,
                                   okid_real *c, okid_real *d, okid_real *work, size_t work_len)
{
    if (model == NULL || ac == NULL || c == NULL || work == NULL || model->mass == NULL ||
        model->damping == NULL || model->stiffness == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (!dims_ok(model)) {
        return OKID_E_BAD_SIZE;
    }
    const int n2 = model->dofs, r = model->num_inputs, m = model->num_outputs, n = 2 * n2;
    if (r > 0 && (model->input == NULL || bc == NULL || d == NULL)) {
        return OKID_E_NULL_POINTER;
    }
    if (work_len < OKID_STATE_SPACE_WORK_REALS(n2, r)) {
        return OKID_E_WORKSPACE_TOO_SMALL;
    }
    if (!okid_all_finite(n2, n2, model->mass, n2) || !okid_all_finite(n2, n2, model->damping, n2) ||
        !okid_all_finite(n2, n2, model->stiffness, n2) || !optional_finite(n2, r, model->input) ||
        !optional_finite(m, n2, model->out_acc) || !optional_finite(m, n2, model->out_vel) ||
        !optional_finite(m, n2, model->out_disp)) {
        return OKID_E_BAD_PARAMETER;
    }

    /* x = M^-1 [K R B2], one LU of a copy of M. */
    okid_real *mass = work;
    okid_real *x = work + (size_t)n2 * (size_t)n2;
    const int nx = 2 * n2 + r;
    okid_copy_matrix(n2, n2, model->mass, n2, mass, n2);
    okid_copy_matrix(n2, n2, model->stiffness, n2, x, n2);
    okid_copy_matrix(n2, n2, model->damping, n2, x + (size_t)n2 * (size_t)n2, n2);
    if (r > 0) {
        okid_copy_matrix(n2, r, model->input, n2, x + 2 * (size_t)n2 * (size_t)n2, n2);
    }
    if (okid_lu_solve(n2, nx, mass, n2, x, n2) != OKID_OK) {
        return OKID_E_BAD_PARAMETER; /* M is singular */
    }
    const okid_real *minv_k = x;
    const okid_real *minv_r = x + (size_t)n2 * (size_t)n2;
    const okid_real *minv_b = x + 2 * (size_t)n2 * (size_t)n2;

    okid_zero_matrix(n, n, ac, n);
    for (int i = 0; i < n2; ++i) {
        OKID_AT(ac, n, i, n2 + i) = 1;
        for (int j = 0; j < n2; ++j) {
            OKID_AT(ac, n, n2 + i, j) = -OKID_AT(minv_k, n2, i, j);
            OKID_AT(ac, n, n2 + i, n2 + j) = -OKID_AT(minv_r, n2, i, j);
        }
    }
    if (r > 0) {
        okid_zero_matrix(n, r, bc, n);
        okid_copy_matrix(n2, r, minv_b, n2, bc + n2, n);
    }

    /* C = [Cd - Ca M^-1 K, Cv - Ca M^-1 R], D = Ca M^-1 B2. */
    okid_zero_matrix(m, n, c, m);
    if (model->out_disp != NULL) {
        okid_copy_matrix(m, n2, model->out_disp, m, c, m);
    }
    if (model->out_vel != NULL) {
        okid_copy_matrix(m, n2, model->out_vel, m, c + (size_t)m * (size_t)n2, m);
    }
    if (r > 0) {
        okid_zero_matrix(m, r, d, m);
    }
    if (model->out_acc != NULL) {
        okid_gemm('N', 'N', m, n2, n2, -1, model->out_acc, m, minv_k, n2, 1, c, m);
        okid_gemm('N', 'N', m, n2, n2, -1, model->out_acc, m, minv_r, n2, 1, c + (size_t)m * (size_t)n2, m);
        if (r > 0) {
            okid_gemm('N', 'N', m, r, n2, 1, model->out_acc, m, minv_b, n2, 0, d, m);
        }
    }
    return OKID_OK;
}

/* Adds the link of coefficient value between masses i-1 and i (index -1 and dofs are the walls). */
static void add_link(int dofs, okid_real *matrix, int i, okid_real value)
{
    if (i - 1 >= 0) {
        OKID_AT(matrix, dofs, i - 1, i - 1) += value;
    }
    if (i < dofs) {
        OKID_AT(matrix, dofs, i, i) += value;
    }
    if (i - 1 >= 0 && i < dofs) {
        OKID_AT(matrix, dofs, i - 1, i) -= value;
        OKID_AT(matrix, dofs, i, i - 1) -= value;
    }
}

okid_status okid_chain_model(int dofs, const okid_real *masses, const okid_real *dampers,
                             const okid_real *springs, okid_real *mass, okid_real *damping,
                             okid_real *stiffness)
{
    if (masses == NULL || dampers == NULL || springs == NULL || mass == NULL || damping == NULL ||
        stiffness == NULL) {
        return OKID_E_NULL_POINTER;
    }
    if (dofs < 1 || dofs > OKID_MAX_ORDER / 2) {
        return OKID_E_BAD_SIZE;
    }
    for (int i = 0; i < dofs; ++i) {
        if (!okid_all_finite(1, 1, &masses[i], 1) || !(masses[i] > 0)) {
            return OKID_E_BAD_PARAMETER;
        }
    }
    for (int i = 0; i <= dofs; ++i) {
        if (!okid_all_finite(1, 1, &dampers[i], 1) || !okid_all_finite(1, 1, &springs[i], 1) ||
            dampers[i] < 0 || springs[i] < 0) {
            return OKID_E_BAD_PARAMETER;
        }
    }
    okid_zero_matrix(dofs, dofs, mass, dofs);
    okid_zero_matrix(dofs, dofs, damping, dofs);
    okid_zero_matrix(dofs, dofs, stiffness, dofs);
    for (int i = 0; i < dofs; ++i) {
        OKID_AT(mass, dofs, i, i) = masses[i];
    }
    for (int i = 0; i <= dofs; ++i) {
        add_link(dofs, damping, i, dampers[i]);
        add_link(dofs, stiffness, i, springs[i]);
    }
    return OKID_OK;
}

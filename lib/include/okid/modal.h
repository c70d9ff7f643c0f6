/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file modal.h
 * \brief Modal parameters of a discrete-time model: eigenvalues, poles, frequencies, damping
 *        ratios and mode shapes (paper eq. 56, 63, 64), and the modal assurance criterion.
 */
#ifndef OKID_MODAL_H
#define OKID_MODAL_H

#include "okid/sizes.h"
#include "okid/status.h"
#include "okid/types.h"

#ifdef __cplusplus
extern "C" {
#endif

/** What the outputs measure, which sets the power c of eq. 64 (c = 0, 1, 2). */
typedef enum okid_sensing {
    OKID_SENSING_DISPLACEMENT = 0,
    OKID_SENSING_VELOCITY = 1,
    OKID_SENSING_ACCELERATION = 2
} okid_sensing;

/**
 * One mode. A complex-conjugate pair of eigenvalues is reported once, with Im(eigenvalue) > 0.
 * Shapes are normalised to unit 2-norm with their largest component real and positive, so two
 * shapes of the same mode agree up to round-off (compare with okid_mac() to be scale-free).
 */
typedef struct okid_mode {
    okid_complex eigenvalue;  /**< discrete-time eigenvalue lambda of A */
    okid_complex pole;        /**< continuous-time pole s = ln(lambda) / dt [1/s] */
    okid_real frequency_hz;   /**< undamped natural frequency |s| / (2 pi) [Hz] */
    okid_real damping_ratio;  /**< -Re(s) / |s| */
    int is_pair;              /**< 1 for a complex-conjugate pair (two states), 0 for a real eigenvalue */
    const okid_complex *sensor_shape; /**< C psi: num_outputs components, at the sensors */
    /**
     * Eq. 64 with continuous poles: [C psi s^-c ; C psi s^(1-c)], 2 * num_outputs components
     * (displacements, then velocities, when the sensors sit on the degrees of freedom).
     */
    const okid_complex *shape;
    /**
     * Accuracy indicators, defined in okid/modal_indicators.h. okid_identify() fills every one;
     * okid_modal_analysis() (which has no Hankel matrix to judge against) fills mpc and sets the
     * others to -1.
     */
    okid_real emac_output; /**< output (C-side) extended modal amplitude coherence, [0, 1] */
    okid_real emac_input;  /**< input (B-side) EMAC, [0, 1] */
    okid_real emac;        /**< EMAC = emac_output * emac_input, [0, 1] */
    okid_real mpc;         /**< modal phase collinearity of sensor_shape, [0, 1] */
    okid_real msv;         /**< mode singular value (units of the Hankel singular values), >= 0 */
    okid_real cmi;         /**< consistent mode indicator EMAC * MPC, [0, 1] */
} okid_mode;

/*
 * NOT API: the members of okid_mode as one table, in the order the JSON writer writes them, which
 * the library's finiteness check of a result and the host tools (the JSON writer, the Python
 * binding) expand: COMPLEX(name) an okid_complex, REAL(name) an okid_real, FLAG(name) an int 0/1,
 * SHAPE(name, k) k * num_outputs okid_complex. A new per-mode quantity is a member above and a row
 * here (docs/design.md, "Adding a per-mode quantity").
 */
#define OKID_MODE_FIELDS(COMPLEX, REAL, FLAG, SHAPE)                                                  \
    COMPLEX(eigenvalue) COMPLEX(pole) REAL(frequency_hz) REAL(damping_ratio) FLAG(is_pair)            \
    SHAPE(sensor_shape, 1) SHAPE(shape, 2) REAL(emac) REAL(emac_output) REAL(emac_input) REAL(mpc)     \
    REAL(msv) REAL(cmi)

/** Bytes of workspace okid_modal_analysis() needs for an n-state model with m outputs. */
#define OKID_MODAL_WORKSPACE_BYTES(n, m) OKID__SIZE(OKID__MODAL_WORKSPACE_BYTES64(n, m))

/**
 * Modal analysis of the discrete model x(k+1) = A x(k), y(k) = C x(k) sampled every dt.
 *
 * Modes are sorted by increasing natural frequency (then by damping ratio).
 *
 * \param[in]  n          number of states, 1..OKID_MAX_ORDER
 * \param[in]  m          number of outputs, 1..OKID_MAX_DIMENSION
 * \param[in]  a          n x n state matrix, column-major, leading dimension lda >= n
 * \param[in]  lda        leading dimension of a
 * \param[in]  c          m x n output matrix, column-major, leading dimension ldc >= m
 * \param[in]  ldc        leading dimension of c
 * \param[in]  dt         sample interval [s], finite and > 0
 * \param[in]  sensing    what the outputs measure (sets c of eq. 64)
 * \param[out] workspace  OKID_MODAL_WORKSPACE_BYTES(n, m) bytes, aligned to 16; the shapes live here
 * \param[in]  bytes      size of workspace
 * \param[out] modes      room for n modes (at most n are written)
 * \param[out] num_modes  number of modes written
 * \param[out] warnings   okid_warning bits (unstable or non-physical poles); may be NULL
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE, OKID_E_BAD_PARAMETER (dt, sensing, or a
 *         non-finite entry of a or c), OKID_E_WORKSPACE_TOO_SMALL, OKID_E_WORKSPACE_ALIGNMENT,
 *         OKID_E_DECOMPOSITION_FAILED
 */
okid_status okid_modal_analysis(int n, int m, const okid_real *a, int lda, const okid_real *c, int ldc,
                                okid_real dt, okid_sensing sensing, void *workspace, size_t bytes,
                                okid_mode *modes, int *num_modes, unsigned *warnings);

/**
 * Modal phase collinearity |phi^T phi|^2 / (phi^H phi)^2 of a complex shape, in [0, 1].
 * \param[in] shape len complex components
 * \param[in] len   number of components
 * \return the MPC; 0 when shape is NULL, len < 1, or the shape is zero
 */
okid_real okid_mpc(const okid_complex *shape, int len);

/**
 * Modal assurance criterion |a^H b|^2 / ((a^H a)(b^H b)) of two complex shapes, in [0, 1]:
 * 1 when they are equal up to a complex scale. Returns 0 when either shape is zero, NULL, or len < 1.
 */
okid_real okid_mac(const okid_complex *a, const okid_complex *b, int len);

#ifdef __cplusplus
}
#endif

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/**
 * \file mode_selection.h
 * \brief The structure's physical modes chosen automatically from a stabilization diagram
 *        (okid_stabilization_compute()): hard criteria per pole, clustering of the poles across
 *        orders, a cluster-size rule, and one representative per cluster with its spread.
 *
 * The rule (docs/quality.md, section 7, has the measurements behind the defaults):
 *
 * 1. Hard criteria. A pole of the table is a candidate when it is a complex pair, stable
 *    (|lambda| < 1), damping_min < zeta <= damping_max, frequency_min_hz <= f <= frequency_max_hz
 *    (0: no upper bound), MPC >= mpc_min and EMAC >= emac_min.
 * 2. Clustering. Candidates are taken by decreasing CMI (ties: higher order first). Each one joins
 *    the cluster whose seed (its first pole) is nearest in d = |f - f_s| / f_s + (1 - MAC), among
 *    the clusters with |f - f_s| <= frequency_distance f_s, |zeta - zeta_s| <= damping_distance
 *    max(zeta, zeta_s), MAC(sensor shapes) >= mac_min, and no pole of this order yet (a cluster
 *    holds at most one pole per order); when there is none it seeds a new cluster.
 * 3. Physical modes. A cluster is a physical mode when it holds poles of at least
 *    min_orders = max(2, ceil(min_fraction K)) of the table's K orders. Of two such clusters whose
 *    seeds are closer than the clustering gates (a pole split in two by the one-per-order rule),
 *    only the one in more orders is kept. Noise-free data: when the table ends at the Hankel
 *    matrix's numerical rank and that rank is one no noise gives (okid_stabilization::noise_free,
 *    and no further order of the step fits under rank_limit), its last order is the exact model
 *    and no higher order can confirm its poles; a cluster holding a pole of that order counts as
 *    in min_orders orders.
 * 4. The representative of a mode is its cluster's pole of median frequency (the lower median),
 *    or on noise-free data (rule 3's exact last order) its pole of that order, the exact model's;
 *    the mean, standard deviation (population) and range of frequency and damping over the cluster
 *    are reported with it. Modes are listed by increasing representative frequency.
 *
 * Memory: a caller workspace of okid_mode_selection_workspace_size() bytes (or the constant
 * OKID_MODE_SELECTION_WORKSPACE_BYTES) for the table of a given largest order and step; no heap.
 * The representatives' shapes point into the table's own workspace, which must outlive the selection.
 */
#ifndef OKID_MODE_SELECTION_H
#define OKID_MODE_SELECTION_H

#include <stddef.h>

#include "okid/identifier.h"
#include "okid/stabilization.h"

#ifdef __cplusplus
extern "C" {
#endif

/** Selection criteria; okid_mode_selection_criteria_default() gives the documented defaults. */
typedef struct okid_mode_selection_criteria {
    okid_real damping_min;        /**< hard: zeta > damping_min; default 0, range [0, damping_max) */
    okid_real damping_max;        /**< hard: zeta <= damping_max; default 0.2, range (damping_min, 1] */
    okid_real frequency_min_hz;   /**< hard: f >= this; default 0, >= 0 */
    okid_real frequency_max_hz;   /**< hard: f <= this; default 0 = no bound, else > frequency_min_hz */
    okid_real mpc_min;            /**< hard: MPC >= this; default 0.5, [0, 1] */
    okid_real emac_min;           /**< hard: EMAC >= this; default 0.5, [0, 1] */
    okid_real frequency_distance; /**< clustering: relative frequency gate; default 0.02, (0, 1] */
    okid_real damping_distance;   /**< clustering: relative damping gate; default 0.5, (0, 1] */
    okid_real mac_min;            /**< clustering: MAC gate; default 0.9, [0, 1] */
    okid_real min_fraction;       /**< physical: fraction of the table's orders; default 0.5, (0, 1] */
} okid_mode_selection_criteria;

/** One physical mode: a representative pole and its cluster's spread across orders. */
typedef struct okid_selected_mode {
    okid_mode mode;            /**< the representative pole, as in the table (shapes point into the table) */
    int order;                 /**< model order of the representative */
    int num_orders;            /**< orders of the table the cluster holds a pole in (= its poles) */
    int lowest_order;          /**< lowest order of the cluster */
    int highest_order;         /**< highest order of the cluster */
    okid_real frequency_mean;  /**< over the cluster [Hz] */
    okid_real frequency_std;   /**< population standard deviation [Hz] */
    okid_real frequency_min;   /**< [Hz] */
    okid_real frequency_max;   /**< [Hz] */
    okid_real damping_mean;    /**< over the cluster */
    okid_real damping_std;     /**< population standard deviation */
    okid_real damping_min;
    okid_real damping_max;
    okid_real cmi_min;         /**< smallest CMI of the cluster */
} okid_selected_mode;

/** The selection. modes points into the caller's selection workspace. */
typedef struct okid_mode_selection {
    int num_modes;                    /**< physical modes, by increasing frequency */
    const okid_selected_mode *modes;  /**< num_modes entries */
    int num_orders;                   /**< K: orders of the table */
    int min_orders;                   /**< max(2, ceil(min_fraction K)): cluster size a mode needs */
    int num_candidates;               /**< poles that met the hard criteria */
    int num_clusters;                 /**< clusters formed */
    int num_dropped;                  /**< physical clusters left out: duplicates, or beyond the room (see below) */
    int exact_last_order;             /**< 1 when the table ends at the Hankel matrix's numerical rank (noise-free
                                           data, rule 3): the last order's poles counted as confirmed */
} okid_mode_selection;

/**
 * Selection workspace bytes as a constant expression for a table of largest order nmax and order
 * step `step` (as passed to okid_stabilization_compute()). Equals okid_mode_selection_workspace_size().
 */
#define OKID_MODE_SELECTION_WORKSPACE_BYTES(nmax, step) \
    OKID__SIZE(OKID__MODESEL_BYTES(OKID__STAB_MODES(nmax, step), nmax))

/**
 * Fill criteria with the defaults above.
 * \return OKID_OK, OKID_E_NULL_POINTER
 */
okid_status okid_mode_selection_criteria_default(okid_mode_selection_criteria *criteria);

/**
 * Check criteria and name the first field out of range.
 * \param[in]  criteria criteria
 * \param[out] issue    the field refused, its value and valid range (field NULL when valid); may be NULL
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_PARAMETER
 */
okid_status okid_mode_selection_criteria_check(const okid_mode_selection_criteria *criteria, okid_config_issue *issue);

/**
 * Workspace bytes of okid_select_modes() for tables up to order max_order with order step `step`.
 * \param[in]  max_order largest order, 1..OKID_MAX_ORDER
 * \param[in]  step      order step, 1..max_order
 * \param[out] bytes     bytes needed
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_ORDER (max_order), OKID_E_BAD_SIZE (step, or above SIZE_MAX)
 */
okid_status okid_mode_selection_workspace_size(int max_order, int step, size_t *bytes);

/**
 * The physical modes of a stabilization table, by the rule above.
 *
 * At most max_order modes fit (the bound for min_fraction >= 0.5: each order has at most
 * max_order / 2 pairs); with a smaller fraction, the clusters in the most orders are kept and
 * num_dropped counts the others.
 *
 * \param[in]  table       from okid_stabilization_compute() (its workspace must stay alive)
 * \param[in]  num_outputs m of the identifier that made the table (length of sensor_shape), 1..OKID_MAX_DIMENSION
 * \param[in]  criteria    NULL = defaults
 * \param[out] workspace   okid_mode_selection_workspace_size() bytes for a max_order and step that
 *                         cover the table, aligned to OKID_WORKSPACE_ALIGN
 * \param[in]  bytes       size of workspace
 * \param[out] out         the selection (views into workspace); untouched on error
 * \param[out] issue       on OKID_E_BAD_PARAMETER the criterion refused; may be NULL
 * \return OKID_OK, OKID_E_NULL_POINTER, OKID_E_BAD_SIZE (num_outputs, or a table with negative
 *         counts), OKID_E_BAD_PARAMETER (criteria), OKID_E_WORKSPACE_ALIGNMENT,
 *         OKID_E_WORKSPACE_TOO_SMALL (the workspace is smaller than this table needs: sized for a lower
 *         max_order or a larger step)
 */
okid_status okid_select_modes(const okid_stabilization *table, int num_outputs,
                              const okid_mode_selection_criteria *criteria, void *workspace, size_t bytes,
                              okid_mode_selection *out, okid_config_issue *issue);

#ifdef __cplusplus
}
#endif

#endif

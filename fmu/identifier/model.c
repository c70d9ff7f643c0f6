/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The identifier FMU: inputs u[num_inputs] and y[num_outputs] each communication step; OKID/ERA
 * re-identification every identify_every samples; outputs per mode (frequency, damping,
 * eigenvalue, eq. 64 shape, accuracy indicators), the one-step prediction and its error, counters
 * and Hankel singular values.
 *
 * The sizes are structural parameters (FMI 3: set in configuration mode; FMI 2: read from
 * resources/okid_identifier.cfg), checked against this build's limits; the arrays are allocated
 * once when the configuration ends, the workspace once at the end of initialization, sized by
 * okid_workspace_size() for the parameters then set. The parameters carry okid_config's names and
 * okid_config_default()'s defaults; a refusal names the setting, its value and its valid range in
 * the host library's words (host_tools/common/config_explain.c, shipped in sources/).
 *
 * The mode outputs are the physical modes (all_poles false, order 0: the default): after each
 * identification the stabilization table of the even orders 2..N from its one SVD and the
 * automatic selection (okid/mode_selection.h) with the CLI's one-window rule (host_tools/common/
 * mode_windows_rule.c, shipped in sources/ too), in memory sized at the end of initialization;
 * with all_poles true or an order given, every pole of the identified model (okid_result::modes).
 * No physical mode: num_modes 0 and OKID_W_NO_PHYSICAL_MODE in warnings.
 *
 * num_inputs = 0 is output-only (ambient) identification, okid identify --inputs 0's: y goes into
 * the correlation sums of okid/ambient.h (lags 0..2L, L = hankel_rows, in a workspace sized by
 * okid_ambient_workspace_size()), each identification realizes their block Hankel and the mode
 * outputs are as above (the table of the even orders 2..min(60, L m)); the observer's parameters
 * must keep their start values, and y_hat, y_error stay NaN, prediction_valid false and
 * regressor_rank 0 (there is no predictor). The record should have zero mean (docs/ambient.md).
 *
 * Every output is current or visibly not (docs/fmu.md): mode outputs are NaN until the first
 * identification and beyond num_modes; after a failed identification they keep the last
 * successful one, status says "failed" and identification_time when that one was; y_hat and
 * y_error are NaN whenever this step has no prediction (prediction_valid = false).
 */
#include <limits.h>
#include <math.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include "config_explain.h"
#include "fmu_config.h"
#include "fmu_model.h"
#include "mode_windows.h"
#include "okid/okid.h"

/* This build's limits on the structural parameters and on the workspace. */
#define MAX_CHANNELS OKID_MAX_DIMENSION
#define MAX_MODES_LIMIT (OKID_MAX_ORDER / 2)
#define MAX_SINGULAR_VALUES OKID_MAX_ORDER
#ifndef OKID_FMU_MAX_WORKSPACE_BYTES
#define OKID_FMU_MAX_WORKSPACE_BYTES (1024.0 * 1024.0 * 1024.0)
#endif

enum { STATUS_COLLECTING = 0, STATUS_IDENTIFIED = 1, STATUS_FAILED = 2 };

typedef struct identifier_data {
    /* structural parameters */
    int num_inputs, num_outputs, max_modes, num_singular_values;
    /* parameters: okid_config's fields, and the FMU's own identify_every */
    int observer_order, order, hankel_rows, hankel_cols, block_rows;
    double dt, forgetting_factor, rank_tolerance;
    int sensing, realization, zero_initial_state, decimation, scaling, estimator, instrument_lags, identify_every;
    int all_poles;
    /* inputs */
    double *u, *y;
    /* outputs */
    int status, last_error, samples, rejected, rank, num_modes, identifications, warnings, prediction_valid;
    double identification_time;
    double *y_hat, *y_error, *singular_values;
    double *frequency, *damping, *eig_re, *eig_im, *emac, *mpc, *cmi, *shape_re, *shape_im;
    /* internal */
    okid_real *u_real, *y_real, *y_hat_real;
    void *arrays;                    /* every array above, one allocation */
    void *workspace_block;           /* the workspace as allocated (aligned inside) */
    size_t arrays_bytes, workspace_block_bytes;
    int since_identify;
    okid_identifier id;              /* num_inputs >= 1 */
    okid_ambient amb;                /* num_inputs = 0: output-only */
    /* the selection of the physical modes (all_poles false, order 0): its own block, scratch
       between identifications (not part of the FMU state) */
    void *selection_block;           /* NULL: the mode outputs are the model's poles */
    void *table_workspace, *selection_workspace; /* aligned, inside selection_block */
    size_t table_bytes, selection_bytes;
    int table_order;                 /* N: the table's largest order (even) */
    okid_mode_selection_criteria criteria;
    auto_mode selected[OKID_MAX_ORDER];
} identifier_data;

/* Table indices of the structural parameters: dimensions refer to them as index + 1. */
enum { G_NUM_INPUTS, G_NUM_OUTPUTS, G_MAX_MODES, G_NUM_SINGULAR_VALUES };
#define BY_INPUTS {G_NUM_INPUTS + 1, 0, 0}
#define BY_OUTPUTS {G_NUM_OUTPUTS + 1, 0, 0}
#define BY_MODES {G_MAX_MODES + 1, 0, 0}
#define BY_SINGULAR_VALUES {G_NUM_SINGULAR_VALUES + 1, 0, 0}
#define BY_SHAPE {G_MAX_MODES + 1, -2, G_NUM_OUTPUTS + 1} /* eq. 64: displacements, then velocities */
#define SCALAR {0, 0, 0}
#define NO_RANGE (double)NAN, (double)NAN

static const char *const SENSING_ITEMS[] = {"displacement", "velocity", "acceleration"};
static const char *const REALIZATION_ITEMS[] = {"system", "combined"};
static const char *const SCALING_ITEMS[] = {"none", "auto"};
static const char *const ESTIMATOR_ITEMS[] = {"least_squares", "instrumental", "correlation"};
static const char *const STATUS_ITEMS[] = {"collecting", "identified", "failed"};
static const fmu_enum_type SENSING = {"okid_sensing", 3, SENSING_ITEMS};
static const fmu_enum_type REALIZATION = {"okid_realization", 2, REALIZATION_ITEMS};
static const fmu_enum_type SCALING = {"okid_scaling", 2, SCALING_ITEMS};
static const fmu_enum_type ESTIMATOR = {"okid_estimator", 3, ESTIMATOR_ITEMS};
static const fmu_enum_type STATUS = {"okid_fmu_status", 3, STATUS_ITEMS};

#define OFF(field) offsetof(identifier_data, field)
#define STRUCTURAL(name, field, start, min, max, text) \
    {name, NULL, FMU_SIZE, FMU_STRUCTURAL, FMU_FIXED, OFF(field), SCALAR, start, min, max, NULL, NULL, text, NULL}
#define PARAM(name, type, field, min, max, enumeration, unit, text) \
    {name, NULL, type, FMU_PARAMETER, FMU_FIXED, OFF(field), SCALAR, 0, min, max, enumeration, unit, text, NULL}
#define OUT(name, type, field, enumeration, unit, text) \
    {name, NULL, type, FMU_OUTPUT, FMU_DISCRETE, OFF(field), SCALAR, 0, NO_RANGE, enumeration, unit, text, NULL}
#define OUTS(name, flat, dims, field, unit, text) \
    {name, flat, FMU_REAL, FMU_OUTPUT, FMU_DISCRETE, OFF(field), dims, 0, NO_RANGE, NULL, unit, text, NULL}

static const fmu_variable_group GROUPS[] = {
    [G_NUM_INPUTS] = STRUCTURAL("num_inputs", num_inputs, 1, 0, MAX_CHANNELS,
                                "r: inputs (forces); 0 = output-only (ambient: modes from the outputs' correlations)"),
    [G_NUM_OUTPUTS] = STRUCTURAL("num_outputs", num_outputs, 2, 1, MAX_CHANNELS, "m: outputs (sensors)"),
    [G_MAX_MODES] = STRUCTURAL("max_modes", max_modes, 4, 1, MAX_MODES_LIMIT, "modes published (the first, by frequency)"),
    [G_NUM_SINGULAR_VALUES] = STRUCTURAL("num_singular_values", num_singular_values, 8, 1, MAX_SINGULAR_VALUES,
                                         "Hankel singular values published"),
    /* Start values: okid_config_default() (set_defaults); the description generator reads them from there. */
    PARAM("observer_order", FMU_INTEGER, observer_order, 1, OKID_MAX_HORIZON, NULL, NULL,
          "p: observer Markov parameters identified (m p >= order)"),
    PARAM("order", FMU_INTEGER, order, 0, OKID_MAX_ORDER, NULL, NULL,
          "n: model order; 0 = automatic (largest gap of the Hankel singular values)"),
    PARAM("hankel_rows", FMU_INTEGER, hankel_rows, 1, OKID_MAX_HORIZON, NULL, NULL, "alpha: Hankel block rows"),
    PARAM("hankel_cols", FMU_INTEGER, hankel_cols, 1, OKID_MAX_HORIZON, NULL, NULL, "beta: Hankel block columns"),
    PARAM("block_rows", FMU_INTEGER, block_rows, 0, 4096, NULL, NULL, "regressor rows folded per QR update; 0 = automatic"),
    PARAM("dt", FMU_REAL, dt, 2.2250738585072014e-308, (double)INFINITY, NULL, "s",
          "sample interval = the communication step size (fixed: the FMU samples once per step)"),
    PARAM("forgetting_factor", FMU_REAL, forgetting_factor, 2.2250738585072014e-308, 1, NULL, NULL,
          "exponential forgetting factor lambda in (0, 1]; 1 keeps every sample"),
    PARAM("rank_tolerance", FMU_REAL, rank_tolerance, 0, 1, NULL, NULL,
          "relative rank tolerance of the least squares: 0 (= 1e-10) or [machine epsilon, 1)"),
    PARAM("sensing", FMU_ENUM, sensing, 0, 2, &SENSING, NULL,
          "what the outputs measure: 0 displacement, 1 velocity, 2 acceleration"),
    PARAM("realization", FMU_ENUM, realization, 0, 1, &REALIZATION, NULL,
          "ERA from 0 system Markov parameters, 1 combined with the observer gain"),
    PARAM("zero_initial_state", FMU_BOOLEAN, zero_initial_state, 0, 1, NULL, NULL,
          "true when the record starts at rest (zero state, zero past inputs)"),
    PARAM("decimation", FMU_INTEGER, decimation, 1, OKID_MAX_DECIMATION, NULL, NULL,
          "K: anti-alias filter and keep every K-th sample; p, alpha, beta count kept samples; no y_hat when K > 1"),
    PARAM("scaling", FMU_ENUM, scaling, 0, 1, &SCALING, NULL,
          "per-channel scaling: 0 none, 1 auto (each channel divided by its RMS)"),
    PARAM("estimator", FMU_ENUM, estimator, 0, 2, &ESTIMATOR, NULL,
          "0 least_squares, 1 instrumental (instrumental variables: no output-noise bias), 2 correlation "
          "(Phi'Phi and Cholesky: faster; identification fails when its guard refuses)"),
    PARAM("instrument_lags", FMU_INTEGER, instrument_lags, 0, OKID_MAX_INSTRUMENT_LAGS, NULL, NULL,
          "L of the instrumental estimator; 0 = automatic"),
    PARAM("identify_every", FMU_INTEGER, identify_every, 1, INT_MAX, NULL, NULL, "re-identify every N samples"),
    PARAM("all_poles", FMU_BOOLEAN, all_poles, 0, 1, NULL, NULL,
          "false (default): with order 0 the mode outputs are the physical modes, stable across the orders 2..N of "
          "the stabilization table (the CLI's modes, docs/fmu.md); true, or an order given: every pole of the "
          "identified model"),
    {"u", "u%d", FMU_REAL, FMU_INPUT, FMU_CONTINUOUS, OFF(u), BY_INPUTS, 0, NO_RANGE, NULL, NULL, "input (force)", NULL},
    {"y", "y%d", FMU_REAL, FMU_INPUT, FMU_CONTINUOUS, OFF(y), BY_OUTPUTS, 0, NO_RANGE, NULL, NULL, "output (sensor)", NULL},
    OUT("status", FMU_ENUM, status, &STATUS, NULL,
        "0 collecting (no identification yet), 1 identified (the mode outputs are from the latest identification), "
        "2 failed (the latest identification failed, see last_error; the mode outputs are from identification_time)"),
    OUT("last_error", FMU_INTEGER, last_error, NULL, NULL, "okid_status of the latest failed identification (0 none)"),
    OUT("identification_time", FMU_REAL, identification_time, NULL, "s",
        "time of the last sample of the identification the mode outputs come from (NaN: none yet)"),
    OUT("prediction_valid", FMU_BOOLEAN, prediction_valid, NULL, NULL,
        "true when y_hat and y_error are this step's one-step prediction (otherwise they are NaN)"),
    OUT("samples", FMU_INTEGER, samples, NULL, NULL, "samples accepted"),
    OUT("rejected", FMU_INTEGER, rejected, NULL, NULL, "samples rejected as non-finite"),
    OUT("regressor_rank", FMU_INTEGER, rank, NULL, NULL, "numerical rank of the regressor"),
    OUT("num_modes", FMU_INTEGER, num_modes, NULL, NULL,
        "physical modes selected, or with all_poles true (or an order given) poles identified; at most max_modes "
        "are published"),
    OUT("identifications", FMU_INTEGER, identifications, NULL, NULL, "successful identifications so far"),
    OUT("warnings", FMU_INTEGER, warnings, NULL, NULL,
        "okid_warning bits of the last identification (okid/status.h); OKID_W_NO_PHYSICAL_MODE (16384): the "
        "selection found no physical mode"),
    OUTS("y_hat", "y_hat%d", BY_OUTPUTS, y_hat, NULL, "one-step prediction of y with the identified observer (NaN: none)"),
    OUTS("y_error", "y_error%d", BY_OUTPUTS, y_error, NULL, "y - y_hat (innovation; NaN: no prediction)"),
    OUTS("singular_values", "singular_value%d", BY_SINGULAR_VALUES, singular_values, NULL,
         "Hankel singular values, decreasing (NaN: none)"),
    OUTS("mode_frequency_hz", "mode%d_frequency_hz", BY_MODES, frequency, "Hz", "undamped natural frequency"),
    OUTS("mode_damping_ratio", "mode%d_damping_ratio", BY_MODES, damping, NULL, "damping ratio"),
    OUTS("mode_emac", "mode%d_emac", BY_MODES, emac, NULL, "extended modal amplitude coherence in [0, 1]"),
    OUTS("mode_mpc", "mode%d_mpc", BY_MODES, mpc, NULL, "modal phase collinearity in [0, 1]"),
    OUTS("mode_cmi", "mode%d_cmi", BY_MODES, cmi, NULL,
         "consistent mode indicator EMAC * MPC in [0, 1]: low for computational modes"),
    OUTS("mode_eigenvalue_re", "mode%d_eigenvalue_re", BY_MODES, eig_re, NULL, "discrete eigenvalue, real part"),
    OUTS("mode_eigenvalue_im", "mode%d_eigenvalue_im", BY_MODES, eig_im, NULL, "discrete eigenvalue, imaginary part"),
    OUTS("mode_shape_re", "mode%d_shape%d_re", BY_SHAPE, shape_re, NULL,
         "eq. 64 mode shape (displacements then velocities at the sensors), real part"),
    OUTS("mode_shape_im", "mode%d_shape%d_im", BY_SHAPE, shape_im, NULL, "eq. 64 mode shape, imaginary part"),
};
enum { NUM_GROUPS = (int)(sizeof GROUPS / sizeof GROUPS[0]) };

static void set_defaults(void *data)
{
    identifier_data *d = data;
    d->num_inputs = (int)GROUPS[G_NUM_INPUTS].start;
    d->num_outputs = (int)GROUPS[G_NUM_OUTPUTS].start;
    d->max_modes = (int)GROUPS[G_MAX_MODES].start;
    d->num_singular_values = (int)GROUPS[G_NUM_SINGULAR_VALUES].start;
    okid_config cfg;
    okid_config_default(&cfg, d->num_inputs, d->num_outputs);
    d->observer_order = cfg.observer_order;
    d->order = cfg.order;
    d->hankel_rows = cfg.hankel_rows;
    d->hankel_cols = cfg.hankel_cols;
    d->block_rows = cfg.block_rows;
    d->dt = 0.01; /* the C placeholder is 1; the FMU's default experiment steps 0.01 s */
    d->forgetting_factor = (double)cfg.forgetting_factor;
    d->rank_tolerance = (double)cfg.rank_tolerance;
    d->sensing = (int)cfg.sensing;
    d->realization = (int)cfg.realization;
    d->zero_initial_state = cfg.zero_initial_state;
    d->decimation = cfg.decimation;
    d->scaling = (int)cfg.scaling;
    d->estimator = (int)cfg.estimator;
    d->instrument_lags = cfg.instrument_lags;
    d->identify_every = 100;
    d->all_poles = 0;
    d->identification_time = (double)NAN;
}

static void token(const void *data, int fmi_version, unsigned long config_hash, char *out, size_t size)
{
    const identifier_data *d = data;
    if (fmi_version == 3) { /* the sizes are set after instantiation */
        snprintf(out, size, "{%s-configurable}", OKID_FMU_TOKEN_BASE);
    } else if (config_hash == 0) {
        snprintf(out, size, "{%s-r%d-m%d-modes%d-sv%d}", OKID_FMU_TOKEN_BASE, d->num_inputs, d->num_outputs,
                 d->max_modes, d->num_singular_values);
    } else {
        snprintf(out, size, "{%s-r%d-m%d-modes%d-sv%d-config%08lx}", OKID_FMU_TOKEN_BASE, d->num_inputs,
                 d->num_outputs, d->max_modes, d->num_singular_values, config_hash);
    }
}

static void release(void *data, const fmu_allocator *memory)
{
    identifier_data *d = data;
    if (d->arrays) memory->release(d->arrays);
    if (d->workspace_block) memory->release(d->workspace_block);
    if (d->selection_block) memory->release(d->selection_block);
    d->arrays = d->workspace_block = d->selection_block = NULL;
    d->table_workspace = d->selection_workspace = NULL;
    d->u = d->y = d->y_hat = d->y_error = d->singular_values = NULL;
    d->frequency = d->damping = d->eig_re = d->eig_im = d->emac = d->mpc = d->cmi = d->shape_re = d->shape_im = NULL;
}

static void fill(double *values, size_t count, double value)
{
    for (size_t i = 0; i < count; ++i) values[i] = value;
}

/* The published model is none: every mode output and singular value NaN. */
static void publish_nothing(identifier_data *d)
{
    const size_t modes = (size_t)d->max_modes, shape = modes * 2u * (size_t)d->num_outputs;
    double *per_mode[] = {d->frequency, d->damping, d->eig_re, d->eig_im, d->emac, d->mpc, d->cmi};
    for (size_t i = 0; i < sizeof per_mode / sizeof per_mode[0]; ++i) fill(per_mode[i], modes, (double)NAN);
    fill(d->shape_re, shape, (double)NAN);
    fill(d->shape_im, shape, (double)NAN);
    fill(d->singular_values, (size_t)d->num_singular_values, (double)NAN);
    d->identification_time = (double)NAN;
    d->num_modes = 0;
}

static fmu_status configure(void *data, const fmu_allocator *memory, fmu_logger *logger)
{
    identifier_data *d = data;
    release(d, memory);
    const struct {
        const char *name;
        int value, min, max;
    } sizes[] = {{"num_inputs", d->num_inputs, 0, MAX_CHANNELS}, {"num_outputs", d->num_outputs, 1, MAX_CHANNELS},
                 {"max_modes", d->max_modes, 1, MAX_MODES_LIMIT},
                 {"num_singular_values", d->num_singular_values, 1, MAX_SINGULAR_VALUES}};
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; ++i) {
        if (sizes[i].value < sizes[i].min || sizes[i].value > sizes[i].max) {
            fmu_log(logger, FMU_ERROR, "logStatusError",
                    "structural parameter %s = %d refused: this build allows %d..%d", sizes[i].name,
                    sizes[i].value, sizes[i].min, sizes[i].max);
            return FMU_ERROR;
        }
    }
    const size_t r = (size_t)d->num_inputs, m = (size_t)d->num_outputs, k = (size_t)d->max_modes;
    const size_t doubles = r + m + 2 * m + (size_t)d->num_singular_values + 7 * k + 2 * k * 2 * m;
    const size_t reals = r + 2 * m;
    d->arrays_bytes = doubles * sizeof(double) + reals * sizeof(okid_real);
    d->arrays = memory->allocate(d->arrays_bytes, 1);
    if (d->arrays == NULL) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "out of memory for the arrays of %zu doubles", doubles);
        return FMU_ERROR;
    }
    double *at = d->arrays;
    double **arrays[] = {&d->u, &d->y, &d->y_hat, &d->y_error, &d->singular_values, &d->frequency, &d->damping,
                         &d->eig_re, &d->eig_im, &d->emac, &d->mpc, &d->cmi, &d->shape_re, &d->shape_im};
    const size_t counts[] = {r, m, m, m, (size_t)d->num_singular_values, k, k, k, k, k, k, k, 2 * k * m, 2 * k * m};
    for (size_t i = 0; i < sizeof counts / sizeof counts[0]; ++i) {
        *arrays[i] = at;
        at += counts[i];
    }
    d->u_real = (okid_real *)at;
    d->y_real = d->u_real + r;
    d->y_hat_real = d->y_real + m;
    fill(d->y_hat, m, (double)NAN);
    fill(d->y_error, m, (double)NAN);
    publish_nothing(d);
    return FMU_OK;
}

static size_t aligned_up(size_t bytes)
{
    return (bytes + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN;
}

static int output_only(const identifier_data *d) { return d->num_inputs == 0; }

/*
 * The selection's memory, sized once from the parameters (all_poles false, order 0): the table of
 * the even orders 2..N and the selection of it. Input-output: N = min(MODE_WINDOWS_MAX_ORDER,
 * alpha m, beta columns, m p) as okid identify takes it for one Hankel window (host_tools/common/
 * auto_settings.c); output-only: N = min(MODE_WINDOWS_MAX_ORDER, L m) as okid identify --inputs 0
 * takes it for one Hankel size (host_tools/common/ambient_modes.c). The criteria are the CLI's:
 * the library's defaults with the damping limit 1/sqrt(2) and the band up to 0.8 times the model's
 * Nyquist frequency; its lower edge is 0 (the CLI's f5/3 comes from the record's spectrum, which a
 * streaming FMU does not hold).
 */
static fmu_status prepare_selection(identifier_data *d, const fmu_allocator *memory, fmu_logger *logger,
                                    const char *values)
{
    if (d->selection_block) memory->release(d->selection_block);
    d->selection_block = d->table_workspace = d->selection_workspace = NULL;
    if (d->all_poles || d->order > 0) return FMU_OK;
    const int m = d->num_outputs, columns = d->realization == OKID_REALIZATION_COMBINED ? d->num_inputs + m : d->num_inputs;
    int top = MODE_WINDOWS_MAX_ORDER;
    if (top > d->hankel_rows * m) top = d->hankel_rows * m;
    if (!output_only(d) && top > d->hankel_cols * columns) top = d->hankel_cols * columns;
    if (!output_only(d) && top > d->observer_order * m) top = d->observer_order * m;
    top -= top % 2;
    okid_status st = top < 2            ? OKID_E_BAD_ORDER
                     : output_only(d) ? okid_ambient_stabilization_workspace_size(&d->amb, top, 2, &d->table_bytes)
                                        : okid_stabilization_workspace_size(&d->id, top, 2, &d->table_bytes);
    if (st == OKID_OK) st = okid_mode_selection_workspace_size(top, 2, &d->selection_bytes);
    if (st != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "all_poles = false (the default) refused: the stabilization table of the even "
                "orders 2..%d (min(%d, hankel_rows num_outputs%s)) cannot be sized: %s (okid_status %d); set all_poles = "
                "true for the model's poles (%s)", top, MODE_WINDOWS_MAX_ORDER,
                output_only(d) ? "" : ", hankel_cols columns, observer_order num_outputs", okid_status_str(st), (int)st,
                values);
        return FMU_ERROR;
    }
    const size_t table = aligned_up(d->table_bytes), total = table + aligned_up(d->selection_bytes);
    if ((double)total + (double)d->workspace_block_bytes > OKID_FMU_MAX_WORKSPACE_BYTES) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: the workspace and the mode "
                "selection's %zu bytes exceed this build's limit of %.0f bytes (%s)", total,
                (double)OKID_FMU_MAX_WORKSPACE_BYTES, values);
        return FMU_ERROR;
    }
    d->selection_block = memory->allocate(total + OKID_WORKSPACE_ALIGN, 1);
    if (d->selection_block == NULL) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "out of memory for the mode selection's %zu bytes", total);
        return FMU_ERROR;
    }
    const uintptr_t raw = (uintptr_t)d->selection_block;
    d->table_workspace = (void *)((raw + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN);
    d->selection_workspace = (char *)d->table_workspace + table;
    d->table_order = top;
    okid_mode_selection_criteria_default(&d->criteria);
    d->criteria.damping_max = (okid_real)0.70710678118654752; /* AUTO_DAMPING_MAX: a resonance peak up to 1/sqrt(2) */
    d->criteria.frequency_max_hz = (okid_real)(0.8 * 0.5 / (d->decimation * d->dt));
    fmu_log(logger, FMU_OK, "logEvents", "mode selection: the stabilization table of the even orders 2..%d (%zu "
            "bytes) and its selection (%zu bytes), beside the identifier's workspace of %zu bytes", top,
            d->table_bytes, d->selection_bytes, d->workspace_block_bytes - OKID_WORKSPACE_ALIGN);
    return FMU_OK;
}

/* The workspace of `bytes` (checked against this build's limit), aligned; NULL after logging why. */
static void *allocate_workspace(identifier_data *d, const fmu_allocator *memory, fmu_logger *logger, size_t bytes,
                                const char *values)
{
    if ((double)bytes > OKID_FMU_MAX_WORKSPACE_BYTES) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: their workspace of %zu bytes "
                "exceeds this build's limit of %.0f bytes (%s)", bytes, (double)OKID_FMU_MAX_WORKSPACE_BYTES, values);
        return NULL;
    }
    if (d->workspace_block) memory->release(d->workspace_block);
    d->workspace_block_bytes = bytes + OKID_WORKSPACE_ALIGN;
    d->workspace_block = memory->allocate(d->workspace_block_bytes, 1);
    if (d->workspace_block == NULL) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "out of memory for the workspace of %zu bytes", bytes);
        return NULL;
    }
    const uintptr_t raw = (uintptr_t)d->workspace_block;
    return (void *)((raw + OKID_WORKSPACE_ALIGN - 1) / OKID_WORKSPACE_ALIGN * OKID_WORKSPACE_ALIGN);
}

/* The initialization `function` refused the parameters `values` with st. */
static fmu_status refused_by(fmu_logger *logger, const char *function, okid_status st, const char *values)
{
    fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused by %s: %s (okid_status %d) for %s",
            function, okid_status_str(st), (int)st, values);
    return FMU_ERROR;
}

/*
 * num_inputs = 0: the output-only identifier (okid/ambient.h) over the outputs' correlations of
 * lags 0..2L, L = hankel_rows, with order, dt and sensing; the parameters that belong to the
 * observer (OKID) must keep their defaults, as okid identify --inputs 0 refuses their flags.
 */
static fmu_status exit_output_only(identifier_data *d, const fmu_allocator *memory, fmu_logger *logger)
{
    okid_config def;
    okid_config_default(&def, 1, d->num_outputs);
    const struct {
        int given;
        const char *name;
    } observer[] = {
        {d->observer_order != def.observer_order, "observer_order"},
        {d->hankel_cols != def.hankel_cols && d->hankel_cols != d->hankel_rows, "hankel_cols (L is both rows and columns: set hankel_rows)"},
        {d->block_rows != def.block_rows, "block_rows"},
        {d->forgetting_factor != (double)def.forgetting_factor, "forgetting_factor"},
        {d->rank_tolerance != (double)def.rank_tolerance, "rank_tolerance"},
        {d->realization != (int)def.realization, "realization"},
        {d->zero_initial_state != def.zero_initial_state, "zero_initial_state"},
        {d->decimation != def.decimation, "decimation"},
        {d->scaling != (int)def.scaling, "scaling (the correlations are always scaled by the channels' RMS)"},
        {d->estimator != (int)def.estimator, "estimator"},
        {d->instrument_lags != def.instrument_lags, "instrument_lags"},
    };
    for (size_t i = 0; i < sizeof observer / sizeof observer[0]; ++i) {
        if (observer[i].given) {
            fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: %s does not apply to "
                    "output-only identification (num_inputs = 0): leave it at its start value", observer[i].name);
            return FMU_ERROR;
        }
    }
    okid_ambient_config cfg;
    okid_ambient_config_default(&cfg, d->num_outputs);
    cfg.hankel_rows = d->hankel_rows;
    cfg.order = d->order;
    cfg.dt = (okid_real)d->dt;
    cfg.sensing = (okid_sensing)d->sensing;
    char values[160];
    snprintf(values, sizeof values, "num_inputs 0, num_outputs %d, hankel_rows %d, order %d, dt %.17g, sensing %d, "
             "all_poles %d", d->num_outputs, d->hankel_rows, d->order, d->dt, d->sensing, d->all_poles);
    size_t bytes = 0;
    okid_status st = okid_ambient_workspace_size(&cfg, &bytes);
    if (st != OKID_OK) { /* the field okid_ambient_config_check names is the FMU variable of that name */
        okid_config_issue issue;
        (void)okid_ambient_config_check(&cfg, &issue);
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused by okid_ambient_workspace_size: "
                "%s = %.17g, valid %.17g..%.17g for output-only identification%s (okid_status %d) for %s",
                issue.field ? issue.field : "?", issue.value, issue.min, issue.max,
                issue.field && strcmp(issue.field, "order") == 0
                    ? (OKID_LINALG_EIGEN ? " (at most hankel_rows num_outputs, and the Eigen backend's OKID_EIGEN_MAX_ORDER)"
                                         : " (at most hankel_rows num_outputs, and 512)")
                    : "",
                (int)st, values);
        return FMU_ERROR;
    }
    void *workspace = allocate_workspace(d, memory, logger, bytes, values);
    if (workspace == NULL) return FMU_ERROR;
    st = okid_ambient_init(&d->amb, &cfg, workspace, bytes, NULL);
    if (st != OKID_OK) return refused_by(logger, "okid_ambient_init", st, values);
    fmu_log(logger, FMU_OK, "logEvents", "output-only identification: the correlations of lags 0..%d of %d outputs "
            "and their ERA in a workspace of %zu bytes", 2 * d->hankel_rows, d->num_outputs, bytes);
    return prepare_selection(d, memory, logger, values);
}

static fmu_status exit_initialization(void *data, const fmu_allocator *memory, fmu_logger *logger)
{
    identifier_data *d = data;
    if (d->identify_every < 1) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: identify_every = %d, must be >= 1",
                d->identify_every);
        return FMU_ERROR;
    }
    if (output_only(d)) return exit_output_only(d, memory, logger);
    okid_config cfg;
    okid_config_default(&cfg, d->num_inputs, d->num_outputs);
    cfg.observer_order = d->observer_order;
    cfg.order = d->order;
    cfg.hankel_rows = d->hankel_rows;
    cfg.hankel_cols = d->hankel_cols;
    cfg.block_rows = d->block_rows;
    cfg.dt = (okid_real)d->dt;
    cfg.forgetting_factor = (okid_real)d->forgetting_factor;
    cfg.rank_tolerance = (okid_real)d->rank_tolerance;
    cfg.sensing = (okid_sensing)d->sensing;
    cfg.realization = (okid_realization)d->realization;
    cfg.zero_initial_state = d->zero_initial_state;
    cfg.decimation = d->decimation;
    cfg.scaling = (okid_scaling)d->scaling;
    cfg.estimator = (okid_estimator)d->estimator;
    cfg.instrument_lags = d->instrument_lags;
    char values[440];
    snprintf(values, sizeof values,
             "num_inputs %d, num_outputs %d, observer_order %d, order %d, hankel_rows %d, hankel_cols %d, block_rows %d, "
             "dt %.17g, forgetting_factor %.17g, rank_tolerance %.17g, sensing %d, realization %d, zero_initial_state %d, "
             "decimation %d, scaling %d, estimator %d, instrument_lags %d, all_poles %d",
             d->num_inputs, d->num_outputs, d->observer_order, d->order, d->hankel_rows, d->hankel_cols, d->block_rows,
             d->dt, d->forgetting_factor, d->rank_tolerance, d->sensing, d->realization, d->zero_initial_state,
             d->decimation, d->scaling, d->estimator, d->instrument_lags, d->all_poles);
    size_t bytes = 0;
    okid_status st = okid_workspace_size(&cfg, &bytes);
    if (st != OKID_OK) { /* the setting, its value and its valid range: the CLI's and Python's words */
        char why[640];
        (void)config_explain(&cfg, st, CONFIG_EXPLAIN_FMU, why, sizeof why);
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused by okid_workspace_size: %s "
                "(okid_status %d) for %s", why, (int)st, values);
        return FMU_ERROR;
    }
    void *workspace = allocate_workspace(d, memory, logger, bytes, values);
    if (workspace == NULL) return FMU_ERROR;
    st = okid_init(&d->id, &cfg, workspace, bytes, NULL);
    if (st != OKID_OK) return refused_by(logger, "okid_init", st, values);
    return prepare_selection(d, memory, logger, values);
}

/* What publish() needs of an identification, input-output (okid_result) or output-only (okid_ambient_result). */
typedef struct identified {
    int num_modes, regressor_rank, num_singular_values;
    const okid_mode *modes;
    const okid_real *singular_values;
    unsigned warnings;
} identified;

/*
 * The physical modes of the last identification into d->selected (the CLI's one-window rule:
 * mode_windows_add, then mode_windows_keep): their count, or a negative okid_status.
 */
static int select_modes(identifier_data *d, const identified *res)
{
    int top = d->table_order < res->num_singular_values ? d->table_order : res->num_singular_values;
    top -= top % 2;
    if (top < 2) return (int)OKID_E_BAD_ORDER;
    okid_stabilization table;
    okid_status st = output_only(d) ? okid_ambient_stabilization_compute(&d->amb, top, 2, NULL, d->table_workspace,
                                                                         d->table_bytes, &table)
                                    : okid_stabilization_compute(&d->id, top, 2, NULL, d->table_workspace,
                                                                 d->table_bytes, &table);
    okid_mode_selection selection;
    if (st == OKID_OK) {
        st = okid_select_modes(&table, d->num_outputs, &d->criteria, d->selection_workspace, d->selection_bytes,
                               &selection, NULL);
    }
    if (st != OKID_OK) return (int)st;
    int count = 0, support[OKID_MAX_ORDER] = {0};
    mode_windows_add(&d->criteria, &selection, 0, d->num_outputs, d->selected, &count, support);
    mode_windows_keep(d->selected, &count, 1);
    return count;
}

/* selected < 0: the model's poles; else the first `selected` of d->selected. */
static void publish(identifier_data *d, const identified *res, int selected, double t)
{
    const int m2 = 2 * d->num_outputs;
    publish_nothing(d);
    d->num_modes = selected < 0 ? res->num_modes : selected;
    d->rank = res->regressor_rank;
    d->warnings = (int)(res->warnings | (selected == 0 ? (unsigned)OKID_W_NO_PHYSICAL_MODE : 0u));
    d->identification_time = t;
    for (int i = 0; i < d->num_singular_values && i < res->num_singular_values; ++i) {
        d->singular_values[i] = (double)res->singular_values[i];
    }
    for (int k = 0; k < d->max_modes && k < d->num_modes; ++k) {
        const okid_mode *md = selected < 0 ? &res->modes[k] : &d->selected[k].selected->mode;
        d->frequency[k] = (double)md->frequency_hz;
        d->damping[k] = (double)md->damping_ratio;
        d->eig_re[k] = (double)md->eigenvalue.re;
        d->eig_im[k] = (double)md->eigenvalue.im;
        d->emac[k] = (double)md->emac;
        d->mpc[k] = (double)md->mpc;
        d->cmi[k] = (double)md->cmi;
        for (int j = 0; j < m2; ++j) {
            d->shape_re[k * m2 + j] = (double)md->shape[j].re;
            d->shape_im[k * m2 + j] = (double)md->shape[j].im;
        }
    }
}

static int saturate(uint64_t count) { return count > INT_MAX ? INT_MAX : (int)count; }

/* The identification st with its model res: the physical modes selected (order 0) and published, or the failure shown. */
static fmu_status conclude(identifier_data *d, okid_status st, const identified *res, double t, fmu_logger *logger)
{
    int selected = -1;
    if (st == OKID_OK && d->selection_block != NULL && (selected = select_modes(d, res)) < 0) {
        st = (okid_status)selected; /* the table or the selection failed: the outputs keep the last ones */
    }
    if (st != OKID_OK) {
        d->last_error = (int)st;
        d->status = STATUS_FAILED;
        fmu_log(logger, FMU_OK, "logEvents",
                "identification at t = %.17g failed: %s (okid_status %d); the mode outputs keep the identification at "
                "t = %.17g (NaN: none)", t, okid_status_str(st), (int)st, d->identification_time);
        return FMU_OK; /* data-dependent: keep collecting */
    }
    publish(d, res, selected, t);
    d->status = STATUS_IDENTIFIED;
    d->last_error = 0;
    ++d->identifications;
    return FMU_OK;
}

/* num_inputs = 0: y into the correlation sums; identify every identify_every samples once 2L + 1 follow one another. */
static fmu_status step_output_only(identifier_data *d, double t, fmu_logger *logger)
{
    for (int i = 0; i < d->num_outputs; ++i) d->y_real[i] = (okid_real)d->y[i];
    const okid_status pushed = okid_ambient_push(&d->amb, d->y_real);
    if (pushed == OKID_E_NONFINITE_SAMPLE) {
        d->rejected = saturate((uint64_t)d->rejected + 1u);
        fmu_log(logger, FMU_WARNING, "logStatusWarning",
                "non-finite output sample at t = %.17g rejected (a gap in the correlations); the sums so far are kept", t);
        return FMU_WARNING;
    }
    if (pushed != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "okid_ambient_push failed: %s (okid_status %d)",
                okid_status_str(pushed), (int)pushed);
        return FMU_ERROR;
    }
    d->samples = saturate((uint64_t)d->samples + 1u);
    if (++d->since_identify < d->identify_every) return FMU_OK;
    okid_ambient_result res;
    memset(&res, 0, sizeof res); /* read only when the identification succeeded */
    const okid_status st = okid_ambient_identify(&d->amb, &res);
    if (st == OKID_E_NOT_ENOUGH_DATA) return FMU_OK; /* no pair at lag 2L yet: try again next step */
    d->since_identify = 0;
    const identified view = {res.num_modes, 0, res.num_singular_values, res.modes, res.singular_values, res.warnings};
    return conclude(d, st, &view, t, logger);
}

static fmu_status do_step(void *data, double t, double h, fmu_logger *logger)
{
    identifier_data *d = data;
    const int r = d->num_inputs, m = d->num_outputs;
    if (fabs(h - d->dt) > 1e-9 * d->dt) {
        fmu_log(logger, FMU_ERROR, "logStatusError",
                "DoStep: communication step %.17g differs from the parameter dt = %.17g (the identifier samples "
                "once per step)", h, d->dt);
        return FMU_ERROR;
    }
    if (output_only(d)) return step_output_only(d, t, logger);
    for (int i = 0; i < r; ++i) d->u_real[i] = (okid_real)d->u[i];
    for (int i = 0; i < m; ++i) d->y_real[i] = (okid_real)d->y[i];
    /* The prediction of this sample from the model and the past, or NaN: never an earlier step's. */
    d->prediction_valid = okid_predict(&d->id, d->u_real, d->y_hat_real) == OKID_OK;
    for (int i = 0; i < m; ++i) {
        d->y_hat[i] = d->prediction_valid ? (double)d->y_hat_real[i] : (double)NAN;
        d->y_error[i] = d->y[i] - d->y_hat[i];
    }
    const okid_status pushed = okid_push(&d->id, d->u_real, d->y_real);
    okid_progress progress;
    okid_get_progress(&d->id, &progress);
    d->samples = saturate(progress.samples);
    d->rejected = saturate(progress.rejected);
    if (pushed == OKID_E_NONFINITE_SAMPLE) {
        fmu_log(logger, FMU_WARNING, "logStatusWarning",
                "non-finite input sample at t = %.17g rejected; the identification so far is kept", t);
        return FMU_WARNING;
    }
    if (pushed != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "okid_push failed: %s (okid_status %d)", okid_status_str(pushed),
                (int)pushed);
        return FMU_ERROR;
    }
    if (++d->since_identify < d->identify_every || progress.rows < (uint64_t)progress.rows_needed) {
        return FMU_OK;
    }
    d->since_identify = 0;
    okid_result res;
    memset(&res, 0, sizeof res); /* read only when the identification succeeded */
    const okid_status st = okid_identify(&d->id, &res);
    const identified view = {res.num_modes, res.regressor_rank, res.num_singular_values, res.modes,
                             res.singular_values, res.warnings};
    return conclude(d, st, &view, t, logger);
}

/* The identifier's state beyond its data: the arrays and the workspace, which okid_identifier points into. */
static int state_blocks(void *data, fmu_block blocks[FMU_MAX_BLOCKS])
{
    identifier_data *d = data;
    blocks[0] = (fmu_block){d->arrays, d->arrays ? d->arrays_bytes : 0};
    blocks[1] = (fmu_block){d->workspace_block, d->workspace_block ? d->workspace_block_bytes : 0};
    /* the selection's memory is scratch between identifications: no bytes saved, but its address is
       checked, so that a state restores only where d->selection_block is this instance's allocation */
    blocks[2] = (fmu_block){d->selection_block, 0};
    return 3;
}

const fmu_model FMU_MODEL = {
    "okid_identifier",
    "OKID/ERA identification of a structure from forces and responses (or from responses alone: num_inputs 0): "
    "modes as they converge",
    0.01,
    0, /* one sample per step: the step must be dt */
    GROUPS,
    NUM_GROUPS,
    sizeof(identifier_data),
    set_defaults,
    token,
    configure,
    exit_initialization,
    do_step,
    NULL,
    release,
    state_blocks,
};

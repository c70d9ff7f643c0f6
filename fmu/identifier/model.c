/*
 * The identifier FMU: inputs u[r] and y[m] each communication step; OKID/ERA re-identification
 * every N samples; outputs per mode (frequency, damping, eigenvalue, eq. 64 shape), the one-step
 * prediction and its error, counters and Hankel singular values. Sizes are fixed per build
 * (OKID_FMU_R, OKID_FMU_M, OKID_FMU_MAX_MODES); the workspace lives inside the instance, sized for
 * the largest settings allowed (OKID_FMU_MAX_OBSERVER_ORDER, OKID_FMU_MAX_HANKEL).
 */
#include <math.h>
#include <stddef.h>
#include <string.h>

#include "fmu_config.h"
#include "fmu_model.h"
#include "okid/okid.h"

#ifndef OKID_FMU_R
#define OKID_FMU_R 1
#endif
#ifndef OKID_FMU_M
#define OKID_FMU_M 2
#endif
#ifndef OKID_FMU_MAX_MODES
#define OKID_FMU_MAX_MODES 4
#endif
#ifndef OKID_FMU_MAX_OBSERVER_ORDER
#define OKID_FMU_MAX_OBSERVER_ORDER 60
#endif
#ifndef OKID_FMU_MAX_HANKEL
#define OKID_FMU_MAX_HANKEL 100
#endif
#ifndef OKID_FMU_MAX_DECIMATION
#define OKID_FMU_MAX_DECIMATION 16
#endif
#define R OKID_FMU_R
#define M OKID_FMU_M
#define MAX_MODES OKID_FMU_MAX_MODES
#define NUM_SV 8
/* the largest settings: combined realization, decimation, scaling and instruments (automatic lags) */
#define WORKSPACE_BYTES                                                                                        \
    OKID_WORKSPACE_BYTES_OPTIONS(R, M, OKID_FMU_MAX_OBSERVER_ORDER, OKID_FMU_MAX_HANKEL, OKID_FMU_MAX_HANKEL, \
                                 2 * MAX_MODES, 0, 1, 2, 1, 1, 0)

enum { STATUS_COLLECTING = 0, STATUS_IDENTIFIED = 1, STATUS_ERROR = 2 };

typedef struct identifier_data {
    /* parameters */
    double dt, forgetting_factor;
    int observer_order, order, hankel_rows, hankel_cols, sensing, realization, identify_every, zero_initial_state;
    int decimation, scaling, estimator;
    /* inputs */
    double u[R], y[M];
    /* outputs */
    int status, samples, rejected, rank, num_modes, identifications, last_error, warnings;
    double y_hat[M], y_error[M], singular_values[NUM_SV];
    double frequency[MAX_MODES], damping[MAX_MODES], eig_re[MAX_MODES], eig_im[MAX_MODES];
    double emac[MAX_MODES], mpc[MAX_MODES], cmi[MAX_MODES];
    double shape_re[MAX_MODES][2 * M], shape_im[MAX_MODES][2 * M];
    /* internal */
    int since_identify, has_model;
    okid_identifier id;
    _Alignas(OKID_WORKSPACE_ALIGN) unsigned char workspace[WORKSPACE_BYTES];
} identifier_data;

#define OFF(field) offsetof(identifier_data, field)
#define PARAM_REAL(name, field, start, unit, text) \
    {name, 0, 0, FMU_REAL, FMU_PARAMETER, FMU_FIXED, OFF(field), 0, 0, start, unit, text}
#define PARAM_INT(name, field, start, text) {name, 0, 0, FMU_INTEGER, FMU_PARAMETER, FMU_FIXED, OFF(field), 0, 0, start, NULL, text}
#define OUT_INT(name, field, text) {name, 0, 0, FMU_INTEGER, FMU_OUTPUT, FMU_DISCRETE, OFF(field), 0, 0, 0, NULL, text}
#define OUT_REALS(name, count, field, unit, text) \
    {name, count, 0, FMU_REAL, FMU_OUTPUT, FMU_DISCRETE, OFF(field), sizeof(double), 0, 0, unit, text}

static const fmu_variable_group GROUPS[] = {
    PARAM_REAL("dt", dt, 0.01, "s", "sample interval = the communication step size"),
    PARAM_INT("observer_order", observer_order, 20, "observer order p (1..max, m p >= n)"),
    PARAM_INT("order", order, 4, "model order n (even, 2..2 x the number of modes of this build)"),
    PARAM_INT("hankel_rows", hankel_rows, 20, "Hankel block rows alpha"),
    PARAM_INT("hankel_cols", hankel_cols, 20, "Hankel block columns beta"),
    PARAM_INT("sensing", sensing, 2, "outputs measure 0 displacement, 1 velocity, 2 acceleration"),
    PARAM_REAL("forgetting_factor", forgetting_factor, 1.0, NULL, "exponential forgetting factor in (0, 1]"),
    PARAM_INT("realization", realization, 0, "0 system Markov parameters, 1 combined with observer gain"),
    PARAM_INT("identify_every", identify_every, 100, "re-identify every N samples"),
    PARAM_INT("zero_initial_state", zero_initial_state, 1, "1 when the record starts at rest"),
    PARAM_INT("decimation", decimation, 1,
              "K: anti-alias filter and keep every K-th sample (1..OKID_FMU_MAX_DECIMATION); p, alpha, beta count "
              "kept samples; no prediction (y_hat) when K > 1"),
    PARAM_INT("scaling", scaling, 0, "0 data as given, 1 each channel divided by its RMS (results independent of units)"),
    PARAM_INT("estimator", estimator, 0, "0 least squares, 1 instrumental variables (no output-noise bias)"),
    {"u%d", R, 0, FMU_REAL, FMU_INPUT, FMU_CONTINUOUS, OFF(u), sizeof(double), 0, 0, NULL, "input (force)"},
    {"y%d", M, 0, FMU_REAL, FMU_INPUT, FMU_CONTINUOUS, OFF(y), sizeof(double), 0, 0, NULL, "output (sensor)"},
    OUT_INT("status", status, "0 collecting, 1 identified, 2 error (see last_error)"),
    OUT_INT("last_error", last_error, "okid_status of the last failed identification (0 none)"),
    OUT_INT("samples", samples, "samples accepted"),
    OUT_INT("rejected", rejected, "samples rejected as non-finite"),
    OUT_INT("regressor_rank", rank, "numerical rank of the regressor"),
    OUT_INT("num_modes", num_modes, "modes identified"),
    OUT_INT("identifications", identifications, "successful identifications so far"),
    OUT_INT("warnings", warnings, "okid_warning bits of the last identification (okid/status.h)"),
    OUT_REALS("y_hat%d", M, y_hat, NULL, "one-step prediction of y with the identified observer"),
    OUT_REALS("y_error%d", M, y_error, NULL, "y - y_hat (innovation)"),
    OUT_REALS("singular_value%d", NUM_SV, singular_values, NULL, "Hankel singular values, decreasing"),
    OUT_REALS("mode%d_frequency", MAX_MODES, frequency, "Hz", "natural frequency"),
    OUT_REALS("mode%d_damping", MAX_MODES, damping, NULL, "damping ratio"),
    OUT_REALS("mode%d_emac", MAX_MODES, emac, NULL, "extended modal amplitude coherence in [0, 1]"),
    OUT_REALS("mode%d_mpc", MAX_MODES, mpc, NULL, "modal phase collinearity in [0, 1]"),
    OUT_REALS("mode%d_cmi", MAX_MODES, cmi, NULL, "consistent mode indicator EMAC * MPC in [0, 1]: low for computational modes"),
    OUT_REALS("mode%d_eigenvalue_re", MAX_MODES, eig_re, NULL, "discrete eigenvalue, real part"),
    OUT_REALS("mode%d_eigenvalue_im", MAX_MODES, eig_im, NULL, "discrete eigenvalue, imaginary part"),
    {"mode%d_shape%d_re", MAX_MODES, 2 * M, FMU_REAL, FMU_OUTPUT, FMU_DISCRETE, OFF(shape_re), sizeof(double) * 2 * M,
     sizeof(double), 0, NULL, "eq. 64 mode shape (displacements then velocities), real part"},
    {"mode%d_shape%d_im", MAX_MODES, 2 * M, FMU_REAL, FMU_OUTPUT, FMU_DISCRETE, OFF(shape_im), sizeof(double) * 2 * M,
     sizeof(double), 0, NULL, "eq. 64 mode shape, imaginary part"},
};

static void set_defaults(void *data)
{
    identifier_data *d = data;
    fmu_variable v;
    const int n = fmu_variable_count(GROUPS, (int)(sizeof GROUPS / sizeof GROUPS[0]));
    for (int i = 0; i < n; ++i) {
        fmu_variable_at(GROUPS, (int)(sizeof GROUPS / sizeof GROUPS[0]), i, &v);
        if (v.causality == FMU_OUTPUT) continue;
        if (v.type == FMU_REAL) {
            memcpy((char *)d + v.offset, &v.start, sizeof(double));
        } else {
            const int value = (int)v.start;
            memcpy((char *)d + v.offset, &value, sizeof(int));
        }
    }
}

static fmu_status refuse(fmu_logger *logger, const char *what)
{
    fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: %s", what);
    return FMU_ERROR;
}

static fmu_status exit_initialization(void *data, fmu_logger *logger)
{
    identifier_data *d = data;
    if (!(isfinite(d->dt) && d->dt > 0)) return refuse(logger, "dt must be finite and > 0");
    if (d->observer_order < 1 || d->observer_order > OKID_FMU_MAX_OBSERVER_ORDER) {
        return refuse(logger, "observer_order must be in 1..OKID_FMU_MAX_OBSERVER_ORDER of this build");
    }
    if (d->order < 2 || d->order > 2 * MAX_MODES || d->order % 2 != 0) {
        return refuse(logger, "order must be even and in 2..2 x the modes of this build");
    }
    if (d->hankel_rows < 1 || d->hankel_cols < 1 || d->hankel_rows > OKID_FMU_MAX_HANKEL ||
        d->hankel_cols > OKID_FMU_MAX_HANKEL) {
        return refuse(logger, "hankel_rows and hankel_cols must be in 1..OKID_FMU_MAX_HANKEL of this build");
    }
    if (d->sensing < 0 || d->sensing > 2) return refuse(logger, "sensing must be 0, 1 or 2");
    if (d->realization < 0 || d->realization > 1) return refuse(logger, "realization must be 0 or 1");
    if (!(isfinite(d->forgetting_factor) && d->forgetting_factor > 0 && d->forgetting_factor <= 1)) {
        return refuse(logger, "forgetting_factor must be in (0, 1]");
    }
    if (d->identify_every < 1) return refuse(logger, "identify_every must be >= 1");
    if (d->decimation < 1 || d->decimation > OKID_FMU_MAX_DECIMATION) {
        return refuse(logger, "decimation must be in 1..OKID_FMU_MAX_DECIMATION of this build");
    }
    if (d->scaling < 0 || d->scaling > 1) return refuse(logger, "scaling must be 0 or 1");
    if (d->estimator < 0 || d->estimator > 1) return refuse(logger, "estimator must be 0 or 1");
    okid_config cfg;
    okid_config_default(&cfg, R, M);
    cfg.dt = d->dt;
    cfg.observer_order = d->observer_order;
    cfg.order = d->order;
    cfg.hankel_rows = d->hankel_rows;
    cfg.hankel_cols = d->hankel_cols;
    cfg.sensing = (okid_sensing)d->sensing;
    cfg.realization = (okid_realization)d->realization;
    cfg.forgetting_factor = d->forgetting_factor;
    cfg.zero_initial_state = d->zero_initial_state != 0;
    cfg.decimation = d->decimation;
    cfg.scaling = (okid_scaling)d->scaling;
    cfg.estimator = (okid_estimator)d->estimator;
    size_t needed = 0;
    const okid_status st = okid_init(&d->id, &cfg, d->workspace, sizeof d->workspace, &needed);
    if (st != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "identifier parameters refused: %s (workspace %zu of %zu bytes)",
                okid_status_str(st), needed, sizeof d->workspace);
        return FMU_ERROR;
    }
    return FMU_OK;
}

static void publish(identifier_data *d, const okid_result *res)
{
    d->num_modes = res->num_modes < MAX_MODES ? res->num_modes : MAX_MODES;
    d->rank = res->regressor_rank;
    d->warnings = (int)res->warnings;
    for (int i = 0; i < NUM_SV; ++i) {
        d->singular_values[i] = i < res->num_singular_values ? (double)res->singular_values[i] : 0.0;
    }
    for (int k = 0; k < MAX_MODES; ++k) {
        const int live = k < d->num_modes;
        const okid_mode *md = &res->modes[k < d->num_modes ? k : 0];
        d->frequency[k] = live ? (double)md->frequency_hz : 0.0;
        d->damping[k] = live ? (double)md->damping_ratio : 0.0;
        d->eig_re[k] = live ? (double)md->eigenvalue.re : 0.0;
        d->eig_im[k] = live ? (double)md->eigenvalue.im : 0.0;
        d->emac[k] = live ? (double)md->emac : 0.0;
        d->mpc[k] = live ? (double)md->mpc : 0.0;
        d->cmi[k] = live ? (double)md->cmi : 0.0;
        for (int j = 0; j < 2 * M; ++j) {
            d->shape_re[k][j] = live ? (double)md->shape[j].re : 0.0;
            d->shape_im[k][j] = live ? (double)md->shape[j].im : 0.0;
        }
    }
}

static fmu_status do_step(void *data, double t, double h, fmu_logger *logger)
{
    identifier_data *d = data;
    (void)t;
    if (fabs(h - d->dt) > 1e-9 * d->dt) {
        fmu_log(logger, FMU_ERROR, "logStatusError",
                "DoStep: communication step %.17g differs from the parameter dt = %.17g (the identifier samples "
                "once per step)", h, d->dt);
        return FMU_ERROR;
    }
    okid_real u[R], y[M], y_hat[M];
    for (int i = 0; i < R; ++i) u[i] = (okid_real)d->u[i];
    for (int i = 0; i < M; ++i) y[i] = (okid_real)d->y[i];
    if (okid_predict(&d->id, u, y_hat) == OKID_OK) {
        for (int i = 0; i < M; ++i) {
            d->y_hat[i] = (double)y_hat[i];
            d->y_error[i] = d->y[i] - d->y_hat[i];
        }
    }
    const okid_status pushed = okid_push(&d->id, u, y);
    okid_progress progress;
    okid_get_progress(&d->id, &progress);
    d->samples = (int)progress.samples;
    d->rejected = (int)progress.rejected;
    if (pushed == OKID_E_NONFINITE_SAMPLE) {
        fmu_log(logger, FMU_WARNING, "logStatusWarning",
                "non-finite input sample at t = %.17g rejected; the identification so far is kept", t);
        return FMU_WARNING;
    }
    if (pushed != OKID_OK) {
        fmu_log(logger, FMU_ERROR, "logStatusError", "okid_push failed: %s", okid_status_str(pushed));
        return FMU_ERROR;
    }
    if (++d->since_identify < d->identify_every || progress.rows < (uint64_t)progress.rows_needed) {
        return FMU_OK;
    }
    d->since_identify = 0;
    okid_result res;
    const okid_status st = okid_identify(&d->id, &res);
    if (st != OKID_OK) {
        d->last_error = (int)st;
        d->status = d->identifications > 0 ? STATUS_IDENTIFIED : STATUS_ERROR;
        fmu_log(logger, FMU_OK, "logEvents", "identification at t = %.6g not possible yet: %s", t,
                okid_status_str(st));
        return FMU_OK; /* data-dependent: keep collecting, the outputs keep the last model */
    }
    publish(d, &res);
    d->status = STATUS_IDENTIFIED;
    d->last_error = 0;
    ++d->identifications;
    return FMU_OK;
}

const fmu_model FMU_MODEL = {
    "okid_identifier",
    "OKID/ERA identification of a structure from forces and responses: modes as they converge",
    OKID_FMU_TOKEN,
    0.01,
    GROUPS,
    (int)(sizeof GROUPS / sizeof GROUPS[0]),
    sizeof(identifier_data),
    OKID_WORKSPACE_ALIGN,
    set_defaults,
    exit_initialization,
    do_step,
    NULL,
};

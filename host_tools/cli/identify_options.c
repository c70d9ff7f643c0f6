/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The options of okid identify, once: name, old spelling, value type, valid range, the okid_config
 * field set (docs/cli.md's vocabulary: the flag is the field's name with '-' for '_') and help.
 * Defaults are okid_config_default()'s.
 */
#include "identify_options.h"

#include <float.h>
#include <stddef.h>
#include <string.h>

#include "auto_settings.h"
#include "cli_common.h"
#include "identify_lift.h"
#include "option_table.h"

/* The working precision of the library this CLI is built on (okid_real is float or double). */
#if OKID_REAL_IS_FLOAT
#define REAL_EPSILON ((double)FLT_EPSILON)
#define REAL_MIN ((double)FLT_MIN)
#define RANK_TOLERANCE_NOTE "0 = 1e-5; below epsilon there is no rank test"
#else
#define REAL_EPSILON DBL_EPSILON
#define REAL_MIN DBL_MIN
#define RANK_TOLERANCE_NOTE "0 = 1e-10; below epsilon there is no rank test"
#endif
/* okid_config::block_rows: regressor rows per fold, at most 4096 (okid_workspace_size) */
#define MAX_BLOCK_ROWS 4096

/* CLI_ENUM and CLI_SWITCH store an int */
_Static_assert(sizeof(okid_sensing) == sizeof(int) && sizeof(okid_realization) == sizeof(int) &&
                   sizeof(okid_scaling) == sizeof(int) && sizeof(okid_estimator) == sizeof(int) &&
                   sizeof(okid_refine_model) == sizeof(int),
               "okid_config's enumerations are stored as int");

#define AT(member) offsetof(identify_options, member)
#define CONFIG(f) AT(cfg.f), sizeof(((okid_config *)0)->f), 0
#define OWN(member) AT(member), sizeof(((identify_options *)0)->member), 0
#define REFINE(f) AT(refine_cfg.f), sizeof(((okid_refine_config *)0)->f), 0

static const cli_option identify_table[] = {
    /* name, alias, kind, offset/size/count, min, max, range, names, field, metavar, note, default, help */
    {"inputs", NULL, CLI_TEXT, OWN(inputs), 0, 0, 0, NULL, "num_inputs", "NAMES|COUNT", NULL, "1",
     "input (force) columns: comma-separated names, or how many columns\n"
     "follow the time column; 1..64 (OKID_MAX_DIMENSION); 0: output-only\n"
     "(ambient) identification from the outputs' correlations (docs/ambient.md)"},
    {"outputs", NULL, CLI_TEXT, OWN(outputs), 0, 0, 0, NULL, "num_outputs", "NAMES|COUNT", NULL,
     "every remaining column", "output (sensor) columns: names, or how many follow the inputs; 1..64"},
    {"references", NULL, CLI_TEXT, OWN(references), 0, 0, 0, NULL, NULL, "NAMES|COUNT", NULL, "every output",
     "with --inputs 0 (output-only): the outputs the correlations are taken\n"
     "against, names or how many of the first outputs (docs/ambient.md)"},
    {"segments", NULL, CLI_INT, OWN(segments), 0, OKID_AMBIENT_MAX_SEGMENTS, 0, NULL, NULL, "NB", "0 or 1 = none",
     NULL, "with --inputs 0: each mode's frequency and damping std from the spread\n"
     "over NB segments of the record (docs/ambient.md)"},
    {"segment-samples", NULL, CLI_INT, OWN(segment_samples), 0, 1000000000, 0, NULL, NULL, "S",
     "0 = 20 (2L + 1); at least 2L + 1", NULL, "with --segments: samples per block dealt to a segment"},
    {"dt", NULL, CLI_REAL, OWN(dt), (double)OKID_MAGNITUDE_MIN, (double)OKID_MAGNITUDE_MAX, 0, NULL, "dt", "S",
     "the library's magnitude range, OKID_MAGNITUDE_MIN..MAX", "the time column's step",
     "sample interval [s]; a time column must be uniform, and agree with --dt"},
    {"observer-order", NULL, CLI_INT, CONFIG(observer_order), 1, OKID_MAX_HORIZON, 0, NULL, "observer_order", "P",
     "and m p >= n", NULL, "observer order p: observer Markov parameters identified"},
    {"order", NULL, CLI_INT, CONFIG(order), 0, OKID_MAX_ORDER, 0, NULL, "order", "N",
     "0 = the largest singular-value gap; at most min(alpha m, beta columns, m p)", NULL, "model order n"},
    {"hankel-rows", NULL, CLI_INT, CONFIG(hankel_rows), 1, OKID_MAX_HORIZON, 0, NULL, "hankel_rows", "A", NULL, NULL,
     "Hankel block rows alpha"},
    {"hankel-cols", NULL, CLI_INT, CONFIG(hankel_cols), 1, OKID_MAX_HORIZON, 0, NULL, "hankel_cols", "B", NULL, NULL,
     "Hankel block columns beta"},
    {"block-rows", NULL, CLI_INT, CONFIG(block_rows), 0, MAX_BLOCK_ROWS, 0, NULL, "block_rows", "R", "0 = automatic (256 rows, fewer for wide regressors)", NULL,
     "regressor rows folded into the QR factor at a time (speed, not results)"},
    {"forgetting-factor", "forgetting", CLI_REAL, CONFIG(forgetting_factor), 0, 1, CLI_MIN_OPEN, NULL,
     "forgetting_factor", "L", NULL, NULL,
     "exponential forgetting: a row folded k samples ago weighs L^k; 1 keeps all alike"},
    {"rank-tolerance", NULL, CLI_REAL, CONFIG(rank_tolerance), REAL_EPSILON, 1, CLI_MAX_OPEN | CLI_ZERO_TOO, NULL,
     "rank_tolerance", "T", RANK_TOLERANCE_NOTE,
     NULL, "relative tolerance of the rank-revealing least squares"},
    {"sensing", NULL, CLI_ENUM, CONFIG(sensing), 0, 0, 0, cli_sensing_names, "sensing", "KIND", NULL, NULL,
     "what the outputs measure (the mode shapes, eq. 64)"},
    {"realization", NULL, CLI_ENUM, CONFIG(realization), 0, 0, 0, cli_realization_names, "realization", "KIND", NULL,
     NULL, "combined also gives the observer gain G"},
    {"zero-initial-state", NULL, CLI_SWITCH, CONFIG(zero_initial_state), 0, 1, 0, NULL, "zero_initial_state", NULL,
     NULL, NULL, "the record starts at rest (use its first samples with zero history)"},
    {"decimation", "decimate", CLI_INT, CONFIG(decimation), 1, OKID_MAX_DECIMATION, 0, NULL, "decimation", "K", NULL,
     NULL,
     "anti-alias filter (Butterworth, order 2) and keep every K-th sample;\n"
     "p, alpha, beta then count decimated samples, dt of the results is K dt"},
    {"decimation-method", NULL, CLI_ENUM, OWN(decimation_method), 0, 0, 0, cli_decimation_method_names, NULL, "KIND",
     NULL, NULL,
     "with --decimation K: filter (the biquad above; biased, 1e-2 on noise-free\n"
     "data) or lift (okid_lift: K samples become one of K r inputs at K dt,\n"
     "exact; K r <= 64; the regressor grows to K r + (K r + m) p columns)"},
    {"scaling", "scale", CLI_ENUM, CONFIG(scaling), 0, 0, 0, cli_scaling_names, "scaling", "KIND", NULL, NULL,
     "auto divides each input and output by its RMS over the first block\n"
     "of rows, so the units of the channels do not matter"},
    {"estimator", NULL, CLI_ENUM, CONFIG(estimator), 0, 0, 0, cli_estimator_names, "estimator", "KIND", NULL, NULL,
     "instrumental removes the bias of output noise with delayed inputs\n"
     "as instruments; correlation accumulates Phi'Phi (half the flops of\n"
     "the QR fold) and falls back to least_squares when its Cholesky\n"
     "guard refuses (old spelling of least_squares: least-squares)"},
    {"instrument-lags", NULL, CLI_INT, CONFIG(instrument_lags), 0, OKID_MAX_INSTRUMENT_LAGS, 0, NULL, "instrument_lags",
     "L", "0 = ceil(q/r) + 2p; r (L + 1) >= q and L >= p", NULL, "instrument lags of --estimator instrumental"},
    /* the refinement: okid_refine_config's fields (docs/refinement.md) */
    {"refine", NULL, CLI_FLAG, OWN(refine), 0, 0, 0, NULL, NULL, NULL, NULL, NULL,
     "prediction-error (maximum-likelihood) refinement of the OKID/ERA model over\n"
     "the record, with the standard deviation of every mode (docs/refinement.md)"},
    {"max-passes", NULL, CLI_INT, REFINE(max_passes), 2, 1000, 0, NULL, NULL, "K", NULL, NULL,
     "with --refine: passes over the record at most"},
    {"step-tolerance", NULL, CLI_REAL, REFINE(step_tolerance), 0, 0, CLI_MIN_OPEN | CLI_NO_MAX, NULL, NULL, "T", NULL, NULL,
     "with --refine: converged when the Gauss-Newton decrement (about the\n"
     "squared step in standard deviations) is below T"},
    {"refine-model", NULL, CLI_ENUM, REFINE(refine_model), 0, 0, 0, cli_refine_model_names, NULL, "KIND", NULL, NULL,
     "with --refine: the predictor fitted; innovation also fits the gain K of\n"
     "x(k+1) = A x + B u + K e, the maximum-likelihood one when forces nobody\n"
     "measured act (white residuals where output_error's are not; docs/refinement.md);\n"
     "auto: output_error, and innovation only where output_error's residual is not\n"
     "white and innovation's is, with modes within 3 sigma of output_error's"},
    /* the command's own options */
    {"observer-seconds", NULL, CLI_REAL, OWN(observer_seconds), 0, 0, CLI_MIN_OPEN | CLI_NO_MAX, NULL, NULL, "S", NULL,
     "--observer-order", "observer order p = round(S / (K dt)) (after --dt, --decimation)"},
    {"hankel-seconds", NULL, CLI_REAL, OWN(hankel_seconds), 0, 0, CLI_MIN_OPEN | CLI_NO_MAX, NULL, NULL, "S", NULL,
     "--hankel-rows, --hankel-cols", "Hankel block rows and columns alpha = beta = round(S / (K dt))"},
    {"stabilization", NULL, CLI_INT, OWN(stabilization), 2, OKID_MAX_ORDER, 0, NULL, NULL, "NMAX",
     "at most the Hankel size min(alpha m, beta r)", "none",
     "stabilization diagram data for the even orders 2..NMAX from one SVD;\n"
     "\"stabilization\" in the JSON, plot it with okid-stabilization (docs/quality.md)"},
    {"ignore-time-column", NULL, CLI_FLAG, OWN(ignore_time_column), 0, 0, 0, NULL, NULL, NULL, NULL, NULL,
     "with --dt: use it although the time column's stamps step otherwise\n"
     "(without it such a --dt is refused: it would scale every frequency)"},
    {"all-poles", NULL, CLI_FLAG, OWN(all_poles), 0, 0, 0, NULL, NULL, NULL, NULL, NULL,
     "list every pole of the model with its verdict: physical, or why it was\n"
     "rejected (the JSON has them always, under \"poles\")"},
    {"json", NULL, CLI_FLAG, OWN(json), 0, 0, 0, NULL, NULL, NULL, NULL, NULL,
     "print one JSON object instead of a table"},
    {"timing", NULL, CLI_FLAG, OWN(timing), 0, 0, 0, NULL, NULL, NULL, NULL, NULL,
     "report the seconds from okid_init to the modes (\"elapsed_seconds\" in JSON)"},
    {"repeat", NULL, CLI_INT, OWN(repeat), 1, 100000, 0, NULL, NULL, "K", NULL, NULL,
     "with --timing: identify K times from scratch, report the fastest"},
    {NULL, NULL, CLI_FLAG, 0, 0, 0, 0, 0, 0, NULL, NULL, NULL, NULL, NULL, NULL},
};

static const char synopsis[] =
    "usage: okid identify [options] FILE.csv      (FILE '-' reads standard input)\n"
    "\n"
    "FILE.csv has a header row of column names; a time column (t, time, timestamp, seconds, ... with an\n"
    "optional unit such as time_ms or t [s], in any position; docs/robustness.md) holds the sample\n"
    "times, which must be uniform (else give --dt). Every other cell is a finite number; a NaN, an empty\n"
    "or a non-numeric cell, or a row with a missing field rejects the file.\n"
    "\n"
    "--decimation, --observer-order and --hankel-rows/--hankel-cols that are not given are chosen from\n"
    "the record (the band of the outputs' energy: the decimation filter above 95 % of it, the observer\n"
    "half and the Hankel window three slowest periods), and without --order the modes listed are the\n"
    "physical ones, stable across model orders and Hankel windows; each choice is printed with its\n"
    "reason (docs/quality.md, section 8). Give all of them and --order to stream the file in fixed\n"
    "memory with exactly those settings.\n"
    "\n"
    "Each option is the okid_config field of the same name (docs/cli.md); '--name=value' works too.\n"
    "In brackets: the valid values and the default (okid_config_default()).\n"
    "\n";

static const char epilogue[] = "\nExit status: 0 success, 1 bad data or identification failure, 2 usage error.\n";

static void identify_defaults(identify_options *o)
{
    memset(o, 0, sizeof *o);
    o->repeat = 1;
    okid_config_default(&o->cfg, 1, 1);
    okid_refine_config_default(&o->refine_cfg);
}

int identify_parse_options(int argc, char **argv, identify_options *o)
{
    identify_options defaults;
    identify_defaults(&defaults);
    const cli_command command = {"identify", synopsis, epilogue, identify_table, &defaults, 1, "input file"};
    const char *file = NULL;
    int files = 0;
    *o = defaults;
    const int rc = cli_parse_options(&command, argc, argv, o, &file, &files);
    if (rc != 0) {
        return rc;
    }
    if (files == 0) {
        return cli_error(EXIT_USAGE, "no input file (usage: okid identify [options] FILE.csv)");
    }
    o->file = file;
    o->have_dt = o->dt > 0;
    /* the settings not given are chosen from the data (auto_settings.h); --refine chooses p and the
       Hankel size itself unless one of them is given (docs/refinement.md) */
    static const struct {
        const char *flag;
        unsigned bit;
    } settings[] = {{"--observer-order", AUTO_GIVEN_OBSERVER}, {"--observer-seconds", AUTO_GIVEN_OBSERVER},
                    {"--hankel-rows", AUTO_GIVEN_HANKEL},      {"--hankel-cols", AUTO_GIVEN_HANKEL},
                    {"--hankel-seconds", AUTO_GIVEN_HANKEL},   {"--decimation", AUTO_GIVEN_DECIMATION},
                    {"--decimate", AUTO_GIVEN_DECIMATION}};
    for (int i = 1; i < argc; ++i) {
        for (size_t k = 0; k < sizeof settings / sizeof settings[0]; ++k) {
            const size_t len = strlen(settings[k].flag);
            if (strncmp(argv[i], settings[k].flag, len) == 0 && (argv[i][len] == '\0' || argv[i][len] == '=')) {
                o->given |= settings[k].bit;
            }
        }
    }
    o->horizons_given = (o->given & (AUTO_GIVEN_OBSERVER | AUTO_GIVEN_HANKEL)) != 0;
    if (o->decimation_method == DECIMATION_LIFT && !(o->given & AUTO_GIVEN_DECIMATION)) {
        return cli_error(EXIT_USAGE, "--decimation-method lift needs --decimation K (lifting does not follow a "
                         "decimation chosen from the data)");
    }
    return 0;
}

/* SPDX-License-Identifier: Apache-2.0 */
/* See json_writer.h. */
#include "json_writer.h"

#include "config_names.h"
#include "okid_fields.h"
#include "warning_poles.h"

#include <math.h>
#include <string.h>

void json_number(FILE *out, double value)
{
    if (isfinite(value)) {
        fprintf(out, "%.17g", value);
    } else {
        fputs("null", out);
    }
}

/* Length of the valid UTF-8 sequence at p (at most end - p bytes), or 0 when it is not one. */
static int utf8_length(const unsigned char *p, const unsigned char *end)
{
    int n = 0;
    unsigned min = 0, cp = 0;
    if (*p < 0x80) return 1;
    if ((*p & 0xe0) == 0xc0) n = 2, min = 0x80, cp = *p & 0x1fu;
    else if ((*p & 0xf0) == 0xe0) n = 3, min = 0x800, cp = *p & 0x0fu;
    else if ((*p & 0xf8) == 0xf0) n = 4, min = 0x10000, cp = *p & 0x07u;
    else return 0;
    if (end - p < n) return 0;
    for (int i = 1; i < n; ++i) {
        if ((p[i] & 0xc0) != 0x80) return 0;
        cp = (cp << 6) | (p[i] & 0x3fu);
    }
    /* overlong forms, surrogates and code points above U+10FFFF are not UTF-8 */
    return (cp < min || (cp >= 0xd800 && cp <= 0xdfff) || cp > 0x10ffff) ? 0 : n;
}

void json_string(FILE *out, const char *text)
{
    const unsigned char *p = (const unsigned char *)text, *end = p + strlen(text);
    fputc('"', out);
    while (p < end) {
        const int n = utf8_length(p, end);
        if (n == 0) {
            fputs("\\ufffd", out); /* column names come from files: keep the JSON valid whatever they hold */
            ++p;
        } else if (*p == '"' || *p == '\\') {
            fprintf(out, "\\%c", *p++);
        } else if (*p < 0x20 || *p == 0x7f) {
            fprintf(out, "\\u%04x", *p++);
        } else {
            fwrite(p, 1, (size_t)n, out);
            p += n;
        }
    }
    fputc('"', out);
}

void json_matrix(FILE *out, okid_matrix m)
{
    fputc('[', out);
    for (int i = 0; i < m.rows; ++i) {
        fputs(i ? ", [" : "[", out);
        for (int j = 0; j < m.cols; ++j) {
            if (j) fputs(", ", out);
            json_number(out, (double)okid_matrix_at(m, i, j));
        }
        fputc(']', out);
    }
    fputc(']', out);
}

void json_vector(FILE *out, const okid_real *values, int count)
{
    fputc('[', out);
    for (int i = 0; i < count; ++i) {
        if (i) fputs(", ", out);
        json_number(out, (double)values[i]);
    }
    fputc(']', out);
}

void json_complex(FILE *out, okid_complex z)
{
    fputc('[', out);
    json_number(out, (double)z.re);
    fputs(", ", out);
    json_number(out, (double)z.im);
    fputc(']', out);
}

void json_complex_vector(FILE *out, const okid_complex *values, int count)
{
    fputc('[', out);
    for (int i = 0; i < count; ++i) {
        if (i) fputs(", ", out);
        json_complex(out, values[i]);
    }
    fputc(']', out);
}

static void json_warnings(FILE *out, unsigned warnings)
{
    fputc('[', out);
    int first = 1;
    for (unsigned bit = 1; bit != 0 && bit <= warnings; bit <<= 1) {
        if (warnings & bit) {
            if (!first) fputs(", ", out);
            json_string(out, okid_warning_str(bit));
            first = 0;
        }
    }
    fputc(']', out);
}

/* "warning_poles": {"unstable_pole": [eigenvalues], ...}: the poles a warning is about (only when there are). */
static void json_warning_poles(FILE *out, const okid_result *res)
{
    const unsigned bits[2] = {OKID_W_UNSTABLE_POLE, OKID_W_NONPHYSICAL_POLE};
    int first = 1;
    for (int b = 0; b < 2; ++b) {
        int which[OKID_MAX_ORDER];
        const int count = (res->warnings & bits[b]) ? warning_poles(res->modes, res->num_modes, bits[b], which, OKID_MAX_ORDER) : 0;
        if (count == 0) continue;
        fprintf(out, "%s\"%s\": [", first ? ",\n  \"warning_poles\": {" : ", ", warning_poles_key(bits[b]));
        for (int i = 0; i < count; ++i) {
            if (i) fputs(", ", out);
            json_complex(out, res->modes[which[i]].eigenvalue);
        }
        fputc(']', out);
        first = 0;
    }
    if (!first) fputc('}', out);
}

static void json_string_list(FILE *out, const char *const *texts, int count)
{
    fputc('[', out);
    for (int i = 0; i < count; ++i) {
        if (i) fputs(", ", out);
        json_string(out, texts[i]);
    }
    fputc(']', out);
}

/* "config": every okid_config field under its C name, enumerations by name (docs/cli.md). */
static void json_config(FILE *out, const okid_config *cfg)
{
    const char *sep = "";
    fputs("  \"config\": {", out);
#define INT(name) fprintf(out, "%s\"" #name "\": %d", sep, cfg->name), sep = ", ";
#define REAL(name) fprintf(out, "%s\"" #name "\": ", sep), json_number(out, (double)cfg->name), sep = ", ";
#define ENUM(name, type) \
    fprintf(out, "%s\"" #name "\": \"%s\"", sep, cli_name_of(cli_##name##_names, (int)cfg->name)), sep = ", ";
    OKID_CONFIG_FIELDS(INT, REAL, ENUM, INT)
#undef INT
#undef REAL
#undef ENUM
    fputs("},\n", out);
}

/* The settings' top-level keys of the previous release, with their old values: kept for one
   release (docs/cli.md), then only "config" holds the settings. */
static void json_old_setting_keys(FILE *out, const okid_config *cfg)
{
    fprintf(out, "  \"observer_order\": %d,\n  \"sensing\": \"%s\",\n", cfg->observer_order,
            cli_name_of(cli_sensing_names, (int)cfg->sensing));
    fprintf(out, "  \"hankel_rows\": %d,\n  \"hankel_cols\": %d,\n", cfg->hankel_rows, cfg->hankel_cols);
    fprintf(out, "  \"realization\": \"%s\",\n  \"sample_dt\": ",
            cli_name_of(cli_realization_names, (int)cfg->realization));
    json_number(out, (double)cfg->dt);
    fprintf(out, ",\n  \"scale\": \"%s\",\n  \"estimator\": \"%s\",\n",
            cli_name_of(cli_scaling_names, (int)cfg->scaling),
            cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL   ? "instrumental"
            : cfg->estimator == OKID_ESTIMATOR_CORRELATION ? "correlation"
                                                           : "least-squares");
}

void json_result_fields(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                        const char *const *output_names, double elapsed)
{
    json_result_header(out, cfg, res, input_names, output_names, elapsed);
    json_result_model(out, res);
}

void json_result_header(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                        const char *const *output_names, double elapsed)
{
    const int m = cfg->num_outputs;
    fprintf(out, "{\n  \"order\": %d,\n", res->order);
    if (input_names != NULL) {
        fputs("  \"inputs\": ", out);
        json_string_list(out, input_names, cfg->num_inputs);
        fputs(",\n", out);
    }
    if (output_names != NULL) {
        fputs("  \"outputs\": ", out);
        json_string_list(out, output_names, m);
        fputs(",\n", out);
    }
    json_config(out, cfg);
    json_old_setting_keys(out, cfg);
    fprintf(out, "  \"decimation\": %d,\n", res->decimation);
    if (cfg->estimator == OKID_ESTIMATOR_INSTRUMENTAL) {
        fprintf(out, "  \"instrument_lags\": %d,\n", res->instrument_lags);
    }
    if (res->input_scales != NULL && res->output_scales != NULL) {
        fputs("  \"input_scales\": ", out);
        json_vector(out, res->input_scales, cfg->num_inputs);
        fputs(",\n  \"output_scales\": ", out);
        json_vector(out, res->output_scales, m);
        fputs(",\n", out);
    }
    fprintf(out, "  \"samples\": %llu,\n  \"rows\": %llu,\n  \"dt\": ", (unsigned long long)res->samples,
            (unsigned long long)res->rows);
    json_number(out, (double)res->dt);
    if (elapsed >= 0) {
        fprintf(out, ",\n  \"elapsed_seconds\": %.9g", elapsed);
    }
}

void json_result_model(FILE *out, const okid_result *res)
{
#define INT(name) fprintf(out, ",\n  \"" #name "\": %d", res->name);
#define REAL(name) fputs(",\n  \"" #name "\": ", out), json_number(out, (double)res->name);
    OKID_RESULT_DIAGNOSTICS(INT, REAL)
#undef INT
#undef REAL
    fprintf(out, ",\n  \"warning_bits\": %u,\n  \"warnings\": ", res->warnings);
    json_warnings(out, res->warnings);
    json_warning_poles(out, res);
    fputs(",\n  \"singular_values\": ", out);
    json_vector(out, res->singular_values, res->num_singular_values);
    const char *names[4] = {"A", "B", "C", "D"};
    const okid_matrix mats[4] = {res->A, res->B, res->C, res->D};
    for (int i = 0; i < 4; ++i) {
        fprintf(out, ",\n  \"%s\": ", names[i]);
        json_matrix(out, mats[i]);
    }
    if (res->G.data != NULL) {
        fputs(",\n  \"G\": ", out);
        json_matrix(out, res->G);
    }
    fputs(",\n  \"markov\": ", out); /* [Y_0 Y_1 ... Y_L], m x r(L+1), eq. 51 */
    json_matrix(out, res->markov);
}

void json_result(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                 const char *const *output_names, double elapsed)
{
    json_result_fields(out, cfg, res, input_names, output_names, elapsed);
    json_modes(out, res, cfg->num_outputs);
}

/* ',\n  "modes": [...]' of count modes with m outputs. */
static void json_mode_list(FILE *out, const okid_mode *modes, int count, int m)
{
    fputs(",\n  \"modes\": [", out);
    for (int i = 0; i < count; ++i) {
        fputs(i ? ",\n    {" : "\n    {", out);
        json_mode_members(out, &modes[i], m);
        fputc('}', out);
    }
    fputs(count ? "\n  ]" : "]", out);
}

void json_modes(FILE *out, const okid_result *res, int m)
{
    json_mode_list(out, res->modes, res->num_modes, m);
}

void json_ambient_fields(FILE *out, const okid_ambient_config *cfg, const okid_ambient_result *res,
                         const char *const *output_names, const char *const *reference_names, double elapsed)
{
    const int m = cfg->num_outputs, nref = res->G.cols;
    fprintf(out, "{\n  \"order\": %d,\n  \"inputs\": [],\n  \"outputs\": ", res->order);
    json_string_list(out, output_names, m);
    fputs(",\n  \"references\": ", out);
    json_string_list(out, reference_names, nref);
    fputs(",\n  \"config\": {\"num_inputs\": 0", out);
#define INT(name) fprintf(out, ", \"" #name "\": %d", cfg->name);
#define REAL(name) fprintf(out, ", \"" #name "\": "), json_number(out, (double)cfg->name);
#define ENUM(name, type) fprintf(out, ", \"" #name "\": \"%s\"", cli_name_of(cli_##name##_names, (int)cfg->name));
    OKID_AMBIENT_CONFIG_FIELDS(INT, REAL, ENUM)
#undef INT
#undef REAL
#undef ENUM
    fprintf(out, "},\n  \"samples\": %llu,\n  \"pairs\": %llu,\n  \"dt\": ", (unsigned long long)res->samples,
            (unsigned long long)res->pairs);
    json_number(out, (double)res->dt);
    if (elapsed >= 0) {
        fprintf(out, ",\n  \"elapsed_seconds\": %.9g", elapsed);
    }
    fputs(",\n  \"realization_condition\": ", out);
    json_number(out, (double)res->realization_condition);
    fprintf(out, ",\n  \"warning_bits\": %u,\n  \"warnings\": ", res->warnings);
    json_warnings(out, res->warnings);
    fputs(",\n  \"singular_values\": ", out);
    json_vector(out, res->singular_values, res->num_singular_values);
    const char *names[3] = {"A", "C", "G"};
    const okid_matrix mats[3] = {res->A, res->C, res->G};
    for (int i = 0; i < 3; ++i) {
        fprintf(out, ",\n  \"%s\": ", names[i]);
        json_matrix(out, mats[i]);
    }
    fputs(",\n  \"correlations\": ", out); /* [R(0) R(1) ... R(2L)], m x r_ref (2L + 1) */
    json_matrix(out, res->correlations);
    fprintf(out, ",\n  \"segments_used\": %d", res->segments_used);
    if (res->frequency_std != NULL) { /* one per mode, in the order of "modes" */
        fputs(",\n  \"frequency_std\": ", out);
        json_vector(out, res->frequency_std, res->num_modes);
        fputs(",\n  \"damping_std\": ", out);
        json_vector(out, res->damping_std, res->num_modes);
    }
}

void json_ambient_result(FILE *out, const okid_ambient_config *cfg, const okid_ambient_result *res,
                         const char *const *output_names, const char *const *reference_names, double elapsed)
{
    json_ambient_fields(out, cfg, res, output_names, reference_names, elapsed);
    json_mode_list(out, res->modes, res->num_modes, cfg->num_outputs);
    fputs("\n}\n", out);
}

void json_mode_members(FILE *out, const okid_mode *md, int m)
{
    const char *sep = "";
#define KEY(name) fprintf(out, "%s\"" #name "\": ", sep), sep = ", "
#define COMPLEX(name) KEY(name), json_complex(out, md->name);
#define REAL(name) KEY(name), json_number(out, (double)md->name);
#define FLAG(name) KEY(name), fputs(md->name ? "true" : "false", out);
#define SHAPE(name, k) KEY(name), json_complex_vector(out, md->name, (k) * m);
    OKID_MODE_FIELDS(COMPLEX, REAL, FLAG, SHAPE)
#undef KEY
#undef COMPLEX
#undef REAL
#undef FLAG
#undef SHAPE
}

void json_stabilization(FILE *out, const okid_stabilization *st, int max_order, int step, int m)
{
    fprintf(out, ",\n  \"stabilization\": {\"max_order\": %d, \"step\": %d, \"rank_limit\": %d, \"orders\": [",
            max_order, step, st->rank_limit);
    for (int i = 0; i < st->num_orders; ++i) {
        const okid_stabilization_order *o = &st->orders[i];
        fprintf(out, "%s{\"order\": %d, \"modes\": [", i ? ",\n    " : "\n    ", o->order);
        for (int k = 0; k < o->num_modes; ++k) {
            const unsigned flags = st->stability[o->first + k];
            fprintf(out, "%s{\"stable_frequency\": %s, \"stable_damping\": %s, \"stable_shape\": %s, ",
                    k ? ",\n      " : "\n      ", (flags & OKID_STABLE_FREQUENCY) ? "true" : "false",
                    (flags & OKID_STABLE_DAMPING) ? "true" : "false", (flags & OKID_STABLE_SHAPE) ? "true" : "false");
            json_mode_members(out, &st->modes[o->first + k], m);
            fputc('}', out);
        }
        fputs("]}", out);
    }
    fputs(st->num_orders ? "\n  ]}" : "]}", out);
}

const char *json_refine_state_name(okid_refine_state state)
{
    static const char *const names[] = {"need_pass", "converged", "diverged", "not_improving", "iteration_limit"};
    return (unsigned)state < sizeof names / sizeof names[0] ? names[state] : "unknown";
}

void json_start(FILE *out, const okid_config *cfg, const okid_result *res)
{
    fprintf(out, ",\n  \"start\": {\"order\": %d", res->order);
    json_result_model(out, res);
    json_modes(out, res, cfg->num_outputs);
    fputc('}', out);
}

static const char *covariance_name(okid_refine_covariance c)
{
    return c == OKID_REFINE_COVARIANCE_SANDWICH ? "sandwich" : "fisher";
}

/* "modes": [...] of a refined result, each mode with its standard deviations. */
static void json_refined_modes(FILE *out, const okid_refine_result *res, int m, const char *pad)
{
    fprintf(out, ",\n%s\"modes\": [", pad);
    for (int i = 0; i < res->num_modes; ++i) {
        const okid_mode_std *sd = &res->mode_std[i];
        fprintf(out, "%s\n%s  {", i ? "," : "", pad);
        json_mode_members(out, &res->modes[i], m);
        fputs(", \"frequency_std\": ", out);
        json_number(out, (double)sd->frequency_hz);
        fputs(", \"damping_std\": ", out);
        json_number(out, (double)sd->damping_ratio);
        fputs(", \"eigenvalue_std\": ", out);
        json_complex(out, sd->eigenvalue);
        fputs(", \"pole_std\": ", out);
        json_complex(out, sd->pole);
        fputs(", \"sensor_shape_std\": ", out);
        json_complex_vector(out, sd->sensor_shape, m);
        fputc('}', out);
    }
    fprintf(out, "%s%s]", res->num_modes ? "\n" : "", res->num_modes ? pad : "");
}

void json_refined_result(FILE *out, const okid_refine_config *cfg, const okid_refine_result *res, int m)
{
    fprintf(out, ",\n  \"warning_bits\": %u,\n  \"warnings\": ", res->warnings);
    json_warnings(out, res->warnings);
    fprintf(out, ",\n  \"std_covariance\": \"%s\"", covariance_name(res->covariance));
    const char *names[4] = {"A", "B", "C", "D"};
    const okid_matrix mats[4] = {res->A, res->B, res->C, res->D};
    for (int i = 0; i < 4; ++i) {
        fprintf(out, ",\n  \"%s\": ", names[i]);
        json_matrix(out, mats[i]);
    }
    if (res->K.data != NULL) {
        fputs(",\n  \"K\": ", out); /* the innovation gain (refine_model innovation) */
        json_matrix(out, res->K);
    }
    fputs(",\n  \"initial_state\": ", out);
    json_vector(out, res->initial_state, res->order);
    json_refined_modes(out, res, m, "  ");
    json_refinement(out, cfg, res, m);
}

/* "residual_tests": the figures of each output (docs/refinement.md). */
static void json_residual_tests(FILE *out, const okid_refine_result *res, int m)
{
    fprintf(out, "    \"residual_tests\": {\"lags\": %d, \"whiteness_bound\": ", OKID_REFINE_LAGS);
    json_number(out, OKID_REFINE_WHITENESS_BOUND);
    fputs(", \"autocorrelation_band\": ", out);
    json_number(out, (double)res->autocorrelation_band);
    fputs(", \"input_correlation_bound\": ", out);
    json_number(out, OKID_REFINE_INPUT_CORRELATION_BOUND);
    fputs(", \"outputs\": [", out);
    const int r = res->B.cols;
    for (int i = 0; i < m; ++i) {
        fprintf(out, "%s{\"whiteness\": ", i ? ", " : "");
        json_number(out, (double)res->whiteness[i]);
        fputs(", \"max_autocorrelation\": ", out);
        json_number(out, (double)res->max_autocorrelation[i]);
        fputs(", \"fit_percent\": ", out);
        json_number(out, (double)res->fit_percent[i]);
        const char *keys[3] = {"input_correlation", "max_input_correlation", "input_correlation_band"};
        const okid_real *vals[3] = {res->input_correlation, res->max_input_correlation, res->input_correlation_band};
        for (int k = 0; k < 3; ++k) { /* one value per input */
            fprintf(out, ", \"%s\": [", keys[k]);
            for (int j = 0; j < r; ++j) {
                if (j) fputs(", ", out);
                json_number(out, (double)vals[k][(size_t)i + (size_t)m * (size_t)j]);
            }
            fputc(']', out);
        }
        fprintf(out, ", \"white\": %s, \"warning_bits\": %u, \"warnings\": ",
                res->output_warnings[i] & OKID_W_RESIDUAL_NOT_WHITE ? "false" : "true", res->output_warnings[i]);
        json_warnings(out, res->output_warnings[i]);
        fputc('}', out);
    }
    fprintf(out, "]},\n    \"std_covariance\": \"%s\",\n", covariance_name(res->covariance));
    if (res->split_modes[0] >= 0) { /* OKID_W_MODE_SPLIT only: indices into "modes" */
        fprintf(out, "    \"split_modes\": [%d, %d],\n", res->split_modes[0], res->split_modes[1]);
    }
}

void json_refinement(FILE *out, const okid_refine_config *cfg, const okid_refine_result *res, int m)
{
    fprintf(out, ",\n  \"refinement\": {\"config\": {\"max_passes\": %d, \"step_tolerance\": ", cfg->max_passes);
    json_number(out, (double)cfg->step_tolerance);
    fprintf(out, ", \"refine_model\": \"%s\"},\n    \"state\": \"%s\", \"message\": ", cli_name_of(cli_refine_model_names, (int)cfg->refine_model),
            json_refine_state_name(res->state));
    json_string(out, okid_refine_state_str(res->state));
    fprintf(out, ", \"passes\": %d, \"iterations\": %d, \"num_parameters\": %d, \"samples\": %llu, \"decrement\": ",
            res->passes, res->iterations, res->num_parameters, (unsigned long long)res->samples);
    json_number(out, (double)res->decrement);
    fputs(",\n", out);
    fputs("    \"residual_rms_start\": ", out);
    json_vector(out, res->residual_rms_start, m);
    fputs(", \"residual_rms\": ", out);
    json_vector(out, res->residual_rms, m);
    fprintf(out, ", \"warnings\": %u,\n", res->warnings);
    json_residual_tests(out, res, m);
    fputs("    \"A\": ", out);
    json_matrix(out, res->A);
    fputs(", \"B\": ", out);
    json_matrix(out, res->B);
    fputs(", \"C\": ", out);
    json_matrix(out, res->C);
    fputs(", \"D\": ", out);
    json_matrix(out, res->D);
    fputs(", \"initial_state\": ", out);
    json_vector(out, res->initial_state, res->order);
    if (res->K.data != NULL) {
        fputs(", \"K\": ", out); /* the innovation gain */
        json_matrix(out, res->K);
    }
    /* the top-level "modes" are these since the refined result became the result: kept here for
       one release (docs/refinement.md) */
    json_refined_modes(out, res, m, "    ");
    fputc('}', out);
}

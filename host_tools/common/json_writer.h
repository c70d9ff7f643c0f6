/* SPDX-License-Identifier: Apache-2.0 */
/* Just enough JSON output for the identification result: numbers round-trip (%.17g), NaN/Inf as
   null, strings always valid UTF-8 (invalid bytes become U+FFFD). */
#ifndef OKID_CLI_JSON_WRITER_H
#define OKID_CLI_JSON_WRITER_H

#include <stdio.h>

#include "okid/okid.h"

void json_number(FILE *out, double value);
void json_string(FILE *out, const char *text);
/* [[row 0], [row 1], ...] of a matrix view. */
void json_matrix(FILE *out, okid_matrix m);
/* [v0, v1, ...] */
void json_vector(FILE *out, const okid_real *values, int count);
/* [re, im] */
void json_complex(FILE *out, okid_complex z);
/* [[re, im], ...] */
void json_complex_vector(FILE *out, const okid_complex *values, int count);

/* The members (no braces) of one mode: eigenvalue, pole, frequency, damping, shapes, indicators (m outputs). */
void json_mode_members(FILE *out, const okid_mode *md, int m);

/*
 * The whole result as the members of one JSON object (keys documented in docs/cli.md): "config" holds
 * cfg, the settings the run used; the other keys are okid_result's. input_names (r) and
 * output_names (m) label the columns (either may be NULL); elapsed >= 0 adds "elapsed_seconds".
 */
void json_result(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                 const char *const *output_names, double elapsed);

/* ',\n  "modes": [...]': the model's modes, json_result's last member. */
void json_modes(FILE *out, const okid_result *res, int m);

/* json_result without its last member, "modes" (okid identify's physical modes replace it):
   json_result_header() then json_result_model(). */
void json_result_fields(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                        const char *const *output_names, double elapsed);

/* json_result() in parts: "{" and the run's settings and sizes; then okid_result's model members
   (diagnostics, warnings, singular values, A..D, markov), each after ",\n"; then json_modes(). */
void json_result_header(FILE *out, const okid_config *cfg, const okid_result *res, const char *const *input_names,
                        const char *const *output_names, double elapsed);
void json_result_model(FILE *out, const okid_result *res);

/*
 * The output-only result (okid identify --inputs 0, docs/ambient.md) as one whole JSON object:
 * "order", "inputs" ([]), "outputs", "references", "config" (okid_ambient_config's fields and
 * num_inputs 0), "samples", "pairs", "dt", "realization_condition", "warning_bits", "warnings",
 * "singular_values", "A", "C", "G", "correlations" ([R(0) .. R(2L)]), "segments_used", with
 * segments "frequency_std" and "damping_std" (one per mode), and "modes" as for json_result().
 * elapsed >= 0 adds "elapsed_seconds".
 */
void json_ambient_result(FILE *out, const okid_ambient_config *cfg, const okid_ambient_result *res,
                         const char *const *output_names, const char *const *reference_names, double elapsed);

/* json_ambient_result()'s opening brace and members before "modes" (the physical modes' report follows). */
void json_ambient_fields(FILE *out, const okid_ambient_config *cfg, const okid_ambient_result *res,
                         const char *const *output_names, const char *const *reference_names, double elapsed);

/* ',\n  "start": {...}': the model a refinement started from (json_result_model's members and its modes). */
void json_start(FILE *out, const okid_config *cfg, const okid_result *res);

/*
 * The refined result as the result (okid identify --refine --json, docs/refinement.md): its
 * warnings, "std_covariance", A..D, initial_state and modes with their standard deviations as
 * top-level members, then json_refinement(). After json_result_header() and json_start().
 */
void json_refined_result(FILE *out, const okid_refine_config *cfg, const okid_refine_result *res, int m);

/* ',\n  "stabilization": {...}': the diagram data (keys documented in docs/quality.md). */
void json_stabilization(FILE *out, const okid_stabilization *st, int max_order, int step, int m);

/*
 * ',\n  "refinement": {...}': the prediction-error refinement (docs/refinement.md): its settings,
 * state, passes, residuals, model and modes, each mode with its standard deviations
 * (frequency_std, damping_std, eigenvalue_std, pole_std, sensor_shape_std).
 */
/* The JSON name of a refinement state: "converged", "diverged", "not_improving", "iteration_limit". */
const char *json_refine_state_name(okid_refine_state state);

void json_refinement(FILE *out, const okid_refine_config *cfg, const okid_refine_result *res, int m);

#endif

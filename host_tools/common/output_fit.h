/* SPDX-License-Identifier: Apache-2.0 */
/*
 * How much of each output an identified model explains, in percent, as MATLAB's compare():
 * fit = 100 (1 - |y - yhat| / |y - mean y|), yhat the model's response to the record's inputs from
 * rest. 100 %: every sample; 0 %: no better than the output's mean; below 0: worse. A model of pure
 * noise explains nothing: when no output reaches OKID_REFINE_FIT_LOW the result gets
 * OKID_W_NO_OUTPUT_EXPLAINED (not the refinement's OKID_W_OUTPUT_NOT_EXPLAINED: that one flags a
 * single output of a refined model, and its sentence says so).
 * The record is fed in blocks, so a file of any length needs no more memory than the model.
 */
#ifndef OKID_HOST_OUTPUT_FIT_H
#define OKID_HOST_OUTPUT_FIT_H

#include <stddef.h>
#include <stdio.h>

#include "okid/okid.h"

typedef struct output_fit output_fit;

/*
 * A fit of res over the record to come, or NULL when none is computed: a decimated model (its
 * inputs are the filtered record, which the identifier keeps to itself), a model with a pole on or
 * outside the unit circle (its response from rest grows without bound, so the fit would measure
 * the growth: -1e38 % or an overflow), or no memory.
 */
output_fit *output_fit_begin(const okid_result *res);

/* The largest |eigenvalue| of res's poles (res->modes: every pole of the model), 0 with none. */
double output_fit_largest_radius(const okid_result *res);

/*
 * Why output_fit_begin() computes no fit for a model of this decimation and largest pole radius
 * (output_fit_largest_radius), into out[size]: 1 with the sentence (decimation > 1, radius >= 1),
 * 0 with "" when it computes one. okid identify's table and okid.Result.fit_note print it.
 */
int output_fit_missing(int decimation, double largest_radius, char *out, size_t size);

/* count samples: u r per sample, y m per sample. A non-finite sample leaves the fit undefined. */
void output_fit_push(output_fit *f, size_t count, const okid_real *u, const okid_real *y);

/*
 * The fit of each output into fit_percent (m values; NaN when undefined: a non-finite sample, a
 * constant output) and f freed. Returns OKID_W_NO_OUTPUT_EXPLAINED when some fit is defined and
 * none reaches OKID_REFINE_FIT_LOW, else 0.
 */
unsigned output_fit_end(output_fit *f, double *fit_percent);

/* The whole record in memory: begin, one push, end. 0 with fit_percent filled and the warning bit
   in *warning, or -1 when no fit is computed (output_fit_begin). */
int output_fit_record(const okid_result *res, size_t n, const okid_real *u, const okid_real *y, double *fit_percent,
                      unsigned *warning);

/* ',\n  "fit_percent": [...]' of okid identify --json (null for an undefined fit). */
void json_output_fit(FILE *out, const double *fit_percent, int m);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/* okid identify --refine: the refinement over the record, the choice of its start, their output. */
#ifndef OKID_CLI_IDENTIFY_REFINE_H
#define OKID_CLI_IDENTIFY_REFINE_H

#include <stddef.h>
#include <stdio.h>

#include "identify_options.h"
#include "start_search.h"

/*
 * The prediction-error refinement of res over the record u (r x n), y (m x n), fed to the refiner
 * once per pass in blocks as a file reader would. *ws (the refiner's workspace) is the caller's to
 * free. A refinement that stops without converging is a warning on stderr (unless quiet); its
 * result is still returned. 0, or an exit code after one line on stderr (quiet: no line).
 */
int identify_refine(const identify_options *o, const okid_result *res, size_t n, const okid_real *u,
                    const okid_real *y, int quiet, okid_refiner *rf, void **ws, okid_refine_result *out);

/*
 * --refine without --observer-order or --hankel-*: the host library's start search
 * (start_search.h), each start refined by identify_refine(); cfg gets the chosen p and Hankel size.
 */
void identify_choose_start(const identify_options *o, okid_config *cfg, size_t n, const okid_real *u,
                           const okid_real *y, start_search *search);

/* The table's parts: the starts tried (their JSON: json_start_search), and the refined modes with their std. */
void print_start_search(const start_search *search);
void print_refinement(const okid_refine_result *rr, int m, const char *const *output_names,
                      const char *const *input_names);
/* One line on stderr per failed residual test, naming the output (and the input of a failed
   cross-correlation test; the names may be NULL). */
void warn_residual_tests(const okid_refine_result *rr, int m, const char *const *output_names,
                         const char *const *input_names);
/* One line on stderr when two refined pairs are one mode split in two (OKID_W_MODE_SPLIT), naming both. */
void warn_mode_split(const okid_refine_result *rr, int m);

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/* The options of okid identify: the option table (identify_options.c) fills this struct. */
#ifndef OKID_CLI_IDENTIFY_OPTIONS_H
#define OKID_CLI_IDENTIFY_OPTIONS_H

#include "okid/okid.h"

typedef struct identify_options {
    const char *file, *inputs, *outputs;
    const char *references; /* --references: output-only identification's reference outputs (NULL: all) */
    int segments, segment_samples; /* --segments, --segment-samples: output-only identification's uncertainty */
    double dt, observer_seconds, hankel_seconds;
    int have_dt, json, timing, repeat, stabilization;
    okid_config cfg; /* okid_config_default() before the options; num_inputs, num_outputs, dt set from the file */
    int refine;                    /* --refine: prediction-error refinement after OKID/ERA */
    okid_refine_config refine_cfg; /* okid_refine_config_default() before the options */
    int horizons_given;            /* --observer-order, --hankel-rows/-cols or --*-seconds was given */
    int ignore_time_column;        /* --ignore-time-column: --dt wins over the stamps */
    unsigned given;                /* AUTO_GIVEN_* (auto_settings.h): the settings given, the others chosen from the data */
    int all_poles;                 /* --all-poles: every pole of the model with its verdict in the table */
    int decimation_method;         /* --decimation-method: DECIMATION_FILTER or DECIMATION_LIFT (identify_lift.h) */
    /* --refine-model auto: the choice made (refine_choice.h), for the report; NULL otherwise */
    const struct refine_choice *refine_choice;
    /* --refine without --order: why the refinement's order (refine_selection.h), for the report; NULL otherwise */
    const char *refine_order_reason;
} identify_options;

/* Fills o from the command line; 0, or EXIT_USAGE after one line on stderr. "--help" exits 0. */
int identify_parse_options(int argc, char **argv, identify_options *o);

#endif

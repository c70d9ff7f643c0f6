/* SPDX-License-Identifier: Apache-2.0 */
/* The names of okid_config's enumerations (docs/cli.md: the C enumerator's suffix in lower case)
   and the strict integer parse, which the CLI's options and the JSON writer share. */
#ifndef OKID_HOST_CONFIG_NAMES_H
#define OKID_HOST_CONFIG_NAMES_H

/* Strict conversion of a whole decimal integer; 0 on success, -1 otherwise. */
int cli_parse_int(const char *text, int *out);

/* A named value of an enumeration; an alias (an old spelling) is accepted but never printed. */
typedef struct cli_name {
    const char *name;
    int value;
    int alias;
} cli_name;

/* The enumerations of okid_config, each ended by a {NULL} entry. */
extern const cli_name cli_sensing_names[], cli_realization_names[], cli_scaling_names[], cli_estimator_names[];
/* okid_refine_config::refine_model, on every surface (docs/refinement.md) */
extern const cli_name cli_refine_model_names[];
/* okid identify --decimation-method, Python decimation_method: 0 filter (okid_config::decimation), 1 lift (okid_lift) */
extern const cli_name cli_decimation_method_names[];

/* Value to name (the first entry that is not an alias); "?" when there is none. */
const char *cli_name_of(const cli_name *names, int value);
/* Name (or alias) to value; 0 on success, -1 when the name is not in the list. */
int cli_value_of(const cli_name *names, const char *text, int *value);

#endif

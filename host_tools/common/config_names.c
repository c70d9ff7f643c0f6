/* SPDX-License-Identifier: Apache-2.0 */
/* See config_names.h. */
#include "config_names.h"
#include "refine_choice.h"

#include <errno.h>
#include <limits.h>
#include <stdlib.h>
#include <string.h>

#include "okid/okid.h"

int cli_parse_int(const char *text, int *out)
{
    char *end = NULL;
    errno = 0;
    const long v = strtol(text, &end, 10);
    if (end == text || *end != '\0' || errno != 0 || v < INT_MIN || v > INT_MAX) {
        return -1;
    }
    *out = (int)v;
    return 0;
}

const cli_name cli_sensing_names[] = {{"displacement", OKID_SENSING_DISPLACEMENT, 0},
                                      {"velocity", OKID_SENSING_VELOCITY, 0},
                                      {"acceleration", OKID_SENSING_ACCELERATION, 0},
                                      {NULL, 0, 0}};
const cli_name cli_realization_names[] = {{"system", OKID_REALIZATION_SYSTEM, 0},
                                          {"combined", OKID_REALIZATION_COMBINED, 0},
                                          {NULL, 0, 0}};
const cli_name cli_scaling_names[] = {{"none", OKID_SCALING_NONE, 0}, {"auto", OKID_SCALING_AUTO, 0}, {NULL, 0, 0}};
/* "least-squares": the old spelling, accepted for one release (docs/cli.md) */
const cli_name cli_estimator_names[] = {{"least_squares", OKID_ESTIMATOR_LEAST_SQUARES, 0},
                                        {"instrumental", OKID_ESTIMATOR_INSTRUMENTAL, 0},
                                        {"correlation", OKID_ESTIMATOR_CORRELATION, 0},
                                        {"least-squares", OKID_ESTIMATOR_LEAST_SQUARES, 1},
                                        {NULL, 0, 0}};
const cli_name cli_decimation_method_names[] = {{"filter", 0, 0}, {"lift", 1, 0}, {NULL, 0, 0}};
const cli_name cli_refine_model_names[] = {{"output_error", OKID_REFINE_OUTPUT_ERROR, 0},
                                           {"innovation", OKID_REFINE_INNOVATION, 0},
                                           {"auto", REFINE_MODEL_AUTO, 0}, /* the host surfaces' choice */
                                           {NULL, 0, 0}};

const char *cli_name_of(const cli_name *names, int value)
{
    for (const cli_name *n = names; n->name != NULL; ++n) {
        if (!n->alias && n->value == value) {
            return n->name;
        }
    }
    return "?";
}

int cli_value_of(const cli_name *names, const char *text, int *value)
{
    for (const cli_name *n = names; n->name != NULL; ++n) {
        if (strcmp(n->name, text) == 0) {
            *value = n->value;
            return 0;
        }
    }
    return -1;
}

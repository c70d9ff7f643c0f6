/* SPDX-License-Identifier: Apache-2.0 */
/* The host side's field tables: okid_config's fields and okid_result's scalars, each once, which
   the JSON writer, the Python binding (and through it okid/_config.py and okid/_result.py) expand.
   okid_mode's table, OKID_MODE_FIELDS, is beside the struct in okid/modal.h (the library's
   finiteness check reads it too). docs/design.md, "Adding a per-mode quantity". */
#ifndef OKID_CLI_FIELDS_H
#define OKID_CLI_FIELDS_H

/* okid_config in the struct's order: INT(name), REAL(name), ENUM(name, type) (its JSON names are
   cli_<name>_names of cli_common.h), FLAG(name) (an int, 0 or 1). test_vocabulary.py checks the
   table against the struct in okid/identifier.h. */
#define OKID_CONFIG_FIELDS(INT, REAL, ENUM, FLAG)                                                       \
    INT(num_inputs) INT(num_outputs) INT(observer_order) INT(order) INT(hankel_rows) INT(hankel_cols)  \
    INT(block_rows) REAL(dt) REAL(forgetting_factor) REAL(rank_tolerance) ENUM(sensing, okid_sensing)   \
    ENUM(realization, okid_realization) FLAG(zero_initial_state) INT(decimation)                       \
    ENUM(scaling, okid_scaling) ENUM(estimator, okid_estimator) INT(instrument_lags)

/* okid_ambient_config's scalars in the struct's order (okid/ambient.h; its reference_channels, an
   array, is written as the references' names): INT(name), REAL(name), ENUM(name, type). */
#define OKID_AMBIENT_CONFIG_FIELDS(INT, REAL, ENUM)                                                    \
    INT(num_outputs) INT(num_references) INT(hankel_rows) INT(order) REAL(dt) ENUM(sensing, okid_sensing)    \
    INT(segments) INT(segment_samples)

/* okid_ambient_result's scalars: INT(name), REAL(name), COUNT(name) (a uint64_t). */
#define OKID_AMBIENT_RESULT_SCALARS(INT, REAL, COUNT)                                                  \
    INT(order) INT(num_modes) INT(num_singular_values) REAL(realization_condition) REAL(dt)             \
    COUNT(samples) COUNT(pairs) INT(warnings) INT(segments_used)

/* okid_result's diagnostics, in the order of the JSON object: INT(name), REAL(name). */
#define OKID_RESULT_DIAGNOSTICS(INT, REAL)                                                             \
    INT(regressor_rank) INT(regressor_columns) INT(input_rank) INT(regressor_rank_expected)            \
    REAL(lsq_condition) REAL(input_condition) REAL(realization_condition)

/* Every scalar of okid_result that okid.Result carries: COUNT(name) is a uint64_t. */
#define OKID_RESULT_SCALARS(INT, REAL, COUNT)                                                          \
    INT(order) REAL(dt) COUNT(samples) COUNT(rows) OKID_RESULT_DIAGNOSTICS(INT, REAL) INT(decimation)  \
    INT(instrument_lags)

#endif

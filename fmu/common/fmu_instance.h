/* SPDX-License-Identifier: Apache-2.0 */
/*
 * One FMU instance, independent of the FMI version: the state machine, value access through the
 * model's variable table with the causality/variability/state rules, stepping checks and logging.
 * fmi2_functions.c and fmi3_functions.c translate the FMI API onto these functions.
 */
#ifndef OKID_FMU_INSTANCE_H
#define OKID_FMU_INSTANCE_H

#include <stddef.h>
#include <stdint.h>

#include "fmu_model.h"

typedef enum fmu_state {
    FMU_STATE_INSTANTIATED = 1 << 0,
    FMU_STATE_INITIALIZATION = 1 << 1,
    FMU_STATE_STEP = 1 << 2,
    FMU_STATE_TERMINATED = 1 << 3,
    FMU_STATE_ERROR = 1 << 4,
    FMU_STATE_CONFIGURATION = 1 << 5 /* FMI 3: structural parameters may change */
} fmu_state;

/* The caller's value type: how the FMI functions of a version see a stored value. */
typedef enum fmu_value_kind {
    FMU_AS_DOUBLE,  /* fmi2Real, fmi3Float64 */
    FMU_AS_INT32,   /* fmi2Integer, fmi3Int32 */
    FMU_AS_BOOL32,  /* fmi2Boolean (an int) */
    FMU_AS_BOOL8,   /* fmi3Boolean (a bool) */
    FMU_AS_INT64,   /* fmi3Int64: FMI 3 enumerations */
    FMU_AS_UINT64   /* fmi3UInt64: FMI 3 structural parameters */
} fmu_value_kind;

/* The kind in which FMI `version` exchanges values of `type`. */
fmu_value_kind fmu_kind_of(int version, fmu_type type);

/* The resources configuration of FMI 2 (name value lines), kept for reset. */
enum { FMU_MAX_CONFIG_BYTES = 4096 };

/* Where log messages go: the FMI version's callback, reached through a small adapter. */
typedef void (*fmu_log_sink)(void *env, const char *instance, fmu_status status, const char *category,
                             const char *message);

struct fmu_logger {
    fmu_log_sink sink;
    void *env;
    const char *instance;
    int logging_on;
    unsigned categories; /* bit set of the enabled categories (all when none were named) */
};

typedef struct fmu_instance {
    uint32_t magic;
    char name[128];
    fmu_state state;
    double time, start_time, stop_time, tolerance;
    int has_stop_time;
    int fmi_version;
    fmu_logger logger;
    fmu_allocator memory;
    void *data; /* the model's data, FMU_MODEL.data_bytes */
    char config[FMU_MAX_CONFIG_BYTES]; /* resources/<model>.cfg, "" when there is none */
    /* The FMI version's callback structure, copied: the logger's environment points here. */
    _Alignas(16) unsigned char callbacks_copy[64];
} fmu_instance;

/*
 * Reads resources/<model>.cfg (FMI 2; resource_location is a file: URI, may be NULL), applies it
 * to the start values, checks the token against the one the configuration gives, allocates the
 * instance, its model data and the model's arrays through `memory`. NULL on error (logged).
 */
fmu_instance *fmu_instantiate(const char *name, const char *token, fmu_log_sink sink, void *env, int logging_on,
                              int fmi_version, const char *resource_location, fmu_allocator memory);
void fmu_free(fmu_instance *inst);

/* FMU_OK when inst is valid and in one of the allowed states; otherwise logs why and returns FMU_ERROR. */
fmu_status fmu_check(fmu_instance *inst, unsigned allowed_states, const char *function);

fmu_status fmu_set_debug_logging(fmu_instance *inst, int logging_on, size_t count, const char *const categories[]);
fmu_status fmu_setup(fmu_instance *inst, double start_time, int has_stop_time, double stop_time);
fmu_status fmu_enter_configuration(fmu_instance *inst);
fmu_status fmu_exit_configuration(fmu_instance *inst);
fmu_status fmu_enter_initialization(fmu_instance *inst);
fmu_status fmu_exit_initialization(fmu_instance *inst);
fmu_status fmu_do_step(fmu_instance *inst, double current_time, double step);
fmu_status fmu_terminate(fmu_instance *inst);
fmu_status fmu_reset(fmu_instance *inst);

/*
 * Values of `kind` for value references vr[0..nvr): in FMI 2 one value per reference; in FMI 3
 * every element of each referenced variable in turn, nValues in all. Setting is all or nothing.
 */
fmu_status fmu_get(fmu_instance *inst, fmu_value_kind kind, const unsigned vr[], size_t nvr, void *values,
                   size_t nvalues, const char *function);
fmu_status fmu_set(fmu_instance *inst, fmu_value_kind kind, const unsigned vr[], size_t nvr, const void *values,
                   size_t nvalues, const char *function);

/* Logs "function is not supported by this FMU" and returns FMU_ERROR. */
fmu_status fmu_unsupported(fmu_instance *inst, const char *function);
/* Logs the reason as an error and returns FMU_ERROR. */
fmu_status fmu_refuse(fmu_instance *inst, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 2, 3)))
#endif
    ;

/*
 * FMU states (fmu_state.c): get into *state (NULL: a new one; else one this instance returned,
 * reused when it fits), set, free; serialization only for models whose states are portable
 * (FMU_MODEL.state_blocks == NULL: the capability flags of the modelDescription say so).
 */
int fmu_state_portable(void);
fmu_status fmu_get_state(fmu_instance *inst, void **state);
fmu_status fmu_set_state(fmu_instance *inst, const void *state);
fmu_status fmu_free_state(fmu_instance *inst, void **state);
fmu_status fmu_serialized_size(fmu_instance *inst, const void *state, size_t *size);
fmu_status fmu_serialize(fmu_instance *inst, const void *state, unsigned char *bytes, size_t size);
fmu_status fmu_deserialize(fmu_instance *inst, const unsigned char *bytes, size_t size, void **state);

#endif

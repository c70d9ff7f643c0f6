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
    FMU_STATE_ERROR = 1 << 4
} fmu_state;

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
    fmu_logger logger;
    void *data; /* the model's data, FMU_MODEL.data_bytes */
    /* The FMI version's callback structure, copied: the logger's environment points here. */
    _Alignas(16) unsigned char callbacks_copy[64];
} fmu_instance;

/* Checks the token, allocates the instance and its model data (the only allocation). NULL on error (logged). */
fmu_instance *fmu_instantiate(const char *name, const char *token, fmu_log_sink sink, void *env, int logging_on);
void fmu_free(fmu_instance *inst);

/* FMU_OK when inst is valid and in one of the allowed states; otherwise logs why and returns FMU_ERROR. */
fmu_status fmu_check(fmu_instance *inst, unsigned allowed_states, const char *function);

fmu_status fmu_set_debug_logging(fmu_instance *inst, int logging_on, size_t count, const char *const categories[]);
fmu_status fmu_setup(fmu_instance *inst, double start_time, int has_stop_time, double stop_time);
fmu_status fmu_enter_initialization(fmu_instance *inst);
fmu_status fmu_exit_initialization(fmu_instance *inst);
fmu_status fmu_do_step(fmu_instance *inst, double current_time, double step);
fmu_status fmu_terminate(fmu_instance *inst);
fmu_status fmu_reset(fmu_instance *inst);

fmu_status fmu_get_real(fmu_instance *inst, const unsigned vr[], size_t count, double values[]);
fmu_status fmu_set_real(fmu_instance *inst, const unsigned vr[], size_t count, const double values[]);
fmu_status fmu_get_integer(fmu_instance *inst, const unsigned vr[], size_t count, int values[]);
fmu_status fmu_set_integer(fmu_instance *inst, const unsigned vr[], size_t count, const int values[]);

/* Logs "function is not supported by this FMU" and returns FMU_ERROR. */
fmu_status fmu_unsupported(fmu_instance *inst, const char *function);

#endif

/*
 * The interface between the generic FMI glue (fmi2_functions.c, fmi3_functions.c, fmu_instance.c)
 * and one model (identifier/ or plant/), after modelica/Reference-FMUs' model.h: the model
 * describes its variables in a table (from which modelDescription.xml is generated too, so the
 * two cannot disagree) and implements a few callbacks; the glue does states, checks and logging.
 */
#ifndef OKID_FMU_MODEL_H
#define OKID_FMU_MODEL_H

#include <stddef.h>

typedef enum fmu_type { FMU_REAL, FMU_INTEGER } fmu_type;
typedef enum fmu_causality { FMU_PARAMETER, FMU_INPUT, FMU_OUTPUT } fmu_causality;
/* Fixed parameters may change only before initialization ends; tunable ones at any time. */
typedef enum fmu_variability { FMU_FIXED, FMU_TUNABLE, FMU_DISCRETE, FMU_CONTINUOUS } fmu_variability;

/* One variable as the glue and the modelDescription generator see it. */
typedef struct fmu_variable {
    unsigned value_reference;
    char name[64];
    fmu_type type;
    fmu_causality causality;
    fmu_variability variability;
    size_t offset;           /* of the double or int inside the model data */
    double start;            /* parameters and inputs */
    const char *unit;        /* NULL when dimensionless */
    const char *description;
} fmu_variable;

/*
 * Variables come in groups: a scalar, or an array of count1 (x count2) elements whose names are
 * name_format with the 1-based indices ("mode%d_frequency", "mode%d_shape%d_re"). Value
 * references are numbered 1, 2, ... in table order (0 is the time); a model's table is const data.
 */
typedef struct fmu_variable_group {
    const char *name_format;
    int count1, count2;      /* 0 means 1 */
    fmu_type type;
    fmu_causality causality;
    fmu_variability variability;
    size_t offset, stride1, stride2;
    double start;
    const char *unit;
    const char *description;
} fmu_variable_group;

/* Number of variables of a table, and variable `index` (0-based; its value reference is index + 1). */
int fmu_variable_count(const fmu_variable_group *groups, int num_groups);
int fmu_variable_at(const fmu_variable_group *groups, int num_groups, int index, fmu_variable *out);

typedef enum fmu_status { FMU_OK = 0, FMU_WARNING = 1, FMU_ERROR = 3 } fmu_status;

/* Logging for the model: category "logStatusError" for errors, "logEvents" for information. */
typedef struct fmu_logger fmu_logger;
void fmu_log(fmu_logger *logger, fmu_status status, const char *category, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

typedef struct fmu_model {
    const char *name;
    const char *description;
    const char *token;                 /* GUID (FMI 2) and instantiation token (FMI 3) */
    double default_step;
    const fmu_variable_group *groups;
    int num_groups;
    size_t data_bytes;                 /* the model's data, allocated once at instantiation */
    size_t data_align;
    /* Everything to start values (also on reset); may not allocate. */
    void (*set_defaults)(void *data);
    /* Validate parameters and prepare; log the reason of a refusal. */
    fmu_status (*exit_initialization)(void *data, fmu_logger *logger);
    /* Advance from time t by h (the glue checked h and t). */
    fmu_status (*do_step)(void *data, double t, double h, fmu_logger *logger);
    /* Recompute outputs that depend on inputs (direct feedthrough) before they are read. */
    void (*update_outputs)(void *data);
} fmu_model;

/* Each model defines this. */
extern const fmu_model FMU_MODEL;

#endif

/* SPDX-License-Identifier: Apache-2.0 */
/*
 * The interface between the generic FMI glue (fmi2_functions.c, fmi3_functions.c, fmu_instance.c)
 * and one model (identifier/ or plant/), after modelica/Reference-FMUs' model.h: the model
 * describes its variables in a table (from which modelDescription.xml is generated too, so the
 * two cannot disagree) and implements a few callbacks; the glue does states, checks and logging.
 */
#ifndef OKID_FMU_MODEL_H
#define OKID_FMU_MODEL_H

#include <stddef.h>

/*
 * Value types. Every non-real value is stored as an int in the model data; the glue converts to
 * the caller's type. FMI 2: Real, Integer (also for enumerations and sizes), Boolean. FMI 3:
 * Float64, Int32, Enumeration (Int64 access), Boolean, UInt64 (the structural parameters).
 */
typedef enum fmu_type { FMU_REAL, FMU_INTEGER, FMU_ENUM, FMU_BOOLEAN, FMU_SIZE } fmu_type;
/* Structural parameters size the arrays: set in FMI 3's configuration mode, read from resources/ in FMI 2. */
typedef enum fmu_causality { FMU_STRUCTURAL, FMU_PARAMETER, FMU_INPUT, FMU_OUTPUT } fmu_causality;
/* Fixed parameters may change only before initialization ends; tunable ones at any time. */
typedef enum fmu_variability { FMU_FIXED, FMU_TUNABLE, FMU_DISCRETE, FMU_CONTINUOUS } fmu_variability;

/* An enumeration: item i has the value i (the C enumerators' values), named by its C suffix in lower case. */
typedef struct fmu_enum_type {
    const char *name;
    int count;
    const char *const *items;
} fmu_enum_type;

enum { FMU_MAX_DIMS = 3 };

/*
 * One variable of the table: a scalar, or an array whose dimensions are structural parameters of
 * the same table (dims[i] = 1 + that parameter's index in the table) or literals (dims[i] = -n).
 * FMI 3 publishes an array as one variable `name`; FMI 2 unrolls it into scalars named after
 * flat_name with the 1-based indices: the first "%d" indexes the first dimension, the second
 * "%d" the remaining ones together ("mode%d_shape%d_re"). Values are stored at `offset` in the
 * model data for a scalar; for an array `offset` holds a pointer to its row-major elements.
 */
typedef struct fmu_variable_group {
    const char *name;
    const char *flat_name;   /* FMI 2 name format of array elements; NULL for scalars */
    fmu_type type;
    fmu_causality causality;
    fmu_variability variability;
    size_t offset;
    int dims[FMU_MAX_DIMS];  /* 0: no further dimension */
    double start;            /* structural parameters, parameters and inputs */
    double min, max;         /* a range when min <= max (NaN or min > max: none) */
    const fmu_enum_type *enumeration;
    const char *unit;        /* NULL when dimensionless */
    const char *description;
    /*
     * Outputs: the input (its name) this output depends on directly, with a factor fixed after
     * initialization (the plant's accelerations on the force, D != 0); NULL: on no input, the output
     * changes only in DoStep. The modelDescription's <ModelStructure> is written from it.
     */
    const char *depends_on;
} fmu_variable_group;

typedef enum fmu_status { FMU_OK = 0, FMU_WARNING = 1, FMU_ERROR = 3 } fmu_status;

/* Logging for the model: category "logStatusError" for errors, "logEvents" for information. */
typedef struct fmu_logger fmu_logger;
void fmu_log(fmu_logger *logger, fmu_status status, const char *category, const char *format, ...)
#if defined(__GNUC__)
    __attribute__((format(printf, 4, 5)))
#endif
    ;

/* The importer's memory (FMI 2 allocateMemory/freeMemory) or the C library's (FMI 3 gives none). */
typedef struct fmu_allocator {
    void *(*allocate)(size_t count, size_t size); /* zeroed, like calloc */
    void (*release)(void *memory);
} fmu_allocator;

/* A block of memory the model allocated whose contents belong to its state (FMU state get/set). */
typedef struct fmu_block {
    void *at;
    size_t bytes;
} fmu_block;
enum { FMU_MAX_BLOCKS = 4 };

typedef struct fmu_model {
    const char *name;
    const char *description;
    double default_step;
    int variable_step;                 /* canHandleVariableCommunicationStepSize */
    const fmu_variable_group *groups;
    int num_groups;
    size_t data_bytes;                 /* the model's fixed data, allocated at instantiation */
    /* Everything to start values (also on reset); may not allocate. */
    void (*set_defaults)(void *data);
    /*
     * The FMI 2 GUID / FMI 3 instantiation token for the data's structural parameters and the
     * hash of the resources configuration (0: none); the same text the generator writes.
     */
    void (*token)(const void *data, int fmi_version, unsigned long config_hash, char *out, size_t size);
    /* Check the structural parameters against the build's limits and allocate the arrays (NULL: none). */
    fmu_status (*configure)(void *data, const fmu_allocator *memory, fmu_logger *logger);
    /* Validate parameters and prepare (may allocate through memory); log the reason of a refusal. */
    fmu_status (*exit_initialization)(void *data, const fmu_allocator *memory, fmu_logger *logger);
    /* Advance from time t by h (the glue checked h and t). */
    fmu_status (*do_step)(void *data, double t, double h, fmu_logger *logger);
    /* Recompute outputs that depend on inputs (direct feedthrough) before they are read (NULL: none). */
    void (*update_outputs)(void *data);
    /* Free what configure and exit_initialization allocated (NULL: nothing). */
    void (*release)(void *data, const fmu_allocator *memory);
    /*
     * The blocks that configure and exit_initialization allocated, now (at most FMU_MAX_BLOCKS;
     * returns how many). NULL: the model data holds no pointers, so a state is its bytes alone and
     * can be serialized and restored into any instance of this build; otherwise a state holds the
     * blocks' contents and restores only into the instance whose blocks they still are.
     */
    int (*state_blocks)(void *data, fmu_block blocks[FMU_MAX_BLOCKS]);
} fmu_model;

/* Each model defines this. */
extern const fmu_model FMU_MODEL;

/* ---- The variable table (fmu_variables.c) ---- */

/* Elements of group g with the structural parameters in data (1 for a scalar). */
size_t fmu_group_size(const fmu_model *model, const void *data, int g);
/* Extent of dimension d of group g (0 when the group has fewer dimensions). */
size_t fmu_group_dim(const fmu_model *model, const void *data, int g, int d);
/* Where element e of group g lives in data (NULL when an array is not allocated). */
void *fmu_group_element(const fmu_model *model, void *data, int g, size_t e);
/* FMI 2's unrolled variables: how many, and which group and element value reference vr (1-based) is. */
size_t fmu_flat_count(const fmu_model *model, const void *data);
int fmu_flat_find(const fmu_model *model, const void *data, unsigned vr, int *group, size_t *element);
/* The FMI 2 name of element e of group g. */
void fmu_flat_name(const fmu_model *model, const void *data, int g, size_t e, char *out, size_t size);
/* The group named `name` (its FMI 3 name), or -1. */
int fmu_group_by_name(const fmu_model *model, const char *name);

/* Applies "name value" lines (# comments) of a resources configuration to the start values; -1 with the reason. */
int fmu_apply_config(const fmu_model *model, void *data, const char *config, char *error, size_t error_size);

/* FNV-1a over bytes: the configuration hash of the token. */
unsigned long fmu_hash(const void *bytes, size_t count);

#endif

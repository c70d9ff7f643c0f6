/* SPDX-License-Identifier: Apache-2.0 */
/* See fmu_instance.h. */
#include "fmu_instance.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FMU_MAGIC 0x464d5531u /* "FMU1" */

static const char *const CATEGORIES[] = {"logEvents", "logStatusWarning", "logStatusError", "logAll"};
enum { NUM_CATEGORIES = 4 };

static int category_index(const char *category)
{
    for (int i = 0; i < NUM_CATEGORIES; ++i) {
        if (strcmp(category, CATEGORIES[i]) == 0) return i;
    }
    return -1;
}

void fmu_log(fmu_logger *logger, fmu_status status, const char *category, const char *format, ...)
{
    if (logger == NULL || logger->sink == NULL || !logger->logging_on) {
        return;
    }
    const int index = category_index(category);
    const unsigned all = 1u << 3;
    if (index < 0 || !(logger->categories & ((1u << index) | all))) {
        return;
    }
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    /* The message is passed on as data, never as a format: a '%' in it stays a '%'. */
    logger->sink(logger->env, logger->instance, status, category, message);
}

static void log_error(fmu_instance *inst, const char *format, ...) __attribute__((format(printf, 2, 3)));

static void log_error(fmu_instance *inst, const char *format, ...)
{
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    fmu_log(&inst->logger, FMU_ERROR, "logStatusError", "%s", message);
}

fmu_value_kind fmu_kind_of(int version, fmu_type type)
{
    switch (type) {
    case FMU_REAL: return FMU_AS_DOUBLE;
    case FMU_BOOLEAN: return version == 2 ? FMU_AS_BOOL32 : FMU_AS_BOOL8;
    case FMU_ENUM: return version == 2 ? FMU_AS_INT32 : FMU_AS_INT64;
    case FMU_SIZE: return version == 2 ? FMU_AS_INT32 : FMU_AS_UINT64;
    default: return FMU_AS_INT32;
    }
}

/* resources/<model>.cfg from a file: URI ("file:///dir", "file:/dir", "file://host/dir", %-escapes). */
static int read_config(const char *location, char *out, size_t size)
{
    out[0] = '\0';
    if (location == NULL || strncmp(location, "file:", 5) != 0) return 0;
    const char *p = location + 5;
    if (strncmp(p, "///", 3) == 0) p += 2;
    else if (strncmp(p, "//", 2) == 0) p = strchr(p + 2, '/') ? strchr(p + 2, '/') : p + 2;
#if defined(_WIN32)
    if (p[0] == '/' && p[1] && p[2] == ':') ++p; /* /C:/dir */
#endif
    char path[1024];
    size_t n = 0;
    for (; *p && n + 1 < sizeof path; ++p) {
        unsigned hex;
        if (p[0] == '%' && p[1] && p[2] && sscanf(p + 1, "%2x", &hex) == 1) {
            path[n++] = (char)hex;
            p += 2;
        } else {
            path[n++] = *p;
        }
    }
    path[n] = '\0';
    char file[1200];
    snprintf(file, sizeof file, "%s%s%s.cfg", path, n && path[n - 1] == '/' ? "" : "/", FMU_MODEL.name);
    FILE *f = fopen(file, "rb");
    if (f == NULL) return 0;
    const size_t got = fread(out, 1, size, f);
    fclose(f);
    if (got >= size) return -1;
    out[got] = '\0';
    return 1;
}

/* Start values, the resources configuration and the model's arrays: what instantiation and reset set up. */
static fmu_status start_values(fmu_instance *inst)
{
    memset(inst->data, 0, FMU_MODEL.data_bytes);
    FMU_MODEL.set_defaults(inst->data);
    char error[300];
    if (fmu_apply_config(&FMU_MODEL, inst->data, inst->config, error, sizeof error) != 0) {
        fmu_log(&inst->logger, FMU_ERROR, "logStatusError", "resources/%s.cfg refused: %s", FMU_MODEL.name, error);
        return FMU_ERROR;
    }
    return FMU_MODEL.configure ? FMU_MODEL.configure(inst->data, &inst->memory, &inst->logger) : FMU_OK;
}

fmu_instance *fmu_instantiate(const char *name, const char *token, fmu_log_sink sink, void *env, int logging_on,
                              int fmi_version, const char *resource_location, fmu_allocator memory)
{
    fmu_logger early = {sink, env, name ? name : "?", 1, ~0u};
    if (name == NULL || name[0] == '\0') {
        fmu_log(&early, FMU_ERROR, "logStatusError", "instantiation refused: the instance name is empty");
        return NULL;
    }
    fmu_instance *inst = memory.allocate(1, sizeof *inst);
    void *data = memory.allocate(1, FMU_MODEL.data_bytes);
    if (inst == NULL || data == NULL) {
        if (inst) memory.release(inst);
        if (data) memory.release(data);
        fmu_log(&early, FMU_ERROR, "logStatusError", "instantiation failed: out of memory");
        return NULL;
    }
    inst->magic = FMU_MAGIC;
    snprintf(inst->name, sizeof inst->name, "%s", name);
    inst->logger = (fmu_logger){sink, env, inst->name, logging_on, ~0u};
    inst->data = data;
    inst->memory = memory;
    inst->fmi_version = fmi_version;
    inst->state = FMU_STATE_INSTANTIATED;
    const int has_config = fmi_version == 2 ? read_config(resource_location, inst->config, sizeof inst->config) : 0;
    if (has_config < 0) {
        fmu_log(&early, FMU_ERROR, "logStatusError", "instantiation refused: resources/%s.cfg is longer than %d bytes",
                FMU_MODEL.name, FMU_MAX_CONFIG_BYTES - 1);
        fmu_free(inst);
        return NULL;
    }
    inst->logger.logging_on = 1; /* refusals of the instantiation are always reported */
    if (start_values(inst) != FMU_OK) {
        fmu_free(inst);
        return NULL;
    }
    char expected[256];
    FMU_MODEL.token(data, fmi_version, has_config ? fmu_hash(inst->config, strlen(inst->config)) : 0ul, expected,
                    sizeof expected);
    if (token == NULL || strcmp(token, expected) != 0) {
        fmu_log(&early, FMU_ERROR, "logStatusError",
                "instantiation refused: token/GUID '%s' is not this FMU's '%s' (a different build or configuration of %s?)",
                token ? token : "(null)", expected, FMU_MODEL.name);
        fmu_free(inst);
        return NULL;
    }
    inst->logger.logging_on = logging_on;
    return inst;
}

void fmu_free(fmu_instance *inst)
{
    if (inst == NULL || inst->magic != FMU_MAGIC) {
        return;
    }
    inst->magic = 0;
    if (FMU_MODEL.release) FMU_MODEL.release(inst->data, &inst->memory);
    const fmu_allocator memory = inst->memory;
    memory.release(inst->data);
    memory.release(inst);
}

static const char *state_name(fmu_state state)
{
    switch (state) {
    case FMU_STATE_INSTANTIATED: return "Instantiated";
    case FMU_STATE_INITIALIZATION: return "InitializationMode";
    case FMU_STATE_STEP: return "StepMode";
    case FMU_STATE_TERMINATED: return "Terminated";
    case FMU_STATE_CONFIGURATION: return "ConfigurationMode";
    default: return "Error";
    }
}

fmu_status fmu_check(fmu_instance *inst, unsigned allowed_states, const char *function)
{
    if (inst == NULL || inst->magic != FMU_MAGIC) {
        return FMU_ERROR; /* nothing to log through */
    }
    if (!(inst->state & allowed_states)) {
        char detail[160];
        snprintf(detail, sizeof detail, "%s must not be called in state %s", function, state_name(inst->state));
        log_error(inst, "%s", detail);
        return FMU_ERROR;
    }
    return FMU_OK;
}

fmu_status fmu_unsupported(fmu_instance *inst, const char *function)
{
    if (inst != NULL && inst->magic == FMU_MAGIC) {
        log_error(inst, "%s is not supported by this FMU", function);
    }
    return FMU_ERROR;
}

fmu_status fmu_refuse(fmu_instance *inst, const char *format, ...)
{
    char message[512];
    va_list args;
    va_start(args, format);
    vsnprintf(message, sizeof message, format, args);
    va_end(args);
    if (inst != NULL && inst->magic == FMU_MAGIC) fmu_log(&inst->logger, FMU_ERROR, "logStatusError", "%s", message);
    return FMU_ERROR;
}

fmu_status fmu_set_debug_logging(fmu_instance *inst, int logging_on, size_t count, const char *const categories[])
{
    if (fmu_check(inst, ~0u, "SetDebugLogging") != FMU_OK) return FMU_ERROR;
    unsigned mask = 0;
    for (size_t i = 0; i < count; ++i) {
        const int index = categories && categories[i] ? category_index(categories[i]) : -1;
        if (index < 0) {
            log_error(inst, "SetDebugLogging: unknown category '%s'", categories && categories[i] ? categories[i] : "(null)");
            return FMU_ERROR;
        }
        mask |= 1u << index;
    }
    inst->logger.logging_on = logging_on;
    inst->logger.categories = count ? mask : ~0u;
    return FMU_OK;
}

fmu_status fmu_setup(fmu_instance *inst, double start_time, int has_stop_time, double stop_time)
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED, "SetupExperiment") != FMU_OK) return FMU_ERROR;
    if (!isfinite(start_time) || (has_stop_time && !(stop_time >= start_time))) {
        log_error(inst, "%s", "SetupExperiment: start time must be finite and not after the stop time");
        return FMU_ERROR;
    }
    inst->start_time = inst->time = start_time;
    inst->has_stop_time = has_stop_time;
    inst->stop_time = stop_time;
    return FMU_OK;
}

fmu_status fmu_enter_configuration(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED, "EnterConfigurationMode") != FMU_OK) return FMU_ERROR;
    inst->state = FMU_STATE_CONFIGURATION;
    return FMU_OK;
}

fmu_status fmu_exit_configuration(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_CONFIGURATION, "ExitConfigurationMode") != FMU_OK) return FMU_ERROR;
    /* The arrays are allocated once here, for the structural parameters now set. */
    if (FMU_MODEL.configure && FMU_MODEL.configure(inst->data, &inst->memory, &inst->logger) != FMU_OK) {
        return FMU_ERROR; /* stays in configuration mode: the structural parameters can be corrected */
    }
    inst->state = FMU_STATE_INSTANTIATED;
    return FMU_OK;
}

fmu_status fmu_enter_initialization(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED, "EnterInitializationMode") != FMU_OK) return FMU_ERROR;
    inst->state = FMU_STATE_INITIALIZATION;
    return FMU_OK;
}

fmu_status fmu_exit_initialization(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_INITIALIZATION, "ExitInitializationMode") != FMU_OK) return FMU_ERROR;
    const fmu_status st = FMU_MODEL.exit_initialization(inst->data, &inst->memory, &inst->logger);
    if (st == FMU_ERROR) {
        inst->state = FMU_STATE_ERROR;
        return FMU_ERROR;
    }
    inst->state = FMU_STATE_STEP;
    return st;
}

fmu_status fmu_do_step(fmu_instance *inst, double current_time, double step)
{
    if (fmu_check(inst, FMU_STATE_STEP, "DoStep") != FMU_OK) return FMU_ERROR;
    /* Communication points must follow each other: a master that skips or repeats one is wrong. */
    const double tolerance = 1e-9 * fmax(1.0, fabs(inst->time));
    if (!isfinite(current_time) || fabs(current_time - inst->time) > tolerance) {
        char detail[160];
        snprintf(detail, sizeof detail, "DoStep: currentCommunicationPoint %.17g is not the FMU's time %.17g",
                 current_time, inst->time);
        log_error(inst, "%s", detail);
        return FMU_ERROR;
    }
    if (!(step > 0) || !isfinite(step)) {
        log_error(inst, "%s", "DoStep: the communication step size must be finite and > 0");
        return FMU_ERROR;
    }
    const fmu_status st = FMU_MODEL.do_step(inst->data, inst->time, step, &inst->logger);
    if (st == FMU_ERROR) {
        return FMU_ERROR; /* the model refused the step and kept its state */
    }
    inst->time = current_time + step;
    return st;
}

fmu_status fmu_terminate(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_STEP | FMU_STATE_INITIALIZATION | FMU_STATE_ERROR, "Terminate") != FMU_OK) {
        return FMU_ERROR;
    }
    inst->state = FMU_STATE_TERMINATED;
    return FMU_OK;
}

fmu_status fmu_reset(fmu_instance *inst)
{
    if (fmu_check(inst, ~0u, "Reset") != FMU_OK) return FMU_ERROR;
    if (FMU_MODEL.release) FMU_MODEL.release(inst->data, &inst->memory);
    inst->time = inst->start_time = 0;
    inst->has_stop_time = 0;
    if (start_values(inst) != FMU_OK) { /* only when memory ran out: the arrays are gone */
        inst->state = FMU_STATE_ERROR;
        return FMU_ERROR;
    }
    inst->state = FMU_STATE_INSTANTIATED;
    return FMU_OK;
}

/* Whether a variable may be set now (FMI 2 table 4.2.4 / FMI 3 section 2.2.5, simplified to our kinds). */
static int settable(const fmu_instance *inst, const fmu_variable_group *v)
{
    switch (v->causality) {
    case FMU_OUTPUT: return 0;
    case FMU_STRUCTURAL: return inst->state == FMU_STATE_CONFIGURATION;
    case FMU_INPUT: return (inst->state & (FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP)) != 0;
    default:
        if (v->variability == FMU_FIXED) return (inst->state & (FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION)) != 0;
        return (inst->state & (FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP)) != 0;
    }
}

static const char *kind_name(fmu_value_kind kind)
{
    static const char *const names[] = {"Float64/Real", "Int32/Integer", "Boolean", "Boolean", "Int64 (enumeration)",
                                        "UInt64 (structural parameter)"};
    return names[kind];
}

/* The variable (group and first element, element count) of vr in this FMI version; -1 when none (logged). */
static int resolve(fmu_instance *inst, fmu_value_kind kind, unsigned vr, const char *function, int *group,
                   size_t *first, size_t *count)
{
    int found;
    if (inst->fmi_version == 2) {
        found = fmu_flat_find(&FMU_MODEL, inst->data, vr, group, first) == 0;
        *count = 1;
    } else {
        found = vr >= 1 && vr <= (unsigned)FMU_MODEL.num_groups;
        if (found) {
            *group = (int)vr - 1;
            *first = 0;
            *count = fmu_group_size(&FMU_MODEL, inst->data, *group);
        }
    }
    if (!found || fmu_kind_of(inst->fmi_version, FMU_MODEL.groups[*group].type) != kind) {
        log_error(inst, "%s: no %s variable has value reference %u", function, kind_name(kind), vr);
        return -1;
    }
    if (fmu_group_element(&FMU_MODEL, inst->data, *group, 0) == NULL && *count > 0) {
        log_error(inst, "%s: variable '%s' has no storage (the configuration failed)", function,
                  FMU_MODEL.groups[*group].name);
        return -1;
    }
    return 0;
}

/* One stored value (double or int) to and from the caller's kind. */
static void to_caller(fmu_value_kind kind, const void *stored, void *values, size_t i)
{
    int v = 0;
    if (kind != FMU_AS_DOUBLE) memcpy(&v, stored, sizeof v);
    switch (kind) {
    case FMU_AS_DOUBLE: memcpy((double *)values + i, stored, sizeof(double)); break;
    case FMU_AS_INT32: ((int32_t *)values)[i] = v; break;
    case FMU_AS_BOOL32: ((int *)values)[i] = v != 0; break;
    case FMU_AS_BOOL8: ((unsigned char *)values)[i] = v != 0; break;
    case FMU_AS_INT64: ((int64_t *)values)[i] = v; break;
    case FMU_AS_UINT64: ((uint64_t *)values)[i] = (uint64_t)(v > 0 ? v : 0); break;
    }
}

/* An Int64 or UInt64 value that int cannot hold, printed as the caller gave it (a UInt64 above
   2^31 is no "-1"): 1 and the text, or 0. */
static int beyond_int(fmu_value_kind kind, const void *values, size_t i, char *text, size_t size)
{
    if (kind == FMU_AS_INT64) {
        const int64_t x = ((const int64_t *)values)[i];
        if (x < INT32_MIN || x > INT32_MAX) return snprintf(text, size, "%lld", (long long)x), 1;
    } else if (kind == FMU_AS_UINT64) {
        const uint64_t x = ((const uint64_t *)values)[i];
        if (x > INT32_MAX) return snprintf(text, size, "%llu", (unsigned long long)x), 1;
    }
    return 0;
}

/* Integers outside int's range are stored as -1, which every range check refuses (fmu_set refuses
   them first, naming the value). */
static void from_caller(fmu_value_kind kind, const void *values, size_t i, void *stored)
{
    int v = 0;
    switch (kind) {
    case FMU_AS_DOUBLE: memcpy(stored, (const double *)values + i, sizeof(double)); return;
    case FMU_AS_INT32: v = ((const int32_t *)values)[i]; break;
    case FMU_AS_BOOL32: v = ((const int *)values)[i] != 0; break;
    case FMU_AS_BOOL8: v = ((const unsigned char *)values)[i] != 0; break;
    case FMU_AS_INT64: {
        const int64_t x = ((const int64_t *)values)[i];
        v = x >= INT32_MIN && x <= INT32_MAX ? (int)x : -1;
        break;
    }
    case FMU_AS_UINT64: {
        const uint64_t x = ((const uint64_t *)values)[i];
        v = x <= INT32_MAX ? (int)x : -1;
        break;
    }
    }
    memcpy(stored, &v, sizeof v);
}

static const unsigned ANY_LIVE = FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP |
                                 FMU_STATE_TERMINATED | FMU_STATE_ERROR | FMU_STATE_CONFIGURATION;

fmu_status fmu_get(fmu_instance *inst, fmu_value_kind kind, const unsigned vr[], size_t nvr, void *values,
                   size_t nvalues, const char *function)
{
    if (fmu_check(inst, ANY_LIVE, function) != FMU_OK) return FMU_ERROR;
    if (nvr > 0 && (vr == NULL || values == NULL)) {
        log_error(inst, "%s: NULL value reference or value array", function);
        return FMU_ERROR;
    }
    if (FMU_MODEL.update_outputs && inst->state != FMU_STATE_CONFIGURATION) FMU_MODEL.update_outputs(inst->data);
    size_t at = 0;
    for (size_t i = 0; i < nvr; ++i) {
        if (vr[i] == 0 && kind == FMU_AS_DOUBLE) { /* the time */
            if (at < nvalues) ((double *)values)[at] = inst->time;
            ++at;
            continue;
        }
        int g;
        size_t first, count;
        if (resolve(inst, kind, vr[i], function, &g, &first, &count) != 0) return FMU_ERROR;
        if (inst->state == FMU_STATE_CONFIGURATION && FMU_MODEL.groups[g].causality != FMU_STRUCTURAL) {
            log_error(inst, "%s: only structural parameters can be read in ConfigurationMode ('%s' is not one)",
                      function, FMU_MODEL.groups[g].name);
            return FMU_ERROR;
        }
        for (size_t e = 0; e < count; ++e, ++at) {
            if (at < nvalues) to_caller(kind, fmu_group_element(&FMU_MODEL, inst->data, g, first + e), values, at);
        }
    }
    if (at != nvalues) {
        log_error(inst, "%s: the variables have %zu values in all, not nValues = %zu", function, at, nvalues);
        return FMU_ERROR;
    }
    return FMU_OK;
}

fmu_status fmu_set(fmu_instance *inst, fmu_value_kind kind, const unsigned vr[], size_t nvr, const void *values,
                   size_t nvalues, const char *function)
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP | FMU_STATE_CONFIGURATION,
                  function) != FMU_OK) {
        return FMU_ERROR;
    }
    if (nvr > 0 && (vr == NULL || values == NULL)) {
        log_error(inst, "%s: NULL value reference or value array", function);
        return FMU_ERROR;
    }
    size_t total = 0;
    for (size_t i = 0; i < nvr; ++i) { /* all or nothing: check every reference first */
        int g;
        size_t first, count;
        if (resolve(inst, kind, vr[i], function, &g, &first, &count) != 0) return FMU_ERROR;
        const fmu_variable_group *v = &FMU_MODEL.groups[g];
        if (!settable(inst, v)) {
            log_error(inst, "%s: variable '%s' (%s) cannot be set in state %s", function, v->name,
                      v->causality == FMU_OUTPUT       ? "an output"
                      : v->causality == FMU_STRUCTURAL ? "a structural parameter: ConfigurationMode only"
                                                       : "a fixed parameter",
                      state_name(inst->state));
            return FMU_ERROR;
        }
        total += count;
    }
    if (total != nvalues) {
        log_error(inst, "%s: the variables have %zu values in all, not nValues = %zu", function, total, nvalues);
        return FMU_ERROR;
    }
    for (size_t i = 0, at = 0; i < nvr; ++i) {
        int g;
        size_t first, count;
        resolve(inst, kind, vr[i], function, &g, &first, &count);
        for (size_t e = 0; e < count; ++e, ++at) {
            char text[32];
            if (beyond_int(kind, values, at, text, sizeof text)) {
                log_error(inst, "%s: %s = %s is outside the integers this FMU stores (%d..%d)", function,
                          FMU_MODEL.groups[g].name, text, (int)INT32_MIN, (int)INT32_MAX);
                return FMU_ERROR;
            }
        }
    }
    size_t at = 0;
    for (size_t i = 0; i < nvr; ++i) {
        int g;
        size_t first, count;
        resolve(inst, kind, vr[i], function, &g, &first, &count);
        for (size_t e = 0; e < count; ++e, ++at) {
            from_caller(kind, values, at, fmu_group_element(&FMU_MODEL, inst->data, g, first + e));
        }
    }
    return FMU_OK;
}

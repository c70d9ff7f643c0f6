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

fmu_instance *fmu_instantiate(const char *name, const char *token, fmu_log_sink sink, void *env, int logging_on)
{
    fmu_logger early = {sink, env, name ? name : "?", 1, ~0u};
    if (name == NULL || name[0] == '\0') {
        fmu_log(&early, FMU_ERROR, "logStatusError", "instantiation refused: the instance name is empty");
        return NULL;
    }
    if (token == NULL || strcmp(token, FMU_MODEL.token) != 0) {
        fmu_log(&early, FMU_ERROR, "logStatusError",
                "instantiation refused: token/GUID '%s' is not this FMU's '%s' (a different build of %s?)",
                token ? token : "(null)", FMU_MODEL.token, FMU_MODEL.name);
        return NULL;
    }
    fmu_instance *inst = calloc(1, sizeof *inst);
    void *data = aligned_alloc(FMU_MODEL.data_align, (FMU_MODEL.data_bytes + FMU_MODEL.data_align - 1) /
                                                         FMU_MODEL.data_align * FMU_MODEL.data_align);
    if (inst == NULL || data == NULL) {
        free(inst);
        free(data);
        fmu_log(&early, FMU_ERROR, "logStatusError", "instantiation failed: out of memory");
        return NULL;
    }
    memset(data, 0, FMU_MODEL.data_bytes);
    inst->magic = FMU_MAGIC;
    snprintf(inst->name, sizeof inst->name, "%s", name);
    inst->logger = (fmu_logger){sink, env, inst->name, logging_on, ~0u};
    inst->data = data;
    inst->state = FMU_STATE_INSTANTIATED;
    FMU_MODEL.set_defaults(data);
    return inst;
}

void fmu_free(fmu_instance *inst)
{
    if (inst == NULL || inst->magic != FMU_MAGIC) {
        return;
    }
    inst->magic = 0;
    free(inst->data);
    free(inst);
}

static const char *state_name(fmu_state state)
{
    switch (state) {
    case FMU_STATE_INSTANTIATED: return "Instantiated";
    case FMU_STATE_INITIALIZATION: return "InitializationMode";
    case FMU_STATE_STEP: return "StepMode";
    case FMU_STATE_TERMINATED: return "Terminated";
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

fmu_status fmu_enter_initialization(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED, "EnterInitializationMode") != FMU_OK) return FMU_ERROR;
    inst->state = FMU_STATE_INITIALIZATION;
    return FMU_OK;
}

fmu_status fmu_exit_initialization(fmu_instance *inst)
{
    if (fmu_check(inst, FMU_STATE_INITIALIZATION, "ExitInitializationMode") != FMU_OK) return FMU_ERROR;
    const fmu_status st = FMU_MODEL.exit_initialization(inst->data, &inst->logger);
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
    memset(inst->data, 0, FMU_MODEL.data_bytes);
    FMU_MODEL.set_defaults(inst->data);
    inst->state = FMU_STATE_INSTANTIATED;
    inst->time = inst->start_time = 0;
    inst->has_stop_time = 0;
    return FMU_OK;
}

/* Variable vr (value references are 1-based table positions; 0 is the time). */
static int find(unsigned vr, fmu_variable *v)
{
    if (vr == 0) return -1;
    return fmu_variable_at(FMU_MODEL.groups, FMU_MODEL.num_groups, (int)vr - 1, v);
}

/* Whether a variable may be set now (FMI 2 table 4.2.4 / FMI 3 section 2.2.5, simplified to our kinds). */
static int settable(const fmu_instance *inst, const fmu_variable *v)
{
    if (v->causality == FMU_OUTPUT) return 0;
    if (v->causality == FMU_INPUT) return 1;
    if (v->variability == FMU_FIXED) return (inst->state & (FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION)) != 0;
    return 1; /* tunable parameter */
}

static int lookup(fmu_instance *inst, unsigned vr, fmu_type type, int for_set, const char *function, fmu_variable *v)
{
    char detail[200];
    if (find(vr, v) != 0 || v->type != type) {
        snprintf(detail, sizeof detail, "%s: no %s variable has value reference %u", function,
                 type == FMU_REAL ? "real" : "integer", vr);
        log_error(inst, "%s", detail);
        return -1;
    }
    if (for_set && !settable(inst, v)) {
        snprintf(detail, sizeof detail, "%s: variable '%s' (%s) cannot be set in state %s", function, v->name,
                 v->causality == FMU_OUTPUT ? "an output" : "a fixed parameter", state_name(inst->state));
        log_error(inst, "%s", detail);
        return -1;
    }
    return 0;
}

static const unsigned ANY_LIVE = FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP |
                                 FMU_STATE_TERMINATED | FMU_STATE_ERROR;

fmu_status fmu_get_real(fmu_instance *inst, const unsigned vr[], size_t count, double values[])
{
    if (fmu_check(inst, ANY_LIVE, "GetReal") != FMU_OK) return FMU_ERROR;
    if (count > 0 && (vr == NULL || values == NULL)) return fmu_unsupported(inst, "GetReal with NULL arrays");
    if (FMU_MODEL.update_outputs) FMU_MODEL.update_outputs(inst->data);
    fmu_variable v;
    for (size_t i = 0; i < count; ++i) {
        if (vr[i] == 0) {
            values[i] = inst->time;
            continue;
        }
        if (lookup(inst, vr[i], FMU_REAL, 0, "GetReal", &v) != 0) return FMU_ERROR;
        memcpy(&values[i], (const char *)inst->data + v.offset, sizeof(double));
    }
    return FMU_OK;
}

fmu_status fmu_set_real(fmu_instance *inst, const unsigned vr[], size_t count, const double values[])
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP, "SetReal") != FMU_OK) {
        return FMU_ERROR;
    }
    if (count > 0 && (vr == NULL || values == NULL)) return fmu_unsupported(inst, "SetReal with NULL arrays");
    fmu_variable v;
    for (size_t i = 0; i < count; ++i) { /* all or nothing: check every reference first */
        if (lookup(inst, vr[i], FMU_REAL, 1, "SetReal", &v) != 0) return FMU_ERROR;
    }
    for (size_t i = 0; i < count; ++i) {
        find(vr[i], &v);
        memcpy((char *)inst->data + v.offset, &values[i], sizeof(double));
    }
    return FMU_OK;
}

fmu_status fmu_get_integer(fmu_instance *inst, const unsigned vr[], size_t count, int values[])
{
    if (fmu_check(inst, ANY_LIVE, "GetInteger") != FMU_OK) return FMU_ERROR;
    if (count > 0 && (vr == NULL || values == NULL)) return fmu_unsupported(inst, "GetInteger with NULL arrays");
    fmu_variable v;
    for (size_t i = 0; i < count; ++i) {
        if (lookup(inst, vr[i], FMU_INTEGER, 0, "GetInteger", &v) != 0) return FMU_ERROR;
        memcpy(&values[i], (const char *)inst->data + v.offset, sizeof(int));
    }
    return FMU_OK;
}

fmu_status fmu_set_integer(fmu_instance *inst, const unsigned vr[], size_t count, const int values[])
{
    if (fmu_check(inst, FMU_STATE_INSTANTIATED | FMU_STATE_INITIALIZATION | FMU_STATE_STEP, "SetInteger") != FMU_OK) {
        return FMU_ERROR;
    }
    if (count > 0 && (vr == NULL || values == NULL)) return fmu_unsupported(inst, "SetInteger with NULL arrays");
    fmu_variable v;
    for (size_t i = 0; i < count; ++i) {
        if (lookup(inst, vr[i], FMU_INTEGER, 1, "SetInteger", &v) != 0) return FMU_ERROR;
    }
    for (size_t i = 0; i < count; ++i) {
        find(vr[i], &v);
        memcpy((char *)inst->data + v.offset, &values[i], sizeof(int));
    }
    return FMU_OK;
}

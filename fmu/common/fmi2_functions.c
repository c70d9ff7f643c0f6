/* SPDX-License-Identifier: Apache-2.0 */
/* The FMI 2.0 co-simulation API over fmu_instance.c (one source for every model). */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi2Functions.h"
#include "fmu_instance.h"

/*
 * FMI 2's logger takes a printf format plus variadic arguments. The finished message goes as the
 * format with every '%' doubled: a printf-style importer prints it literally, and importers that
 * cannot see variadic arguments (ctypes callbacks, as in fmpy) still get the text.
 */
static void fmi2_sink(void *env, const char *instance, fmu_status status, const char *category, const char *message)
{
    const fmi2CallbackFunctions *cb = env;
    if (cb == NULL || cb->logger == NULL) {
        return;
    }
    char escaped[1024];
    size_t n = 0;
    for (const char *p = message; *p && n + 2 < sizeof escaped; ++p) {
        if (*p == '%') escaped[n++] = '%';
        escaped[n++] = *p;
    }
    escaped[n] = '\0';
    cb->logger(cb->componentEnvironment, instance, (fmi2Status)status, category, escaped);
}

#define INST ((fmu_instance *)c)
#define RET(expr) return (fmi2Status)(expr)

/* The callbacks must outlive the instance: keep a copy next to it. */
typedef struct fmi2_wrapper {
    fmu_instance *inst;
    fmi2CallbackFunctions callbacks;
} fmi2_wrapper;

const char *fmi2GetTypesPlatform(void) { return fmi2TypesPlatform; }
const char *fmi2GetVersion(void) { return fmi2Version; }

fmi2Component fmi2Instantiate(fmi2String instanceName, fmi2Type fmuType, fmi2String fmuGUID,
                              fmi2String fmuResourceLocation, const fmi2CallbackFunctions *functions,
                              fmi2Boolean visible, fmi2Boolean loggingOn)
{
    (void)visible;
    static const fmi2CallbackFunctions none = {0};
    const fmi2CallbackFunctions *cb = functions ? functions : &none;
    if (fmuType != fmi2CoSimulation) {
        fmu_logger early = {fmi2_sink, (void *)cb, instanceName ? instanceName : "?", 1, ~0u};
        fmu_log(&early, FMU_ERROR, "logStatusError", "%s supports co-simulation only", FMU_MODEL.name);
        return NULL;
    }
    /* The importer's memory functions (FMI 2 requires them; the C library's if one passes none). */
    fmu_allocator memory = {calloc, free};
    if (cb->allocateMemory != NULL && cb->freeMemory != NULL) memory = (fmu_allocator){cb->allocateMemory, cb->freeMemory};
    fmu_instance *inst = fmu_instantiate(instanceName, fmuGUID, fmi2_sink, (void *)cb, loggingOn, 2,
                                         fmuResourceLocation, memory);
    if (inst == NULL) {
        return NULL;
    }
    /* The environment pointer must stay valid: store the callbacks inside the model-independent part. */
    _Static_assert(sizeof(fmi2CallbackFunctions) <= sizeof(((fmu_instance *)0)->callbacks_copy),
                  "room for the FMI 2 callbacks");
    memcpy(inst->callbacks_copy, cb, sizeof *cb);
    inst->logger.env = inst->callbacks_copy;
    return inst;
}

void fmi2FreeInstance(fmi2Component c) { fmu_free(INST); }

fmi2Status fmi2SetDebugLogging(fmi2Component c, fmi2Boolean loggingOn, size_t nCategories,
                               const fmi2String categories[])
{
    RET(fmu_set_debug_logging(INST, loggingOn, nCategories, categories));
}

fmi2Status fmi2SetupExperiment(fmi2Component c, fmi2Boolean toleranceDefined, fmi2Real tolerance,
                               fmi2Real startTime, fmi2Boolean stopTimeDefined, fmi2Real stopTime)
{
    (void)toleranceDefined;
    (void)tolerance;
    RET(fmu_setup(INST, startTime, stopTimeDefined, stopTime));
}

fmi2Status fmi2EnterInitializationMode(fmi2Component c) { RET(fmu_enter_initialization(INST)); }
fmi2Status fmi2ExitInitializationMode(fmi2Component c) { RET(fmu_exit_initialization(INST)); }
fmi2Status fmi2Terminate(fmi2Component c) { RET(fmu_terminate(INST)); }
fmi2Status fmi2Reset(fmi2Component c) { RET(fmu_reset(INST)); }

fmi2Status fmi2GetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Real value[])
{
    RET(fmu_get(INST, FMU_AS_DOUBLE, vr, nvr, value, nvr, "fmi2GetReal"));
}

fmi2Status fmi2GetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Integer value[])
{
    RET(fmu_get(INST, FMU_AS_INT32, vr, nvr, value, nvr, "fmi2GetInteger"));
}

fmi2Status fmi2GetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2Boolean value[])
{
    RET(fmu_get(INST, FMU_AS_BOOL32, vr, nvr, value, nvr, "fmi2GetBoolean"));
}

fmi2Status fmi2GetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, fmi2String value[])
{
    (void)vr;
    (void)value;
    RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi2GetString") : fmu_unsupported(INST, "fmi2GetString (no String variables)"));
}

fmi2Status fmi2SetReal(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Real value[])
{
    RET(fmu_set(INST, FMU_AS_DOUBLE, vr, nvr, value, nvr, "fmi2SetReal"));
}

fmi2Status fmi2SetInteger(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Integer value[])
{
    RET(fmu_set(INST, FMU_AS_INT32, vr, nvr, value, nvr, "fmi2SetInteger"));
}

fmi2Status fmi2SetBoolean(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2Boolean value[])
{
    RET(fmu_set(INST, FMU_AS_BOOL32, vr, nvr, value, nvr, "fmi2SetBoolean"));
}

fmi2Status fmi2SetString(fmi2Component c, const fmi2ValueReference vr[], size_t nvr, const fmi2String value[])
{
    (void)vr;
    (void)value;
    RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi2SetString") : fmu_unsupported(INST, "fmi2SetString (no String variables)"));
}

fmi2Status fmi2GetFMUstate(fmi2Component c, fmi2FMUstate *s) { RET(fmu_get_state(INST, s)); }
fmi2Status fmi2SetFMUstate(fmi2Component c, fmi2FMUstate s) { RET(fmu_set_state(INST, s)); }
fmi2Status fmi2FreeFMUstate(fmi2Component c, fmi2FMUstate *s) { RET(fmu_free_state(INST, s)); }

fmi2Status fmi2SerializedFMUstateSize(fmi2Component c, fmi2FMUstate s, size_t *size)
{
    RET(fmu_serialized_size(INST, s, size));
}

fmi2Status fmi2SerializeFMUstate(fmi2Component c, fmi2FMUstate s, fmi2Byte bytes[], size_t size)
{
    RET(fmu_serialize(INST, s, (unsigned char *)bytes, size));
}

fmi2Status fmi2DeSerializeFMUstate(fmi2Component c, const fmi2Byte bytes[], size_t size, fmi2FMUstate *s)
{
    RET(fmu_deserialize(INST, (const unsigned char *)bytes, size, s));
}

fmi2Status fmi2GetDirectionalDerivative(fmi2Component c, const fmi2ValueReference vUnknown[], size_t nUnknown,
                                        const fmi2ValueReference vKnown[], size_t nKnown, const fmi2Real dvKnown[],
                                        fmi2Real dvUnknown[])
{
    (void)vUnknown, (void)nUnknown, (void)vKnown, (void)nKnown, (void)dvKnown, (void)dvUnknown;
    RET(fmu_unsupported(INST, "fmi2GetDirectionalDerivative"));
}

fmi2Status fmi2SetRealInputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                       const fmi2Integer order[], const fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    RET(fmu_unsupported(INST, "fmi2SetRealInputDerivatives"));
}

fmi2Status fmi2GetRealOutputDerivatives(fmi2Component c, const fmi2ValueReference vr[], size_t nvr,
                                        const fmi2Integer order[], fmi2Real value[])
{
    (void)vr, (void)nvr, (void)order, (void)value;
    RET(fmu_unsupported(INST, "fmi2GetRealOutputDerivatives"));
}

fmi2Status fmi2DoStep(fmi2Component c, fmi2Real currentCommunicationPoint, fmi2Real communicationStepSize,
                      fmi2Boolean noSetFMUStatePriorToCurrentPoint)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    RET(fmu_do_step(INST, currentCommunicationPoint, communicationStepSize));
}

fmi2Status fmi2CancelStep(fmi2Component c) { RET(fmu_unsupported(INST, "fmi2CancelStep (steps never run asynchronously)")); }

fmi2Status fmi2GetStatus(fmi2Component c, const fmi2StatusKind s, fmi2Status *value)
{
    (void)s, (void)value;
    RET(fmu_unsupported(INST, "fmi2GetStatus"));
}

fmi2Status fmi2GetRealStatus(fmi2Component c, const fmi2StatusKind s, fmi2Real *value)
{
    if (fmu_check(INST, FMU_STATE_STEP | FMU_STATE_TERMINATED, "fmi2GetRealStatus") != FMU_OK || value == NULL) {
        return fmi2Error;
    }
    if (s != fmi2LastSuccessfulTime) RET(fmu_unsupported(INST, "fmi2GetRealStatus for this status kind"));
    *value = INST->time;
    return fmi2OK;
}

fmi2Status fmi2GetIntegerStatus(fmi2Component c, const fmi2StatusKind s, fmi2Integer *value)
{
    (void)s, (void)value;
    RET(fmu_unsupported(INST, "fmi2GetIntegerStatus"));
}

fmi2Status fmi2GetBooleanStatus(fmi2Component c, const fmi2StatusKind s, fmi2Boolean *value)
{
    (void)s, (void)value;
    RET(fmu_unsupported(INST, "fmi2GetBooleanStatus"));
}

fmi2Status fmi2GetStringStatus(fmi2Component c, const fmi2StatusKind s, fmi2String *value)
{
    (void)s, (void)value;
    RET(fmu_unsupported(INST, "fmi2GetStringStatus"));
}

/* Model-exchange functions: exported as the standard asks, refused (this FMU is co-simulation only). */
fmi2Status fmi2EnterEventMode(fmi2Component c) { RET(fmu_unsupported(INST, "fmi2EnterEventMode (co-simulation only)")); }

fmi2Status fmi2NewDiscreteStates(fmi2Component c, fmi2EventInfo *info)
{
    (void)info;
    RET(fmu_unsupported(INST, "fmi2NewDiscreteStates (co-simulation only)"));
}

fmi2Status fmi2EnterContinuousTimeMode(fmi2Component c)
{
    RET(fmu_unsupported(INST, "fmi2EnterContinuousTimeMode (co-simulation only)"));
}

fmi2Status fmi2CompletedIntegratorStep(fmi2Component c, fmi2Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi2Boolean *enterEventMode, fmi2Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint, (void)enterEventMode, (void)terminateSimulation;
    RET(fmu_unsupported(INST, "fmi2CompletedIntegratorStep (co-simulation only)"));
}

fmi2Status fmi2SetTime(fmi2Component c, fmi2Real time)
{
    (void)time;
    RET(fmu_unsupported(INST, "fmi2SetTime (co-simulation only)"));
}

fmi2Status fmi2SetContinuousStates(fmi2Component c, const fmi2Real x[], size_t nx)
{
    (void)x, (void)nx;
    RET(fmu_unsupported(INST, "fmi2SetContinuousStates (co-simulation only)"));
}

fmi2Status fmi2GetDerivatives(fmi2Component c, fmi2Real derivatives[], size_t nx)
{
    (void)derivatives, (void)nx;
    RET(fmu_unsupported(INST, "fmi2GetDerivatives (co-simulation only)"));
}

fmi2Status fmi2GetEventIndicators(fmi2Component c, fmi2Real eventIndicators[], size_t ni)
{
    (void)eventIndicators, (void)ni;
    RET(fmu_unsupported(INST, "fmi2GetEventIndicators (co-simulation only)"));
}

fmi2Status fmi2GetContinuousStates(fmi2Component c, fmi2Real x[], size_t nx)
{
    (void)x, (void)nx;
    RET(fmu_unsupported(INST, "fmi2GetContinuousStates (co-simulation only)"));
}

fmi2Status fmi2GetNominalsOfContinuousStates(fmi2Component c, fmi2Real x_nominal[], size_t nx)
{
    (void)x_nominal, (void)nx;
    RET(fmu_unsupported(INST, "fmi2GetNominalsOfContinuousStates (co-simulation only)"));
}

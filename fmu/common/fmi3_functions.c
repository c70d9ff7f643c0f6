/* SPDX-License-Identifier: Apache-2.0 */
/* The FMI 3.0 co-simulation API over fmu_instance.c (one source for every model). */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "fmu_instance.h"

typedef struct fmi3_env {
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} fmi3_env;

static void fmi3_sink(void *env, const char *instance, fmu_status status, const char *category, const char *message)
{
    (void)instance;
    const fmi3_env *e = env;
    if (e != NULL && e->log != NULL) {
        e->log(e->env, (fmi3Status)status, category, message);
    }
}

#define INST ((fmu_instance *)instance)
#define RET(expr) return (fmi3Status)(expr)

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[])
{
    RET(fmu_set_debug_logging(INST, loggingOn, nCategories, categories));
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                          fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage)
{
    (void)instanceName, (void)instantiationToken, (void)resourcePath, (void)visible, (void)loggingOn;
    if (logMessage) logMessage(instanceEnvironment, fmi3Error, "logStatusError", "this FMU supports co-simulation only");
    return NULL;
}

fmi3Instance fmi3InstantiateCoSimulation(fmi3String instanceName, fmi3String instantiationToken,
                                         fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                         fmi3Boolean eventModeUsed, fmi3Boolean earlyReturnAllowed,
                                         const fmi3ValueReference requiredIntermediateVariables[],
                                         size_t nRequiredIntermediateVariables,
                                         fmi3InstanceEnvironment instanceEnvironment, fmi3LogMessageCallback logMessage,
                                         fmi3IntermediateUpdateCallback intermediateUpdate)
{
    (void)visible, (void)earlyReturnAllowed, (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables, (void)intermediateUpdate;
    fmi3_env early = {instanceEnvironment, logMessage};
    if (eventModeUsed) {
        fmi3_sink(&early, instanceName, FMU_ERROR, "logStatusError", "event mode is not supported by this FMU");
        return NULL;
    }
    /* FMI 3 passes no memory functions: the C library's. */
    fmu_instance *inst = fmu_instantiate(instanceName, instantiationToken, fmi3_sink, &early, loggingOn, 3,
                                         resourcePath, (fmu_allocator){calloc, free});
    if (inst == NULL) {
        return NULL;
    }
    _Static_assert(sizeof(fmi3_env) <= sizeof(((fmu_instance *)0)->callbacks_copy), "room for the FMI 3 callbacks");
    memcpy(inst->callbacks_copy, &early, sizeof early);
    inst->logger.env = inst->callbacks_copy;
    return inst;
}

fmi3Instance fmi3InstantiateScheduledExecution(fmi3String instanceName, fmi3String instantiationToken,
                                               fmi3String resourcePath, fmi3Boolean visible, fmi3Boolean loggingOn,
                                               fmi3InstanceEnvironment instanceEnvironment,
                                               fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
                                               fmi3LockPreemptionCallback lockPreemption,
                                               fmi3UnlockPreemptionCallback unlockPreemption)
{
    (void)instanceName, (void)instantiationToken, (void)resourcePath, (void)visible, (void)loggingOn;
    (void)clockUpdate, (void)lockPreemption, (void)unlockPreemption;
    if (logMessage) logMessage(instanceEnvironment, fmi3Error, "logStatusError", "this FMU supports co-simulation only");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) { fmu_free(INST); }

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined, fmi3Float64 tolerance,
                                       fmi3Float64 startTime, fmi3Boolean stopTimeDefined, fmi3Float64 stopTime)
{
    (void)toleranceDefined, (void)tolerance;
    if (fmu_setup(INST, startTime, stopTimeDefined, stopTime) != FMU_OK) return fmi3Error;
    RET(fmu_enter_initialization(INST));
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) { RET(fmu_exit_initialization(INST)); }
fmi3Status fmi3Terminate(fmi3Instance instance) { RET(fmu_terminate(INST)); }
fmi3Status fmi3Reset(fmi3Instance instance) { RET(fmu_reset(INST)); }

#define ACCESS(Name, Type, kind)                                                                              \
    fmi3Status fmi3Get##Name(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, Type values[],   \
                             size_t nValues)                                                                     \
    {                                                                                                            \
        RET(fmu_get(INST, kind, vr, nvr, values, nValues, "fmi3Get" #Name));                                     \
    }                                                                                                            \
    fmi3Status fmi3Set##Name(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const Type values[], \
                             size_t nValues)                                                                     \
    {                                                                                                            \
        RET(fmu_set(INST, kind, vr, nvr, values, nValues, "fmi3Set" #Name));                                     \
    }

_Static_assert(sizeof(fmi3Boolean) == 1, "fmi3Boolean is a one-byte bool");
ACCESS(Float64, fmi3Float64, FMU_AS_DOUBLE)
ACCESS(Int32, fmi3Int32, FMU_AS_INT32)
ACCESS(Int64, fmi3Int64, FMU_AS_INT64)
ACCESS(UInt64, fmi3UInt64, FMU_AS_UINT64)
ACCESS(Boolean, fmi3Boolean, FMU_AS_BOOL8)

/* Types this FMU has no variables of: an empty call is fine, anything else is an error. */
#define NO_VARIABLES_GET(Name, Type)                                                                           \
    fmi3Status fmi3Get##Name(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, Type values[], \
                             size_t nValues)                                                                   \
    {                                                                                                          \
        (void)vr, (void)values, (void)nValues;                                                                 \
        RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi3Get" #Name) : fmu_unsupported(INST, "fmi3Get" #Name " (no such variables)")); \
    }
#define NO_VARIABLES_SET(Name, Type)                                                                                 \
    fmi3Status fmi3Set##Name(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const Type values[], \
                             size_t nValues)                                                                         \
    {                                                                                                                \
        (void)vr, (void)values, (void)nValues;                                                                       \
        RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi3Set" #Name) : fmu_unsupported(INST, "fmi3Set" #Name " (no such variables)")); \
    }
#define NO_VARIABLES(Name, Type) NO_VARIABLES_GET(Name, Type) NO_VARIABLES_SET(Name, Type)

NO_VARIABLES(Float32, fmi3Float32)
NO_VARIABLES(Int8, fmi3Int8)
NO_VARIABLES(UInt8, fmi3UInt8)
NO_VARIABLES(Int16, fmi3Int16)
NO_VARIABLES(UInt16, fmi3UInt16)
NO_VARIABLES(UInt32, fmi3UInt32)
NO_VARIABLES(String, fmi3String)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, size_t valueSizes[],
                         fmi3Binary values[], size_t nValues)
{
    (void)vr, (void)valueSizes, (void)values, (void)nValues;
    RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi3GetBinary") : fmu_unsupported(INST, "fmi3GetBinary (no such variables)"));
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const size_t valueSizes[],
                         const fmi3Binary values[], size_t nValues)
{
    (void)vr, (void)valueSizes, (void)values, (void)nValues;
    RET(nvr == 0 ? fmu_check(INST, ~0u, "fmi3SetBinary") : fmu_unsupported(INST, "fmi3SetBinary (no such variables)"));
}

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Clock values[])
{
    (void)vr, (void)nvr, (void)values;
    RET(fmu_unsupported(INST, "fmi3GetClock"));
}

fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, const fmi3Clock values[])
{
    (void)vr, (void)nvr, (void)values;
    RET(fmu_unsupported(INST, "fmi3SetClock"));
}

fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference vr, size_t *n)
{
    (void)vr, (void)n;
    RET(fmu_unsupported(INST, "fmi3GetNumberOfVariableDependencies"));
}

fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent, size_t elementIndices[],
                                       fmi3ValueReference independents[], size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[], size_t nDependencies)
{
    (void)dependent, (void)elementIndices, (void)independents, (void)elementIndicesOfIndependents;
    (void)dependencyKinds, (void)nDependencies;
    RET(fmu_unsupported(INST, "fmi3GetVariableDependencies"));
}

fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *s) { RET(fmu_get_state(INST, s)); }
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState s) { RET(fmu_set_state(INST, s)); }
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *s) { RET(fmu_free_state(INST, s)); }

fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState s, size_t *size)
{
    RET(fmu_serialized_size(INST, s, size));
}

fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState s, fmi3Byte bytes[], size_t size)
{
    RET(fmu_serialize(INST, s, bytes, size));
}

fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte bytes[], size_t size, fmi3FMUState *s)
{
    RET(fmu_deserialize(INST, bytes, size, s));
}

fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                        const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                        size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed, (void)sensitivity;
    (void)nSensitivity;
    RET(fmu_unsupported(INST, "fmi3GetDirectionalDerivative"));
}

fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference unknowns[], size_t nUnknowns,
                                    const fmi3ValueReference knowns[], size_t nKnowns, const fmi3Float64 seed[],
                                    size_t nSeed, fmi3Float64 sensitivity[], size_t nSensitivity)
{
    (void)unknowns, (void)nUnknowns, (void)knowns, (void)nKnowns, (void)seed, (void)nSeed, (void)sensitivity;
    (void)nSensitivity;
    RET(fmu_unsupported(INST, "fmi3GetAdjointDerivative"));
}

fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) { RET(fmu_enter_configuration(INST)); }
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) { RET(fmu_exit_configuration(INST)); }

fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr, (void)nvr, (void)intervals, (void)qualifiers;
    RET(fmu_unsupported(INST, "fmi3GetIntervalDecimal"));
}

fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   fmi3UInt64 counters[], fmi3UInt64 resolutions[], fmi3IntervalQualifier qualifiers[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions, (void)qualifiers;
    RET(fmu_unsupported(INST, "fmi3GetIntervalFraction"));
}

fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr, fmi3Float64 shifts[])
{
    (void)vr, (void)nvr, (void)shifts;
    RET(fmu_unsupported(INST, "fmi3GetShiftDecimal"));
}

fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                fmi3UInt64 counters[], fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    RET(fmu_unsupported(INST, "fmi3GetShiftFraction"));
}

fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                  const fmi3Float64 intervals[])
{
    (void)vr, (void)nvr, (void)intervals;
    RET(fmu_unsupported(INST, "fmi3SetIntervalDecimal"));
}

fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                   const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    RET(fmu_unsupported(INST, "fmi3SetIntervalFraction"));
}

fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                               const fmi3Float64 shifts[])
{
    (void)vr, (void)nvr, (void)shifts;
    RET(fmu_unsupported(INST, "fmi3SetShiftDecimal"));
}

fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                const fmi3UInt64 counters[], const fmi3UInt64 resolutions[])
{
    (void)vr, (void)nvr, (void)counters, (void)resolutions;
    RET(fmu_unsupported(INST, "fmi3SetShiftFraction"));
}

fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) { RET(fmu_unsupported(INST, "fmi3EvaluateDiscreteStates")); }

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation, fmi3Boolean *nominalsChanged,
                                    fmi3Boolean *valuesChanged, fmi3Boolean *nextEventTimeDefined,
                                    fmi3Float64 *nextEventTime)
{
    (void)discreteStatesNeedUpdate, (void)terminateSimulation, (void)nominalsChanged, (void)valuesChanged;
    (void)nextEventTimeDefined, (void)nextEventTime;
    RET(fmu_unsupported(INST, "fmi3UpdateDiscreteStates"));
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) { RET(fmu_unsupported(INST, "fmi3EnterEventMode")); }
fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) { RET(fmu_unsupported(INST, "fmi3EnterContinuousTimeMode")); }

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance, fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode, fmi3Boolean *terminateSimulation)
{
    (void)noSetFMUStatePriorToCurrentPoint, (void)enterEventMode, (void)terminateSimulation;
    RET(fmu_unsupported(INST, "fmi3CompletedIntegratorStep"));
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time)
{
    (void)time;
    RET(fmu_unsupported(INST, "fmi3SetTime"));
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 states[], size_t n)
{
    (void)states, (void)n;
    RET(fmu_unsupported(INST, "fmi3SetContinuousStates"));
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 derivatives[], size_t n)
{
    (void)derivatives, (void)n;
    RET(fmu_unsupported(INST, "fmi3GetContinuousStateDerivatives"));
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 indicators[], size_t n)
{
    (void)indicators, (void)n;
    RET(fmu_unsupported(INST, "fmi3GetEventIndicators"));
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 states[], size_t n)
{
    (void)states, (void)n;
    RET(fmu_unsupported(INST, "fmi3GetContinuousStates"));
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[], size_t n)
{
    (void)nominals, (void)n;
    RET(fmu_unsupported(INST, "fmi3GetNominalsOfContinuousStates"));
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n)
{
    (void)n;
    RET(fmu_unsupported(INST, "fmi3GetNumberOfEventIndicators"));
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n)
{
    (void)n;
    RET(fmu_unsupported(INST, "fmi3GetNumberOfContinuousStates"));
}

fmi3Status fmi3EnterStepMode(fmi3Instance instance) { RET(fmu_unsupported(INST, "fmi3EnterStepMode (no event mode)")); }

fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                                    const fmi3Int32 orders[], fmi3Float64 values[], size_t nValues)
{
    (void)vr, (void)nvr, (void)orders, (void)values, (void)nValues;
    RET(fmu_unsupported(INST, "fmi3GetOutputDerivatives"));
}

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint, fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint, fmi3Boolean *eventHandlingNeeded,
                      fmi3Boolean *terminateSimulation, fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime)
{
    (void)noSetFMUStatePriorToCurrentPoint;
    const fmu_status st = fmu_do_step(INST, currentCommunicationPoint, communicationStepSize);
    if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
    if (terminateSimulation) *terminateSimulation = fmi3False;
    if (earlyReturn) *earlyReturn = fmi3False;
    if (lastSuccessfulTime && st != FMU_ERROR) *lastSuccessfulTime = INST->time;
    RET(st);
}

fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clockReference,
                                      fmi3Float64 activationTime)
{
    (void)clockReference, (void)activationTime;
    RET(fmu_unsupported(INST, "fmi3ActivateModelPartition"));
}

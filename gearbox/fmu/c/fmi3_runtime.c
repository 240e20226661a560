/* fmi3_runtime.c: FMI 3.0 (Model Exchange and Co-Simulation) for the gearbox FMUs.
 *
 * A thin layer over the FMI 2.0 runtime (fmi2_runtime.c compiled with GBX_FMI3, so
 * that its functions are the internal gbx_fmi2<name>): the same state machine,
 * checks, messages and integrator. FMI 3.0 specifics handled here: the log callback
 * without varargs (messages are formatted before they are passed on), the resource
 * path given as a path, the independent variable "time" (value reference GBX_NR),
 * array-shaped get/set calls (scalars only here), fmi3DoStep's extra results.
 * Not supported (fmi3Error with a message): event mode in Co-Simulation, early
 * return, Scheduled Execution, clocks, FMU state, directional derivatives.
 */
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "fmi3Functions.h"
#include "gbx_model.h"

#define VR_TIME GBX_NR

/* the FMI 2.0 layer, internal names */
fmi2SetDebugLoggingTYPE gbx_fmi2SetDebugLogging;
fmi2InstantiateTYPE gbx_fmi2Instantiate;
fmi2FreeInstanceTYPE gbx_fmi2FreeInstance;
fmi2SetupExperimentTYPE gbx_fmi2SetupExperiment;
fmi2EnterInitializationModeTYPE gbx_fmi2EnterInitializationMode;
fmi2ExitInitializationModeTYPE gbx_fmi2ExitInitializationMode;
fmi2TerminateTYPE gbx_fmi2Terminate;
fmi2ResetTYPE gbx_fmi2Reset;
fmi2GetRealTYPE gbx_fmi2GetReal;
fmi2SetRealTYPE gbx_fmi2SetReal;
fmi2EnterEventModeTYPE gbx_fmi2EnterEventMode;
fmi2NewDiscreteStatesTYPE gbx_fmi2NewDiscreteStates;
fmi2EnterContinuousTimeModeTYPE gbx_fmi2EnterContinuousTimeMode;
fmi2CompletedIntegratorStepTYPE gbx_fmi2CompletedIntegratorStep;
fmi2SetTimeTYPE gbx_fmi2SetTime;
fmi2SetContinuousStatesTYPE gbx_fmi2SetContinuousStates;
fmi2GetDerivativesTYPE gbx_fmi2GetDerivatives;
fmi2GetContinuousStatesTYPE gbx_fmi2GetContinuousStates;
fmi2GetNominalsOfContinuousStatesTYPE gbx_fmi2GetNominalsOfContinuousStates;
fmi2DoStepTYPE gbx_fmi2DoStep;

typedef struct {
    fmi3InstanceEnvironment env;
    fmi3LogMessageCallback log;
} Env3;

static fmi3Status status3(fmi2Status s) {
    switch (s) {
    case fmi2OK:
        return fmi3OK;
    case fmi2Warning:
        return fmi3Warning;
    case fmi2Discard:
        return fmi3Discard;
    case fmi2Error:
        return fmi3Error;
    default:
        return fmi3Fatal;
    }
}

/* fmi2 logger (varargs) -> fmi3 logMessage (formatted string) */
static void log2to3(fmi2ComponentEnvironment env, fmi2String name, fmi2Status status,
                    fmi2String category, fmi2String message, ...) {
    Env3 *e = (Env3 *)env;
    char buf[2048];
    va_list ap;
    (void)name;
    if (!e || !e->log) return;
    va_start(ap, message);
    vsnprintf(buf, sizeof buf, message, ap);
    va_end(ap);
    e->log(e->env, status3(status), category, buf);
}

static void *calloc2(size_t n, size_t size) { return calloc(n, size); }
static void free2(void *p) { free(p); }

static void log3(ModelInstance *m, const char *message) {
    gbx_log(m, fmi2Error, "logStatusError", "%s", message);
}

static fmi3Instance instantiate(fmi3String name, fmi3String token, fmi3String resources,
                                fmi3Boolean loggingOn, fmi3InstanceEnvironment env,
                                fmi3LogMessageCallback log, fmi2Type type) {
    fmi2CallbackFunctions cb;
    Env3 *e = (Env3 *)calloc(1, sizeof(Env3));
    char *uri;
    fmi2Component c;
    size_t n;
    if (!e) return NULL;
    e->env = env;
    e->log = log;
    cb.logger = log2to3;
    cb.allocateMemory = calloc2;
    cb.freeMemory = free2;
    cb.stepFinished = NULL;
    cb.componentEnvironment = e;
    n = resources ? strlen(resources) : 0;
    uri = (char *)calloc(n + 8, 1);
    if (!uri) {
        free(e);
        return NULL;
    }
    if (resources && resources[0] == '/') snprintf(uri, n + 8, "file://%s", resources);
    c = gbx_fmi2Instantiate(name, type, token, resources && resources[0] == '/' ? uri : resources,
                            &cb, fmi2False, loggingOn);
    free(uri);
    if (!c) free(e);
    return c;
}

/* ------------------------------------------------------------------ common */

const char *fmi3GetVersion(void) { return fmi3Version; }

fmi3Status fmi3SetDebugLogging(fmi3Instance instance, fmi3Boolean loggingOn, size_t nCategories,
                               const fmi3String categories[]) {
    return status3(gbx_fmi2SetDebugLogging(instance, loggingOn, nCategories, categories));
}

fmi3Instance fmi3InstantiateModelExchange(fmi3String instanceName, fmi3String instantiationToken,
                                          fmi3String resourcePath, fmi3Boolean visible,
                                          fmi3Boolean loggingOn, fmi3InstanceEnvironment env,
                                          fmi3LogMessageCallback logMessage) {
    (void)visible;
    return instantiate(instanceName, instantiationToken, resourcePath, loggingOn, env, logMessage,
                       fmi2ModelExchange);
}

fmi3Instance fmi3InstantiateCoSimulation(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3Boolean eventModeUsed,
    fmi3Boolean earlyReturnAllowed, const fmi3ValueReference requiredIntermediateVariables[],
    size_t nRequiredIntermediateVariables, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback logMessage, fmi3IntermediateUpdateCallback intermediateUpdate) {
    (void)visible;
    (void)earlyReturnAllowed;
    (void)requiredIntermediateVariables;
    (void)nRequiredIntermediateVariables;
    (void)intermediateUpdate;
    if (eventModeUsed) {
        if (logMessage)
            logMessage(env, fmi3Error, "logStatusError",
                       "fmi3InstantiateCoSimulation: eventModeUsed is not supported (no events)");
        return NULL;
    }
    return instantiate(instanceName, instantiationToken, resourcePath, loggingOn, env, logMessage,
                       fmi2CoSimulation);
}

fmi3Instance fmi3InstantiateScheduledExecution(
    fmi3String instanceName, fmi3String instantiationToken, fmi3String resourcePath,
    fmi3Boolean visible, fmi3Boolean loggingOn, fmi3InstanceEnvironment env,
    fmi3LogMessageCallback logMessage, fmi3ClockUpdateCallback clockUpdate,
    fmi3LockPreemptionCallback lockPreemption, fmi3UnlockPreemptionCallback unlockPreemption) {
    (void)instanceName;
    (void)instantiationToken;
    (void)resourcePath;
    (void)visible;
    (void)loggingOn;
    (void)clockUpdate;
    (void)lockPreemption;
    (void)unlockPreemption;
    if (logMessage)
        logMessage(env, fmi3Error, "logStatusError", "Scheduled Execution is not supported");
    return NULL;
}

void fmi3FreeInstance(fmi3Instance instance) {
    ModelInstance *m = (ModelInstance *)instance;
    Env3 *e;
    if (!m) return;
    e = (Env3 *)m->cb.componentEnvironment;
    gbx_fmi2FreeInstance(instance);
    free(e);
}

fmi3Status fmi3EnterInitializationMode(fmi3Instance instance, fmi3Boolean toleranceDefined,
                                       fmi3Float64 tolerance, fmi3Float64 startTime,
                                       fmi3Boolean stopTimeDefined, fmi3Float64 stopTime) {
    fmi2Status s = gbx_fmi2SetupExperiment(instance, toleranceDefined, tolerance, startTime,
                                           stopTimeDefined, stopTime);
    if (s != fmi2OK) return status3(s);
    return status3(gbx_fmi2EnterInitializationMode(instance));
}

fmi3Status fmi3ExitInitializationMode(fmi3Instance instance) {
    return status3(gbx_fmi2ExitInitializationMode(instance));
}

fmi3Status fmi3EnterEventMode(fmi3Instance instance) {
    return status3(gbx_fmi2EnterEventMode(instance));
}

fmi3Status fmi3Terminate(fmi3Instance instance) { return status3(gbx_fmi2Terminate(instance)); }

fmi3Status fmi3Reset(fmi3Instance instance) { return status3(gbx_fmi2Reset(instance)); }

/* ------------------------------------------------------------ get / set */

fmi3Status fmi3GetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          fmi3Float64 values[], size_t nValues) {
    ModelInstance *m = (ModelInstance *)instance;
    size_t i;
    if (!m) return fmi3Error;
    if (nValues != nvr) {
        log3(m, "fmi3GetFloat64: nValues must equal nValueReferences (scalar variables)");
        return fmi3Error;
    }
    for (i = 0; i < nvr; i++) {
        fmi2Status s;
        if (vr[i] == VR_TIME) {
            values[i] = m->time;
            continue;
        }
        s = gbx_fmi2GetReal(instance, &vr[i], 1, &values[i]);
        if (s != fmi2OK) return status3(s);
    }
    return fmi3OK;
}

fmi3Status fmi3SetFloat64(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                          const fmi3Float64 values[], size_t nValues) {
    ModelInstance *m = (ModelInstance *)instance;
    size_t i;
    if (!m) return fmi3Error;
    if (nValues != nvr) {
        log3(m, "fmi3SetFloat64: nValues must equal nValueReferences (scalar variables)");
        return fmi3Error;
    }
    for (i = 0; i < nvr; i++) {
        if (vr[i] == VR_TIME) {
            log3(m, "fmi3SetFloat64: time is the independent variable and cannot be set");
            return fmi3Error;
        }
    }
    return status3(gbx_fmi2SetReal(instance, vr, nvr, values));
}

#define NO_VARIABLES3(kind, ctype)                                                                  \
    fmi3Status fmi3Get##kind(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,     \
                             ctype values[], size_t nValues) {                                      \
        (void)vr;                                                                                   \
        (void)values;                                                                               \
        (void)nValues;                                                                              \
        if (nvr == 0) return fmi3OK;                                                                \
        log3((ModelInstance *)instance, "fmi3Get" #kind ": the model has no such variables"); \
        return fmi3Error;                                                                           \
    }                                                                                               \
    fmi3Status fmi3Set##kind(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,     \
                             const ctype values[], size_t nValues) {                                \
        (void)vr;                                                                                   \
        (void)values;                                                                               \
        (void)nValues;                                                                              \
        if (nvr == 0) return fmi3OK;                                                                \
        log3((ModelInstance *)instance, "fmi3Set" #kind ": the model has no such variables"); \
        return fmi3Error;                                                                           \
    }

NO_VARIABLES3(Float32, fmi3Float32)
NO_VARIABLES3(Int8, fmi3Int8)
NO_VARIABLES3(UInt8, fmi3UInt8)
NO_VARIABLES3(Int16, fmi3Int16)
NO_VARIABLES3(UInt16, fmi3UInt16)
NO_VARIABLES3(Int32, fmi3Int32)
NO_VARIABLES3(UInt32, fmi3UInt32)
NO_VARIABLES3(Int64, fmi3Int64)
NO_VARIABLES3(UInt64, fmi3UInt64)
NO_VARIABLES3(Boolean, fmi3Boolean)
NO_VARIABLES3(String, fmi3String)

fmi3Status fmi3GetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         size_t valueSizes[], fmi3Binary values[], size_t nValues) {
    (void)vr;
    (void)valueSizes;
    (void)values;
    (void)nValues;
    if (nvr == 0) return fmi3OK;
    log3((ModelInstance *)instance, "fmi3GetBinary: the model has no such variables");
    return fmi3Error;
}

fmi3Status fmi3SetBinary(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                         const size_t valueSizes[], const fmi3Binary values[], size_t nValues) {
    (void)vr;
    (void)valueSizes;
    (void)values;
    (void)nValues;
    if (nvr == 0) return fmi3OK;
    log3((ModelInstance *)instance, "fmi3SetBinary: the model has no such variables");
    return fmi3Error;
}

/* ------------------------------------------------------------ unsupported */

#define UNSUPPORTED3(fn)                                                                           \
    {                                                                                              \
        if (instance) log3((ModelInstance *)instance, fn " is not supported by this FMU");   \
        return fmi3Error;                                                                          \
    }

fmi3Status fmi3GetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        fmi3Clock values[]) {
    (void)vr;
    (void)nvr;
    (void)values;
    UNSUPPORTED3("fmi3GetClock")
}
fmi3Status fmi3SetClock(fmi3Instance instance, const fmi3ValueReference vr[], size_t nvr,
                        const fmi3Clock values[]) {
    (void)vr;
    (void)nvr;
    (void)values;
    UNSUPPORTED3("fmi3SetClock")
}
fmi3Status fmi3GetNumberOfVariableDependencies(fmi3Instance instance, fmi3ValueReference vr,
                                               size_t *n) {
    (void)vr;
    (void)n;
    UNSUPPORTED3("fmi3GetNumberOfVariableDependencies")
}
fmi3Status fmi3GetVariableDependencies(fmi3Instance instance, fmi3ValueReference dependent,
                                       size_t elementIndicesOfDependent[],
                                       fmi3ValueReference independents[],
                                       size_t elementIndicesOfIndependents[],
                                       fmi3DependencyKind dependencyKinds[], size_t n) {
    (void)dependent;
    (void)elementIndicesOfDependent;
    (void)independents;
    (void)elementIndicesOfIndependents;
    (void)dependencyKinds;
    (void)n;
    UNSUPPORTED3("fmi3GetVariableDependencies")
}
fmi3Status fmi3GetFMUState(fmi3Instance instance, fmi3FMUState *s) {
    (void)s;
    UNSUPPORTED3("fmi3GetFMUState")
}
fmi3Status fmi3SetFMUState(fmi3Instance instance, fmi3FMUState s) {
    (void)s;
    UNSUPPORTED3("fmi3SetFMUState")
}
fmi3Status fmi3FreeFMUState(fmi3Instance instance, fmi3FMUState *s) {
    (void)s;
    UNSUPPORTED3("fmi3FreeFMUState")
}
fmi3Status fmi3SerializedFMUStateSize(fmi3Instance instance, fmi3FMUState s, size_t *size) {
    (void)s;
    (void)size;
    UNSUPPORTED3("fmi3SerializedFMUStateSize")
}
fmi3Status fmi3SerializeFMUState(fmi3Instance instance, fmi3FMUState s, fmi3Byte b[], size_t n) {
    (void)s;
    (void)b;
    (void)n;
    UNSUPPORTED3("fmi3SerializeFMUState")
}
fmi3Status fmi3DeserializeFMUState(fmi3Instance instance, const fmi3Byte b[], size_t n,
                                   fmi3FMUState *s) {
    (void)s;
    (void)b;
    (void)n;
    UNSUPPORTED3("fmi3DeserializeFMUState")
}
fmi3Status fmi3GetDirectionalDerivative(fmi3Instance instance, const fmi3ValueReference u[],
                                        size_t nu, const fmi3ValueReference k[], size_t nk,
                                        const fmi3Float64 seed[], size_t ns,
                                        fmi3Float64 sens[], size_t nsens) {
    (void)u;
    (void)nu;
    (void)k;
    (void)nk;
    (void)seed;
    (void)ns;
    (void)sens;
    (void)nsens;
    UNSUPPORTED3("fmi3GetDirectionalDerivative")
}
fmi3Status fmi3GetAdjointDerivative(fmi3Instance instance, const fmi3ValueReference u[],
                                    size_t nu, const fmi3ValueReference k[], size_t nk,
                                    const fmi3Float64 seed[], size_t ns, fmi3Float64 sens[],
                                    size_t nsens) {
    (void)u;
    (void)nu;
    (void)k;
    (void)nk;
    (void)seed;
    (void)ns;
    (void)sens;
    (void)nsens;
    UNSUPPORTED3("fmi3GetAdjointDerivative")
}
fmi3Status fmi3EnterConfigurationMode(fmi3Instance instance) UNSUPPORTED3("fmi3EnterConfigurationMode")
fmi3Status fmi3ExitConfigurationMode(fmi3Instance instance) UNSUPPORTED3("fmi3ExitConfigurationMode")
fmi3Status fmi3GetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  fmi3Float64 intervals[], fmi3IntervalQualifier q[]) {
    (void)vr;
    (void)n;
    (void)intervals;
    (void)q;
    UNSUPPORTED3("fmi3GetIntervalDecimal")
}
fmi3Status fmi3GetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                   fmi3UInt64 c[], fmi3UInt64 r[], fmi3IntervalQualifier q[]) {
    (void)vr;
    (void)n;
    (void)c;
    (void)r;
    (void)q;
    UNSUPPORTED3("fmi3GetIntervalFraction")
}
fmi3Status fmi3GetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                               fmi3Float64 shifts[]) {
    (void)vr;
    (void)n;
    (void)shifts;
    UNSUPPORTED3("fmi3GetShiftDecimal")
}
fmi3Status fmi3GetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                fmi3UInt64 c[], fmi3UInt64 r[]) {
    (void)vr;
    (void)n;
    (void)c;
    (void)r;
    UNSUPPORTED3("fmi3GetShiftFraction")
}
fmi3Status fmi3SetIntervalDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                  const fmi3Float64 intervals[]) {
    (void)vr;
    (void)n;
    (void)intervals;
    UNSUPPORTED3("fmi3SetIntervalDecimal")
}
fmi3Status fmi3SetIntervalFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                   const fmi3UInt64 c[], const fmi3UInt64 r[]) {
    (void)vr;
    (void)n;
    (void)c;
    (void)r;
    UNSUPPORTED3("fmi3SetIntervalFraction")
}
fmi3Status fmi3SetShiftDecimal(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                               const fmi3Float64 shifts[]) {
    (void)vr;
    (void)n;
    (void)shifts;
    UNSUPPORTED3("fmi3SetShiftDecimal")
}
fmi3Status fmi3SetShiftFraction(fmi3Instance instance, const fmi3ValueReference vr[], size_t n,
                                const fmi3UInt64 c[], const fmi3UInt64 r[]) {
    (void)vr;
    (void)n;
    (void)c;
    (void)r;
    UNSUPPORTED3("fmi3SetShiftFraction")
}
fmi3Status fmi3EvaluateDiscreteStates(fmi3Instance instance) {
    (void)instance;
    return fmi3OK; /* no discrete states */
}
fmi3Status fmi3EnterStepMode(fmi3Instance instance) UNSUPPORTED3("fmi3EnterStepMode (event mode in Co-Simulation)")
fmi3Status fmi3GetOutputDerivatives(fmi3Instance instance, const fmi3ValueReference vr[],
                                    size_t nvr, const fmi3Int32 orders[], fmi3Float64 values[],
                                    size_t nValues) {
    (void)vr;
    (void)nvr;
    (void)orders;
    (void)values;
    (void)nValues;
    UNSUPPORTED3("fmi3GetOutputDerivatives")
}
fmi3Status fmi3ActivateModelPartition(fmi3Instance instance, fmi3ValueReference clock,
                                      fmi3Float64 time) {
    (void)clock;
    (void)time;
    UNSUPPORTED3("fmi3ActivateModelPartition")
}

/* ------------------------------------------------------------ Model Exchange */

fmi3Status fmi3UpdateDiscreteStates(fmi3Instance instance, fmi3Boolean *discreteStatesNeedUpdate,
                                    fmi3Boolean *terminateSimulation,
                                    fmi3Boolean *nominalsOfContinuousStatesChanged,
                                    fmi3Boolean *valuesOfContinuousStatesChanged,
                                    fmi3Boolean *nextEventTimeDefined, fmi3Float64 *nextEventTime) {
    fmi2EventInfo info;
    fmi2Status s = gbx_fmi2NewDiscreteStates(instance, &info);
    if (s != fmi2OK) return status3(s);
    if (discreteStatesNeedUpdate) *discreteStatesNeedUpdate = info.newDiscreteStatesNeeded;
    if (terminateSimulation) *terminateSimulation = info.terminateSimulation;
    if (nominalsOfContinuousStatesChanged)
        *nominalsOfContinuousStatesChanged = info.nominalsOfContinuousStatesChanged;
    if (valuesOfContinuousStatesChanged)
        *valuesOfContinuousStatesChanged = info.valuesOfContinuousStatesChanged;
    if (nextEventTimeDefined) *nextEventTimeDefined = info.nextEventTimeDefined;
    if (nextEventTime) *nextEventTime = info.nextEventTime;
    return fmi3OK;
}

fmi3Status fmi3EnterContinuousTimeMode(fmi3Instance instance) {
    return status3(gbx_fmi2EnterContinuousTimeMode(instance));
}

fmi3Status fmi3CompletedIntegratorStep(fmi3Instance instance,
                                       fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                                       fmi3Boolean *enterEventMode,
                                       fmi3Boolean *terminateSimulation) {
    fmi2Boolean e = fmi2False, t = fmi2False;
    fmi2Status s = gbx_fmi2CompletedIntegratorStep(instance, noSetFMUStatePriorToCurrentPoint, &e, &t);
    if (enterEventMode) *enterEventMode = e;
    if (terminateSimulation) *terminateSimulation = t;
    return status3(s);
}

fmi3Status fmi3SetTime(fmi3Instance instance, fmi3Float64 time) {
    return status3(gbx_fmi2SetTime(instance, time));
}

fmi3Status fmi3SetContinuousStates(fmi3Instance instance, const fmi3Float64 x[], size_t nx) {
    return status3(gbx_fmi2SetContinuousStates(instance, x, nx));
}

fmi3Status fmi3GetContinuousStateDerivatives(fmi3Instance instance, fmi3Float64 dx[], size_t nx) {
    return status3(gbx_fmi2GetDerivatives(instance, dx, nx));
}

fmi3Status fmi3GetEventIndicators(fmi3Instance instance, fmi3Float64 ei[], size_t ni) {
    (void)ei;
    if (ni == 0) return fmi3OK;
    log3((ModelInstance *)instance, "fmi3GetEventIndicators: the model has none");
    return fmi3Error;
}

fmi3Status fmi3GetContinuousStates(fmi3Instance instance, fmi3Float64 x[], size_t nx) {
    return status3(gbx_fmi2GetContinuousStates(instance, x, nx));
}

fmi3Status fmi3GetNominalsOfContinuousStates(fmi3Instance instance, fmi3Float64 nominals[],
                                             size_t nx) {
    return status3(gbx_fmi2GetNominalsOfContinuousStates(instance, nominals, nx));
}

fmi3Status fmi3GetNumberOfEventIndicators(fmi3Instance instance, size_t *n) {
    (void)instance;
    if (!n) return fmi3Error;
    *n = 0;
    return fmi3OK;
}

fmi3Status fmi3GetNumberOfContinuousStates(fmi3Instance instance, size_t *n) {
    (void)instance;
    if (!n) return fmi3Error;
    *n = GBX_NX;
    return fmi3OK;
}

/* ------------------------------------------------------------ Co-Simulation */

fmi3Status fmi3DoStep(fmi3Instance instance, fmi3Float64 currentCommunicationPoint,
                      fmi3Float64 communicationStepSize,
                      fmi3Boolean noSetFMUStatePriorToCurrentPoint,
                      fmi3Boolean *eventHandlingNeeded, fmi3Boolean *terminateSimulation,
                      fmi3Boolean *earlyReturn, fmi3Float64 *lastSuccessfulTime) {
    ModelInstance *m = (ModelInstance *)instance;
    fmi2Status s = gbx_fmi2DoStep(instance, currentCommunicationPoint, communicationStepSize,
                                  noSetFMUStatePriorToCurrentPoint);
    if (eventHandlingNeeded) *eventHandlingNeeded = fmi3False;
    if (terminateSimulation) *terminateSimulation = fmi3False;
    if (earlyReturn) *earlyReturn = fmi3False;
    if (lastSuccessfulTime && m) *lastSuccessfulTime = m->time;
    return status3(s);
}

"""Helpers shared by the FMU tests: a kept-alive fmi2 logger, the light-load scene
variant whose drive flank separates, Co-Simulation instances and Model Exchange
derivatives."""

from ctypes import byref

import numpy as np


class FmuLog:
    """fmi2 callbacks with a Python logger behind fmpy's varargs-formatting proxy; the
    messages as (status, text)."""

    def __init__(self):
        from fmpy import calloc, free
        from fmpy.fmi2 import (
            fmi2CallbackAllocateMemoryTYPE,
            fmi2CallbackFreeMemoryTYPE,
            fmi2CallbackFunctions,
            fmi2CallbackLoggerTYPE,
        )
        from fmpy.logging import addLoggerProxy

        self.messages = []

        def log(env, name, status, category, message):
            self.messages.append((status, message.decode()))

        self.callbacks = fmi2CallbackFunctions()
        self.callbacks.logger = fmi2CallbackLoggerTYPE(log)
        self.callbacks.allocateMemory = fmi2CallbackAllocateMemoryTYPE(calloc)
        self.callbacks.freeMemory = fmi2CallbackFreeMemoryTYPE(free)
        addLoggerProxy(byref(self.callbacks))


_LOGS: list[FmuLog] = []


def fmu_log() -> FmuLog:
    """A logger kept alive for the session: fmpy's proxy holds one logger for every
    instance (default callbacks included), and a collected one would crash the next
    message logged in this process."""
    _LOGS.append(FmuLog())
    return _LOGS[-1]


def light_load(backlash_mm: float) -> dict:
    """``[drivetrain]`` entries for 60 N m at 3500 rpm with an eightfold firing ripple:
    the drive flank separates."""
    return {
        "engine_power_kW": 60.0 * 3500 * np.pi / 30 / 1e3,
        "firing_torque_ripple": 8.0,
        "backlash_mm": backlash_mm,
    }


def me_derivatives(path, times, states, *, start=None, inputs=None, name="rhs"):
    """The Model Exchange FMU at ``path`` evaluated at each (t, x) of ``times`` (S,) and
    ``states`` (S, m): (its initial continuous states (m,), the derivatives (S, m)).
    start: {variable: value} set before leaving initialization; inputs(t, i) ->
    {variable: value} set before the i-th evaluation."""
    import shutil
    from ctypes import c_double

    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Model

    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(path)
    m = states.shape[1]
    out = np.empty_like(states, dtype=float)
    try:
        fmu = FMU2Model(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.modelExchange.modelIdentifier,
            instanceName=name,
        )
        fmu.instantiate()
        fmu.setupExperiment(startTime=0.0)
        fmu.enterInitializationMode()
        if start:
            fmu.setReal([vr[k] for k in start], list(start.values()))
        fmu.exitInitializationMode()
        x0 = (c_double * m)()
        fmu.getContinuousStates(x0, m)
        fmu.enterContinuousTimeMode()
        for i, (t, x) in enumerate(zip(times, states, strict=True)):
            fmu.setTime(float(t))
            if inputs is not None:
                values = inputs(t, i)
                fmu.setReal([vr[k] for k in values], list(values.values()))
            fmu.setContinuousStates((c_double * m)(*x), m)
            dx = (c_double * m)()
            fmu.getDerivatives(dx, m)
            out[i] = np.array(dx)
        fmu.terminate()
        fmu.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)
    return np.array(x0), out


def cs_slave(path_dir, md, name="robust"):
    from fmpy.fmi2 import FMU2Slave

    return FMU2Slave(
        guid=md.guid,
        unzipDirectory=path_dir,
        modelIdentifier=md.coSimulation.modelIdentifier,
        instanceName=name,
    )


def cs_instance(path, log=None, start=None, name="fixed"):
    """(slave in initialization mode, vr map, unzip dir) of a Co-Simulation FMU."""
    from fmpy import extract, read_model_description

    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(path)
    fmu = cs_slave(d, md, name)
    if log is None:
        fmu.instantiate()
    else:
        fmu.instantiate(callbacks=log.callbacks)
    fmu.setupExperiment(startTime=0.0)
    fmu.enterInitializationMode()
    for k, v in (start or {}).items():
        fmu.setReal([vr[k]], [v])
    return fmu, vr, d

"""Helpers shared by the FMU tests: a kept-alive fmi2 logger, the light-load scene
variant whose drive flank separates, Co-Simulation instances, Model Exchange
derivatives (FMI 2.0 and 3.0) with the gearbox FMU's flange inputs and the numpy
right-hand side they are checked against (with the FMU's rows among the model's), the
scipy reference and the libcosim run against the drivetrain FMU."""

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
    """``[drivetrain]`` entries for 50 N m (the default table's lowest level) at 3500 rpm
    with an eightfold firing ripple: the drive flank separates."""
    return {
        "engine_power_kW": 50.0 * 3500 * np.pi / 30 / 1e3,
        "firing_torque_ripple": 8.0,
        "backlash_mm": backlash_mm,
    }


def me_derivatives(path, times, states, *, start=None, inputs=None, name="rhs"):
    """The Model Exchange FMU at ``path`` (FMI 2.0 or 3.0) evaluated at each (t, x) of
    ``times`` (S,) and ``states`` (S, m): (its initial continuous states (m,), the
    derivatives (S, m)). start: {variable: value} set before leaving initialization;
    inputs(t, i) -> {variable: value} set before the i-th evaluation."""
    import shutil
    from ctypes import c_double

    from fmpy import extract, read_model_description

    md = read_model_description(path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(path)
    m = states.shape[1]
    out = np.empty_like(states, dtype=float)
    fmi3 = md.fmiVersion.startswith("3")
    try:
        if fmi3:
            from fmpy.fmi3 import FMU3Model as Model
        else:
            from fmpy.fmi2 import FMU2Model as Model
        fmu = Model(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.modelExchange.modelIdentifier,
            instanceName=name,
        )
        set_real = fmu.setFloat64 if fmi3 else fmu.setReal
        fmu.instantiate()
        if fmi3:
            fmu.enterInitializationMode(startTime=0.0)
        else:
            fmu.setupExperiment(startTime=0.0)
            fmu.enterInitializationMode()
        if start:
            set_real([vr[k] for k in start], list(start.values()))
        fmu.exitInitializationMode()
        if fmi3:
            fmu.updateDiscreteStates()
        x0 = (c_double * m)()
        fmu.getContinuousStates(x0, m)
        fmu.enterContinuousTimeMode()
        derivatives = fmu.getContinuousStateDerivatives if fmi3 else fmu.getDerivatives
        for i, (t, x) in enumerate(zip(times, states, strict=True)):
            fmu.setTime(float(t))
            if inputs is not None:
                values = inputs(t, i)
                set_real([vr[k] for k in values], list(values.values()))
            fmu.setContinuousStates((c_double * m)(*x), m)
            dx = (c_double * m)()
            derivatives(dx, m)
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


def scipy_reference(model, stop, dt=1e-4):
    """The FMU tests' reference: the scipy solver (DOP853, rtol 1e-10) on the numpy
    right-hand side from the static state, sampled every ``dt`` up to ``stop`` (s):
    (time, the channels of ``gearbox.drivetrain.model.outputs``)."""
    from gearbox.drivetrain.model import outputs
    from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy

    t = np.linspace(0.0, stop, int(round(stop / dt)) + 1)
    tt, y, info = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    assert info["status"] == "success", info
    return tt, outputs(model, tt, y)


def flange_inputs(model, states):
    """``inputs`` of :func:`me_derivatives` for the gearbox FMU: its flange angles and
    speeds from the engine and propeller rows of the model's states (S, 2 n)."""
    n = model.n_dof

    def inputs(t, i):
        y = states[i]
        return {
            "input_flange.phi": model.speed * t + y[0],
            "input_flange.w": model.speed + y[n],
            "output_flange.phi": model.gear_speed * t + y[3],
            "output_flange.w": model.gear_speed + y[n + 3],
        }

    return inputs


def cosim_against_drivetrain(model, table, gearbox, drivetrain, out, stop=0.01, step=5e-5):
    """Engine, the ``gearbox`` build and propeller FMUs on libcosim (``cosim_drivetrain``,
    communication step ``step``) against the drivetrain FMU at path ``drivetrain`` (its
    DOPRI5 at rtol 1e-10) at the communication points: RMS difference over the AC RMS
    of the mesh force and of the input shaft torque, and the mean mesh force's relative
    difference."""
    from gearbox.fmu import build_fmu, engine_fmu, propeller_fmu
    from gearbox.fmu.cosim import cosim_drivetrain
    from gearbox.fmu.run import ac_relative_error, simulate_fmu

    builds = {
        "engine": build_fmu(engine_fmu(model), out),
        "gearbox": gearbox,
        "propeller": build_fmu(propeller_fmu(model), out),
    }
    res = cosim_drivetrain(model, table, out, step=step, stop_time=stop, builds=builds)
    assert res.success, res.message
    t, ch, _ = simulate_fmu(
        drivetrain,
        stop_time=stop,
        step=1e-5,
        rtol=1e-10,
        outputs=["mesh.force", "input_shaft.torque"],
    )
    k = (np.abs(t / step - np.round(t / step)) < 1e-6) & (t <= res.time[-1] + 1e-12)
    mean = ch["mesh.force"][k].mean()  # at the same sample times
    return (
        ac_relative_error(res.time, res["mesh_force_N"], t[k], ch["mesh.force"][k]),
        ac_relative_error(
            res.time, res["input_shaft_torque_Nm"], t[k], ch["input_shaft.torque"][k]
        ),
        abs(res["mesh_force_N"].mean() - mean) / abs(mean),
    )


def fmu_rows(model, kind: str) -> np.ndarray:
    """The FMU's states among the model's (the gearbox FMU: without engine and propeller)."""
    n = model.n_dof
    dofs = [i for i in range(n) if "gearbox" not in kind or i not in (0, 3)]
    return np.array(dofs + [n + i for i in dofs])


def rhs_derivatives(params, times, states, rows=None) -> np.ndarray:
    """The numpy reference ``gearbox.drivetrain.model.rhs`` with ``params`` at each (t, y)
    of ``times`` (S,) and unscaled ``states`` (S, 2 n): dy/dt, shape (S, 2 n), or its
    ``rows``."""
    from gearbox.drivetrain.model import rhs

    sc = params["scale"]
    out = np.array([rhs(t, y / sc, params) * sc for t, y in zip(times, states, strict=True)])
    return out if rows is None else out[:, rows]

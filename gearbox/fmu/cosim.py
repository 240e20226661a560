"""Co-simulation of engine, gearbox and propeller FMUs on libcosim (libcosimpy).

The three FMUs of :mod:`gearbox.fmu.models` are coupled through an OSP system
structure file (``OspSystemStructure.xml``, the Open Simulation Platform's format)
and run by libcosim's fixed-step master; nothing here steps the FMUs itself::

    engine.engine.phi, engine.engine.w          -> gearbox.input_flange.phi, .w
    gearbox.input_shaft.torque                  -> engine.input_shaft.torque
    gearbox.output_shaft.torque                 -> propeller.output_shaft.torque
    propeller.propeller.phi, propeller.propeller.w -> gearbox.output_flange.phi, .w

The coupling error against the monolithic model (one FMU, or the Python solvers)
comes from holding the exchanged torques and speeds over a communication step; the
gearbox extrapolates the flange angles with the flange speeds. docs/fmu.md gives the
measured error as a function of the step.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any
from xml.sax.saxutils import quoteattr

import numpy as np

from .._pickling import PicklesReadOnly
from ..commands._common import write_atomic
from ..errors import InputError, Problems
from .build import FmuBuild, build_fmu
from .models import engine_fmu, gearbox_fmu, propeller_fmu

__all__ = [
    "CONNECTIONS",
    "RATE_CONNECTIONS",
    "CHANNELS",
    "OPTIONAL_CHANNELS",
    "CosimResult",
    "build_cosim_fmus",
    "channels_for",
    "cosim_drivetrain",
    "run_system",
    "system_structure",
]

#: (from simulator, variable) -> (to simulator, variable)
CONNECTIONS = (
    (("engine", "engine.phi"), ("gearbox", "input_flange.phi")),
    (("engine", "engine.w"), ("gearbox", "input_flange.w")),
    (("gearbox", "input_shaft.torque"), ("engine", "input_shaft.torque")),
    (("gearbox", "output_shaft.torque"), ("propeller", "output_shaft.torque")),
    (("propeller", "propeller.phi"), ("gearbox", "output_flange.phi")),
    (("propeller", "propeller.w"), ("gearbox", "output_flange.w")),
)

#: Rates that let each FMU extrapolate its inputs linearly over a communication step
#: (speeds with accelerations, torques with torque rates): second-order coupling.
RATE_CONNECTIONS = (
    (("engine", "engine.a"), ("gearbox", "input_flange.a")),
    (("gearbox", "input_shaft.torque_rate"), ("engine", "input_shaft.torque_rate")),
    (("gearbox", "output_shaft.torque_rate"), ("propeller", "output_shaft.torque_rate")),
    (("propeller", "propeller.a"), ("gearbox", "output_flange.a")),
)

#: result channel -> (simulator, variable); channel names as gearbox.drivetrain.model.outputs
CHANNELS = {
    "engine_speed_rad_per_s": ("engine", "engine.w"),
    "pinion_speed_rad_per_s": ("gearbox", "pinion.w"),
    "gear_speed_rad_per_s": ("gearbox", "gear.w"),
    "propeller_speed_rad_per_s": ("propeller", "propeller.w"),
    "mesh_force_N": ("gearbox", "mesh.force"),
    "mesh_deflection_m": ("gearbox", "mesh.deflection"),
    "dynamic_transmission_error_m": ("gearbox", "mesh.dte"),
    "input_shaft_torque_Nm": ("gearbox", "input_shaft.torque"),
    "output_shaft_torque_Nm": ("gearbox", "output_shaft.torque"),
    "engine_torque_Nm": ("engine", "engine.torque"),
    "propeller_torque_Nm": ("propeller", "propeller.torque"),
}

#: The gearbox FMU's outputs that exist only with their feature (docs/fmu.md): mesh
#: friction, eccentricities, pitch deviations; :func:`channels_for` adds those a model
#: has.
OPTIONAL_CHANNELS = {
    "pinion_friction_torque_Nm": ("gearbox", "mesh.pinion_friction_torque"),
    "gear_friction_torque_Nm": ("gearbox", "mesh.gear_friction_torque"),
    "mesh_friction_power_W": ("gearbox", "mesh.friction_power"),
    "eccentricity_approach_m": ("gearbox", "mesh.eccentricity_approach"),
    "pitch_approach_m": ("gearbox", "mesh.pitch_approach"),
}


def channels_for(model) -> dict[str, tuple[str, str]]:
    """:data:`CHANNELS` plus the :data:`OPTIONAL_CHANNELS` of the features ``model``
    has (mesh friction coefficient > 0, an eccentricity, pitch deviations)."""
    out = dict(CHANNELS)
    names = []
    if model.mesh_friction_coefficient > 0:
        names += ["pinion_friction_torque_Nm", "gear_friction_torque_Nm", "mesh_friction_power_W"]
    if model.has_eccentricity:
        names.append("eccentricity_approach_m")
    if getattr(model, "pitch", None) is not None:
        names.append("pitch_approach_m")
    out.update({k: OPTIONAL_CHANNELS[k] for k in names})
    return out


_UNITS = {
    "engine_speed_rad_per_s": "rad/s",
    "pinion_speed_rad_per_s": "rad/s",
    "gear_speed_rad_per_s": "rad/s",
    "propeller_speed_rad_per_s": "rad/s",
    "mesh_force_N": "N",
    "mesh_deflection_m": "m",
    "dynamic_transmission_error_m": "m",
    "input_shaft_torque_Nm": "N m",
    "output_shaft_torque_Nm": "N m",
    "engine_torque_Nm": "N m",
    "propeller_torque_Nm": "N m",
    "pinion_friction_torque_Nm": "N m",
    "gear_friction_torque_Nm": "N m",
    "mesh_friction_power_W": "W",
    "eccentricity_approach_m": "m",
    "pitch_approach_m": "m",
}


@dataclass(frozen=True)
class CosimResult(PicklesReadOnly):
    """Channels of a co-simulation sampled at every communication step.

    time: ndarray, shape (n_t,) (s); channels: name -> ndarray, shape (n_t,), SI, named
    as :data:`CHANNELS`. status: 'success' or 'failure' (with ``message``). step:
    communication step (s); steps: communication steps taken; wall_time (s);
    system_structure: path of the OSP system structure file that was run.
    """

    time: np.ndarray
    channels: Any
    step: float
    status: str = "success"
    message: str = ""
    steps: int = 0
    wall_time: float = 0.0
    system_structure: str = ""
    units: Any = field(default_factory=lambda: MappingProxyType(dict(_UNITS)))

    @property
    def success(self) -> bool:
        return self.status == "success"

    def __getitem__(self, name: str) -> np.ndarray:
        return self.channels[name]

    def to_dict(self) -> dict[str, Any]:
        return {
            "time_s": self.time.tolist(),
            "channels": {k: np.asarray(v).tolist() for k, v in self.channels.items()},
            "units": dict(self.units),
            "step_s": self.step,
            "status": self.status,
            "message": self.message,
            "steps": self.steps,
            "wall_time_s": self.wall_time,
            "system_structure": self.system_structure,
        }

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> CosimResult:
        return cls(
            time=np.asarray(d["time_s"], dtype=float),
            channels=MappingProxyType({k: np.asarray(v, float) for k, v in d["channels"].items()}),
            step=float(d["step_s"]),
            status=d["status"],
            message=d.get("message", ""),
            steps=int(d.get("steps", 0)),
            wall_time=float(d.get("wall_time_s", 0.0)),
            system_structure=d.get("system_structure", ""),
            units=MappingProxyType(dict(d.get("units", _UNITS))),
        )

    def to_csv(self) -> str:
        """CSV with time first, one column per channel (SI units in the header)."""
        names = list(self.channels)
        lines = [",".join(["time_s", *names])]
        cols = [self.channels[n] for n in names]
        for i, t in enumerate(self.time):
            lines.append(",".join([repr(float(t)), *(repr(float(c[i])) for c in cols)]))
        return "\n".join(lines) + "\n"


def build_cosim_fmus(model, table, out_dir: str | Path) -> dict[str, FmuBuild]:
    """Build the engine, gearbox and propeller FMUs of a model into ``out_dir``."""
    out_dir = Path(out_dir)
    return {
        "engine": build_fmu(engine_fmu(model), out_dir),
        "gearbox": build_fmu(gearbox_fmu(model, table), out_dir),
        "propeller": build_fmu(propeller_fmu(model), out_dir),
    }


def system_structure(
    fmus: dict[str, str | Path],
    step: float,
    *,
    initial_values: dict[str, dict[str, float]] | None = None,
    extrapolate: bool = True,
    connections: tuple | None = None,
) -> str:
    """OSP system structure (``OspSystemStructure.xml``) text coupling the three FMUs.

    fmus: simulator name -> FMU path (relative to the structure file, or absolute);
    step: communication step (s); initial_values: simulator -> variable -> value;
    extrapolate: also connect :data:`RATE_CONNECTIONS` (second-order coupling),
    otherwise every exchanged value is held over a step (zero-order hold);
    connections: ((from simulator, variable), (to simulator, variable)) pairs that
    replace the engine-gearbox-propeller ones (``()`` for a single FMU).
    """
    initial_values = initial_values or {}
    lines = [
        '<?xml version="1.0" encoding="utf-8"?>',
        '<OspSystemStructure xmlns="http://opensimulationplatform.com/MSMI/OSPSystemStructure"'
        ' version="0.1">',
        "    <StartTime>0.0</StartTime>",
        f"    <BaseStepSize>{step!r}</BaseStepSize>",
        "    <Algorithm>fixedStep</Algorithm>",
        "    <Simulators>",
    ]
    for name, path in fmus.items():
        lines.append(
            f"        <Simulator name={quoteattr(name)} source={quoteattr(str(path))}"
            f' stepSize="{step!r}">'
        )
        values = initial_values.get(name, {})
        if values:
            lines.append("            <InitialValues>")
            for var, val in values.items():
                lines.append(
                    f"                <InitialValue variable={quoteattr(var)}>"
                    f'<Real value="{float(val)!r}"/></InitialValue>'
                )
            lines.append("            </InitialValues>")
        lines.append("        </Simulator>")
    lines += ["    </Simulators>", "    <Connections>"]
    if connections is None:
        connections = CONNECTIONS + (RATE_CONNECTIONS if extrapolate else ())
    for (s1, v1), (s2, v2) in connections:
        lines += [
            "        <VariableConnection>",
            f"            <Variable simulator={quoteattr(s1)} name={quoteattr(v1)}/>",
            f"            <Variable simulator={quoteattr(s2)} name={quoteattr(v2)}/>",
            "        </VariableConnection>",
        ]
    lines += ["    </Connections>", "</OspSystemStructure>", ""]
    return "\n".join(lines)


def run_system(
    structure_file: str | Path, stop_time: float, step: float, *, channels: dict | None = None
) -> CosimResult:
    """Run an OSP system structure on libcosim until ``stop_time`` (s) and sample channels.

    channels: result name -> (simulator, variable), default :data:`CHANNELS`.
    """
    try:
        from libcosimpy.CosimEnums import CosimVariableType
        from libcosimpy.CosimExecution import CosimExecution
        from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
        from libcosimpy.CosimObserver import CosimObserver
    except ImportError as exc:  # pragma: no cover - depends on the installation
        raise InputError(
            [], f"co-simulation needs libcosimpy (pip install libcosimpy): {exc}"
        ) from None
    channels = channels or CHANNELS
    n_steps = int(round(stop_time / step))
    log_output_level(CosimLogLevel.ERROR)
    start = _time.perf_counter()
    try:
        execution = CosimExecution.from_osp_config_file(str(structure_file))
    except AssertionError as exc:
        raise InputError([], f"libcosim cannot load {structure_file}: {exc}") from None
    index = {info.name.decode(): info.index for info in execution.slave_infos()}
    refs = {}
    for sim in {s for s, _ in channels.values()}:
        refs[sim] = {v.name.decode(): v.reference for v in execution.slave_variables(index[sim])}
    observer = CosimObserver.create_time_series(buffer_size=n_steps + 2)
    execution.add_observer(observer)
    for sim, var in channels.values():
        observer.start_time_series(index[sim], refs[sim][var], CosimVariableType.REAL)
    ok = execution.simulate_until(int(round(n_steps * step * 1e9)))
    wall = _time.perf_counter() - start
    status = execution.status()
    out = {}
    time = None
    for name, (sim, var) in channels.items():
        t_ns, _steps, values = observer.time_series_real_samples(
            index[sim], refs[sim][var], from_step=0, sample_count=n_steps + 1
        )
        out[name] = np.asarray(values, dtype=float)
        if time is None:
            time = np.asarray(t_ns, dtype=float) * 1e-9
    n = min(len(v) for v in out.values())
    out = {k: v[:n] for k, v in out.items()}
    reached = status.current_time * 1e-9
    done = ok and abs(reached - n_steps * step) <= 0.5 * step
    return CosimResult(
        time=time[:n],
        channels=MappingProxyType(out),
        step=step,
        status="success" if done else "failure",
        message="" if done else f"libcosim stopped at t = {reached:g} s",
        steps=int(round(reached / step)),
        wall_time=wall,
        system_structure=str(structure_file),
    )


def cosim_drivetrain(
    model,
    table,
    out_dir: str | Path,
    *,
    step: float = 1e-4,
    stop_time: float = 0.1,
    solver_rtol: float = 1e-8,
    builds: dict[str, FmuBuild] | None = None,
    extrapolate: bool = True,
) -> CosimResult:
    """Build the three FMUs (unless ``builds`` are given), write the system structure
    and run it on libcosim.

    step: communication step (s), > 0; stop_time (s), a multiple of the step;
    solver_rtol: tolerance of each FMU's internal integrator; extrapolate: second-order
    coupling (inputs extrapolated with their rates) or zero-order hold.
    """
    p = Problems()
    p.in_range("step", step, 0, 0.01, lo_open=True)
    p.in_range("stop_time", stop_time, 0, None, lo_open=True)
    p.in_range("solver_rtol", solver_rtol, 1e-14, 0.1)
    if step > 0 and stop_time > 0:
        k = stop_time / step
        p.check(
            abs(k - round(k)) < 1e-6 * max(1.0, k),
            "stop_time",
            stop_time,
            f"must be a multiple of the step {step:g} s",
        )
    p.raise_if_any("invalid co-simulation settings")
    out_dir = Path(out_dir)
    builds = builds or build_cosim_fmus(model, table, out_dir)
    fmus = {name: Path(b.fmu).resolve() for name, b in builds.items()}
    # adaptive DOPRI5 at solver_rtol in every FMU (solver.method = 0): the coupling
    # error table of docs/fmu.md was measured so
    init = {
        name: {"solver.method": 0.0, "solver.rtol": solver_rtol, "solver.max_step": step}
        for name in fmus
    }
    structure = write_atomic(
        out_dir / "OspSystemStructure.xml",
        system_structure(fmus, step, initial_values=init, extrapolate=extrapolate),
    )
    return run_system(structure, stop_time, step, channels=channels_for(model))


def compare_monolithic(model, table, out_dir: str | Path, res: CosimResult, *, rtol: float = 1e-8):
    """Coupling error of a co-simulation against the monolithic drivetrain FMU.

    Returns channel -> RMS error over the AC RMS of the monolithic result, at the
    co-simulation's sample times.
    """
    from .models import drivetrain_fmu
    from .run import ac_relative_error, simulate_fmu

    mono = build_fmu(drivetrain_fmu(model, table), out_dir)
    names = {
        "mesh_force_N": "mesh.force",
        "dynamic_transmission_error_m": "mesh.dte",
        "input_shaft_torque_Nm": "input_shaft.torque",
        "output_shaft_torque_Nm": "output_shaft.torque",
        "engine_speed_rad_per_s": "engine.w",
        "propeller_speed_rad_per_s": "propeller.w",
    }
    stop = float(res.time[-1]) if res.time.size else res.step
    t, ch, _ = simulate_fmu(
        mono.fmu, stop_time=stop, step=res.step, rtol=rtol, outputs=list(names.values())
    )
    return {k: ac_relative_error(res.time, res[k], t, ch[v]) for k, v in names.items()}

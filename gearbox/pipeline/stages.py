"""The stages of ``gearbox run`` and what each reads (docs/pipeline.md draws the graph).

Each stage function (in :mod:`gearbox.pipeline.adapters`) imports its stage module
when it runs, so ``import gearbox`` stays light and a stage whose module (or optional
extra) is missing is reported as unavailable rather than replaced by anything else.

Declared ``reads`` decide the cache keys: a change in ``[drivetrain]`` (say, the
propeller) changes the keys of dynamics, spectra, waterfall and Campbell only, so
design, contact analysis and mesh tables come from the cache.
"""

from __future__ import annotations

import dataclasses
from types import MappingProxyType

from .adapters import dynamics, fmu, geometry, mesh
from .adapters._require import require
from .stage import Stage

__all__ = ["STAGES", "require"]

_PAIR = ("pair", "pinion", "gear", "tool")
_DRIVE = ("drivetrain", "simulation", "load.torques_Nm", "load.operating_torque_Nm")
_LOADS = ("load.torques_Nm", "load.operating_torque_Nm")
#: What of [simulation] each drivetrain stage reads, so that a change of the Campbell
#: diagram's flags (operating range, resonance threshold) redoes that stage alone, and
#: one of the sweep's speeds leaves the operating point's run
_RUN = tuple(
    f"simulation.{k}"
    for k in ("solver", "rtol", "settle_time_s", "settled_mesh_cycles", "samples_per_mesh_cycle")
)
_SWEEP = ("simulation.speed_sweep_rpm", "simulation.sweep_speeds")
_CAMPBELL = ("simulation.operating_range_rpm", "simulation.resonance_threshold")
_PITCH_READS = (
    *_PAIR,
    "assembly",
    "tca",
    "ltca",
    "material",
    "load.torques_Nm",
    "load.operating_torque_Nm",
    "pitch",
)


def _pitch_if_on(scene) -> tuple[str, ...]:
    """The ``[pitch]`` section, read by the drivetrain stages only when the dynamics
    carry the deviations (``drivetrain.pitch_deviations``): otherwise a change there
    redoes the ``pitch`` stage alone."""
    return ("pitch",) if scene["drivetrain"]["pitch_deviations"] else ()


def _on_tables(name, compute, validate, doc, *code, reads=_DRIVE) -> Stage:
    """A drivetrain stage: reads the drive sections, runs on the mesh tables."""
    return Stage(
        name,
        compute,
        reads=reads,
        reads_also=_pitch_if_on,
        depends=("tables",),
        route=dynamics.drive_depends,
        code=("gearbox.drivetrain", "gearbox.meshtable", *code),
        validate=validate,
        blas_threads=1,
        doc=doc,
    )


STAGES: MappingProxyType[str, Stage] = MappingProxyType(
    {
        "design": Stage(
            "design",
            geometry.compute_design,
            reads=_PAIR,
            code=("gearbox.geometry",),
            validate=geometry.pair_spec,
            doc="Pitch cone design, FPD angles and checks (paper section 2).",
        ),
        "sweep": Stage(
            "sweep",
            geometry.compute_sweep,
            reads=_PAIR,
            code=("gearbox.geometry",),
            validate=geometry.pair_spec,
            doc="Parameter studies around the design (paper Figs. 6-9).",
        ),
        "tca": Stage(
            "tca",
            mesh.compute_tca,
            reads=(*_PAIR, "assembly", "tca"),
            depends=("design",),
            code=("gearbox.surface", "gearbox.tca"),
            doc="Unloaded tooth contact analysis: contact path, transmission error.",
        ),
        "ltca": Stage(
            "ltca",
            mesh.compute_ltca,
            reads=(*_PAIR, "assembly", "tca", "ltca", "material", "load.torques_Nm"),
            depends=("design",),
            validate=mesh.validate_ltca,
            code=("gearbox.surface", "gearbox.tca", "gearbox.ltca", "gearbox.meshtable"),
            doc="Loaded TCA over the mesh cycle, torque levels and flanks.",
        ),
        "pitch": Stage(
            "pitch",
            mesh.compute_pitch,
            reads=_PITCH_READS,
            depends=("design", "ltca"),
            validate=mesh.validate_pitch,
            code=("gearbox.ltca",),
            doc="Pitch deviations: loaded TE over a hunting period and its orders.",
        ),
        "approach": Stage(
            "approach",
            mesh.compute_approach,
            reads=_PITCH_READS,
            route=mesh.approach_depends,
            validate=mesh.validate_pitch,
            code=("gearbox.ltca",),
            doc="Tooth deviations at the torque levels for the dynamics: exact records or "
            "the measured traces' turns.",
        ),
        "tables": Stage(
            "tables",
            mesh.compute_tables,
            reads=(*_PAIR, "ltca", "load.torques_Nm", "outputs.mesh_tables"),
            route=mesh.tables_depends,
            code=("gearbox.meshtable", "gearbox.mesh_analytical"),
            doc="Mesh tables k(theta, T), LTE, P, n (loaded TCA or analytical).",
        ),
        # Campbell before the dynamics: it needs neither jax nor a simulation, so under
        # `gearbox run` the output worker draws its section while the dynamics stage
        # imports jax and simulates (docs/pipeline.md, "Files and report sections")
        "campbell": _on_tables(
            "campbell",
            dynamics.compute_campbell,
            dynamics.validate_sweep_torques,
            "Eigenfrequencies against speed with excitation orders and crossings.",
            "gearbox.spectrum",
            reads=("drivetrain", *_SWEEP, *_CAMPBELL, *_LOADS),
        ),
        "dynamics": _on_tables(
            "dynamics",
            dynamics.compute_dynamics,
            dynamics.validate_operating_torque,
            "Settled drivetrain response at the operating point.",
            reads=("drivetrain", *_RUN, *_LOADS),
        ),
        "spectra": Stage(
            "spectra",
            dynamics.compute_spectra,
            depends=("dynamics",),
            code=("gearbox.spectrum",),
            blas_threads=1,
            doc="Order spectra of mesh force, DTE and bearing forces.",
        ),
        "waterfall": dataclasses.replace(
            _on_tables(
                "waterfall",
                dynamics.compute_waterfall,
                dynamics.validate_sweep_torques,
                "Speed sweep on the propeller law: order spectra against speed.",
                "gearbox.spectrum",
                reads=("drivetrain", *_RUN, *_SWEEP, *_LOADS),
            ),
            route=dynamics.waterfall_depends,
        ),
        "fmu": _on_tables(
            "fmu",
            fmu.compute_fmu,
            dynamics.validate_operating_torque,
            "The drivetrain at the operating point as an FMI 2.0 FMU (C, gcc).",
            "gearbox.fmu",
        ),
    }
)

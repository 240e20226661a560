"""The stages of ``gearbox run`` and what each reads (docs/pipeline.md draws the graph).

Each stage function (in :mod:`gearbox.pipeline.adapters`) imports its stage module
when it runs, so ``import gearbox`` stays light and a stage whose module (or optional
extra) is missing is reported as unavailable rather than replaced by anything else.

Declared ``reads`` decide the cache keys: a change in ``[drivetrain]`` (say, the
propeller) changes the keys of dynamics, spectra, waterfall and Campbell only, so
design, contact analysis and mesh tables come from the cache.
"""

from __future__ import annotations

from types import MappingProxyType

from .adapters import dynamics, fmu, geometry, mesh
from .adapters._require import require
from .stage import Stage

__all__ = ["STAGES", "require"]

_PAIR = ("pair", "pinion", "gear", "tool")
_DRIVE = ("drivetrain", "simulation", "load.torques_Nm", "load.operating_torque_Nm")


def _check_torques(scene):
    dynamics.validate_torques(scene)


def _check_sweep(scene):
    dynamics.validate_torques(scene, sweep=True)


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
            code=("gearbox.surface", "gearbox.tca", "gearbox.ltca", "gearbox.meshtable"),
            doc="Loaded TCA over the mesh cycle, torque levels and flanks.",
        ),
        "tables": Stage(
            "tables",
            mesh.compute_tables,
            reads=(*_PAIR, "ltca", "load.torques_Nm", "outputs.mesh_tables"),
            route=mesh.tables_depends,
            code=("gearbox.meshtable", "gearbox.mesh_analytical"),
            doc="Mesh tables k(theta, T), LTE, P, n (loaded TCA or analytical).",
        ),
        "dynamics": Stage(
            "dynamics",
            dynamics.compute_dynamics,
            reads=_DRIVE,
            depends=("tables",),
            code=("gearbox.drivetrain", "gearbox.meshtable"),
            validate=_check_torques,
            doc="Settled drivetrain response at the operating point.",
        ),
        "spectra": Stage(
            "spectra",
            dynamics.compute_spectra,
            depends=("dynamics",),
            code=("gearbox.spectrum",),
            doc="Order spectra of mesh force, DTE and bearing forces.",
        ),
        "waterfall": Stage(
            "waterfall",
            dynamics.compute_waterfall,
            reads=_DRIVE,
            depends=("tables",),
            code=("gearbox.drivetrain", "gearbox.meshtable", "gearbox.spectrum"),
            validate=_check_sweep,
            doc="Speed sweep on the propeller law: order spectra against speed.",
        ),
        "campbell": Stage(
            "campbell",
            dynamics.compute_campbell,
            reads=_DRIVE,
            depends=("tables",),
            code=("gearbox.drivetrain", "gearbox.meshtable", "gearbox.spectrum"),
            validate=_check_sweep,
            doc="Eigenfrequencies against speed with excitation orders and crossings.",
        ),
        "fmu": Stage(
            "fmu",
            fmu.compute_fmu,
            reads=_DRIVE,
            depends=("tables",),
            code=("gearbox.fmu", "gearbox.drivetrain", "gearbox.meshtable"),
            validate=_check_torques,
            doc="The drivetrain at the operating point as an FMI 2.0 FMU (C, gcc).",
        ),
    }
)

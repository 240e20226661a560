"""Contact stages: unloaded TCA (gearbox.tca), loaded TCA (gearbox.ltca) and the mesh
tables the dynamics reads (gearbox.meshtable)."""

from __future__ import annotations

from ...errors import InputError, Problem
from ..stage import StageContext, StageUnavailable
from ._require import require

__all__ = [
    "compute_ltca",
    "compute_pitch",
    "compute_tables",
    "compute_tca",
    "tables_depends",
    "validate_ltca",
    "validate_pitch",
]


def compute_tca(ctx: StageContext):
    """Unloaded TCA of the designed pair (gearbox.tca)."""
    tca = require("gearbox.tca", "run_tca")
    return tca.run_tca(ctx.inputs["design"], ctx.scene)


def compute_ltca(ctx: StageContext):
    """Loaded TCA over the mesh cycle, torque levels and flanks (gearbox.ltca); with the
    run's progress bars, one per flank over its contact solves (the longest stage:
    seconds at the fast level, minutes at the FE level)."""
    ltca = require("gearbox.ltca.table", "scene_ltca")
    analysis = require("gearbox.ltca.analysis", "LTCAOptions")
    options = analysis.LTCAOptions(positions=ctx.scene["ltca"]["positions"], progress=ctx.progress)
    return ltca.scene_ltca(ctx.inputs["design"], ctx.scene, options=options)


def validate_ltca(scene) -> None:
    """Check, before anything runs, the loaded-TCA inputs that need the design: the
    flank modifications' lengths against the teeth and, for a parallel pair, its
    assembly errors. Raises one InputError naming every key; a pair that does not
    design is left to the design stage."""
    from .geometry import pair_spec

    geometry = require("gearbox.geometry", "design_pair")
    beveloid = require("gearbox.ltca.beveloid", "modifications_from_scene")
    table = require("gearbox.ltca.table", "parallel_pair_from_design", "is_parallel")
    try:
        design = geometry.design_pair(pair_spec(scene))
    except InputError:
        return
    problems = []
    checks = [beveloid.modifications_from_scene]
    if table.is_parallel(design):
        checks.append(table.parallel_pair_from_design)
    for check in checks:
        try:
            check(design, scene)
        except InputError as exc:
            problems += exc.problems
    if problems:
        raise InputError(problems, "invalid loaded TCA inputs")


def tables_depends(scene) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """(required, optional) upstream stages of ``tables`` for the scene's source."""
    source = scene["outputs"]["mesh_tables"]
    if source == "loaded_tca":
        return ("design", "ltca"), ()
    if source == "auto":
        return ("design",), ("ltca",)
    return ("design",), ()


def _table_of(ltca_result):
    table = getattr(ltca_result, "table", None)
    if table is None:
        raise StageUnavailable("the loaded TCA result carries no mesh table in this version")
    return table


def compute_tables(ctx: StageContext):
    """The :class:`gearbox.meshtable.MeshTable` of the pair.

    From the loaded TCA when ``outputs.mesh_tables`` is ``loaded_tca`` (or ``auto``
    and the loaded TCA ran); else the analytical tables of
    :func:`gearbox.mesh_analytical.analytical_table` (ISO 6336-1:2019 method B mean
    stiffness, variation from the contact line length), whose ``attrs["method"]``
    says so in the report.
    """
    if "ltca" in ctx.inputs:
        return _table_of(ctx.inputs["ltca"])
    if ctx.scene["outputs"]["mesh_tables"] == "loaded_tca":  # pragma: no cover - runner skips
        raise StageUnavailable("the loaded TCA did not run")
    ma = require("gearbox.mesh_analytical", "analytical_table", "pair_from_scene")
    lt = ctx.scene["ltca"]
    return ma.analytical_table(
        ma.pair_from_scene(ctx.scene),
        ctx.scene["load"]["torques_Nm"],
        positions=max(int(lt["positions"]), 24),
        flanks=tuple(lt["flanks"]),
        scene=ctx.scene.name,
    )


def _pitch_torque(scene) -> float:
    t = scene["pitch"]["torque_Nm"]
    return float(scene["load"]["operating_torque_Nm"] if t is None else t)


def validate_pitch(scene) -> None:
    """Before anything runs: the deviation lists against the teeth, the torque within
    the mesh tables' levels, the drive flank among the analysed ones. One InputError
    naming every key; a pair that does not design is left to the design stage."""
    from .geometry import pair_spec

    geometry = require("gearbox.geometry", "design_pair")
    pitch = require("gearbox.ltca.pitch", "deviations_from_scene")
    problems = []
    flank = scene["pitch"]["flank"]
    if flank not in scene["ltca"]["flanks"]:
        problems.append(
            Problem(
                "ltca.flanks",
                list(scene["ltca"]["flanks"]),
                f"must hold {flank!r} for pitch (pitch.flank)",
            )
        )
    tq = scene["load"]["torques_Nm"]
    t = _pitch_torque(scene)
    if not min(tq) <= t <= max(tq):
        key = (
            "pitch.torque_Nm"
            if scene["pitch"]["torque_Nm"] is not None
            else ("load.operating_torque_Nm")
        )
        problems.append(Problem(key, t, f"must lie within load.torques_Nm [{min(tq)}, {max(tq)}]"))
    try:
        # the evaluation lengths left empty and the crownings' vertices come from the
        # loaded TCA: stand-ins here
        design = geometry.design_pair(pair_spec(scene))
        pitch.deviations_from_scene(design, scene, flank_range=[[0.0, 1.0]] * 4)
    except InputError as exc:
        problems += [p for p in exc.problems if p.path.startswith("pitch.")]
    if problems:
        raise InputError(problems, "invalid pitch-deviation inputs")


def compute_pitch(ctx: StageContext):
    """Pitch deviations' loaded TE over a hunting period on the flank ``pitch.flank``
    (gearbox.ltca.pitch): linear through the loaded TCA's pair weights (root stresses
    from first-order point loads), or exact (one contact solve per sample); the
    positions go through the run's executor."""
    pitch = require(
        "gearbox.ltca.pitch",
        "hunting_lte",
        "PitchResult",
        "flank_grids",
        "deviations_from_scene",
    )
    scene = ctx.scene
    design = ctx.inputs["design"]
    flank = scene["pitch"]["flank"]
    res = ctx.inputs["ltca"].flanks[flank]
    dev = pitch.deviations_from_scene(design, scene, res.flank_range)
    method = scene["pitch"]["method"]
    # the grids give the exact method its solves and the linear one its root stresses
    # from first-order point loads
    grids, compliance = pitch.flank_grids(design, scene, res.fraction.size, flank)
    kw = {"grids": grids, "compliance": compliance, "mapper": ctx.map}
    teeth = (design.pinion.teeth, design.gear.teeth)
    rec = pitch.hunting_lte(res, dev, _pitch_torque(scene), teeth=teeth, method=method, **kw)
    return pitch.PitchResult(dev, rec, flank)


def approach_depends(scene) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Upstream of the ``approach`` stage: design and loaded TCA, and with the exact
    method the ``pitch`` stage, whose record at the operating torque joins the levels."""
    if scene["pitch"]["method"] == "exact":
        return ("design", "ltca", "pitch"), ()
    return ("design", "ltca"), ()


def compute_approach(ctx: StageContext):
    """The tooth deviations at the loaded TCA's torque levels for the dynamics
    (gearbox.ltca.pitch): with ``pitch.method = "exact"`` the exact hunting records at
    each level and the pitch stage's (``level_records``), else the measured traces'
    turns (``trace_turns``); the positions go through the run's executor."""
    pitch = require(
        "gearbox.ltca.pitch",
        "DeviationLevels",
        "flank_grids",
        "deviations_from_scene",
        "trace_turns",
        "level_records",
    )
    scene = ctx.scene
    design = ctx.inputs["design"]
    res = ctx.inputs["ltca"].flanks["drive"]  # the dynamics carry the drive flank's
    dev = pitch.deviations_from_scene(design, scene, res.flank_range)
    exact = scene["pitch"]["method"] == "exact"
    if not exact and dev.traces is None:
        return pitch.DeviationLevels()  # the mesh table's weights carry them all
    grids, compliance = pitch.flank_grids(design, scene, res.fraction.size, "drive")
    if exact:
        teeth = (design.pinion.teeth, design.gear.teeth)
        own = ctx.inputs.get("pitch")
        known = (own.record,) if own is not None and own.flank == "drive" else ()
        levels = pitch.level_records(
            res,
            dev,
            teeth=teeth,
            grids=grids,
            compliance=compliance,
            mapper=ctx.map,
            known=known,  # the operating torque's, a level of its own
        )
        return pitch.DeviationLevels(levels=levels)
    turns = pitch.trace_turns(res, grids, compliance, dev.traces, mapper=ctx.map)
    return pitch.DeviationLevels(turns=turns)

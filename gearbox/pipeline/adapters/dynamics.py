"""Drivetrain stages: the operating point, its spectra, the speed sweep (waterfall) and
the Campbell diagram (gearbox.drivetrain, gearbox.spectrum).

Speed sweeps follow the propeller law: a fixed-pitch propeller absorbs a torque
proportional to the square of its speed, so at engine speed n the mean pinion torque
is ``T(n) = T_op (n / n_op)**2`` (engine power ``P(n) = P_op (n / n_op)**3``), with
``T_op`` and ``n_op`` the scene's operating point (``drivetrain.engine_power_kW`` /
``engine_speed_rpm``, else ``load.operating_torque_Nm``). The mesh tables must cover
the torques of the sweep; :func:`validate_torques` says so before anything runs.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

import numpy as np

from ...errors import InputError, Problem
from ...scene import Scene
from .. import jaxcache
from ..stage import StageContext
from ._require import require

__all__ = [
    "OperatingPoint",
    "SpeedSweep",
    "Spectra",
    "compute_campbell",
    "compute_dynamics",
    "compute_spectra",
    "compute_waterfall",
    "operating_torque",
    "sweep_speeds",
    "validate_operating_torque",
    "validate_sweep_torques",
    "validate_torques",
    "waterfall_depends",
]

#: Channels analysed in spectra and waterfalls when the run has them.
SPECTRUM_CHANNELS = (
    "mesh_force_N",
    "dynamic_transmission_error_m",
    "pinion_bearing_force_N",
    "gear_bearing_force_N",
)

#: Solvers whose runs may share this process's cores as threads: a compiled jax run
#: releases the GIL (exudyn and scipy runs stay one after the other, or in processes).
THREADED = ("diffrax",)

#: Speeds of the Campbell diagram's mode curves (eigenvalues are cheap).
CAMPBELL_SPEEDS = 61


def operating_torque(scene: Scene) -> tuple[float, float]:
    """(T_op (N m), n_op (rpm)): mean pinion torque and speed of the operating point."""
    d = scene["drivetrain"]
    n0 = float(d["engine_speed_rpm"])
    if d["engine_power_kW"] is not None:
        return d["engine_power_kW"] * 1e3 / (n0 * math.pi / 30.0), n0
    return float(scene["load"]["operating_torque_Nm"]), n0


def propeller_law_torque(scene: Scene, speed_rpm: float) -> float:
    """Mean pinion torque (N m) at ``speed_rpm`` on the propeller law (module doc)."""
    t0, n0 = operating_torque(scene)
    return t0 * (speed_rpm / n0) ** 2


def sweep_speeds(scene: Scene) -> np.ndarray:
    """Engine speeds of the sweep (rpm), shape (simulation.sweep_speeds,)."""
    lo, hi = scene["simulation"]["speed_sweep_rpm"][:2]
    return np.linspace(lo, hi, scene["simulation"]["sweep_speeds"])


def validate_torques(scene: Scene, *, sweep: bool = False) -> None:
    """Raise InputError unless ``load.torques_Nm`` covers the torques the run needs."""
    tq = scene["load"]["torques_Nm"]
    lo, hi = min(tq), max(tq)

    def outside(x: float) -> bool:
        return x < lo * (1 - 1e-9) or x > hi * (1 + 1e-9)

    # one problem per need, the same text from every stage that has it (the runner
    # lists a problem once)
    problems = []
    t_op = operating_torque(scene)[0]
    source = (
        "load.operating_torque_Nm"
        if scene["drivetrain"]["engine_power_kW"] is None
        else "drivetrain.engine_power_kW at drivetrain.engine_speed_rpm"
    )
    if outside(t_op):
        problems.append(
            Problem(
                "load.torques_Nm",
                list(tq),
                f"must cover the operating torque, {t_op:.4g} N m ({source}; mesh tables "
                "are not extrapolated)",
            )
        )
    if sweep:
        s = scene["simulation"]["speed_sweep_rpm"]
        a, b = propeller_law_torque(scene, s[0]), propeller_law_torque(scene, s[-1])
        if outside(a) or outside(b):
            problems.append(
                Problem(
                    "load.torques_Nm",
                    list(tq),
                    f"must cover the speed sweep's propeller-law torques, [{a:.4g}, {b:.4g}] "
                    f"N m at {s[0]:g} to {s[-1]:g} rpm (mesh tables are not extrapolated)",
                )
            )
    if problems:
        raise InputError(problems)
    if not sweep:
        return
    sim = scene["simulation"]["speed_sweep_rpm"]
    if not sim[0] < sim[-1]:
        raise InputError(
            Problem("simulation.speed_sweep_rpm", list(sim), "must be [min, max], min < max")
        )


def validate_operating_torque(scene: Scene) -> None:
    """The checks of a stage that runs the operating point: :func:`validate_torques`."""
    validate_torques(scene)


def validate_sweep_torques(scene: Scene) -> None:
    """The checks of a stage that runs the speed sweep: :func:`validate_torques` with the
    sweep's torques."""
    validate_torques(scene, sweep=True)


def _at_speed(scene: Scene, speed_rpm: float) -> Scene:
    """The scene with the engine at ``speed_rpm`` on the propeller law."""
    torque = propeller_law_torque(scene, speed_rpm)
    d = dict(scene["drivetrain"])
    d["engine_speed_rpm"] = float(speed_rpm)
    d["engine_power_kW"] = torque * speed_rpm * math.pi / 30.0 / 1e3
    data = dict(scene.data)
    data["drivetrain"] = MappingProxyType(d)
    return Scene(MappingProxyType(data), scene.path)


def model_at(scene: Scene, table, speed_rpm: float | None = None, approach=None, mesh_law=None):
    """:class:`gearbox.drivetrain.DrivetrainModel` at ``speed_rpm`` (default: operating);
    ``approach``: the ``approach`` stage's result when the stage runs on it (the exact
    level records or the traces' turns, :func:`drive_depends`); ``mesh_law``: instead
    of ``drivetrain.mesh_law`` (whose ``"auto"`` builds the tangent law)."""
    drivetrain = require("gearbox.drivetrain", "DrivetrainModel")
    if speed_rpm is not None:
        scene = _at_speed(scene, speed_rpm)
    kw = {"mesh_law": mesh_law}
    if approach is not None:
        kw |= {"trace_turns": approach.turns, "level_records": approach.levels}
    return drivetrain.DrivetrainModel.from_scene(scene, table, **kw)


def loaded_twin(scene: Scene, table, speed_rpm: float | None = None, approach=None):
    """With ``drivetrain.mesh_law = "auto"``: the drive at ``speed_rpm`` with the loaded
    law, to repeat a tangent-law run on (``run_with_auto_law``); None for the other laws,
    or when the tables cannot take the loaded law (one torque level, an LTE that does
    not grow with the torque): the runs then keep the tangent law
    (``gearbox.drivetrain.simulate.loaded_twin``)."""
    twin = require("gearbox.drivetrain.simulate", "loaded_twin").loaded_twin
    return twin(scene, lambda law: model_at(scene, table, speed_rpm, approach, mesh_law=law))


def solver_of(scene: Scene, mesh_law: str | None = None):
    """The solver object named by ``simulation.solver``: scipy with ``simulation.rtol``;
    diffrax with fixed steps (``DiffraxSolver()``, as ``gearbox simulate`` without
    ``--rtol``), whose runs that lose contact are repeated with adaptive steps
    (``DiffraxSolver.contact_rtol``); exudyn's fixed-step RK67, on its Python user
    functions for the loaded law (its symbolic ones carry the tangent law only).
    ``mesh_law``: the law of the model it runs, default ``drivetrain.mesh_law``."""
    sim = require("gearbox.drivetrain.simulate", "default_solver")
    s = scene["simulation"]
    rtol = None if s["solver"] == "diffrax" else s["rtol"]
    return sim.default_solver(s["solver"], rtol, mesh_law or scene["drivetrain"]["mesh_law"])


def solvers_of(scene: Scene) -> dict[str, Any]:
    """:func:`solver_of` for each mesh law a run may take: ``{law: solver}``."""
    return {law: solver_of(scene, law) for law in ("tangent", "loaded")}


def contact_metrics(series) -> dict[str, float]:
    """Fractions of the record with the drive flank open (mesh force <= 0) and with
    the coast flank in contact (mesh force < 0): contact loss and back-flank impacts."""
    f = np.asarray(series["mesh_force_N"])
    if f.size == 0:
        return {"contact_loss_fraction": math.nan, "coast_contact_fraction": math.nan}
    return {
        "contact_loss_fraction": float(np.mean(f <= 0.0)),
        "coast_contact_fraction": float(np.mean(f < 0.0)),
    }


@dataclass(frozen=True)
class OperatingPoint:
    """The drivetrain at the scene's operating point.

    ``model``: DrivetrainModel (SI); ``series``: TimeSeries of the settled record;
    ``metrics``: mesh-force RMS / mesh-order amplitude (N), contact fractions;
    ``modes``: linear modes about the operating point; ``speed_rpm``, ``torque_Nm``.
    """

    speed_rpm: float
    torque_Nm: float
    model: Any
    series: Any
    metrics: Mapping[str, float]
    modes: Any


def _simulate(model, solver, sim: Mapping[str, Any]):
    simulate = require(
        "gearbox.drivetrain.simulate", "simulate", "mesh_force_metrics", "friction_metrics"
    )
    if getattr(solver, "name", "") == "diffrax":
        jaxcache.attach()  # the run's compiled executables (a new process skips tracing)
    ts = simulate.simulate(
        model,
        solver,
        settle_time=sim["settle_time_s"],
        mesh_cycles=int(sim["settled_mesh_cycles"]),
        samples_per_cycle=int(sim["samples_per_mesh_cycle"]),
    )
    metrics = dict(simulate.mesh_force_metrics(ts, model)) | contact_metrics(ts)
    return ts, metrics | simulate.friction_metrics(ts)


def law_metrics(model, table, metrics: Mapping[str, float]) -> dict[str, float]:
    """gearbox.drivetrain.simulate.law_metrics: how far the run's force range reaches
    along the loaded TCA's stiffness."""
    return require("gearbox.drivetrain.simulate", "law_metrics").law_metrics(model, table, metrics)


def _settled(model, solvers: Mapping[str, Any], sim: Mapping[str, Any], table, loaded=None):
    """``(model, series, metrics)``: the settled run of ``model`` with its law metrics;
    with ``loaded`` (:func:`loaded_twin`) repeated on it where the run reaches beyond
    the tangent law (``gearbox.drivetrain.simulate.run_with_auto_law``). ``solvers``:
    :func:`solvers_of`."""
    auto = require("gearbox.drivetrain.simulate", "run_with_auto_law").run_with_auto_law
    return auto(lambda m: _simulate(m, solvers[m.mesh_law], sim), model, table, loaded)


def compute_dynamics(ctx: StageContext) -> OperatingPoint:
    """Settled response at the operating point (gearbox.drivetrain.simulate); with
    ``drivetrain.mesh_law = "auto"`` on the loaded law where the tangent law's run
    reaches beyond it (the point's ``model`` is the one run)."""
    linear = require("gearbox.drivetrain.linear", "modes")
    scene = ctx.scene
    table = ctx.inputs["tables"]
    approach = ctx.inputs.get("approach")
    model = model_at(scene, table, approach=approach)
    loaded = loaded_twin(scene, table, approach=approach)
    model, ts, metrics = _settled(model, solvers_of(scene), scene["simulation"], table, loaded)
    t0, n0 = operating_torque(scene)
    return OperatingPoint(n0, t0, model, ts, metrics, linear.modes(model))


# -- spectra ----------------------------------------------------------------------------


@dataclass(frozen=True)
class Spectra:
    """Order spectra (pinion orders) of the operating point's channels.

    ``spectra``: channel -> :class:`gearbox.spectrum.OrderSpectrum`; ``excitations``:
    the excitation orders of the drive (:func:`gearbox.spectrum.excitation_orders`);
    ``linear``: channel -> {order: peak amplitude} of the same orders from the model
    about the operating point (:func:`gearbox.drivetrain.linear.order_responses`),
    beside which the simulated spectrum is read.
    """

    speed_rpm: float
    spectra: Mapping[str, Any]
    excitations: tuple
    linear: Mapping[str, Mapping[float, float]] = field(default_factory=dict)


def _orders(model) -> tuple:
    """The model's excitation orders: mesh (3 harmonics), firing and blade-pass orders
    with the harmonics the model applies, half orders when it has cylinder imbalance,
    the eccentric members' once per revolution, the pitch deviations' first pinion and
    gear orders and the approach's three largest lines beyond them that reach a tenth
    of its largest (a ghost order, a wobble's sidebands: "deviations, <kind>")."""
    spectrum = require("gearbox.spectrum.campbell", "excitation_orders", "PITCH_ORDERS")
    kw = dict(
        pinion_teeth=model.pinion_teeth,
        gear_teeth=model.gear_teeth,
        cylinders=model.engine_cylinders,
        blades=model.propeller_blades,
        firing_harmonics=max(int(model.engine_harmonics), 1),
        blade_harmonics=max(int(model.blade_pass_harmonics), 1),
        half_orders=model.half_order_ripple > 0,
        max_half_order=1.5,  # the half orders the model applies (0.5, 1, 1.5)
        pinion_eccentricity=model.pinion_eccentricity > 0,
        gear_eccentricity=model.gear_eccentricity > 0,
        pitch_orders=spectrum.PITCH_ORDERS if getattr(model, "pitch", None) is not None else 0,
    )
    named = spectrum.excitation_orders(**kw)
    if getattr(model, "pitch", None) is None:
        return named
    linear = require("gearbox.drivetrain.linear", "deviation_lines")
    kind = require("gearbox.ltca.pitch", "order_kind").order_kind
    z1, z2 = model.pinion_teeth, model.gear_teeth
    lines = linear.deviation_lines(model, [e.order for e in named])
    extra = tuple((f"deviations, {kind(o, z1, z2)}", o) for o, _ in lines)
    return spectrum.excitation_orders(**kw, deviation_orders=extra)


def spectra_of(series, excitations) -> dict[str, Any]:
    """Order spectra of :data:`SPECTRUM_CHANNELS` against the pinion angle.

    Whole common periods of all excitation orders (rectangular window: every order
    on a bin) when the record holds at least one; else whole pinion revolutions with
    a flat-top window (orders that are not whole numbers fall between bins; the
    flat-top window keeps their peak amplitude), so that every speed of a sweep has
    the same order resolution.
    """
    spectrum = require("gearbox.spectrum", "order_spectrum", "common_period_revs")
    angle = np.asarray(series["pinion_angle_rad"])
    n = angle.size
    # revolutions the samples stand for: n sample intervals (the record is periodic)
    revs = (angle[-1] - angle[0]) / (2 * math.pi) * n / (n - 1) if n > 1 else 0.0
    try:
        period = spectrum.common_period_revs([e.order for e in excitations])
    except InputError:
        period = None
    window = "rectangular"
    if period is None or revs < period * (1 - 1e-3):
        period, window = 1.0, "flattop"
    out = {}
    for name in SPECTRUM_CHANNELS:
        if name not in series.channels:
            continue
        args = (series.time, series[name])
        opts = {"angle": angle, "name": name, "unit": series.units.get(name, "")}
        try:
            out[name] = spectrum.order_spectrum(*args, period_revs=period, window=window, **opts)
        except InputError:  # the record holds slightly less than whole periods
            out[name] = spectrum.order_spectrum(*args, period_revs=None, **opts)
    return out


def compute_spectra(ctx: StageContext) -> Spectra:
    """Order spectra of the operating point (gearbox.spectrum.order_spectrum)."""
    op = ctx.inputs["dynamics"]
    if not op.series.success or op.series.time.size < 2:
        raise RuntimeError(f"the dynamics run did not succeed ({op.series.status})")
    linear = require("gearbox.drivetrain.linear", "order_responses")
    exc = _orders(op.model)
    r = linear.order_responses(op.model, sideband_harmonics=0)
    lin = {
        name: {e.order: r.peaks(e.order)[name] for e in exc}
        for name, *_ in linear.RESPONSE_CHANNELS
        if name in SPECTRUM_CHANNELS and name in op.series.channels
    }
    return Spectra(op.speed_rpm, spectra_of(op.series, exc), tuple(exc), lin)


# -- speed sweep: waterfall ----------------------------------------------------------------


@dataclass(frozen=True)
class SweepPoint:
    """One speed of a sweep: spectra per channel, metrics, solver status and work, and
    the mesh law of its run (``"tangent"`` or ``"loaded"``)."""

    speed_rpm: float
    torque_Nm: float
    status: str
    spectra: Mapping[str, Any]
    metrics: Mapping[str, float]
    nfev: int
    wall_time: float
    mesh_law: str = "tangent"


def _point(model, ts, metrics, speed_rpm: float, torque: float, law: str = "") -> SweepPoint:
    """A sweep point from a settled run ``ts`` of ``model`` and its metrics, with the
    mesh order's amplitude from the model about the operating point beside them
    (``linear_mesh_order_amplitude_N``, :func:`gearbox.drivetrain.linear.order_responses`)
    and the one of its order spectrum (``mesh_order_amplitude_spectrum_N``, against the
    pinion angle; ``mesh_force_mesh_order_amplitude_N`` is the time DFT at the nominal
    mesh frequency, which parts from it where a shaft mode swings the speed);
    ``law``: the mesh law of the run when it is not ``model``'s (the loaded twin's run
    of ``mesh_law = "auto"``, whose linearisation is ``model``'s)."""
    linear = require("gearbox.drivetrain.linear", "order_responses")
    spectra = spectra_of(ts, _orders(model)) if ts.success and ts.time.size > 1 else {}
    z1 = float(model.pinion_teeth)
    lin = linear.order_responses(model, sideband_harmonics=0).peaks(z1)["mesh_force_N"]
    extra = {"linear_mesh_order_amplitude_N": lin}
    if "mesh_force_N" in spectra:
        try:  # against the pinion's angle, as the waterfall (the metric: the time DFT)
            extra["mesh_order_amplitude_spectrum_N"] = spectra["mesh_force_N"].amplitude_at(z1)
        except InputError:
            pass
    return SweepPoint(
        float(speed_rpm),
        float(torque),
        ts.status,
        spectra,
        dict(metrics) | extra,
        int(ts.nfev),
        float(ts.wall_time),
        law or model.mesh_law,
    )


def sweep_point(job: tuple) -> SweepPoint:
    """Simulate one speed and keep its spectra (module level: runs in worker processes):
    ``job`` = (model, solvers, simulation settings, speed, torque, tables, loaded twin
    or None), as :func:`_settled` takes them."""
    model, solvers, sim, speed_rpm, torque, table, loaded = job
    ran, ts, metrics = _settled(model, solvers, sim, table, loaded)
    return _point(model, ts, metrics, speed_rpm, torque, ran.mesh_law)


@dataclass(frozen=True)
class SpeedSweep:
    """A speed sweep on the propeller law.

    ``points``: one :class:`SweepPoint` per speed; ``waterfalls``: channel ->
    :class:`gearbox.spectrum.Waterfall` over the speeds that succeeded;
    ``excitations``: the drive's excitation orders.
    """

    speeds_rpm: np.ndarray
    points: tuple[SweepPoint, ...]
    waterfalls: Mapping[str, Any] = field(default_factory=dict)
    excitations: tuple = ()


def on_approach_stage(scene: Scene) -> bool:
    """Whether the drivetrain stages need the ``approach`` stage: the dynamics carry the
    deviations (``drivetrain.pitch_deviations``) and either ``[pitch]`` sets measured
    traces (their turns) or ``pitch.method = "exact"`` (the exact records at the torque
    levels)."""
    if not scene["drivetrain"]["pitch_deviations"]:
        return False
    section = scene["pitch"]
    traces = any(k.endswith("_trace_um") and v for k, v in section.items())
    return traces or section["method"] == "exact"


def drive_depends(scene: Scene) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Upstream of a drivetrain stage: the mesh tables, and the ``approach`` stage when
    :func:`on_approach_stage`."""
    return (("tables", "approach") if on_approach_stage(scene) else ("tables",)), ()


def waterfall_depends(scene: Scene) -> tuple[tuple[str, ...], tuple[str, ...]]:
    """Upstream of the waterfall: as :func:`drive_depends`, and the operating point when
    its speed is one of the sweep's (its settled run is then one point of the sweep)."""
    req = drive_depends(scene)[0]
    n_op = float(scene["drivetrain"]["engine_speed_rpm"])
    if np.any(np.isclose(sweep_speeds(scene), n_op, rtol=1e-12, atol=0.0)):
        return req, ("dynamics",)
    return req, ()


def _reused_point(op, model, speed_rpm: float, torque: float) -> SweepPoint | None:
    """The sweep point at ``speed_rpm`` from the operating point's run (with the law
    that run took), when that run is the same simulation (same speed and torque; same
    scene, tables and settings, since both stages read them); else None. ``model``: the
    sweep's own at that speed, for the linear analysis, as at every other speed."""
    if op is None or not math.isclose(op.speed_rpm, speed_rpm, rel_tol=1e-12):
        return None
    if not math.isclose(op.torque_Nm, torque, rel_tol=1e-9):
        return None
    return _point(model, op.series, op.metrics, speed_rpm, torque, op.model.mesh_law)


def compute_waterfall(ctx: StageContext) -> SpeedSweep:
    """Speed sweep through the run's executor, one simulation per speed; the speed of
    the operating point takes the dynamics stage's run when there is one."""
    spectrum = require("gearbox.spectrum", "waterfall")
    scene = ctx.scene
    table = ctx.inputs["tables"]
    speeds = sweep_speeds(scene)
    solvers = solvers_of(scene)
    approach = ctx.inputs.get("approach")
    sim = dict(scene["simulation"])
    jobs = [
        (
            model_at(scene, table, n, approach),
            solvers,
            sim,
            n,
            propeller_law_torque(scene, n),
            table,
            loaded_twin(scene, table, n, approach),
        )
        for n in speeds
    ]
    op = ctx.inputs.get("dynamics")
    reused = {i: _reused_point(op, j[0], j[3], j[4]) for i, j in enumerate(jobs)}
    reused = {i: p for i, p in reused.items() if p is not None}
    todo = [j for i, j in enumerate(jobs) if i not in reused]
    threads = getattr(solvers["tangent"], "name", "") in THREADED
    run = iter(ctx.map(sweep_point, todo, threads=threads))
    points = tuple(reused[i] if i in reused else next(run) for i in range(len(jobs)))
    waterfalls = {}
    for name in SPECTRUM_CHANNELS:
        ok = [p for p in points if name in p.spectra]
        if len(ok) < 2:
            continue
        specs = [p.spectra[name] for p in ok]
        # one order resolution for all speeds: the shortest record's
        revs = min(s.revs for s in specs)
        if all(math.isclose(s.revs, revs, rel_tol=1e-9) for s in specs):
            waterfalls[name] = spectrum.waterfall(specs, [p.speed_rpm for p in ok])
    return SpeedSweep(speeds, points, waterfalls, tuple(_orders(jobs[0][0])))


# -- Campbell --------------------------------------------------------------------------


def compute_campbell(ctx: StageContext):
    """Campbell diagram: linear-model eigenfrequencies along the propeller law against
    the excitation orders; crossings in the sweep's speed range flagged, each with the
    steady response its excitation drives there, and the order cuts (every order's
    response along the speeds, the crossing speeds among them)."""
    spectrum = require("gearbox.spectrum", "campbell")
    linear = require("gearbox.drivetrain.linear", "modes")
    scene = ctx.scene
    table = ctx.inputs["tables"]
    lo, hi = scene["simulation"]["speed_sweep_rpm"][:2]
    grid = np.linspace(lo, hi, CAMPBELL_SPEEDS)
    approach = ctx.inputs.get("approach")
    models = {float(n): model_at(scene, table, n, approach) for n in grid}
    freqs = np.array([linear.modes(m).frequencies for m in models.values()])
    op_model = model_at(scene, table, approach=approach)
    op_modes = linear.modes(op_model)
    kinds = [d.split(" mode")[0] for d in op_modes.descriptions()]
    curves = {}
    for i in range(freqs.shape[1]):
        if np.all(freqs[:, i] < 1e-3):  # rigid-body rotation of the whole line
            continue
        curves[f"mode {i} ({kinds[i]})"] = (grid, freqs[:, i])
    excitations = _orders(op_model)
    service = tuple(scene["simulation"]["operating_range_rpm"]) or (lo, hi)
    diagram = spectrum.campbell(curves, excitations, (lo, hi), operating_range_rpm=service)
    for c in diagram.crossings:
        models.setdefault(float(c.speed_rpm), model_at(scene, table, c.speed_rpm, approach))
    speeds = np.array(sorted(models))
    # the excitation orders' own lines: no sidebands needed
    responses = [linear.order_responses(models[float(n)], sideband_harmonics=0) for n in speeds]
    at = dict(zip(speeds.tolist(), responses, strict=True))
    return diagram.with_responses(
        lambda c: at[float(c.speed_rpm)].peaks(c.order),
        scene["simulation"]["resonance_threshold"],
        _order_cuts(spectrum, speeds, excitations, responses),
    )


def _order_cuts(spectrum, speeds, excitations, responses):
    """:class:`gearbox.spectrum.OrderCuts` from one OrderResponse per speed."""
    linear = require("gearbox.drivetrain.linear", "RESPONSE_CHANNELS")
    amps, means, units = {}, {}, {}
    for name, _, mean, unit in linear.RESPONSE_CHANNELS:
        amps[name] = np.array([[r.peaks(e.order)[name] for r in responses] for e in excitations])
        means[name] = np.array([getattr(r, mean) for r in responses])
        units[name] = unit
    return spectrum.OrderCuts(speeds, tuple(excitations), amps, units, means)

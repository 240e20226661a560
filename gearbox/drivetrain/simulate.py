"""One entry point for every solver: settle, record whole mesh cycles, return a TimeSeries.

The run starts at the operating point (static equilibrium plus the linear periodic
response, :func:`gearbox.drivetrain.linear.periodic_start_state`), integrates a
settling time, then records ``mesh_cycles`` whole mesh cycles at
``samples_per_cycle`` samples each, so spectra see whole periods. Settling is
checked, not assumed: the mesh-order amplitudes of the mesh force over the record's
two halves (whole mesh cycles each) are compared (``attrs['settling_change']``,
relative). Engine and propeller orders are not whole periods of a half record, so
the total RMS is not used for this check. When the record holds one common period
of all excitations (``DrivetrainModel.common_period_mesh_cycles``; 870 mesh cycles,
30 pinion revolutions, for the default scene), ``attrs['periodicity_residual']``
compares the state one common period apart: the settled response is periodic with
that period.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from .linear import periodic_start_state
from .model import CHANNEL_UNITS, DrivetrainModel, outputs
from .timeseries import TimeSeries

__all__ = [
    "LAW_SPAN",
    "default_solver",
    "friction_metrics",
    "law_metrics",
    "law_reach",
    "loaded_twin",
    "mesh_force_metrics",
    "mesh_force_metrics_arrays",
    "record_times",
    "run_with_auto_law",
    "simulate",
]


def default_solver(name: str = "diffrax", rtol: float | None = None, mesh_law: str = "tangent"):
    """Solver object by name ('diffrax', 'scipy', 'exudyn') with an optional rtol.

    'diffrax' without rtol: fixed steps (``DiffraxSolver()``); with rtol: adaptive steps.
    'exudyn' (fixed steps, no rtol): its symbolic user functions, or with ``mesh_law =
    "loaded"`` its Python ones, the only ones that carry that law.
    """
    if name == "scipy":
        from .scipy_backend import ScipySolver

        return ScipySolver() if rtol is None else ScipySolver(rtol=rtol)
    if name == "diffrax":
        from .diffrax_backend import DiffraxSolver

        return DiffraxSolver() if rtol is None else DiffraxSolver(rtol=rtol)
    if name == "exudyn":
        from .exudyn_backend import ExudynSolver

        return ExudynSolver(user_functions="python" if mesh_law == "loaded" else "symbolic")
    from ..errors import InputError, Problem

    raise InputError(Problem("solver", name, "must be one of diffrax, scipy, exudyn"))


def _check_run_arguments(settle_time, mesh_cycles, samples_per_cycle, start) -> None:
    """:func:`simulate`'s own arguments: one InputError naming every bad one."""
    from ..errors import Problems, is_real

    p = Problems()
    if settle_time is not None:
        ok = is_real(settle_time) and math.isfinite(settle_time) and settle_time >= 0
        p.check(ok, "settle_time", settle_time, "must be >= 0 s, or None")
    p.integer("mesh_cycles", mesh_cycles, 1)
    p.integer("samples_per_cycle", samples_per_cycle, 1)
    p.check(
        start in ("operating_point", "periodic"),
        "start",
        start,
        "must be 'operating_point' or 'periodic'",
    )
    p.raise_if_any("invalid simulation arguments")


def record_times(
    model: DrivetrainModel, settle_time: float, mesh_cycles: int, samples_per_cycle: int
) -> np.ndarray:
    """Sample times (s) of the record: whole mesh cycles after ``settle_time``."""
    tm = 1.0 / model.mesh_frequency
    n = mesh_cycles * samples_per_cycle
    return settle_time + np.arange(1, n + 1) * (tm / samples_per_cycle)


def mesh_force_metrics(ts: TimeSeries, model: DrivetrainModel) -> dict[str, float]:
    """RMS, dynamic (AC) RMS, mean, largest and least value and mesh-order amplitude of
    the mesh force (N), and the dynamic factor.

    The mesh-order amplitude is the single-sided DFT amplitude at exactly N_1 x the
    nominal pinion speed over the record (whole mesh cycles, uniform samples). The
    dynamic factor is the largest mesh force over the mean over the record: the
    simulated counterpart of ISO 6336-1's K_v (the nominal load plus the internal
    dynamic load, over the nominal load), with every excitation of the drive in it.
    """
    f = np.asarray(ts["mesh_force_N"])
    t = np.asarray(ts.time)
    m = mesh_force_metrics_arrays(t[None, :], f[None, :], np.array([model.mesh_frequency]))
    return {k: float(v[0]) for k, v in m.items()}


def law_metrics(model: DrivetrainModel, table, metrics) -> dict[str, float]:
    """The loaded mesh law's mean drive tangent stiffness at a run's least and largest
    mesh force (``metrics`` of :func:`mesh_force_metrics`) over the model's, less 1:
    ``law_stiffness_at_min_force``, ``law_stiffness_at_max_force``
    (:func:`gearbox.drivetrain.model.law_stiffness_ratio`, docs §3d): how far the run's
    force range reaches along the loaded TCA's stiffness, which the tangent law holds
    constant. NaN without the two forces, or for a table of one level or one the law
    cannot take."""
    from .model import law_stiffness_ratio

    f = [metrics.get("mesh_force_min_N", math.nan), metrics.get("mesh_force_max_N", math.nan)]
    if not all(math.isfinite(x) for x in f) or table.torque.size < 2:
        lo = hi = math.nan
    else:
        lo, hi = (float(r) for r in law_stiffness_ratio(table, model, f))
    return {"law_stiffness_at_min_force": lo, "law_stiffness_at_max_force": hi}


#: The tangent mesh law's reach (docs/drivetrain.md §3d): the share by which the loaded
#: TCA's mean tangent stiffness at a run's least or largest mesh force (:func:`law_metrics`)
#: may depart from the law's constant one. Beyond it the report warns of a tangent-law
#: run, and ``drivetrain.mesh_law = "auto"`` repeats the run with the loaded law. A
#: choice; docs/drivetrain.md §3d gives what the loaded law moves on the default scene
#: on either side of it.
LAW_SPAN = 0.10


def law_reach(metrics) -> float:
    """The larger magnitude of a run's ``law_stiffness_at_min_force`` and
    ``law_stiffness_at_max_force`` (:func:`law_metrics`); 0 when neither is recorded
    (or finite)."""
    vals = (metrics.get("law_stiffness_at_min_force"), metrics.get("law_stiffness_at_max_force"))
    return max((abs(float(v)) for v in vals if v is not None and math.isfinite(v)), default=0.0)


def loaded_twin(scene, build):
    """With ``drivetrain.mesh_law = "auto"``: ``build("loaded")``, the drive with the
    loaded law that :func:`run_with_auto_law` repeats a run on; None for the other laws,
    or where the tables cannot take the loaded law (``build`` raises InputError: one
    torque level, an LTE that does not grow with the torque), whose runs then keep the
    tangent law. ``build(mesh_law)``: the model with that law."""
    from ..errors import InputError

    if scene["drivetrain"]["mesh_law"] != "auto":
        return None
    try:
        return build("loaded")
    except InputError:
        return None


def run_with_auto_law(run, model: DrivetrainModel, table, loaded=None):
    """``(model, result, metrics)``: ``run(model) -> (result, metrics)`` (metrics of
    :func:`mesh_force_metrics`) with the run's :func:`law_metrics` added; with
    ``loaded`` (the same drive with ``mesh_law = "loaded"``: ``drivetrain.mesh_law =
    "auto"``) the run is repeated on it when ``model``'s run reaches beyond
    :data:`LAW_SPAN` (:func:`law_reach`), and that run is returned, its metrics with
    ``tangent_law_reach``, the reach that sent it there."""
    result, metrics = run(model)
    metrics = dict(metrics) | law_metrics(model, table, metrics)
    reach = law_reach(metrics)
    if loaded is None or reach <= LAW_SPAN:
        return model, result, metrics
    result, again = run(loaded)
    return (
        loaded,
        result,
        dict(again) | law_metrics(loaded, table, again) | {"tangent_law_reach": reach},
    )


def friction_metrics(ts: TimeSeries) -> dict[str, float]:
    """With mesh friction (its channels in the record): the mean friction power (W) and
    the mesh efficiency, 1 - that over the mean power the input shaft puts into the
    pinion; nothing without friction."""
    if "mesh_friction_power_W" not in ts.channels or ts.time.size == 0:
        return {}
    loss = float(np.mean(ts["mesh_friction_power_W"]))
    into = float(np.mean(ts["input_shaft_torque_Nm"] * ts["pinion_speed_rad_per_s"]))
    return {"mesh_friction_power_W": loss, "mesh_efficiency": 1.0 - loss / into}


def mesh_force_metrics_arrays(
    t: np.ndarray, f: np.ndarray, mesh_frequency: np.ndarray
) -> dict[str, np.ndarray]:
    """:func:`mesh_force_metrics` of B records at once: t (s) and f (N) shape (B, n_t),
    mesh_frequency (Hz) shape (B,); each value shape (B,). Non-finite samples (a run that
    stopped) are left out of their record; an empty record gives NaN."""
    t = np.asarray(t, dtype=float)
    f = np.asarray(f, dtype=float)
    ok = np.isfinite(f)
    cnt = ok.sum(axis=1)
    fz = np.where(ok, f, 0.0)
    w = 2 * math.pi * np.asarray(mesh_frequency, dtype=float)[:, None]
    with np.errstate(invalid="ignore", divide="ignore"):
        mean = fz.sum(axis=1) / cnt
        ms = (fz**2).sum(axis=1) / cnt
        var = (np.where(ok, f - mean[:, None], 0.0) ** 2).sum(axis=1) / cnt
        amp = 2.0 * np.abs((fz * np.exp(-1j * w * np.where(ok, t, 0.0))).sum(axis=1) / cnt)
        peak = np.where(cnt > 0, np.where(ok, f, -np.inf).max(axis=1), np.nan)
        least = np.where(cnt > 0, np.where(ok, f, np.inf).min(axis=1), np.nan)
        factor = peak / mean
    return {
        "mesh_force_rms_N": np.sqrt(ms),
        "mesh_force_dynamic_rms_N": np.sqrt(var),
        "mesh_force_mean_N": mean,
        "mesh_force_max_N": peak,
        "mesh_force_min_N": least,
        "dynamic_factor": factor,
        "mesh_force_mesh_order_amplitude_N": amp,
    }


def _settling_change(ts: TimeSeries, model: DrivetrainModel, samples_per_cycle: int) -> float:
    n = ts.time.size
    half = (n // samples_per_cycle // 2) * samples_per_cycle
    if half < samples_per_cycle:
        return math.nan
    a = mesh_force_metrics(ts.window(ts.time[0], ts.time[half]), model)
    b = mesh_force_metrics(ts.window(ts.time[n - half]), model)
    k = "mesh_force_mesh_order_amplitude_N"
    return float(abs(a[k] - b[k]) / max(abs(b[k]), 1e-300))


def periodicity_residual(
    t: np.ndarray, Y: np.ndarray, model: DrivetrainModel, period_samples: int
) -> float:
    """max |c(t_end) - c(t_end - T)| / max |c - mean(c)| over the elastic coordinates c
    (shaft twists, mesh deflection, bearing translations) and the speeds, over the last
    common period T of the record (NaN when the record is shorter than T).

    0 for an exactly periodic response; a transient still decaying, or a response that
    is not periodic (e.g. chaotic impacts), gives a large value.
    """
    if period_samples <= 0 or len(t) <= period_samples:
        return math.nan
    n = model.n_dof
    seg = Y[-period_samples - 1 :]
    x, v = seg[:, :n], seg[:, n:]
    # Elastic coordinates only: the rigid-body rotation may drift (the mean speed settles
    # slightly off nominal: the quadratic propeller load rectifies the ripple).
    cols = [x[:, 0] - x[:, 1], x @ model.mesh_vectors()[0], x[:, 2] - x[:, 3]]
    cols += [x[:, i] for i in range(4, n)] + [v[:, i] for i in range(n)]
    worst = 0.0
    for c in cols:
        spread = np.max(np.abs(c - c.mean()))
        if spread > 0:
            worst = max(worst, abs(c[-1] - c[0]) / spread)
    return float(worst)


def simulate(
    model: DrivetrainModel,
    solver: Any = None,
    *,
    settle_time: float | None = None,
    mesh_cycles: int = 200,
    samples_per_cycle: int = 32,
    y0: np.ndarray | None = None,
    start: str = "operating_point",
) -> TimeSeries:
    """Integrate ``model`` with ``solver`` (ScipySolver, DiffraxSolver, ExudynSolver,
    or a name for :func:`default_solver`: 'diffrax', 'scipy', 'exudyn').

    settle_time (s): simulated before the record; default 20 mesh cycles (the start
    state already holds the linear periodic response). mesh_cycles, samples_per_cycle:
    the record's length and sampling (>= 1 each). start: 'operating_point'
    (:func:`periodic_start_state`) or 'periodic' (the settled periodic response by
    shooting, :func:`gearbox.drivetrain.shooting.periodic_response`; settle_time then
    defaults to 0). Returns the record only. Bad arguments raise one
    :class:`~gearbox.errors.InputError` naming each.
    """
    _check_run_arguments(settle_time, mesh_cycles, samples_per_cycle, start)
    if isinstance(solver, str):
        solver = default_solver(solver, mesh_law=model.mesh_law)
    shoot = None
    if start == "periodic" and y0 is None:
        from .shooting import periodic_response

        shoot = periodic_response(model)
        y0 = shoot.y0
        settle_time = 0.0 if settle_time is None else settle_time
    solver = solver if solver is not None else default_solver()
    tm = 1.0 / model.mesh_frequency
    settle = 20 * tm if settle_time is None else float(settle_time)
    t_rec = record_times(model, settle, mesh_cycles, samples_per_cycle)
    # the state at the record's start (t = settle) is sampled too, for the periodicity
    # check, and dropped from the record
    t_eval = np.concatenate([[settle], t_rec]) if settle > 0 else t_rec
    y0 = periodic_start_state(model) if y0 is None else np.asarray(y0, float)
    name = getattr(solver, "name", type(solver).__name__)
    if name == "scipy":
        from .scipy_backend import integrate_scipy

        t, Y, info = integrate_scipy(model, y0, t_eval, solver)
    elif name == "diffrax":
        from .diffrax_backend import integrate_diffrax

        t, Y, info = integrate_diffrax(model, y0, t_eval, solver)
    else:
        from . import exudyn_backend

        t, Y, info = exudyn_backend.integrate_exudyn(model, y0, t_eval, solver)
    t, Y = np.asarray(t), np.asarray(Y)
    if settle > 0 and len(t) and t[0] == settle:
        t_start, y_start = t[0], Y[0]
        t, Y = t[1:], Y[1:]
    else:
        t_start, y_start = 0.0, np.asarray(y0, float)
    ok = np.all(np.isfinite(Y), axis=1) if len(Y) else np.zeros(0, bool)
    t, Y = t[ok], Y[ok]
    ch = outputs(model, t, Y) if len(t) else {k: np.zeros(0) for k in CHANNEL_UNITS}
    attrs = {
        "solver": name,
        "settings": repr(solver),
        "settle_time_s": settle,
        "mesh_cycles": mesh_cycles,
        "samples_per_mesh_cycle": samples_per_cycle,
        "mesh_frequency_Hz": model.mesh_frequency,
        "compile_time_s": info.get("compile_time", 0.0),
        "start": start,
    }
    for k in ("stepping", "contact_loss_steps"):  # the jax backend's fixed-step path
        if k in info:
            attrs[k] = info[k]
    if name == "exudyn":  # its fixed step and build time, as simulate_exudyn gives them
        attrs.update(step_s=info["step"], build_time_s=info["build_time"])
    if shoot is not None:
        attrs.update(
            shooting_iterations=shoot.iterations,
            shooting_residual=shoot.residuals[-1],
            shooting_converged=shoot.converged,
        )
    attrs.update({f"model_{k}": v for k, v in model.meta.items()})
    ts = TimeSeries(
        time=t,
        channels=ch,
        units={k: CHANNEL_UNITS[k] for k in ch},
        status=info["status"],
        failure=info["failure"],
        nfev=info.get("nfev", 0),
        steps=info.get("steps", 0),
        rejected=info.get("rejected", 0),
        wall_time=info["wall_time"],
        attrs=attrs,
    )
    if ts.success:
        import dataclasses

        pc = model.common_period_mesh_cycles()
        tt = np.concatenate([[t_start], t])
        YY = np.concatenate([y_start[None, :], Y])
        res = periodicity_residual(tt, YY, model, pc * samples_per_cycle) if pc else math.nan
        ts = dataclasses.replace(
            ts,
            attrs={
                **attrs,
                "settling_change": _settling_change(ts, model, samples_per_cycle),
                "common_period_mesh_cycles": pc,
                "periodicity_residual": res,
            },
        )
    return ts

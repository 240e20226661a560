"""Reference solver: scipy ``solve_ivp`` on the numpy right-hand side (docs/drivetrain.md).

Integrates the scaled state (``DrivetrainModel.state_scale``), so one ``atol`` fits
every state. Divergence (a mesh deflection beyond ``divergence_factor`` times the
static one plus the backlash), NaN and step-size collapse stop the run and are
reported with the time and the state.
"""

from __future__ import annotations

import time as _time
from dataclasses import dataclass

import numpy as np

from ..errors import Problems
from .model import DrivetrainModel, rhs
from .timeseries import SolverFailure

__all__ = ["ScipySolver", "integrate_scipy"]

_METHODS = ("DOP853", "RK45", "RK23", "LSODA", "Radau", "BDF")


@dataclass(frozen=True)
class ScipySolver:
    """solve_ivp settings. rtol, atol: tolerances on the scaled state (atol None = rtol).

    max_step (s), first_step (s): as in solve_ivp. divergence_factor: see module doc.
    """

    method: str = "DOP853"
    rtol: float = 1e-10
    atol: float | None = None
    max_step: float = np.inf
    first_step: float | None = None
    divergence_factor: float = 1e3

    name = "scipy"

    def validate(self) -> None:
        p = Problems()
        p.check(self.method in _METHODS, "method", self.method, f"must be one of {_METHODS}")
        p.in_range("rtol", self.rtol, 1e-14, 1, lo_open=False, hi_open=True)
        if self.atol is not None:
            p.in_range("atol", self.atol, 0, None, lo_open=True)
        p.in_range("divergence_factor", self.divergence_factor, 1, None, lo_open=True)
        p.raise_if_any("invalid scipy solver settings")


def _check_y0(model: DrivetrainModel, y0) -> None:
    y = np.asarray(y0, dtype=float)
    pr = Problems()
    if pr.check(
        y.shape == (2 * model.n_dof,),
        "y0",
        f"shape {y.shape}",
        f"must have shape ({2 * model.n_dof},)",
    ):
        pr.check(bool(np.all(np.isfinite(y))), "y0", y.tolist(), "must be finite")
    pr.raise_if_any("invalid initial state")


def divergence_bound(model: DrivetrainModel, factor: float) -> float:
    """Mesh deflection (m) beyond which a run counts as diverged."""
    static = model.torque / model.drive.lambda1 / model.drive.mean_stiffness
    b = model.coast.backlash if model.coast is not None else 0.0
    return factor * static + 10 * b


def integrate_scipy(
    model: DrivetrainModel,
    y0: np.ndarray,
    t_eval: np.ndarray,
    solver: ScipySolver = ScipySolver(),
    *,
    t0: float = 0.0,
):
    """Integrate from (t0, y0) and sample at ``t_eval`` (s).

    Returns (t, Y, info): Y unscaled states, shape (n_t, 2 n); info: dict with status,
    failure (SolverFailure or None), nfev, steps, wall_time.
    """
    from scipy.integrate import solve_ivp  # here: the jax path's checks import this module

    solver.validate()
    _check_y0(model, y0)
    p = model.params()
    scale = p["scale"]
    n = model.n_dof
    g = p["G"][0]
    bound = divergence_bound(model, solver.divergence_factor)
    last = {"t": t0, "z": np.asarray(y0, float) / scale, "bad": None}

    def f(t, z):
        dz = rhs(t, z, p)
        if not np.all(np.isfinite(dz)):
            last["bad"] = (t, z.copy())
            raise _NonFinite
        last["t"], last["z"] = t, z
        return dz

    def diverged(t, z):
        return bound - abs(g @ (z[:n] * scale[:n]))

    diverged.terminal = True

    def nan_event(t, z):
        return 1.0 if np.all(np.isfinite(z)) else -1.0

    nan_event.terminal = True
    t_eval = np.asarray(t_eval, dtype=float)
    opts = {}
    if solver.first_step is not None:
        opts["first_step"] = solver.first_step
    start = _time.perf_counter()
    try:
        with np.errstate(all="ignore"):
            sol = solve_ivp(
                f,
                (t0, float(t_eval[-1])),
                np.asarray(y0, float) / scale,
                method=solver.method,
                t_eval=t_eval,
                rtol=solver.rtol,
                atol=solver.atol if solver.atol is not None else solver.rtol,
                max_step=solver.max_step,
                events=[diverged, nan_event],
                **opts,
            )
    except _NonFinite:
        wall = _time.perf_counter() - start
        tb, zb = last["bad"]
        failure = SolverFailure(
            "nan", float(tb), "non-finite right-hand side", tuple((zb * scale).tolist())
        )
        info = {
            "status": "nan",
            "failure": failure,
            "nfev": 0,
            "steps": 0,
            "rejected": 0,
            "wall_time": wall,
            "message": failure.message,
        }
        return np.zeros(0), np.zeros((0, 2 * n)), info
    wall = _time.perf_counter() - start
    Y = (sol.y.T * scale) if sol.y.size else np.zeros((0, 2 * n))
    failure = None
    if sol.status == 1 and len(sol.t_events[0]):
        te = float(sol.t_events[0][0])
        ye = sol.y_events[0][0] * scale
        failure = SolverFailure(
            "divergence", te, f"mesh deflection beyond {bound:.3g} m", tuple(ye.tolist())
        )
    elif sol.status == 1:
        failure = SolverFailure(
            "nan",
            float(sol.t_events[1][0]),
            "non-finite state",
            tuple((sol.y_events[1][0] * scale).tolist()),
        )
    elif sol.status == -1:
        kind = "step_collapse" if "step size" in sol.message.lower() else "solver_error"
        failure = SolverFailure(
            kind, float(last["t"]), sol.message, tuple((last["z"] * scale).tolist())
        )
    info = {
        "status": "success" if failure is None else failure.kind,
        "failure": failure,
        "nfev": int(sol.nfev),
        "steps": int(max(sol.nfev // _stages(solver.method), 0)),
        "rejected": 0,
        "wall_time": wall,
        "message": sol.message,
    }
    return sol.t, Y, info


class _NonFinite(Exception):
    """Raised inside the right-hand side to stop solve_ivp at the first NaN/inf."""


def _stages(method: str) -> int:
    return {"DOP853": 12, "RK45": 6, "RK23": 3}.get(method, 1)

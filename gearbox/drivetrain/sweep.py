"""Speed sweeps: one model at many engine speeds, batched with ``vmap`` (diffrax) or in a loop.

Each speed starts at its own operating point (:func:`periodic_start_state`), settles
for ``settle_cycles`` mesh cycles and records ``mesh_cycles`` whole mesh cycles. The
mean torque and mesh law stay those of the model (the operating torque); only the
speed changes (``DrivetrainModel.with_speed``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import Problems
from .linear import periodic_start_states
from .model import CHANNEL_UNITS, DrivetrainModel, outputs
from .simulate import mesh_force_metrics, mesh_force_metrics_arrays
from .timeseries import TimeSeries

__all__ = ["SpeedSweep", "speed_sweep"]


@dataclass(frozen=True)
class SpeedSweep:
    """Results per speed: rpm, shape (n,); metrics name -> ndarray (n,) (N); status per
    speed; wall_time (s) of the integration (batch) and per speed; timeseries (optional,
    one TimeSeries per speed); setup_time (s): parameters and step plans of a batch;
    contact_loss_steps: per speed, fixed steps out of the nominal contact (those speeds
    were repeated with adaptive steps, DiffraxSolver.contact_rtol)."""

    rpm: np.ndarray
    metrics: dict[str, np.ndarray]
    status: tuple[str, ...]
    wall_time: float
    compile_time: float
    timeseries: tuple[TimeSeries, ...] = ()
    setup_time: float = 0.0
    contact_loss_steps: np.ndarray | None = None

    @property
    def time_per_speed(self) -> float:
        return self.wall_time / max(len(self.rpm), 1)

    def to_dict(self) -> dict[str, Any]:
        return {
            "rpm": self.rpm.tolist(),
            "metrics": {k: v.tolist() for k, v in self.metrics.items()},
            "status": list(self.status),
            "wall_time_s": self.wall_time,
            "compile_time_s": self.compile_time,
            "time_per_speed_s": self.time_per_speed,
            "setup_time_s": self.setup_time,
            "contact_loss_steps": None
            if self.contact_loss_steps is None
            else self.contact_loss_steps.tolist(),
        }


def speed_sweep(
    model: DrivetrainModel,
    rpms,
    solver: Any = None,
    *,
    settle_cycles: int = 20,
    mesh_cycles: int = 100,
    samples_per_cycle: int = 16,
    keep_timeseries: bool = False,
    batch: str = "auto",
) -> SpeedSweep:
    """Run ``model`` at every engine speed in ``rpms`` (rpm).

    With a DiffraxSolver (default), ``batch='vmap'`` runs all speeds as one ``vmap``
    batch (all speeds step in lockstep until the slowest is done: right for a GPU),
    ``batch='loop'`` one compiled run after the other (fixed steps: one compilation for
    all speeds, each running its own steps only); 'auto' picks vmap on a GPU or TPU and
    loop on a CPU (docs/drivetrain.md §11 has the measurements). The set-up per speed
    (start states, parameters, step plans) is array arithmetic, not one model per speed.
    Other solvers, and adaptive diffrax in a loop, run one speed after the other through
    :func:`gearbox.drivetrain.simulate.simulate`.
    """
    from .diffrax_backend import DiffraxSolver, integrate_speeds

    r = np.asarray(rpms, dtype=float).ravel()
    p = Problems()
    p.check(r.size >= 1, "rpms", r.tolist(), "must hold at least one speed")
    p.check(
        bool(np.all(np.isfinite(r) & (r > 0))), "rpms", r.tolist(), "must be finite and > 0 rpm"
    )
    p.check(mesh_cycles >= 1, "mesh_cycles", mesh_cycles, "must be >= 1")
    p.check(batch in ("auto", "vmap", "loop"), "batch", batch, "must be auto, vmap or loop")
    p.raise_if_any("invalid speed sweep")
    solver = solver if solver is not None else DiffraxSolver()
    is_diffrax = getattr(solver, "name", "") == "diffrax"
    if is_diffrax and batch == "auto":
        import jax

        batch = "vmap" if jax.default_backend() != "cpu" else "loop"
    omega = r * math.pi / 30
    if is_diffrax and (batch == "vmap" or not solver.adaptive):
        # Per-speed set-up as array arithmetic: start states by one batched solve, record
        # times by broadcasting, parameters by model.speed_params (no model per speed).
        y0s = periodic_start_states(model, omega)
        tm = 2 * math.pi / (model.pinion_teeth * omega)
        k = np.arange(1, mesh_cycles * samples_per_cycle + 1)
        tev = settle_cycles * tm[:, None] + k[None, :] * (tm / samples_per_cycle)[:, None]
        res = integrate_speeds(
            model, omega, y0s, tev, solver, keep_states=keep_timeseries, batch=batch
        )
        metrics = mesh_force_metrics_arrays(
            tev, res["mesh_force"], model.pinion_teeth * omega / (2 * math.pi)
        )
        series = []
        if keep_timeseries:
            for i, w in enumerate(omega):
                m = model.with_speed(w)
                ok = np.all(np.isfinite(res["states"][i]), axis=1)
                ch = outputs(m, tev[i][ok], res["states"][i][ok])
                series.append(
                    TimeSeries(
                        time=tev[i][ok],
                        channels=ch,
                        units={k: CHANNEL_UNITS[k] for k in ch},
                        status=res["status"][i],
                        failure=res["failure"][i],
                        steps=int(res["steps"][i]),
                        wall_time=res["wall_time"] / r.size,
                        attrs={"solver": "diffrax", "batched": r.size},
                    )
                )
        return SpeedSweep(
            rpm=r,
            metrics=metrics,
            status=res["status"],
            wall_time=res["wall_time"],
            compile_time=res["compile_time"],
            timeseries=tuple(series),
            setup_time=res["setup_time"],
            contact_loss_steps=res["contact_loss_steps"],
        )
    from .simulate import simulate

    wall, comp = 0.0, 0.0
    series: list[TimeSeries] = []
    for w in omega:
        m = model.with_speed(w)
        ts = simulate(
            m,
            solver,
            settle_time=settle_cycles / m.mesh_frequency,
            mesh_cycles=mesh_cycles,
            samples_per_cycle=samples_per_cycle,
        )
        wall += ts.wall_time  # integration only, as for the batch
        comp += float(ts.attrs.get("compile_time_s", 0.0))
        series.append(ts)
    mets = [
        mesh_force_metrics(ts, model.with_speed(w)) for ts, w in zip(series, omega, strict=True)
    ]
    metrics = {k: np.array([d[k] for d in mets]) for k in mets[0]}
    return SpeedSweep(
        rpm=r,
        metrics=metrics,
        status=tuple(ts.status for ts in series),
        wall_time=wall,
        compile_time=comp,
        timeseries=tuple(series) if keep_timeseries else (),
    )

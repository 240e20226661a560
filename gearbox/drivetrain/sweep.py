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
from .linear import periodic_start_state
from .model import CHANNEL_UNITS, DrivetrainModel, outputs
from .simulate import mesh_force_metrics, record_times
from .timeseries import TimeSeries

__all__ = ["SpeedSweep", "speed_sweep"]


@dataclass(frozen=True)
class SpeedSweep:
    """Results per speed: rpm, shape (n,); metrics name -> ndarray (n,) (N); status per
    speed; wall_time (s) of the integration (batch) and per speed; timeseries (optional,
    one TimeSeries per speed)."""

    rpm: np.ndarray
    metrics: dict[str, np.ndarray]
    status: tuple[str, ...]
    wall_time: float
    compile_time: float
    timeseries: tuple[TimeSeries, ...] = ()

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
    ``batch='loop'`` one compiled run after the other (right for a CPU: measured 3x
    cheaper per speed on 200 speeds, 500-3000 rpm, on a 2-core CPU); 'auto' picks vmap
    on a GPU or TPU and loop on a CPU. Other solvers run one speed after the other
    through :func:`gearbox.drivetrain.simulate.simulate`.
    """
    from .diffrax_backend import DiffraxSolver, integrate_diffrax_batch

    r = np.asarray(rpms, dtype=float).ravel()
    p = Problems()
    p.check(r.size >= 1, "rpms", r.tolist(), "must hold at least one speed")
    p.check(bool(np.all(np.isfinite(r) & (r > 0))), "rpms", r.tolist(), "must be > 0 rpm")
    p.check(mesh_cycles >= 1, "mesh_cycles", mesh_cycles, "must be >= 1")
    p.check(batch in ("auto", "vmap", "loop"), "batch", batch, "must be auto, vmap or loop")
    p.raise_if_any("invalid speed sweep")
    solver = solver if solver is not None else DiffraxSolver()
    models = [model.with_speed(x * math.pi / 30) for x in r]
    series: list[TimeSeries] = []
    is_diffrax = getattr(solver, "name", "") == "diffrax"
    if is_diffrax and batch == "auto":
        import jax

        batch = "loop" if jax.default_backend() == "cpu" else "vmap"
    if is_diffrax and batch == "vmap":
        y0s = np.stack([periodic_start_state(m) for m in models])
        tev = np.stack(
            [
                record_times(m, settle_cycles / m.mesh_frequency, mesh_cycles, samples_per_cycle)
                for m in models
            ]
        )
        Y, infos = integrate_diffrax_batch(models, y0s, tev, solver)
        wall, comp = infos[0]["batch_wall_time"], infos[0]["compile_time"]
        for i, m in enumerate(models):
            ok = np.all(np.isfinite(Y[i]), axis=1)
            if keep_timeseries:
                ch = outputs(m, tev[i][ok], Y[i][ok])
            else:  # the mesh force only, computed in the batch (cheap for many speeds)
                ch = {"mesh_force_N": infos[i]["mesh_force"][ok]}
            series.append(
                TimeSeries(
                    time=tev[i][ok],
                    channels=ch,
                    units={k: CHANNEL_UNITS[k] for k in ch},
                    status=infos[i]["status"],
                    failure=infos[i]["failure"],
                    steps=infos[i]["steps"],
                    rejected=infos[i]["rejected"],
                    wall_time=wall / len(models),
                    attrs={"solver": "diffrax", "batched": len(models)},
                )
            )
    else:
        from .simulate import simulate

        wall, comp = 0.0, 0.0
        for m in models:
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
    mets = [mesh_force_metrics(ts, m) for ts, m in zip(series, models, strict=True)]
    metrics = {k: np.array([d[k] for d in mets]) for k in mets[0]}
    return SpeedSweep(
        rpm=r,
        metrics=metrics,
        status=tuple(ts.status for ts in series),
        wall_time=wall,
        compile_time=comp,
        timeseries=tuple(series) if keep_timeseries else (),
    )

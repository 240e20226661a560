"""Work-precision of the exudyn backend: wall time against error, per option and step.

    python benchmarks/bench_exudyn.py [--cycles 100] [--repeat 3] [--quick]

Scene: models/marine_drive.toml (the default scene), analytical mesh tables. Every
run starts from the same operating point, settles 20 mesh cycles and records
``--cycles`` whole mesh cycles at 8 samples per cycle (the fixed-step methods sample
on their step grid, so a coarse record leaves the step free). Error measures of the
dynamic mesh force against scipy DOP853 at rtol 1e-12 (the reference, same run):

- ``err``: RMS of the sample-wise difference over the reference's dynamic (AC) RMS;
- ``dRMS``, ``dAmp``: relative error of the dynamic RMS and of the mesh-order
  amplitude (the quantities the issue's 1e-4 agreement is about).

Options measured (issue 6: "symbolic user functions, pre-step updates, or generic
ODE2 objects: measure the options and keep the best"):

- ``symbolic/components``: the default (bodies, connectors, loads; mesh as a generic
  ODE2 object with a symbolic force function, no Python call per right-hand side);
- ``symbolic/generic``: one generic ODE2 object with matrices and one symbolic force;
- ``python/components``, ``python/generic``: the same with Python user functions;
- ``prestep``: the mesh law k(theta), e(theta), e'(theta) evaluated in Python once per
  step (a pre-step user function) and held in symbolic variables over the step's
  stages; the mesh force itself stays symbolic. One Python call per step instead of
  one per stage, at the price of a frozen mesh law within a step (first order).

Wall times are medians over ``--repeat`` runs on a shared machine; ratios are against
scipy DOP853 measured in the same run. Nothing here is asserted.
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path

import numpy as np

from gearbox.drivetrain import exudyn_backend as xb
from gearbox.drivetrain.model import DrivetrainModel, outputs
from gearbox.drivetrain.scipy_backend import ScipySolver
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
from gearbox.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def metrics(ts, model, ref_force, ref_metrics):
    f = np.asarray(ts["mesh_force_N"])
    if f.size != ref_force.size:
        return math.nan, math.nan, math.nan
    m = mesh_force_metrics(ts, model)
    err = float(np.sqrt(np.mean((f - ref_force) ** 2)) / np.std(ref_force))
    d_rms = abs(m["mesh_force_dynamic_rms_N"] / ref_metrics["mesh_force_dynamic_rms_N"] - 1)
    d_amp = abs(
        m["mesh_force_mesh_order_amplitude_N"] / ref_metrics["mesh_force_mesh_order_amplitude_N"]
        - 1
    )
    return err, d_rms, d_amp


def timed(fn, repeat):
    walls, out = [], None
    for _ in range(repeat):
        out = fn()
        walls.append(out.wall_time)
    return out, statistics.median(walls)


# ------------------------------------------------------------------ pre-step variant
def prestep_run(model, t_eval, y0, step):
    """Mesh law frozen per step: k, e, e' set by a Python pre-step function."""
    import exudyn as exu

    esym = exu.symbolic
    plan = xb._plan_from_model(model)
    plan = xb.dataclasses.replace(plan, x0=y0[: plan.n].copy(), v0=y0[plan.n :].copy())
    solver = xb.ExudynSolver()
    sysm = xb._build_components(plan, solver)
    mbs = sysm.mbs
    # Replace the mesh object's symbolic force by one reading per-step variables.
    names = [(f"k_{fl.name}", f"e_{fl.name}", f"de_{fl.name}") for fl in plan.flanks]
    variables = [tuple(esym.Real(nm, 0.0) for nm in trip) for trip in names]
    mesh_dofs = sorted({1} | {d for fl in plan.flanks for d in np.flatnonzero(fl.G).tolist()})
    pos = {d: j for j, d in enumerate(mesh_dofs)}
    size = len(mesh_dofs)

    def mesh(mbs_, t, itemNumber, q, q_t):
        total = None
        for fl, (k, e, de) in zip(plan.flanks, variables, strict=True):
            term = xb.flank_force_symbolic(plan, fl, pos, size, q, q_t, k, e, de)
            total = term if total is None else total + term
        return total

    uf, keep = xb._record_symbolic(mbs, mesh, "generic", size)
    mbs.SetObjectParameter(sysm.mesh_object, "forceUserFunction", uf)
    arrays = plan.flank_arrays
    pinion = sysm.nodes[1]

    def pre_step(mbs_, t):
        q1 = mbs_.GetNodeOutput(pinion, exu.OutputVariableType.Coordinates)
        theta = plan.omega * t + q1 + plan.theta10
        for fl, ((wk, Rk, pk), (we, Re, pe)), (k, e, de) in zip(
            plan.flanks, arrays, variables, strict=True
        ):
            arg = we * theta - pe
            k.SetValue(fl.k.a0 + float(Rk @ np.cos(wk * theta - pk)))
            e.SetValue(fl.e.a0 + float(Re @ np.cos(arg)))
            de.SetValue(-float((we * Re) @ np.sin(arg)))
        return True

    pre_step(mbs, 0.0)
    mbs.SetPreStepUserFunction(pre_step)
    xb.add_state_sensors(sysm)
    lead = float(t_eval[0])
    n1 = math.ceil(lead / step - 1e-9)
    dt = float(t_eval[1] - t_eval[0])
    sub = math.ceil(dt / step - 1e-9)
    wall = 0.0
    for a, b, nst, wp in (
        (0.0, lead, n1, lead),
        (lead, float(t_eval[-1]), sub * (t_eval.size - 1), dt),
    ):
        t1 = time.perf_counter()
        ok, err, _ = xb._solve(mbs, xb._settings(a, b, nst, wp), "RK67")
        wall += time.perf_counter() - t1
        assert ok, err
    t, Y = xb._stored(sysm)
    del keep, uf
    return t, Y, wall, n1 + sub * (t_eval.size - 1)


class _TS:
    """Minimal stand-in holding the mesh force of a pre-step run for the metrics."""

    def __init__(self, model, t, Y, wall):
        self.time = t
        self.wall_time = wall
        self._f = outputs(model, t, Y)["mesh_force_N"]

    def __getitem__(self, key):
        return self._f


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cycles", type=int, default=100, help="recorded mesh cycles")
    ap.add_argument("--repeat", type=int, default=3, help="runs per setting (median wall)")
    ap.add_argument("--quick", action="store_true", help="fewer settings")
    args = ap.parse_args()

    model = DrivetrainModel.from_scene(load_scene(ROOT / "models" / "marine_drive.toml"))
    tm = 1.0 / model.mesh_frequency
    kw = {"mesh_cycles": args.cycles, "samples_per_cycle": 8}
    print(
        f"scene marine_drive: mesh frequency {model.mesh_frequency:.1f} Hz, "
        f"{args.cycles} recorded mesh cycles ({args.cycles * tm * 1e3:.1f} ms) after 20 settling cycles"
    )
    f_mode, _ = xb._max_frequency(xb._plan_from_model(model))
    print(
        f"highest eigenfrequency (mesh at max stiffness) {f_mode:.0f} Hz; "
        f"stability limit RK67 {xb.stability_step_limit(model, 'RK67'):.3e} s, "
        f"RK44 {xb.stability_step_limit(model, 'RK44'):.3e} s"
    )
    t0 = time.perf_counter()
    ref = simulate(model, ScipySolver(rtol=1e-12), **kw)
    print(f"reference scipy DOP853 rtol 1e-12: {time.perf_counter() - t0:.1f} s, nfev {ref.nfev}\n")
    ref_f = np.asarray(ref["mesh_force_N"])
    ref_m = mesh_force_metrics(ref, model)

    rows = []
    for rtol in (1e-6, 1e-8) if args.quick else (1e-5, 1e-6, 1e-7, 1e-8):
        ts, wall = timed(lambda r=rtol: simulate(model, ScipySolver(rtol=r), **kw), args.repeat)
        rows.append(
            ("scipy DOP853", f"rtol {rtol:g}", wall, ts.nfev, *metrics(ts, model, ref_f, ref_m))
        )
    base = {r[1]: r[2] for r in rows}

    spcs = (10, 20, 40) if args.quick else (8, 10, 14, 20, 28, 40)
    for method in ("RK67", "RK44"):
        for spc in spcs:
            s = xb.ExudynSolver(method=method, steps_per_period=spc)
            ts, wall = timed(lambda s=s: simulate(model, s, **kw), args.repeat)
            rows.append(
                (
                    f"exudyn {method} symbolic/components",
                    f"{spc} steps/period",
                    wall,
                    ts.nfev,
                    *metrics(ts, model, ref_f, ref_m),
                )
            )
    for uf, layout in (("symbolic", "generic"), ("python", "components"), ("python", "generic")):
        s = xb.ExudynSolver(user_functions=uf, layout=layout)
        ts, wall = timed(lambda s=s: simulate(model, s, **kw), args.repeat)
        rows.append(
            (
                f"exudyn RK67 {uf}/{layout}",
                "20 steps/period (default)",
                wall,
                ts.nfev,
                *metrics(ts, model, ref_f, ref_m),
            )
        )
    # pre-step updates, same step as the default
    from gearbox.drivetrain.linear import periodic_start_state
    from gearbox.drivetrain.simulate import record_times

    plan = xb._plan_from_model(model)
    for spc in (20, 80):
        step = 1.0 / (spc * max(xb._max_frequency(plan)))
        t_eval = record_times(model, 20 * tm, args.cycles, 8)
        y0 = periodic_start_state(model)
        walls = []
        for _ in range(args.repeat):
            t, Y, wall, steps = prestep_run(model, t_eval, y0, step)
            walls.append(wall)
        ts = _TS(model, t_eval, Y[-t_eval.size :], statistics.median(walls))
        rows.append(
            (
                "exudyn RK67 prestep",
                f"{spc} steps/period",
                ts.wall_time,
                7 * steps,
                *metrics(ts, model, ref_f, ref_m),
            )
        )

    print(
        f"{'solver':40s} {'setting':26s} {'wall s':>8s} {'nfev':>8s} {'err':>9s} {'dRMS':>9s} "
        f"{'dAmp':>9s} {'vs DOP853 1e-6':>15s}"
    )
    b6 = base.get("rtol 1e-06", rows[0][2])
    for name, setting, wall, nfev, err, drms, damp in rows:
        print(
            f"{name:40s} {setting:26s} {wall:8.3f} {nfev:8d} {err:9.1e} {drms:9.1e} {damp:9.1e} "
            f"{b6 / wall:14.1f}x"
        )

    # Throughput: one simulated second at the rated speed, default settings, no record
    # spacing limit (samples every 8 steps' worth).
    s = xb.ExudynSolver()
    y0 = model.static_state()
    h = xb._target_step(plan, s)
    t_eval = np.arange(1, 1001) * 1e-3
    walls = []
    for _ in range(args.repeat):
        _, _, info = xb.integrate_exudyn(model, y0, t_eval, s)
        walls.append(info["wall_time"])
    print(
        f"\none simulated second (default RK67, step {info['step']:.3e} s, target {h:.3e} s): "
        f"median wall {statistics.median(walls):.2f} s, {info['steps']} steps, "
        f"{statistics.median(walls) / info['nfev'] * 1e6:.2f} us per right-hand side"
    )


if __name__ == "__main__":
    main()

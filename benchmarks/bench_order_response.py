"""Steady order responses against the nonlinear runs: run time and error.

For the default scene (or ``--scene``), on its propeller law at ``--speeds`` engine
speeds across the sweep range, the mesh force's amplitude at every excitation order
from

- the nonlinear fixed-step run of ``gearbox run`` (settled record over one common
  period of all orders, rectangular window): the reference;
- ``gearbox.drivetrain.linear.order_responses``: every order by harmonic balance with
  the time-varying stiffness (engine and propeller orders with their sidebands about
  the mesh orders, docs/drivetrain.md "Steady order responses");
- the mean-stiffness solution of the start states (every order alone on the linear
  model, mesh forcing to first order): what the harmonic balance replaces.

Prints per order the largest relative error over the speeds of both linear
solutions (orders under ``--floor`` of the largest line at a speed are left out),
and the wall time per speed of each: medians over the speeds; the ratio of the run's
time to the response's, measured in the same run. Usage::

    PYTHONPATH=. python3 benchmarks/bench_order_response.py [--speeds 10] [--cache DIR]
"""

from __future__ import annotations

import argparse
import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]


def mean_stiffness_mesh_force(model, orders):
    """Mesh force amplitudes of the start states' linear solution: each order alone,
    the mesh forcing to first order (k_bar in the stiffness), by order."""
    from gearbox.drivetrain import linear

    y = model.static_state()
    exc = linear._excitations(model, y[: model.n_dof], 12)
    w, X = linear._steady_amplitudes(model, np.array([model.speed]), exc)
    g = model.mesh_vectors()[0]
    fl = model.drive
    f = (fl.mean_stiffness + 1j * w[0] * fl.damping) * (X[0] @ g) + exc.mesh_forcing
    out = {}
    for o in orders:
        hit = np.flatnonzero(np.isclose(exc.orders, o, rtol=1e-9))
        out[o] = float(abs(f[hit[0]])) if hit.size else 0.0
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--scene", default=str(ROOT / "models" / "marine_drive.toml"))
    ap.add_argument("--speeds", type=int, default=10)
    ap.add_argument("--cache", default=None, help="cache folder of the mesh tables")
    ap.add_argument("--floor", type=float, default=1e-2, help="orders below this x largest")
    args = ap.parse_args()

    from gearbox import load_scene, spectrum
    from gearbox.drivetrain.linear import order_responses
    from gearbox.pipeline import run_pipeline
    from gearbox.pipeline.adapters import dynamics as dy

    scene = load_scene(args.scene)
    table = run_pipeline(scene, ["tables"], cache=args.cache or True)["tables"]
    lo, hi = scene["simulation"]["speed_sweep_rpm"][:2]
    solver = dy.solver_of(scene)
    sim = dict(scene["simulation"])
    t_run, t_hb, t_lin = [], [], []
    err_hb: dict[str, float] = {}
    err_lin: dict[str, float] = {}
    for n in np.linspace(lo, hi, args.speeds):
        model = dy.model_at(scene, table, n)
        exc = dy._orders(model)
        t0 = time.perf_counter()
        ts, _ = dy._simulate(model, solver, sim)
        t_run.append(time.perf_counter() - t0)
        period = spectrum.common_period_revs([e.order for e in exc])
        s = spectrum.order_spectrum(
            ts.time,
            ts["mesh_force_N"],
            angle=np.asarray(ts["pinion_angle_rad"]),
            period_revs=period,
            window="rectangular",
        )
        ref = {e.order: s.amplitudes[np.argmin(np.abs(s.orders - e.order))] for e in exc}
        t0 = time.perf_counter()
        r = order_responses(model)
        t_hb.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        lin = mean_stiffness_mesh_force(model, [e.order for e in exc])
        t_lin.append(time.perf_counter() - t0)
        big = max(ref.values())
        for e in exc:
            if ref[e.order] < args.floor * big:
                continue
            a = abs(r.peaks(e.order)["mesh_force_N"] / ref[e.order] - 1)
            b = abs(lin[e.order] / ref[e.order] - 1)
            err_hb[e.label] = max(err_hb.get(e.label, 0.0), a)
            err_lin[e.label] = max(err_lin.get(e.label, 0.0), b)
    print(f"scene {args.scene}; {args.speeds} speeds {lo:g}-{hi:g} rpm on the propeller law")
    print(f"orders above {args.floor:g} x the largest line at each speed\n")
    print(f"{'order':<14}{'harmonic balance':>18}{'mean stiffness':>18}")
    print("-" * 50)
    for label in err_hb:
        print(f"{label:<14}{100 * err_hb[label]:>16.3f} %{100 * err_lin[label]:>16.3f} %")
    run, hb, li = (statistics.median(x) for x in (t_run, t_hb, t_lin))
    print("\nwall time per speed, median (s)")
    print(f"  nonlinear run (after the first's compilation): {run:.4f}")
    print(f"  order_responses (harmonic balance):            {hb:.5f}  run / this {run / hb:.0f}")
    print(f"  mean-stiffness solution:                       {li:.5f}  run / this {run / li:.0f}")


if __name__ == "__main__":
    main()

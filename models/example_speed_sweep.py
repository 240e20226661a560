"""Speed sweep of the default marine drive with a heavier propeller: a script to copy.

What it does, step by step:

1. load the default scene and change one parameter (the propeller inertia);
2. get the mesh tables through the pipeline (cached on disk, see docs/pipeline.md);
3. build one drivetrain model per engine speed on the propeller law
   (torque proportional to speed squared);
4. simulate the speeds in parallel (any ``concurrent.futures.Executor``);
5. take the order spectrum of the mesh force at each speed and plot the spectrum at
   the top speed and the mesh-order amplitude against speed.

Run it from the repository root::

    python models/example_speed_sweep.py                      # 8 speeds, all cores
    python models/example_speed_sweep.py --speeds 4 --jobs 2 --out sweep.png
"""

from __future__ import annotations

import argparse
from pathlib import Path

from gearbox import load_scene
from gearbox.drivetrain import DrivetrainModel
from gearbox.drivetrain.simulate import default_solver, simulate
from gearbox.pipeline import map_items, run_pipeline
from gearbox.spectrum import order_spectrum

HERE = Path(__file__).resolve().parent


def one_speed(job):
    """Simulate one speed; return (speed_rpm, order spectrum of the mesh force).

    Module level, so that worker processes can run it.
    """
    speed_rpm, model, solver, mesh_cycles = job
    ts = simulate(model, solver, mesh_cycles=mesh_cycles, samples_per_cycle=32)
    if not ts.success:
        raise RuntimeError(f"{speed_rpm:.0f} rpm: {ts.status}")
    spectrum = order_spectrum(
        ts.time,
        ts["mesh_force_N"],
        angle=ts["pinion_angle_rad"],  # order tracking on the pinion angle
        period_revs=1.0,  # whole pinion revolutions ...
        window="flattop",  # ... and a flat-top window for the non-integer orders
        name="mesh force",
        unit="N",
    )
    return speed_rpm, spectrum


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--speeds", type=int, default=8, help="engine speeds in the sweep")
    ap.add_argument("--mesh-cycles", type=int, default=120, help="recorded mesh cycles per speed")
    ap.add_argument("--jobs", type=int, default=None, help="worker processes (default: all cores)")
    ap.add_argument("--out", default="example_speed_sweep.png", help="figure file (PNG)")
    args = ap.parse_args(argv)

    # 1. the default scene with a heavier propeller (0.08 -> 0.12 kg m^2)
    scene = load_scene(HERE / "marine_drive.toml")
    scene = scene.replaced(drivetrain={"propeller_inertia_kgm2": 0.12})

    # 2. mesh tables (loaded TCA where installed, else analytical: see table.attrs)
    table = run_pipeline(scene, ["tables"])["tables"]
    print("mesh tables:", table.attrs["method"])

    # 3. one model per speed on the propeller law: P ~ n^3, i.e. T ~ n^2
    drive = scene["drivetrain"]
    n0, p0 = drive["engine_speed_rpm"], drive["engine_power_kW"]
    lo, hi = scene["simulation"]["speed_sweep_rpm"]
    solver = default_solver(scene["simulation"]["solver"], scene["simulation"]["rtol"])
    jobs = []
    for i in range(args.speeds):
        n = lo + (hi - lo) * i / max(args.speeds - 1, 1)
        at_n = scene.replaced(
            drivetrain={"engine_speed_rpm": n, "engine_power_kW": p0 * (n / n0) ** 3}
        )
        jobs.append((n, DrivetrainModel.from_scene(at_n, table), solver, args.mesh_cycles))

    # 4. the sweep, in parallel (pass executor=... to use a Dask cluster instead)
    results = map_items(one_speed, jobs, jobs=args.jobs, progress=True, desc="speeds")

    # 5. mesh-order amplitude against speed, and the spectrum at the top speed
    mesh_order = scene["pinion"]["teeth"]
    amplitudes = [(n, s.amplitude_at(mesh_order)) for n, s in results]
    for n, a in amplitudes:
        print(f"{n:7.0f} rpm  mesh-order amplitude of the mesh force {a:10.1f} N")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gearbox.spectrum.plotting import plot_order_spectrum

    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4), layout="constrained")
    plot_order_spectrum(results[-1][1], ax1, max_order=3.2 * mesh_order)
    ax2.plot([n for n, _ in amplitudes], [a / 1e3 for _, a in amplitudes], "o-")
    ax2.set(xlabel="engine speed (rpm)", ylabel="mesh-order amplitude (kN)")
    ax2.set_title(f"order {mesh_order} (mesh) of the mesh force", fontsize=9)
    ax2.grid(True, alpha=0.3)
    fig.savefig(args.out, dpi=110)
    plt.close(fig)
    print("wrote", args.out)
    return {"amplitudes": amplitudes, "spectra": [s for _, s in results], "figure": args.out}


if __name__ == "__main__":
    main()

"""Benchmark: the drivetrain FMU against real time and beside the Python solvers.

One second of the default scene (models/marine_drive.toml) at 2000 rpm and the scene's
operating torque, from the static equilibrium. The FMU runs in Co-Simulation with a
communication step of 1 ms (about one mesh period; the internal integrator takes its
own steps in between: adaptive DOPRI5 at several tolerances, and the fixed-step Tsit5,
the Co-Simulation default, with its default rule and with fewer steps), driven three ways: from C (fmus/harness/fmu_bench.c: the wall
time of the doStep calls alone, no importer), from a Python loop over fmpy's FMU2Slave
(wall time of the loop and, separately, of its doStep calls) and by fmpy's
simulate_fmu. Prints the median wall time over repeats (21 runs for the C driver, whose
smallest time, nearest to an unloaded machine, is in the note), the real-time factor
(simulated time over wall time), the ratio to the C driver at rtol 1e-6 (the baseline, measured in
the same run), the error of the mesh force (RMS difference over the AC RMS of a
reference run: the FMU in Co-Simulation at rtol 1e-12, compared at the communication
points; tests/test_fmu.py checks the FMU against the scipy solver) and the integrator's
work.

    python3 benchmarks/bench_fmu.py            # all tables (about 3 minutes)
    python3 benchmarks/bench_fmu.py --quick    # FMU rows of the performance table only

Two more tables at the scene's own speed (3500 rpm): the agreement of the FMU (both
interfaces) with the scipy solver at rtol 1e-10 over 0.1 s, and the coupling error of
the libcosim co-simulation against the monolithic FMU (rtol 1e-10) over 0.05 s as a
function of the communication step, with held and with extrapolated inputs.
"""

from __future__ import annotations

import argparse
import math
import shutil
import statistics
import subprocess
import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.drivetrain.model import outputs
from gearbox.fmu import build_fmu, drivetrain_fmu
from gearbox.fmu.cosim import build_cosim_fmus, cosim_drivetrain
from gearbox.fmu.models import model_from_scene
from gearbox.fmu.run import ac_relative_error, simulate_fmu

SCENE = Path(__file__).parents[1] / "models" / "marine_drive.toml"
SPEED_RPM = 2000.0
STOP = 1.0
DT = 1e-4  # output step of the reference and of the Python solvers
COMM = 1e-3  # communication step of the FMU rows
RTOLS = (1e-4, 1e-5, 1e-6, 1e-7, 1e-8)
#: Fixed-step Tsit5 rows (solver.method = 1): the default rule, and the bare 1 / (12 f_max)
#: without the cap of 32 steps per mesh period (at 2000 rpm: 35.5 us instead of 32.3 us).
FIXED = {
    "fixed Tsit5 (default)": {},
    "fixed Tsit5, 12 / period of f_max only": {"solver.steps_per_mesh_period": 2.0},
}


def adaptive(rtol: float) -> dict[str, float]:
    """Settings of the FMU's adaptive DOPRI5 at ``rtol``."""
    return {"solver.method": 0.0, "solver.rtol": rtol}


C_REPEATS = 21  # runs of the C driver per row (each well under 0.1 s)


def median_time(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def common_points(t, t_ref) -> tuple[np.ndarray, np.ndarray]:
    """All of t, and the points of t_ref on t's grid (both grids start at 0)."""
    step = float(t[1] - t[0])
    k = np.abs(t_ref / step - np.round(t_ref / step)) < 1e-6
    k &= t_ref <= t[-1] + 1e-12
    return np.arange(len(t)), np.flatnonzero(k)


def c_driver(fmu_path: str, tmp: Path) -> tuple[Path, Path, str, str, dict[str, int]]:
    """Compile fmus/harness/fmu_bench.c against the FMU's headers; unzip the FMU."""
    from fmpy import read_model_description

    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = tmp / "unzipped"
    zipfile.ZipFile(fmu_path).extractall(d)
    exe = tmp / "fmu_bench"
    src = Path(__file__).parents[1] / "fmus" / "harness" / "fmu_bench.c"
    subprocess.run(
        ["gcc", "-std=c11", "-O2", "-I", str(d / "sources"), str(src), "-ldl", "-o", str(exe)],
        check=True,
    )
    return exe, d, md.coSimulation.modelIdentifier, md.guid, vr


def c_driver_wall(driver, settings: dict, step: float, repeats: int) -> tuple[float, float]:
    """Median and smallest wall time (s) of the doStep calls of one run, from C, with the
    parameter ``settings`` (name -> value) set in initialization mode."""
    exe, d, ident, guid, vr = driver
    sets = ",".join(f"{vr[k]}={v!r}" for k, v in settings.items()) or f"{vr['solver.method']}=1.0"
    p = subprocess.run(
        [str(exe), str(d), ident, guid, sets, repr(STOP), repr(step), str(repeats)],
        capture_output=True,
        text=True,
        check=True,
    )
    words = p.stdout.split()
    return float(words[2]), float(words[-2])


def python_loop(fmu_path: str, settings: dict, step: float):
    """One Co-Simulation run from a Python loop over fmpy's FMU2Slave with the parameter
    ``settings``: (wall time of the loop, wall time of its doStep calls, time, mesh force,
    (steps, rejected, rhs, fixed step (s)))."""
    from fmpy import extract, read_model_description
    from fmpy.fmi2 import FMU2Slave

    md = read_model_description(fmu_path)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    d = extract(fmu_path)
    try:
        s = FMU2Slave(
            guid=md.guid,
            unzipDirectory=d,
            modelIdentifier=md.coSimulation.modelIdentifier,
            instanceName="bench",
        )
        s.instantiate()
        s.setupExperiment(startTime=0.0)
        s.enterInitializationMode()
        for k, v in settings.items():
            s.setReal([vr[k]], [v])
        s.exitInitializationMode()
        n = int(round(STOP / step))
        force = [vr["mesh.force"]]
        f = np.empty(n + 1)
        f[0] = s.getReal(force)[0]
        in_step = 0.0
        t0 = time.perf_counter()
        for i in range(n):
            a = time.perf_counter()
            s.doStep(i * step, step)
            in_step += time.perf_counter() - a
            f[i + 1] = s.getReal(force)[0]
        wall = time.perf_counter() - t0
        work = s.getReal(
            [vr[f"solver.{k}"] for k in ("steps", "rejected", "rhs_evaluations", "step_size")]
        )
        s.terminate()
        s.freeInstance()
    finally:
        shutil.rmtree(d, ignore_errors=True)
    return wall, in_step, np.arange(n + 1) * step, f, tuple(work)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--quick", action="store_true", help="FMU rows only")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args()
    scene = load_scene(SCENE)
    d = scene["drivetrain"]
    # same engine torque as the scene's operating point (inside the mesh table), at 2000 rpm
    torque = d["engine_power_kW"] * 1e3 / (d["engine_speed_rpm"] * math.pi / 30)
    scene = scene.replaced(
        drivetrain={
            "engine_speed_rpm": SPEED_RPM,
            "engine_power_kW": torque * SPEED_RPM * math.pi / 30 / 1e3,
        }
    )
    model, table = model_from_scene(scene)
    tmp = Path(tempfile.mkdtemp(prefix="bench_fmu_"))
    fmu = build_fmu(drivetrain_fmu(model, table), tmp).fmu
    t_ref, ch, _ = simulate_fmu(fmu, stop_time=STOP, step=DT, rtol=1e-12, outputs=["mesh.force"])
    f_ref = ch["mesh.force"]
    print(
        f"scene {SCENE.name} at {SPEED_RPM:g} rpm, {STOP:g} s simulated, "
        f"mesh frequency {model.mesh_frequency:.1f} Hz; FMU communication step {COMM:g} s, "
        f"Python solvers' outputs every {DT:g} s"
    )
    print(
        f"reference: FMU Co-Simulation, DOPRI5 rtol 1e-12; mesh force AC RMS {np.std(f_ref):.1f} N"
    )
    rows = []

    def err_of(t, f):
        if f is None:
            return float("nan")
        i, k = common_points(t, t_ref)
        return ac_relative_error(t[i], f[i], t_ref[k], f_ref[k])

    def row(name, setting, wall, t, f, note=""):
        rows.append((name, setting, wall, err_of(t, f), note))

    driver = c_driver(fmu, tmp)
    settings = {f"rtol {r:.0e}": adaptive(r) for r in RTOLS}
    settings.update(FIXED)
    for label, sets in settings.items():
        loop = [python_loop(fmu, sets, COMM) for _ in range(args.repeats)]
        wall = statistics.median(r[0] for r in loop)
        in_step = statistics.median(r[1] for r in loop)
        _, _, t, f, (steps, rejected, rhs, h) = loop[0]
        err = err_of(t, f)
        c_wall, c_min = c_driver_wall(driver, sets, COMM, C_REPEATS)
        work = (
            f"min {c_min:.4f} s ({STOP / c_min:.0f} x); {steps:.0f} steps, {rejected:.0f} "
            f"rejected, {rhs:.0f} rhs ({c_min / rhs * 1e9:.0f} ns per rhs at the min)"
        )
        if label.startswith("fixed"):
            work += f"; step {h * 1e6:.2f} us"
        rows.append(("FMU Co-Simulation, C driver", label, c_wall, err, work))
        rows.append(
            (
                "FMU Co-Simulation, Python loop",
                label,
                wall,
                err,
                f"doStep calls {in_step:.4f} s ({STOP / in_step:.0f} x real time)",
            )
        )
    for label in ("rtol 1e-06", "rtol 1e-08", "fixed Tsit5 (default)"):
        c_wall, c_min = c_driver_wall(driver, settings[label], DT, C_REPEATS)
        wall, (t, c, _) = median_time(
            lambda s=settings[label]: simulate_fmu(
                fmu, stop_time=STOP, step=DT, start_values=s, outputs=["mesh.force"]
            ),
            3,
        )
        rows.append(
            (
                "FMU Co-Simulation, C driver",
                f"{label}, step {DT:g} s",
                c_wall,
                err_of(t, c["mesh.force"]),
                f"10^4 doStep calls; min {c_min:.4f} s ({STOP / c_min:.0f} x)",
            )
        )
        row(
            "FMU Co-Simulation, fmpy simulate_fmu",
            f"{label}, step {DT:g} s",
            wall,
            t,
            c["mesh.force"],
        )
    wall, (t, c, _) = median_time(
        lambda: simulate_fmu(
            fmu,
            interface="ModelExchange",
            stop_time=STOP,
            step=DT,
            rtol=1e-8,
            outputs=["mesh.force"],
        ),
        1,
    )
    row("FMU Model Exchange (fmpy CVode)", "rtol 1e-8", wall, t, c["mesh.force"])
    builds = build_cosim_fmus(model, table, tmp / "cosim")
    for step in (1e-4, 5e-5):
        wall, res = median_time(
            lambda s=step: cosim_drivetrain(
                model, table, tmp / "cosim", step=s, stop_time=STOP, builds=builds
            ),
            1,
        )
        rows.append(
            (
                "libcosim: engine + gearbox + propeller",
                f"step {step:g} s, rates",
                wall,
                err_of(res.time, res["mesh_force_N"]),
                "coupling error",
            )
        )
    if not args.quick:
        y0 = model.static_state()
        t_eval = t_ref
        from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy

        wall, (t, y, _) = median_time(
            lambda: integrate_scipy(model, y0, t_eval, ScipySolver(rtol=1e-6)), 1
        )
        row("scipy solve_ivp DOP853", "rtol 1e-6", wall, t, outputs(model, t, y)["mesh_force_N"])
        try:
            from gearbox.drivetrain.diffrax_backend import DiffraxSolver, integrate_diffrax

            wall0, _ = median_time(
                lambda: integrate_diffrax(model, y0, t_eval, DiffraxSolver(rtol=1e-6)), 1
            )
            wall, (t, y, _) = median_time(
                lambda: integrate_diffrax(model, y0, t_eval, DiffraxSolver(rtol=1e-6)), 1
            )
            row(
                "diffrax Tsit5 (jit)",
                "rtol 1e-6",
                wall,
                t,
                outputs(model, t, y)["mesh_force_N"],
                f"first call {wall0:.2f} s incl. compile",
            )
            wall0, _ = median_time(lambda: integrate_diffrax(model, y0, t_eval, DiffraxSolver()), 1)
            wall, (t, y, info) = median_time(
                lambda: integrate_diffrax(model, y0, t_eval, DiffraxSolver()), 3
            )
            row(
                "diffrax fixed Tsit5 (default, jit)",
                "12 / period of f_max",
                wall,
                t,
                outputs(model, t, y)["mesh_force_N"],
                f"first call {wall0:.2f} s incl. compile; {info.get('steps')} steps",
            )
        except Exception as exc:  # a backend missing on this machine is a row, not a crash
            rows.append(("diffrax Tsit5", "rtol 1e-6", float("nan"), float("nan"), repr(exc)[:60]))
        try:
            from gearbox.drivetrain.exudyn_backend import ExudynSolver, integrate_exudyn

            wall, (t, y, _) = median_time(
                lambda: integrate_exudyn(model, y0, t_eval, ExudynSolver()), 1
            )
            row("exudyn", "RK67, default step", wall, t, outputs(model, t, y)["mesh_force_N"])
        except Exception as exc:
            rows.append(("exudyn", "RK67", float("nan"), float("nan"), repr(exc)[:60]))
    base = next(r[2] for r in rows if r[0].endswith("C driver") and r[1] == "rtol 1e-06")
    print()
    print(
        f"| {'method':<38} | {'setting':<22} | wall (s) | x real time | / C 1e-6 | error | note |"
    )
    print(f"|{'-' * 40}|{'-' * 24}|---|---|---|---|---|")
    for name, setting, wall, err, note in rows:
        print(
            f"| {name:<38} | {setting:<22} | {wall:8.4f} | {STOP / wall:11.3g} | "
            f"{wall / base:8.2f} | {err:.1e} | {note} |"
        )
    if not args.quick:
        agreement(tmp)
        coupling(tmp)
    shutil.rmtree(tmp, ignore_errors=True)


def agreement(tmp: Path) -> None:
    from gearbox.drivetrain.scipy_backend import ScipySolver, integrate_scipy

    model, table = model_from_scene(load_scene(SCENE))
    fmu = build_fmu(drivetrain_fmu(model, table), tmp / "agree").fmu
    stop = 0.1
    t = np.linspace(0.0, stop, int(round(stop / DT)) + 1)
    tt, y, _ = integrate_scipy(model, model.static_state(), t, ScipySolver(rtol=1e-10))
    ref = outputs(model, tt, y)
    pairs = {
        "mesh.force": "mesh_force_N",
        "mesh.dte": "dynamic_transmission_error_m",
        "input_shaft.torque": "input_shaft_torque_Nm",
        "output_shaft.torque": "output_shaft_torque_Nm",
        "engine.w": "engine_speed_rad_per_s",
    }
    print(
        f"\nagreement with scipy DOP853 rtol 1e-10, {SCENE.name} at "
        f"{model.speed * 30 / math.pi:g} rpm, {stop:g} s: RMS error / AC RMS of scipy"
    )
    print("| interface | rtol | " + " | ".join(pairs) + " |")
    print("|---|---|" + "---|" * len(pairs))
    runs = [("CoSimulation", None), ("CoSimulation", 1e-6), ("CoSimulation", 1e-8)]
    runs += [("ModelExchange", 1e-6), ("ModelExchange", 1e-8)]
    for interface, rtol in runs:
        t1, ch, _ = simulate_fmu(
            fmu, interface=interface, stop_time=stop, step=DT, rtol=rtol, outputs=list(pairs)
        )
        errs = [ac_relative_error(t1, ch[k], tt, ref[v]) for k, v in pairs.items()]
        setting = "fixed Tsit5 (default)" if rtol is None else f"{rtol:.0e}"
        print(f"| {interface} | {setting} | " + " | ".join(f"{e:.1e}" for e in errs) + " |")


def coupling(tmp: Path) -> None:
    model, table = model_from_scene(load_scene(SCENE))
    stop = 0.05
    mono = build_fmu(drivetrain_fmu(model, table), tmp / "coupling").fmu
    t, ch, _ = simulate_fmu(
        mono,
        stop_time=stop,
        step=5e-6,
        rtol=1e-10,
        outputs=["mesh.force", "input_shaft.torque", "output_shaft.torque"],
    )
    builds = build_cosim_fmus(model, table, tmp / "coupling")
    print(
        f"\ncoupling error against the monolithic FMU, {SCENE.name} at "
        f"{model.speed * 30 / math.pi:g} rpm, {stop:g} s: RMS error / AC RMS at the "
        "communication points"
    )
    print(
        "| step (s) | inputs | mesh force | input shaft torque | output shaft torque | wall (s) |"
    )
    print("|---|---|---|---|---|---|")
    for step in (1e-4, 5e-5, 2e-5, 1e-5, 5e-6):
        for extrapolate in (False, True):
            res = cosim_drivetrain(
                model,
                table,
                tmp / "coupling",
                step=step,
                stop_time=stop,
                builds=builds,
                extrapolate=extrapolate,
            )
            k = np.abs(t / step - np.round(t / step)) < 1e-6
            k &= t <= res.time[-1] + 1e-12
            errs = [
                ac_relative_error(res.time, res[a], t[k], ch[b][k])
                for a, b in (
                    ("mesh_force_N", "mesh.force"),
                    ("input_shaft_torque_Nm", "input_shaft.torque"),
                    ("output_shaft_torque_Nm", "output_shaft.torque"),
                )
            ]
            how = "extrapolated" if extrapolate else "held"
            print(
                f"| {step:g} | {how} | "
                + " | ".join(f"{e:.1e}" for e in errs)
                + f" | {res.wall_time:.2f} |"
            )


if __name__ == "__main__":
    main()

"""Work-precision of the drivetrain solvers on the default scene (paper case 03).

Prints tables, not pass/fail:

1. work-precision: wall time against the relative error of the RMS and of the
   mesh-order amplitude of the mesh force, for scipy solve_ivp (LSODA, DOP853, Radau)
   and diffrax (Tsit5, Dopri8) at several tolerances, against a tight reference
   (scipy DOP853, rtol 1e-11) on the same record; the ratio of the fastest scipy
   setting reaching 1e-4 to the fastest diffrax setting reaching it;
2. one second of simulated time at 2000 rpm: the default solver and the options tried
   for it (diffrax adaptive and constant-step, lax.scan with other right-hand sides,
   truncated mesh tables), wall time (after compilation), steps, per-step cost, errors
   against diffrax Dopri8 at rtol 1e-12;
3. a sweep of N speeds, vmap batch and loop, fixed and adaptive steps: set-up, compile
   and integration time per speed.

Walls are medians of repeated runs (the machine is shared); ratios are measured in the
same run. Usage:

    python benchmarks/bench_dynamics.py            # full (several minutes on 2 cores)
    python benchmarks/bench_dynamics.py --quick    # shorter record, fewer settings
    python benchmarks/bench_dynamics.py --sweep-only --speeds 4096   # e.g. on a GPU
    python benchmarks/bench_dynamics.py --sweep-only --no-adaptive-sweep
    python benchmarks/bench_dynamics.py --no-work-precision   # sections 2 and 3
"""

from __future__ import annotations

import argparse
import math
import statistics
import time
from pathlib import Path

import numpy as np

from gearbox.drivetrain.diffrax_backend import DiffraxSolver
from gearbox.drivetrain.model import DrivetrainModel
from gearbox.drivetrain.scipy_backend import ScipySolver
from gearbox.drivetrain.simulate import mesh_force_metrics, simulate
from gearbox.drivetrain.sweep import speed_sweep
from gearbox.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]


def model_at(rpm: float | None = None) -> DrivetrainModel:
    return DrivetrainModel.from_scene(load_scene(ROOT / "models" / "case03.toml"), speed_rpm=rpm)


def timed(fn, repeats: int):
    walls, out = [], None
    for _ in range(repeats):
        out = fn()
        walls.append(out.wall_time)
    return statistics.median(walls), out


def work_precision(m, cycles: int, quick: bool) -> None:
    print(
        f"\n## 1. Work-precision: {cycles} mesh cycles ({cycles / m.mesh_frequency:.3f} s) at "
        f"{m.speed * 30 / math.pi:.0f} rpm, after 20 settling cycles"
    )
    t0 = time.perf_counter()
    ref = simulate(m, ScipySolver(method="DOP853", rtol=1e-11), mesh_cycles=cycles)
    print(
        f"reference scipy DOP853 rtol 1e-11: {time.perf_counter() - t0:.2f} s wall, "
        f"status {ref.status}, nfev {ref.nfev}"
    )
    r = mesh_force_metrics(ref, m)
    rows = []
    settings = [
        ("scipy", "DOP853", [1e-5, 1e-6, 1e-7, 1e-8]),
        ("scipy", "LSODA", [1e-5, 1e-6, 1e-7, 1e-8]),
        ("scipy", "Radau", [1e-5, 1e-6] if quick else [1e-5, 1e-6, 1e-7]),
        ("diffrax", "Tsit5", [1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-9]),
        ("diffrax", "Dopri8", [1e-6, 1e-8, 1e-10]),
        # fixed steps (the default): "rtol" column holds steps per period of f_max
        ("fixed", "Tsit5", [12.0, 24.0, 48.0]),
        ("fixed", "Dopri8", [6.0, 12.0]),
    ]
    for backend, method, rtols in settings:
        for rtol in rtols:
            if backend == "scipy":
                solver = ScipySolver(method=method, rtol=rtol)
                reps = 1
            else:
                if backend == "fixed":
                    solver = DiffraxSolver(solver=method, steps_per_period=rtol)
                else:
                    solver = DiffraxSolver(solver=method, rtol=rtol)
                simulate(m, solver, mesh_cycles=cycles)  # compile
                reps = 5
            wall, ts = timed(lambda s=solver: simulate(m, s, mesh_cycles=cycles), reps)
            a = mesh_force_metrics(ts, m)
            e_rms = abs(a["mesh_force_rms_N"] / r["mesh_force_rms_N"] - 1)
            e_dyn = abs(a["mesh_force_dynamic_rms_N"] / r["mesh_force_dynamic_rms_N"] - 1)
            e_amp = abs(
                a["mesh_force_mesh_order_amplitude_N"] / r["mesh_force_mesh_order_amplitude_N"] - 1
            )
            rows.append((backend, method, rtol, wall, e_rms, e_dyn, e_amp, ts.nfev, ts.status))
    print(
        "| solver | method | rtol (fixed: steps per period) | wall (s, median) | err RMS "
        "| err dynamic RMS | err mesh-order amp | nfev | status |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for b, mth, rtol, wall, e1, e2, e3, nfev, st in rows:
        setting = f"{rtol:g}" if b == "fixed" else f"{rtol:.0e}"
        print(
            f"| {b} | {mth} | {setting} | {wall:.4f} | {e1:.1e} | {e2:.1e} | {e3:.1e} "
            f"| {nfev} | {st} |"
        )

    def best(backend):
        ok = [
            w
            for b, _, _, w, e1, e2, e3, _, st in rows
            if b == backend and st == "success" and max(e1, e3) <= 1e-4
        ]
        return min(ok) if ok else math.nan

    bs, bd, bf = best("scipy"), best("diffrax"), best("fixed")
    default = [
        (w, max(e1, e3))
        for b, mth, st_, w, e1, _, e3, _, _ in rows
        if b == "fixed" and mth == "Tsit5" and st_ == 12.0
    ][0]
    print(
        f"\nfastest to 1e-4 (RMS and mesh-order amplitude): scipy {bs:.4f} s, diffrax adaptive "
        f"{bd:.4f} s ({bs / bd:.1f}x), fixed steps {bf:.4f} s ({bs / bf:.1f}x); "
        f"default (fixed Tsit5, 12 steps per period) {default[0]:.4f} s, error "
        f"{default[1]:.1e}: {bs / default[0]:.1f}x faster than scipy"
    )


def _scan_variant(m, rhs_fn, h: float, n: int):
    """A fixed-step Tsit5 in lax.scan over ``n`` steps of ``h`` (one per sample) with the
    right-hand side ``rhs_fn(t, z, p)``: the building block of the options below."""
    import jax
    import jax.numpy as jnp

    from gearbox.drivetrain.fixed_step import explicit_tableau
    from gearbox.drivetrain.linear import periodic_start_state

    A, b, c = explicit_tableau("Tsit5")
    p = {k: jnp.asarray(v) for k, v in m.params().items()}
    z0 = jnp.asarray(periodic_start_state(m) / m.params()["scale"])

    def run(p, z0):
        def body(z, t):
            ks = []
            for i in range(len(b)):
                zi = z
                for j in range(i):
                    if A[i, j]:
                        zi = zi + (h * A[i, j]) * ks[j]
                ks.append(rhs_fn(t + c[i] * h, zi, p))
            for i in range(len(b)):
                if b[i]:
                    z = z + (h * b[i]) * ks[i]
            return z, z

        return jax.lax.scan(body, z0, jnp.arange(n) * h)[1]

    fn = jax.jit(run)
    fn(p, z0).block_until_ready()  # compile
    walls = []
    for _ in range(5):
        t0 = time.perf_counter()
        zs = fn(p, z0).block_until_ready()
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls), np.asarray(zs) * m.params()["scale"]


def _lean(laws: str):
    """lean_rhs with the mesh laws from the Fourier series: 'sincos' (one sin and cos per
    harmonic) or 'recurrence' (cos/sin of the first harmonic, the others by angle
    addition)."""
    import jax.numpy as jnp

    from gearbox.drivetrain.fixed_step import _time_excitations, lean_rhs
    from gearbox.drivetrain.model import mesh_laws

    def f(t, z, p):
        if laws == "sincos":

            def laws_at(phi):
                k, _, e, de = mesh_laws(phi / p["N1"], p, jnp)
                return jnp.concatenate([k, e, de])
        else:

            def laws_at(phi):
                kc, ec = p["kc"], p["ec"]
                h = (kc.shape[-1] - 1) // 2
                c1, s1 = jnp.cos(phi), jnp.sin(phi)
                ck, sk = c1, s1
                k, e, de = kc[:, 0], ec[:, 0], jnp.zeros(2)
                for j in range(1, h + 1):
                    k = k + kc[:, j] * ck + kc[:, h + j] * sk
                    e = e + ec[:, j] * ck + ec[:, h + j] * sk
                    de = de + j * p["N1"] * (ec[:, h + j] * ck - ec[:, j] * sk)
                    ck, sk = ck * c1 - sk * s1, sk * c1 + ck * s1
                return jnp.concatenate([k, e, de])

        te0, rp = _time_excitations(p, t, jnp)
        return lean_rhs(t, z, p, laws_at, te0, rp)

    return f


def one_second(m) -> None:
    import jax.numpy as jnp

    from gearbox.drivetrain.model import outputs, rhs

    print("\n## 2. One second of simulated time at 2000 rpm (32 samples per mesh cycle)")
    cycles = int(round(1.0 * m.mesh_frequency))
    spc = 32
    t0 = time.perf_counter()
    ref = simulate(
        m, DiffraxSolver(solver="Dopri8", rtol=1e-12), mesh_cycles=cycles, settle_time=0.0
    )
    print(f"reference diffrax Dopri8 rtol 1e-12: {time.perf_counter() - t0:.1f} s, {ref.status}")
    fr = ref["mesh_force_N"]
    w = 2 * math.pi * m.mesh_frequency

    def errors(t, f, every=1):
        r = fr[every - 1 :: every]
        tr = ref.time[every - 1 :: every]
        assert np.allclose(t, tr)

        def amp(x):
            return 2 * abs(np.mean(x * np.exp(-1j * w * t)))

        e_rms = abs(np.sqrt(np.mean(f**2)) / np.sqrt(np.mean(r**2)) - 1)
        return e_rms, abs(amp(f) / amp(r) - 1), np.sqrt(np.mean((f - r) ** 2)) / np.std(r)

    rows = []

    def add(name, wall, steps, t, f, every=1):
        rows.append((name, wall, steps, *errors(t, f, every)))
        print(f"  {name}: {wall:.4f} s", flush=True)

    def run_simulate(name, solver, model=m, every=1):
        first = simulate(
            model, solver, mesh_cycles=cycles, settle_time=0.0, samples_per_cycle=spc // every
        )
        walls = [
            simulate(
                model, solver, mesh_cycles=cycles, settle_time=0.0, samples_per_cycle=spc // every
            ).wall_time
            for _ in range(5)
        ]
        add(
            name,
            statistics.median(walls),
            first.steps + first.rejected,
            first.time,
            first["mesh_force_N"],
            every,
        )
        return first

    default = run_simulate("default: fixed Tsit5 scan, lean rhs, Hermite table", DiffraxSolver())
    h = 1.0 / (spc * m.mesh_frequency)
    run_simulate(
        "diffrax adaptive Tsit5 rtol 1e-6 (old default), SaveAt 32/cycle", DiffraxSolver(rtol=1e-6)
    )
    run_simulate(
        "diffrax adaptive Tsit5 rtol 1e-6, SaveAt 4/cycle", DiffraxSolver(rtol=1e-6), every=8
    )
    # diffrax with a constant step: no error estimate, no rejections
    import diffrax
    import jax

    from gearbox.drivetrain.linear import periodic_start_state

    p = {k: jnp.asarray(v) for k, v in m.params().items()}
    z0 = jnp.asarray(periodic_start_state(m) / m.params()["scale"])
    ts = jnp.asarray(ref.time)
    term = diffrax.ODETerm(lambda t, z, p: rhs(t, z, p, xp=jnp))

    @jax.jit
    def const(p, z0):
        return diffrax.diffeqsolve(
            term,
            diffrax.Tsit5(),
            0.0,
            ts[-1],
            h,
            z0,
            args=p,
            saveat=diffrax.SaveAt(ts=ts),
            stepsize_controller=diffrax.ConstantStepSize(),
            max_steps=2 * cycles * spc,
        ).ys

    const(p, z0).block_until_ready()
    walls = []
    for _ in range(5):
        t1 = time.perf_counter()
        ys = const(p, z0).block_until_ready()
        walls.append(time.perf_counter() - t1)
    Y = np.asarray(ys) * m.params()["scale"]
    add(
        "diffrax ConstantStepSize Tsit5, same step",
        statistics.median(walls),
        cycles * spc,
        ref.time,
        outputs(m, ref.time, Y)["mesh_force_N"],
    )
    for name, f in (
        (
            "scan, model.rhs (BLAS matvecs, sin/cos per harmonic)",
            lambda t, z, p: rhs(t, z, p, xp=jnp),
        ),
        ("scan, lean rhs, Fourier series by sin/cos per harmonic", _lean("sincos")),
        ("scan, lean rhs, harmonics by angle-addition recurrence", _lean("recurrence")),
    ):
        wall, Y = _scan_variant(m, f, h, cycles * spc)
        add(name, wall, cycles * spc, ref.time, outputs(m, ref.time, Y)["mesh_force_N"])
    for hk in (12, 6):
        mt = DrivetrainModel.from_scene(
            load_scene(ROOT / "models" / "case03.toml").replaced(drivetrain={"mesh_harmonics": hk})
        )
        run_simulate(
            f"default, table truncated to {hk} harmonics (truncation error included)",
            DiffraxSolver(),
            model=mt,
        )
    print(
        "\n| option | wall (s, median of 5) | steps | us per step | err RMS | err mesh-order amp | err sample-wise |"
    )
    print("|---|---|---|---|---|---|---|")
    for name, wall, steps, e1, e2, e3 in rows:
        print(
            f"| {name} | {wall:.4f} | {steps} | {1e6 * wall / steps:.2f} | {e1:.1e} | {e2:.1e} | {e3:.1e} |"
        )
    print(
        f"\ndefault: compile {default.attrs['compile_time_s']:.2f} s, {default.steps} steps, "
        f"status {default.status}; walls are integration only (after compilation)"
    )


def sweep(n_speeds: int, cycles: int, adaptive: bool = True) -> None:
    import jax

    print(
        f"\n## 3. Sweep: {n_speeds} speeds 500-3000 rpm, {cycles} mesh cycles each (16 samples "
        f"per cycle, no settling), device {jax.devices()[0].platform}"
    )
    rpms = np.linspace(500.0, 3000.0, n_speeds)
    base = model_at()
    runs = [("fixed steps, loop (default on a CPU)", DiffraxSolver(), "loop")]
    runs.append(("fixed steps, vmap batch (default on a GPU)", DiffraxSolver(), "vmap"))
    if adaptive:
        runs.append(("adaptive rtol 1e-6, vmap batch", DiffraxSolver(rtol=1e-6), "vmap"))
        runs.append(
            ("adaptive rtol 1e-6, loop (earlier CPU default)", DiffraxSolver(rtol=1e-6), "loop")
        )
    print(
        "| sweep | set-up (s) | compile (s) | integration (s) | per speed, integration (ms) "
        "| total (s) | per speed, total (ms) | succeeded |"
    )
    print("|---|---|---|---|---|---|---|---|")
    amps = []
    for name, solver, mode in runs:
        t0 = time.perf_counter()
        sw = speed_sweep(base, rpms, solver, settle_cycles=0, mesh_cycles=cycles, batch=mode)
        total = time.perf_counter() - t0
        ok = sum(st == "success" for st in sw.status)
        if sw.contact_loss_steps is not None:
            reruns = int(np.count_nonzero(sw.contact_loss_steps))
            name = f"{name}; {reruns} speeds with contact loss re-run adaptively"
        amps.append(sw.metrics["mesh_force_mesh_order_amplitude_N"])
        print(
            f"| {name} | {sw.setup_time:.2f} | {sw.compile_time:.2f} | {sw.wall_time:.3f} "
            f"| {1e3 * sw.time_per_speed:.2f} | {total:.2f} | {1e3 * total / n_speeds:.2f} "
            f"| {ok}/{n_speeds} |",
            flush=True,
        )
    for (name, _, _), a in zip(runs[1:], amps[1:], strict=True):
        d = np.abs(a / amps[0] - 1)
        i = int(np.argmax(d))
        print(
            f"mesh-order amplitude, {name} against the first: largest relative difference "
            f"{d[i]:.1e} at {rpms[i]:.0f} rpm"
        )


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--sweep-only", action="store_true")
    ap.add_argument(
        "--no-work-precision", action="store_true", help="skip section 1 (scipy runs, minutes)"
    )
    ap.add_argument("--speeds", type=int, default=200)
    ap.add_argument("--sweep-cycles", type=int, default=100)
    ap.add_argument("--no-adaptive-sweep", action="store_true", help="skip the adaptive sweeps")
    a = ap.parse_args()
    m = model_at()
    if not a.sweep_only:
        if not a.no_work_precision:
            work_precision(m, 50 if a.quick else 200, a.quick)
        one_second(m)
    sweep(a.speeds, a.sweep_cycles, adaptive=not a.no_adaptive_sweep)


if __name__ == "__main__":
    main()

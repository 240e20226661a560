"""A ghost order: a waviness the grinding machine puts on every tooth, and the line it
puts into the loaded transmission error. A script to copy.

A generating grinding machine rolls the gear past its wheel while its table turns. An
error of the table drive with N cycles per table revolution (the teeth of its index
worm wheel, say) is ground into every flank as a profile waviness that runs on from
tooth to tooth: at roll length x of tooth j the flank stands off by
A sin(N (x / r_b2 - 2 pi j / z2)), one pattern fixed to the gear. In mesh the same
kinematics read it back: the loaded TE carries a line at gear order N, which is no
multiple of the tooth count, a "ghost" order the teeth alone cannot explain. The
measured traces (docs/ltca.md "Measured traces") carry it into the loaded TCA's
hunting record.

What it does, step by step:

1. load the default scene, sample the waviness on the gear's profile traces
   (``--waves`` N per revolution, ``--amplitude`` um, from -20 to +20 mm of roll
   length about the reference circle) and the pitch deviations a pitch checker reads
   from it at the reference circle (the traces are taken less their value there), no
   other deviations;
2. run the pipeline to the ``pitch`` stage (the linear method; ``--exact`` also solves
   the contact problem at every sample) and print the loaded TE's largest added lines,
   named;
3. with ``--dynamics``, carry the traces into the drive (``drivetrain.pitch_deviations``:
   the ``approach`` stage makes the traces' turns, docs/drivetrain.md section 3c)
   and print the ghost's dynamic mesh force at ``--speeds`` speeds on the propeller law
   (harmonic balance about each speed's operating point), and the mesh mode it
   approaches;
   ``--simulate`` runs the drive at the top speed over a hunting period and sets the
   simulated ghost beside the harmonic balance's;
4. with ``--plot FILE``, draw the TE and its spectrum.

Measured (default scene, 24 positions, N = 52, A = 0.5 um): the line at gear order 52
(pinion order 33.51, named "mesh 1 + gear 7": it lies 7 gear orders above the mesh
order) is by far the largest the waviness adds, 0.326 um (the contact lines, which
cross the waviness, average part of it away); then its sidebands with the mesh orders,
gear order 7 (0.038 um), "mesh 1 - gear 7" (0.030 um), "mesh 2 + gear 7" (0.017 um):
the mesh stiffness varies within the mesh cycle and modulates it. Every added line lies
at a gear order. ``--exact`` (45 distinct samples per position: the pattern repeats
every gear revolution) agrees on the ghost within 0.06 %.

In the drive (``--dynamics --simulate``): the Campbell diagram lists the ghost and
its sidebands among the excitations; at 52 waves the ghost meets the mesh mode only
above the speed range (its sideband at gear order 7 crosses a shaft mode at 1141 rpm
with next to no force), at ``--waves 61`` (pinion order 39.31, "mesh 1 + gear 16") it
crosses it at 3063 rpm (2007 Hz), flagged as a resonance risk, 1946 N. The ghost's
mesh force grows along the
propeller law from 28 N at 1000 rpm (558 Hz) to 1745 N at 3500 rpm, where its 1955 Hz
lie 4 % under the mesh mode (2035 Hz): 84 % of the mesh order's own line (2078
N) from a waviness of half a micrometre. Simulated over the hunting period at 3500 rpm
it reads 1745.32 N against the harmonic balance's 1745.40 N (the balance +0.004 %, as printed). Run it from
the repository root::

    python models/example_ghost_order.py
    python models/example_ghost_order.py --waves 61 --exact --plot ghost.png
    python models/example_ghost_order.py --dynamics --simulate
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.pipeline import run_pipeline

HERE = Path(__file__).resolve().parent


def waviness(design, waves: int, amplitude_um: float, positions_mm):
    """The gear's profile traces (um, one row per tooth at ``positions_mm``) of a
    waviness with ``waves`` cycles per gear revolution, and the cumulative pitch
    deviations (um, on the reference arc) it shows at the reference circle."""
    z2 = design.gear.teeth
    rb2 = design.gear.base_radius[0]  # the drive flank's
    alpha_t = design.gear.transverse_pressure_angle[0]
    x = np.asarray(positions_mm, dtype=float) * 1e-3
    j = np.arange(z2)[:, None]
    rows = amplitude_um * np.sin(waves * (x[None, :] / rb2 - 2 * math.pi * j / z2))
    at_ref = amplitude_um * np.sin(-waves * 2 * math.pi * np.arange(z2) / z2)
    return rows, at_ref / math.cos(alpha_t)


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--scene", default=str(HERE / "marine_drive.toml"))
    ap.add_argument("--waves", type=int, default=52, help="waviness cycles per gear revolution")
    ap.add_argument("--amplitude", type=float, default=0.5, help="waviness amplitude (um)")
    ap.add_argument("--positions", type=int, default=None, help="loaded-TCA positions")
    ap.add_argument("--exact", action="store_true", help="also solve every sample")
    ap.add_argument("--dynamics", action="store_true", help="the ghost in the drive's mesh force")
    ap.add_argument("--speeds", type=int, default=6, help="speeds on the propeller law")
    ap.add_argument(
        "--simulate", action="store_true", help="with --dynamics: check at the rated speed"
    )
    ap.add_argument("--plot", help="write a figure (PNG)")
    args = ap.parse_args(argv)

    scene = load_scene(args.scene)
    if args.positions:
        scene = scene.replaced(ltca={"positions": args.positions})
    design = run_pipeline(scene, ["design"])["design"]
    z1, z2 = design.pinion.teeth, design.gear.teeth
    x_mm = np.linspace(-20.0, 20.0, 161)
    rows, fp = waviness(design, args.waves, args.amplitude, x_mm)
    pitch = {
        "random_single_um": 0.0,
        "gear_cumulative_um": fp.tolist(),
        "gear_profile_trace_mm": x_mm.tolist(),
        "gear_profile_trace_um": rows.tolist(),
    }
    if args.dynamics:  # the dynamics carry the deviations
        scene = scene.replaced(drivetrain={"pitch_deviations": True})
    out = {}
    for method in ("linear", "exact") if args.exact else ("linear",):
        wanted = ["pitch"]
        if method == "linear" and args.dynamics:
            wanted += ["tables", "approach"]  # the traces' turns for the dynamics
        out[method] = run_pipeline(scene.replaced(pitch={**pitch, "method": method}), wanted)
    rec = out["linear"]["pitch"].record
    ghost = args.waves * z1 / z2
    print(
        f"gear profile waviness {args.amplitude:g} um, {args.waves} waves per gear revolution: "
        f"gear order {args.waves} = pinion order {ghost:.3f}; {rec.cycles} mesh cycles at "
        f"{rec.torque:g} N m"
    )
    print("largest lines the waviness adds (pinion order, kind, amplitude um):")
    lines = []
    for line in out["linear"]["pitch"].lines(8, added=True):
        o, kind, a = line["order"], line["kind"], line["amplitude_m"]
        lines.append((o, kind, a))
        extra = ""
        if "exact" in out:
            eo, ea = out["exact"]["pitch"].record.order_spectrum()
            extra = f"  (exact {ea[int(np.argmin(np.abs(eo - o)))] * 1e6:.4f})"
        mark = "  <- ghost" if abs(o - ghost) < 1e-9 else ""
        print(f"  {o:8.3f}  {kind:24s} {a * 1e6:.4f}{extra}{mark}")
    if args.dynamics:
        drive = scene.replaced(pitch={**pitch, "method": "linear"})
        out["dynamics"] = ghost_along_the_propeller_law(drive, out["linear"], ghost, args.speeds)
        out["crossings"] = ghost_crossings(drive)
        if args.simulate:
            out["simulated"] = simulated_ghost(drive, out["linear"], ghost)
    if args.plot:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        from gearbox.ltca.plot import plot_hunting_lte, plot_hunting_spectrum

        fig, ax = plt.subplots(2, 1, figsize=(10, 6.5))
        plot_hunting_lte(rec, ax[0])
        plot_hunting_spectrum(rec, ax[1])
        fig.tight_layout()
        fig.savefig(args.plot, dpi=110)
        print(f"figure: {args.plot}")
    return lines, out


def ghost_along_the_propeller_law(scene, run, ghost: float, count: int) -> list[tuple]:
    """The ghost's dynamic mesh force (N) at ``count`` speeds of the sweep on the
    propeller law: the harmonic balance of the drive with the traces' approach
    (:func:`gearbox.drivetrain.linear.pitch_harmonic_balance`), with the frequency
    (Hz) and the linearised drive's mesh mode. Rows (rpm, Hz, N, mesh mode Hz)."""
    from gearbox.drivetrain.linear import modes, pitch_harmonic_balance
    from gearbox.pipeline.adapters.dynamics import model_at

    table, approach = run["tables"], run["approach"]
    lo, hi = scene["simulation"]["speed_sweep_rpm"][:2]
    rows = []
    print("the ghost in the drive's mesh force (harmonic balance, propeller law):")
    for rpm in np.linspace(lo, hi, count):
        m = model_at(scene, table, float(rpm), approach)
        orders, _, f = pitch_harmonic_balance(m)
        i = int(np.argmin(np.abs(orders - ghost)))
        hz = ghost * rpm / 60.0
        md = modes(m)
        kinds = zip(md.frequencies, md.descriptions(), strict=True)
        mesh = [float(fr) for fr, d in kinds if d.startswith("mesh mode")][0]
        rows.append((float(rpm), hz, float(abs(f[0, i])), mesh))
        print(f"  {rpm:7.0f} rpm: {hz:7.1f} Hz  {abs(f[0, i]):8.2f} N  (mesh mode {mesh:.0f} Hz)")
    return rows


def ghost_crossings(scene) -> list:
    """The Campbell diagram's crossings of the deviations' own lines (the approach's
    largest beyond the named orders: the ghost and its sidebands) with the drive's
    modes in the speed range, each with its steady mesh force."""
    diagram = run_pipeline(scene, ["campbell"])["campbell"]
    hits = [c for c in diagram.crossings if c.excitation.startswith("deviations")]
    named = [e.label[12:] for e in diagram.excitations if e.label.startswith("deviations, ")]
    print(f"Campbell diagram: the deviations' lines {', '.join(named)}")
    for c in hits:
        force = (c.response or {}).get("mesh_force_N", float("nan"))
        print(
            f"  crosses {c.mode} at {c.speed_rpm:.0f} rpm ({c.frequency_hz:.0f} Hz): "
            f"{c.excitation}, {force:.0f} N"
        )
    if not hits:
        print("  no crossing in the speed range")
    return hits


def simulated_ghost(scene, run, ghost: float) -> tuple[float, float]:
    """The ghost's mesh force (N) at the sweep's top speed, simulated over a hunting
    period (engine and propeller orders off: the constant-speed spectrum then holds
    the mesh orders and the traces' lines alone) and from the harmonic balance."""
    from gearbox.drivetrain.linear import pitch_harmonic_balance
    from gearbox.drivetrain.simulate import default_solver, simulate
    from gearbox.pipeline.adapters.dynamics import model_at

    quiet = {"firing_torque_ripple": 0.0, "half_order_ripple": 0.0, "blade_pass_ripple": 0.0}
    rpm = float(scene["simulation"]["speed_sweep_rpm"][1])
    m = model_at(scene.replaced(drivetrain=quiet), run["tables"], rpm, run["approach"])
    cycles = m.common_period_mesh_cycles()  # the hunting period
    ts = simulate(m, default_solver(), settle_time=1.0, mesh_cycles=cycles, samples_per_cycle=24)
    force = ts.channels["mesh_force_N"]
    amp = np.abs(np.fft.rfft(force)) / force.size * 2  # bins of 1 / (pinion revolutions)
    sim = float(amp[int(round(ghost * cycles / m.pinion_teeth))])
    orders, _, f = pitch_harmonic_balance(m)
    lin = float(abs(f[0, int(np.argmin(np.abs(orders - ghost)))]))
    mesh = float(amp[cycles])  # the mesh order
    print(
        f"at {rpm:g} rpm over {cycles} mesh cycles: ghost {sim:.2f} N simulated, {lin:.2f} N "
        f"harmonic balance ({100 * (lin / sim - 1):+.3f} %); the mesh order {mesh:.0f} N"
    )
    return sim, lin


if __name__ == "__main__":
    main()

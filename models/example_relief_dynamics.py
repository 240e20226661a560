"""What a tip relief does to the drive's vibration: a script to copy.

From flank modification to the dynamic response in one go: the default marine drive is
run twice through the pipeline, with the paper's unmodified flanks and with a long tip
relief on both gears, and the script compares the loaded transmission error of the
mesh tables with the order spectra of the dynamic mesh force and the dynamic
transmission error at the operating point (mesh order N_1 and its harmonics).

What it does, step by step:

1. load the default scene (shortened with ``--mesh-cycles`` and ``--positions`` if
   asked) and make a copy with the relief keys of ``[ltca]`` set;
2. run the pipeline to the ``spectra`` stage for both (loaded TCA, mesh tables,
   settled simulation at the operating point, order spectra; cached on disk);
3. print the LTE harmonics of the tables at the torque level nearest the operating
   torque and the mesh-order amplitudes of the dynamic responses.

Measured (defaults, 40 um over 3 mm; the full record): the relief lowers the tables' LTE
first mesh harmonic at 900 N m from 1.44 to 0.03 um, and the mesh-order amplitude of the
dynamic mesh force at 3500 rpm falls from 2078 to 400 N, that of the DTE from 2.84 to
0.68 um. The relief also lowers the mean tangent mesh stiffness, which moves the mesh
mode from 2035 to 1830 Hz, towards the mesh frequency of 1692 Hz:
here the smaller excitation wins, but a relief sized on the quasi-static TE alone can
move a mode onto an excitation order; ``gearbox modes`` and the Campbell diagram of
``gearbox run`` show where the mode sits. (With the fast level's earlier, softer
compliance the same relief raised the dynamic mesh force instead, next to a mode that
had moved onto the mesh frequency: the answer depends on the tables.)

Run it from the repository root::

    python models/example_relief_dynamics.py
    python models/example_relief_dynamics.py --relief-um 20 --length-mm 3.0
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.pipeline import run_pipeline

HERE = Path(__file__).resolve().parent


def responses(scene, harmonics: int = 3) -> dict:
    """LTE harmonics (m) of the mesh tables near the operating torque and the mesh-order
    amplitudes (N, m) of the dynamic mesh force and DTE at the operating point."""
    run = run_pipeline(scene, ["spectra"])
    if not run.summary.ok:
        raise RuntimeError(run.summary.table())
    table = run["tables"]
    op = run["dynamics"]
    t = float(table.torque[np.argmin(np.abs(np.asarray(table.torque) - op.torque_Nm))])
    lte = table.summary(harmonics)["drive"][f"{t:g}"]["lte_harmonics_m"]
    n1 = scene["pinion"]["teeth"]
    sp = run["spectra"].spectra
    force = [sp["mesh_force_N"].amplitude_at(k * n1) for k in range(1, harmonics + 1)]
    dte = [sp["dynamic_transmission_error_m"].amplitude_at(k * n1) for k in range(1, harmonics + 1)]
    freqs = np.asarray(op.modes.frequencies)
    mesh_mode = float(freqs[np.argmax(np.asarray(op.modes.mesh_energy_fraction))])
    return {
        "mesh_mode_Hz": mesh_mode,
        "mesh_frequency_Hz": float(op.model.mesh_frequency),
        "table_torque_Nm": t,
        "operating_torque_Nm": op.torque_Nm,
        "speed_rpm": op.speed_rpm,
        "lte_harmonics_m": list(lte),
        "mesh_force_N": force,
        "dte_m": dte,
        "computed": run.summary.names("computed"),
    }


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--relief-um", type=float, default=40.0, help="tip relief C_a, both gears")
    ap.add_argument("--length-mm", type=float, default=3.0, help="relief length (radial)")
    ap.add_argument("--mesh-cycles", type=int, default=None, help="recorded mesh cycles")
    ap.add_argument("--positions", type=int, default=None, help="LTCA positions per cycle")
    args = ap.parse_args(argv)

    scene = load_scene(HERE / "marine_drive.toml").replaced(ltca={"flanks": ["drive", "coast"]})
    if args.mesh_cycles:
        scene = scene.replaced(simulation={"settled_mesh_cycles": args.mesh_cycles})
    if args.positions:
        scene = scene.replaced(ltca={"positions": args.positions})
    relief = {
        f"{g}_tip_relief_{k}": v
        for g in ("pinion", "gear")
        for k, v in (("um", args.relief_um), ("length_mm", args.length_mm))
    }
    out = {}
    modes = {}
    for label, s in (("unmodified", scene), ("relieved", scene.replaced(ltca=relief))):
        out[label] = r = responses(s)
        modes[label] = r["mesh_mode_Hz"]
        print(f"{label}: stages computed {', '.join(r['computed']) or '-'}")
    a, b = out["unmodified"], out["relieved"]
    print(
        f"\ntip relief {args.relief_um:g} um over {args.length_mm:g} mm on both gears; "
        f"operating point {a['speed_rpm']:.0f} rpm, {a['operating_torque_Nm']:.0f} N m "
        f"(tables at {a['table_torque_Nm']:g} N m)"
    )
    print(
        f"mesh mode {modes['unmodified']:.0f} -> {modes['relieved']:.0f} Hz, mesh frequency "
        f"{a['mesh_frequency_Hz']:.0f} Hz"
    )
    print(f"{'mesh harmonic':<16} {'LTE (um)':>18} {'mesh force (N)':>20} {'DTE (um)':>18}")
    for k in range(3):
        print(
            f"{k + 1:<16d} "
            f"{1e6 * a['lte_harmonics_m'][k]:8.3f} -> {1e6 * b['lte_harmonics_m'][k]:6.3f} "
            f"{a['mesh_force_N'][k]:9.0f} -> {b['mesh_force_N'][k]:7.0f} "
            f"{1e6 * a['dte_m'][k]:8.3f} -> {1e6 * b['dte_m'][k]:6.3f}"
        )
    return out


if __name__ == "__main__":
    main()

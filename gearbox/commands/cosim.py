"""``gearbox cosim``: engine, gearbox and propeller FMUs coupled on libcosim."""

HELP = "Co-simulate engine, gearbox and propeller FMUs on libcosim (OSP system structure)."
EXAMPLES = """  gearbox cosim models/marine_drive.toml
  gearbox cosim models/marine_drive.toml --step 2e-5 --stop-time 0.2 --out out/cosim
  gearbox cosim models/marine_drive.toml --compare --json   coupling error vs one FMU
"""


def add_arguments(parser):
    parser.add_argument("scene", help="scene file (TOML), e.g. models/marine_drive.toml")
    parser.add_argument(
        "--out", default=None, metavar="DIR", help="output folder (default out/<scene>/cosim)"
    )
    parser.add_argument(
        "--step", type=float, default=5e-5, help="communication step (s), default 5e-5"
    )
    parser.add_argument(
        "--stop-time", type=float, default=0.1, help="simulated time (s), default 0.1"
    )
    parser.add_argument(
        "--rtol", type=float, default=1e-8, help="tolerance of each FMU's integrator"
    )
    parser.add_argument(
        "--table", default=None, help="mesh table (netCDF); default: analytical ISO 6336-1 table"
    )
    parser.add_argument(
        "--speed-rpm", type=float, default=None, help="engine speed (rpm), overrides the scene"
    )
    parser.add_argument(
        "--hold",
        action="store_true",
        help="zero-order hold of the exchanged values (default: extrapolate with their rates)",
    )
    parser.add_argument(
        "--compare",
        action="store_true",
        help="also run the monolithic drivetrain FMU and report the coupling error",
    )
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")


def run(args) -> int:
    from pathlib import Path

    from ..fmu.cosim import compare_monolithic, cosim_drivetrain
    from ..fmu.models import model_from_scene
    from ..scene import load_scene
    from ._common import dumps_json, output_folder, write_atomic

    scene = load_scene(args.scene)
    out = output_folder(args.out or Path("out") / scene.name / "cosim")
    model, table = model_from_scene(scene, table_path=args.table, speed_rpm=args.speed_rpm)
    res = cosim_drivetrain(
        model,
        table,
        out,
        step=args.step,
        stop_time=args.stop_time,
        solver_rtol=args.rtol,
        extrapolate=not args.hold,
    )
    force = res["mesh_force_N"]
    summary = {
        "scene": scene.name,
        "status": res.status,
        "message": res.message,
        "step_s": res.step,
        "coupling": "zero-order hold" if args.hold else "extrapolated with rates",
        "steps": res.steps,
        "stop_time_s": args.stop_time,
        "wall_time_s": res.wall_time,
        "mesh_force_mean_N": float(force.mean()),
        "mesh_force_ac_rms_N": float(force.std()),
        "system_structure": res.system_structure,
    }
    if args.compare:
        summary["coupling_error"] = compare_monolithic(model, table, out, res, rtol=args.rtol)
    write_atomic(out / "cosim.csv", res.to_csv())
    write_atomic(out / "summary.json", dumps_json(summary))
    if args.json:
        print(dumps_json(summary))
    else:
        for k, v in summary.items():
            print(f"{k:<22} {v}")
    return 0 if res.success else 1

"""``gearbox fmu build``: export the drivetrain (or its parts) as FMI 2.0 FMUs."""

HELP = "Build FMUs (FMI 2.0 or 3.0, Model Exchange + Co-Simulation) of the drivetrain or its parts."
EXAMPLES = """  gearbox fmu build models/marine_drive.toml --out out/fmu
  gearbox fmu build models/marine_drive.toml --out out/fmu --kind gearbox
  gearbox fmu build models/marine_drive.toml --out out/fmu --kind all --json
  gearbox fmu build models/marine_drive.toml --out out/fmu --fmi-version 3
  gearbox fmu build models/case03.toml --out out/fmu --table out/ltca/mesh_table.nc
"""

KINDS = ("drivetrain", "gearbox", "engine", "propeller")


def add_arguments(parser):
    parser.add_argument("action", choices=("build",), help="what to do (build)")
    parser.add_argument("scene", help="scene file (TOML), e.g. models/marine_drive.toml")
    parser.add_argument("--out", required=True, metavar="DIR", help="output folder")
    parser.add_argument(
        "--kind",
        choices=(*KINDS, "all"),
        default="drivetrain",
        help="drivetrain (whole chain, default), gearbox (flanges as inputs), engine, "
        "propeller, or all four",
    )
    parser.add_argument(
        "--table", default=None, help="mesh table (netCDF); default: analytical ISO 6336-1 table"
    )
    parser.add_argument(
        "--speed-rpm", type=float, default=None, help="engine speed (rpm), overrides the scene"
    )
    parser.add_argument(
        "--fmi-version",
        type=int,
        choices=(2, 3),
        default=2,
        help="FMI 2.0 (default, <id>.fmu) or FMI 3.0 (<id>_fmi3.fmu)",
    )
    parser.add_argument("--json", action="store_true", help="print the builds as one JSON object")


def run(args) -> int:
    from ..fmu import build_fmu
    from ..fmu.models import (
        drivetrain_fmu,
        engine_fmu,
        gearbox_fmu,
        model_from_scene,
        propeller_fmu,
    )
    from ..scene import load_scene
    from ._common import dumps_json, output_folder

    scene = load_scene(args.scene)
    output_folder(args.out)
    model, table = model_from_scene(scene, table_path=args.table, speed_rpm=args.speed_rpm)
    makers = {
        "drivetrain": lambda: drivetrain_fmu(model, table),
        "gearbox": lambda: gearbox_fmu(model, table),
        "engine": lambda: engine_fmu(model),
        "propeller": lambda: propeller_fmu(model),
    }
    kinds = KINDS if args.kind == "all" else (args.kind,)
    builds = {k: build_fmu(makers[k](), args.out, fmi_version=args.fmi_version) for k in kinds}
    if args.json:
        print(dumps_json({k: b.to_dict() for k, b in builds.items()}))
    else:
        for k, b in builds.items():
            print(f"{k:<11} {b.fmu}  ({b.n_variables} variables, {b.n_states} states)")
            print(f"{'':<11} sources {b.source_dir}")
    return 0

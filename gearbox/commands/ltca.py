HELP = "Loaded tooth contact analysis: mesh stiffness and loaded transmission error tables."
EXAMPLES = """  gearbox ltca models/case03.toml --out out/ltca03
  gearbox ltca models/case03.toml --out out/ltca03 --json > summary.json
  gearbox ltca tests/data/ltca_parallel_helical.toml --out out/par --positions 48
"""


def add_arguments(parser):
    from ._common import add_scene_argument

    add_scene_argument(parser)
    parser.add_argument("--out", required=True, help="output folder (created)")
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    parser.add_argument(
        "--fidelity",
        choices=("fast", "fe"),
        default=None,
        help="compliance level (default: the scene's ltca.fidelity)",
    )
    parser.add_argument(
        "--positions", type=int, default=None, help="positions per mesh cycle (>= 4)"
    )
    parser.add_argument("--no-figures", action="store_true", help="skip the PNG figures")
    parser.add_argument("--progress", action="store_true", help="show a progress bar")


def run(args):

    from ..errors import Problem
    from ..geometry import PairSpec, design_pair
    from ..ltca.analysis import LTCAOptions
    from ..ltca.table import scene_ltca
    from ._common import dumps_json, output_folder, scene_and_options, staged_files, write_atomic

    options = []
    if args.positions is not None and not 4 <= args.positions <= 10000:
        options.append(Problem("--positions", args.positions, "must be in [4, 10000]"))
    scene = scene_and_options(args.scene, options)
    if args.positions is not None:
        scene = scene.replaced(ltca={"positions": args.positions})
    if args.fidelity is not None:
        scene = scene.replaced(ltca={"fidelity": args.fidelity})
    out = output_folder(args.out)
    design = design_pair(PairSpec.from_scene(scene))
    ltca_options = LTCAOptions(positions=scene["ltca"]["positions"], progress=args.progress)
    result = scene_ltca(design, scene, options=ltca_options)
    summary = result.summary()
    with staged_files(out) as stage:  # all the files, or none of them
        result.table.to_netcdf(stage / "mesh_table.nc")
        write_atomic(stage / "mesh_table.csv", result.table.to_csv())
        write_atomic(stage / "ltca_summary.json", dumps_json(summary))
        if not args.no_figures:
            from ..ltca.plot import save_figures

            t = int(abs(result.table.torque - scene["load"]["operating_torque_Nm"]).argmin())
            save_figures(result.flanks, stage, t=t, modification_maps=result.modification_maps)
    if args.json:
        print(dumps_json(summary))
    else:
        print(f"gearbox ltca: {scene.name} -> {out}")
        for flank, rows in summary["flanks"].items():
            for tq, r in rows.items():
                print(
                    f"  {flank:5s} {float(tq):7.1f} N m  k = {r['mean_mesh_stiffness_N_per_m'] / 1e6:7.1f}"
                    f" MN/m (p-p {r['mesh_stiffness_peak_to_peak_N_per_m'] / 1e6:6.1f})"
                    f"  LTE p-p {r['lte_peak_to_peak_m'] * 1e6:6.3f} um"
                    f"  pattern {100 * r['contact_pattern_area_fraction']:5.1f} %"
                    + (f"  H {r['mesh_loss_factor']:.3f}" if "mesh_loss_factor" in r else "")
                    + ("  EDGE CONTACT" if r["edge_contact"] else "")
                )
        for note in summary["notes"]:
            print(f"  note: {note}")
    return 0

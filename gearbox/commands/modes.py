HELP = "Linear modes of the drivetrain (docs/drivetrain.md): eigenfrequencies and mode shapes."
EXAMPLES = """  gearbox modes models/case03.toml
  gearbox modes models/case03.toml --json
  gearbox modes models/case03.toml --table out/ltca/mesh_table.nc --speed-rpm 1500 --json
  gearbox modes models/marine_drive.toml --orders   steady response to each excitation order
"""


def add_arguments(parser):
    from ._common import add_scene_argument
    from .simulate import add_model_arguments

    add_scene_argument(parser)
    add_model_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    parser.add_argument(
        "--orders",
        action="store_true",
        help="add the steady response to each engine, propeller and mesh order at this "
        "speed (peak mesh force and shaft torques; mesh orders by harmonic balance)",
    )


def run(args):
    from ._common import dumps_json, scene_and_options
    from .simulate import model_from_args, model_option_problems, modes_summary

    scene = scene_and_options(args.scene, model_option_problems(args))
    model, table = model_from_args(scene, args)
    out = modes_summary(scene, model, table)
    if args.orders:
        out["order_responses"] = order_rows(model)
    if args.json:
        print(dumps_json(out))
        return 0
    print(f"gearbox modes: {scene.name} at {out['engine_speed_rpm']:.6g} rpm")
    print(
        f"  mesh frequency {out['mesh_frequency_Hz']:.6g} Hz, "
        f"mean mesh stiffness {out['mean_mesh_stiffness_N_per_m']:.4g} N/m"
    )
    for i, mode in enumerate(out["modes"]):
        print(f"  {i}: {mode['description']}")
    if args.orders:
        print("  steady response per order (peak, and % of the mean load):")
        head = ("order", "source", "mesh force (N)", "%", "input shaft (N m)", "%")
        head += ("output shaft (N m)", "%")
        print("    {:<8} {:<12} {:>14} {:>9} {:>17} {:>9} {:>18} {:>9}".format(*head))
        for r in out["order_responses"]:
            cells = [r["order"], r["source"]]
            for key in ("mesh_force", "input_shaft_torque", "output_shaft_torque"):
                amp = r[key + ("_N" if key == "mesh_force" else "_Nm")]
                cells += [amp, 100 * r[key + "_fraction"]]
            print(
                "    {:<8.4g} {:<12} {:>14.4g} {:>9.3g} {:>17.4g} {:>9.3g} {:>18.4g} {:>9.3g}".format(
                    *cells
                )
            )
    return 0


def order_rows(model) -> list[dict]:
    """One dict per excitation order of ``model`` at its speed: ``order``, ``source``
    and :meth:`gearbox.drivetrain.linear.OrderResponse.peaks`, by order."""
    from ..drivetrain.linear import order_responses

    r = order_responses(model)
    rows = [
        {"order": float(o), "source": src, **r.peaks(o)}
        for o, src in zip(r.orders, r.sources, strict=True)
    ]
    return sorted(rows, key=lambda row: row["order"])

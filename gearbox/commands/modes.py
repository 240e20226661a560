HELP = "Linear modes of the drivetrain (docs/drivetrain.md): eigenfrequencies and mode shapes."
EXAMPLES = """  gearbox modes models/case03.toml
  gearbox modes models/case03.toml --json
  gearbox modes models/case03.toml --table out/ltca/mesh_table.nc --speed-rpm 1500 --json
"""


def add_arguments(parser):
    from ._common import add_scene_argument
    from .simulate import add_model_arguments

    add_scene_argument(parser)
    add_model_arguments(parser)
    parser.add_argument("--json", action="store_true", help="print one JSON object")


def run(args):
    from ..scene import load_scene
    from ._common import dumps_json
    from .simulate import model_from_args, modes_summary

    scene = load_scene(args.scene)
    model, table = model_from_args(scene, args)
    out = modes_summary(scene, model, table)
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
    return 0

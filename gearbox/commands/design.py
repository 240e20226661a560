HELP = "Design a crossed beveloid pair (paper section 2) and run the design checks."
EXAMPLES = """  gearbox design models/case03.toml
  gearbox design models/case03.toml --json > design.json
  gearbox design models/case03.toml --strict           exit 1 when a design check fails
"""


def add_arguments(parser):
    from ._common import add_scene_argument

    add_scene_argument(parser)
    parser.add_argument(
        "--json", action="store_true", help="print one JSON object instead of the table"
    )
    parser.add_argument(
        "--strict",
        action="store_true",
        help="exit 1 when a design check fails (default: the checks are reported, exit 0)",
    )


def run(args):
    from ..geometry import PairSpec, design_pair
    from ..geometry.summary import design_summary, design_table
    from ..scene import load_scene
    from ._common import dumps_json

    scene = load_scene(args.scene)
    design = design_pair(PairSpec.from_scene(scene))
    if args.json:
        print(dumps_json(design_summary(design)))
    else:
        print(f"gearbox design: {scene.name}\n")
        print(design_table(design))
    failed = [name for name, c in design.checks.items() if not c.ok]
    if args.strict and failed:
        import sys

        print(f"gearbox design: design checks failed: {', '.join(failed)}", file=sys.stderr)
        return 1
    return 0

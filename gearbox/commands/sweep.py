HELP = "Parameter studies of the design (paper Figs. 6-9): CSV and PNG per study."
EXAMPLES = """  gearbox sweep models/case03.toml --out out/sweep
  gearbox sweep models/case03.toml --out out/sweep --points 201
"""


def add_arguments(parser):
    from ._common import add_scene_argument

    add_scene_argument(parser)
    parser.add_argument(
        "--out", default=None, metavar="DIR", help="output folder (default out/<scene>/sweep)"
    )
    parser.add_argument(
        "--points", type=int, default=101, help="points along each curve (default 101)"
    )


def run(args):
    import io

    from ..errors import InputError, Problem
    from ..geometry import PairSpec
    from ..geometry.sweep import PAPER_STUDIES
    from ..scene import load_scene
    from ._common import output_folder, staged_files, write_atomic

    if not 2 <= args.points <= 100000:
        raise InputError(Problem("--points", args.points, "must be in [2, 100000]"))
    from pathlib import Path

    scene = load_scene(args.scene)
    spec = PairSpec.from_scene(scene)
    out = output_folder(args.out or Path("out") / scene.name / "sweep")
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from ..geometry.plotting import plot_study

    lines = []
    with staged_files(out) as stage:  # every study's files, or none of them
        for st in PAPER_STUDIES(spec, args.points):
            write_atomic(stage / f"{st.name}.csv", st.to_csv())
            axes = plot_study(st)
            buf = io.BytesIO()
            axes[0].figure.savefig(buf, format="png", dpi=110)
            plt.close(axes[0].figure)
            write_atomic(stage / f"{st.name}.png", buf.getvalue())
            n_ok = int(st.ok.sum())
            lines.append(
                f"{st.name}: {n_ok}/{st.ok.size} designs solved -> {out / st.name}.csv/.png"
            )
    print("\n".join(lines))
    return 0

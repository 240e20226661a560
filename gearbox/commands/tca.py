"""``gearbox tca``: flank surfaces and unloaded tooth contact analysis of a scene."""

HELP = "Unloaded tooth contact analysis: contact path, transmission error, FPD angles from the surfaces."
EXAMPLES = """  gearbox tca models/case03.toml --out out/tca03
  gearbox tca models/case03.toml --out out/tca03 --json      summary also on stdout
"""


def add_arguments(parser):
    from ._common import add_scene_argument

    add_scene_argument(parser)
    parser.add_argument(
        "--out", required=True, help="output folder (CSV, JSON summary, PNG figures)"
    )
    parser.add_argument("--json", action="store_true", help="print the JSON summary on stdout")
    parser.add_argument("--no-figures", action="store_true", help="skip the PNG figures")


def _num(value, spec: str) -> str:
    """A summary number in ``spec``, or "n/a" where the summary has none (None)."""
    return "n/a" if value is None else format(value, spec)


def _path_csv(result) -> str:
    """One row per (side, position, tooth pair) with contact; angle first. ``edge``:
    the border that sets the position's gear angle where no pair's surfaces touch
    (``FlankContact.edge``), empty elsewhere."""
    import numpy as np

    lines = [
        "side,pinion_angle_deg,pair,active,limit,gear_angle_deg,te_arcsec,x_mm,y_mm,z_mm,nx,ny,nz,"
        "pinion_z_mm,pinion_face,pinion_profile,gear_z_mm,gear_face,gear_profile,fpd_deg,"
        "ellipse_major_mm,ellipse_minor_mm,ellipse_angle_deg,iterations,edge"
    ]
    arcsec = 180 / np.pi * 3600
    for fc in (result.drive, result.coast):
        for i, phi in enumerate(fc.pinion_angle):
            for j, pair in enumerate(fc.pair):
                p, n = fc.point[i, j] * 1e3, fc.normal[i, j]
                a, b = fc.ellipse_axes[i, j] * 1e3
                te = (
                    fc.transmission_error[i] * arcsec
                    if np.isfinite(fc.transmission_error[i])
                    else float("nan")
                )
                lines.append(
                    f"{fc.name},{np.degrees(phi):.9f},{pair},{int(fc.active[i, j])},{fc.limit[i, j] or 'on flank'},"
                    f"{np.degrees(fc.gear_angle_pairs[i, j]):.9f},{te:.6g},{p[0]:.6f},{p[1]:.6f},{p[2]:.6f},"
                    f"{n[0]:.9f},{n[1]:.9f},{n[2]:.9f},{fc.pinion_zu[i, j, 0] * 1e3:.6f},"
                    f"{fc.pinion_flank[i, j, 0]:.6f},{fc.pinion_flank[i, j, 1]:.6f},{fc.gear_zu[i, j, 0] * 1e3:.6f},"
                    f"{fc.gear_flank[i, j, 0]:.6f},{fc.gear_flank[i, j, 1]:.6f},{np.degrees(fc.fpd_angle[i, j]):.9f},"
                    f"{a:.6g},{b:.6g},{np.degrees(fc.ellipse_angle[i, j]):.6f},{fc.iterations[i, j]},"
                    f"{fc.edge[i] if fc.edge is not None else ''}"
                )
    return "\n".join(lines) + "\n"


def run(args):

    from ..geometry import PairSpec, design_pair
    from ..scene import load_scene
    from ..surface import tooth_csv, tooth_grid
    from ..tca import run_tca
    from ._common import dumps_json, output_folder, staged_files, write_atomic

    scene = load_scene(args.scene)
    out = output_folder(args.out)
    design = design_pair(PairSpec.from_scene(scene))
    result = run_tca(design, scene)
    summary = result.summary()
    summary = {"scene": scene.name, **summary}
    with staged_files(out) as stage:  # all the files, or none of them
        write_atomic(stage / "tca_summary.json", dumps_json(summary) + "\n")
        write_atomic(stage / "tca_path.csv", _path_csv(result))
        grids = {"pinion": tooth_grid(result.pinion), "gear": tooth_grid(result.gear)}
        for who, grid in grids.items():
            write_atomic(stage / f"{who}_tooth.csv", tooth_csv(grid))
        if not args.no_figures:
            _figures(result, grids, stage, write_atomic)
    if args.json:
        print(dumps_json(summary))
    else:
        s = summary
        print(f"gearbox tca: {scene.name}  status {s['status']}")
        for m in s["messages"]:
            print(f"  note: {m}")
        print(
            f"  FPD angle measured on the surfaces: right {_num(s['measured_fpd_angle_right_deg'], '.6f')} deg, "
            f"left {_num(s['measured_fpd_angle_left_deg'], '.6f')} deg "
            f"(design {_num(s.get('designed_fpd_angle_right_deg'), '.6f')}, "
            f"{_num(s.get('designed_fpd_angle_left_deg'), '.6f')})"
        )
        for side in ("drive", "coast"):
            pp = s["path_position"][side]
            print(
                f"  {side}: TE p-p {_num(s['unloaded_te_peak_to_peak_arcsec'][side], '.3g')} arcsec, "
                f"contact ratio {_num(s['contact_ratio'][side], '.3f')}, path limits "
                f"{' / '.join(s['path_limits'][side])}, path centre pinion face "
                f"{_num(pp['pinion']['face_centroid'], '+.3f')}, gear face "
                f"{_num(pp['gear']['face_centroid'], '+.3f')} (-1 toe .. +1 heel)"
            )
        print(f"  written to {out}/")
    return 0


def _figures(result, grids, out, write_atomic):
    import io

    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    from ..surface.plot import plot_tooth, plot_tooth_sections
    from ..tca.plot import plot_contact_path, plot_transmission_error

    def save(fig, name):
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=120, bbox_inches="tight")
        plt.close(fig)
        write_atomic(out / name, buf.getvalue())

    fig, axes = plt.subplots(2, 1, figsize=(6.5, 6.5))
    plot_contact_path(result, "pinion", ax=axes[0])
    plot_contact_path(result, "gear", ax=axes[1])
    fig.tight_layout()
    save(fig, "tca_contact_path.png")
    fig, ax = plt.subplots(figsize=(6, 3))
    plot_transmission_error(result, ax=ax)
    save(fig, "tca_transmission_error.png")
    for who, grid in grids.items():
        fig = plt.figure(figsize=(10, 5))
        ax = fig.add_subplot(1, 2, 1, projection="3d")
        plot_tooth(grid, ax=ax, title=f"{who} tooth 0 (R blue, L red, fillet grey)")
        plot_tooth_sections(grid, ax=fig.add_subplot(1, 2, 2), title="transverse sections")
        save(fig, f"{who}_tooth.png")

"""The fast level's plane-strain tooth tables: their lattice along the profile shift
against their error and cost.

    python3 benchmarks/ltca_slice_tables.py [--cases 01 02 03 04] [--check 4]
        [--steps 0.005 0.01 0.02 0.04 0.08] [--radii 13 25]

The fast level solves each slice's tooth (the virtual spur tooth of its normal
section) as a plane-strain FE body once per cell of its shape and keeps the table for
the process (``gearbox.ltca.slice_fe``: ``KEY_STEPS``, read linearly between the two
tables either side along the profile shift, which changes along a beveloid's face).
For each lattice step this prints, per paper case (drive flank, both gears, the
grids of a 24-position mesh cycle):

- the tooth compliance's largest and rms error against every section solved on its
  own at its own load radius (``tabulated=False``, the baseline, at ``--check``
  positions spread over the cycle);
- the tables a 24-position cycle needs and the time to solve them in a fresh table
  store, against the baseline's time per position (scaled to 24 positions).

The default step is ``slice_fe.KEY_STEPS[1]``; the other steps change only the
lattice (each cell's own section is generated the same way). ``--radii``: the tables'
load heights (``slice_fe.TABLE_RADII``, a cubic spline between them), each count with
every step.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np

from gearbox import PairSpec, design_pair, load_scene
from gearbox.ltca import slice_fe
from gearbox.ltca.beveloid import scene_grids
from gearbox.ltca.slice_model import normal_section

ROOT = Path(__file__).resolve().parents[1]

FE_GRIDS = {"edge_borders": False}  # the stored FE runs' grids (see bench_fe.py)
POSITIONS = 24


def sections_of(case: str):
    """The normal sections of pinion and gear at each position of the drive flank's
    cycle, and the material constants."""
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=FE_GRIDS)
    grids, _, _ = scene_grids(design_pair(PairSpec.from_scene(scene)), scene, "R", POSITIONS)
    out = [[normal_section(t)[0] for t in (g.tooth1, g.tooth2)] for g in grids]
    return out, grids[0].youngs_modulus, grids[0].poisson_ratio


def with_step(step: float):
    """Set the lattice step along the profile shift; returns the previous steps."""
    old = slice_fe.KEY_STEPS
    steps = list(old)
    steps[slice_fe._LATTICE] = step
    slice_fe.KEY_STEPS = tuple(steps)
    return old


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--cases", nargs="+", default=["01", "02", "03", "04"])
    ap.add_argument("--check", type=int, default=4, help="positions checked against the baseline")
    ap.add_argument("--steps", nargs="+", type=float, default=[0.005, 0.01, 0.02, 0.04, 0.08])
    ap.add_argument("--radii", nargs="+", type=int, default=[slice_fe.TABLE_RADII])
    args = ap.parse_args(argv)
    default = slice_fe.KEY_STEPS[slice_fe._LATTICE]
    checked = np.unique(np.linspace(0, POSITIONS - 1, args.check).round().astype(int))
    print(
        f"tooth compliance of the slices, tables against each section solved alone "
        f"({checked.size} of {POSITIONS} positions, both gears); tables and their time "
        f"for {POSITIONS} positions in a fresh store (default lattice step {default}, "
        f"{slice_fe.TABLE_RADII} load heights)"
    )
    head = f"{'case':>4} {'radii':>5} {'step':>6} {'max err %':>9} {'rms err %':>9} {'tables':>6} {'time s':>7}"
    head += f" {'alone s':>8} {'ratio':>6}"
    print(head)
    for case in args.cases:
        sections, E, nu = sections_of(case)
        t0 = time.perf_counter()
        alone = {
            (j, k): slice_fe.fe_tooth_compliance(v, E, nu, tabulated=False)
            for j in checked
            for k, v in enumerate(sections[j])
        }
        t_alone = (time.perf_counter() - t0) / checked.size * POSITIONS
        for radii, step in ((n, st) for n in args.radii for st in args.steps):
            old, old_radii = with_step(step), slice_fe.TABLE_RADII
            slice_fe.TABLE_RADII = radii
            try:
                slice_fe._TABLES.clear()
                t0 = time.perf_counter()
                values = [[slice_fe.fe_tooth_compliance(v, E, nu) for v in pos] for pos in sections]
                t_tab = time.perf_counter() - t0
                n_tables = len(slice_fe._TABLES)
            finally:
                slice_fe.KEY_STEPS, slice_fe.TABLE_RADII = old, old_radii
                slice_fe._TABLES.clear()
            err = np.concatenate([values[j][k] / alone[j, k] - 1.0 for (j, k) in alone])
            mark = " (default)" if (step, radii) == (default, old_radii) else ""
            print(
                f"{case:>4} {radii:5d} {step:>6g} {100 * np.abs(err).max():9.3f} "
                f"{100 * np.sqrt(np.mean(err**2)):9.3f} {n_tables:6d} {t_tab:7.2f} "
                f"{t_alone:8.1f} {t_alone / t_tab:6.0f}{mark}"
            )


if __name__ == "__main__":
    main()

"""Stress test of the unloaded TCA on random valid beveloid designs under random
assembly errors.

    python3 benchmarks/tca_random_errors.py [--seed 11] [--designs 40] [--positions 21]

Designs are drawn as ``benchmarks/ltca_random_designs.py`` draws them (case 03's tool
and module, pinion teeth 12..35, gear teeth 30..60, x_t1 -0.3..0.8, helix 5..25 deg,
cones 0..4 deg, shaft angle 5..20 deg); each gets an offset error of -0.1..0.1 mm, a
shaft-angle error of -0.05..0.05 deg and a pinion axial error of -0.5..0.5 mm, all
uniform. Many of these designs are near line contact on one flank, where such errors
move the surfaces' contact off the face and the teeth touch at a border of a flank
(gearbox.tca.edge).

Prints the count of each outcome (the TCA's status, "+edges" where some position has
edge contact, "+N nan" where N positions have no contact at all, the refusals and
failures with their last line) and the median and largest time of a TCA.
"""

from __future__ import annotations

import argparse
import collections
import math
import statistics
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from ltca_random_designs import draw_design  # noqa: E402


def main(argv=None) -> None:
    from gearbox import load_scene
    from gearbox.errors import InputError
    from gearbox.tca import TCASettings, run_tca
    from gearbox.tca.assembly import AssemblyErrors

    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--designs", type=int, default=40)
    ap.add_argument("--positions", type=int, default=21)
    args = ap.parse_args(argv)
    base = load_scene(ROOT / "models" / "case03.toml")
    rng = np.random.default_rng(args.seed)
    outcomes: collections.Counter = collections.Counter()
    seconds = []
    n = 0
    while n < args.designs:
        got = draw_design(rng, base)
        if got is None:
            continue
        n += 1
        _, _, design = got
        err = AssemblyErrors(
            offset=float(rng.uniform(-0.1, 0.1)) * 1e-3,
            shaft_angle=math.radians(float(rng.uniform(-0.05, 0.05))),
            pinion_axial=float(rng.uniform(-0.5, 0.5)) * 1e-3,
        )
        t0 = time.perf_counter()
        try:
            res = run_tca(design, errors=err, settings=TCASettings(positions=args.positions))
            kind = res.status
            sides = (res.drive, res.coast)
            if any((fc.edge != "").any() for fc in sides):
                kind += " +edges"
            nan = sum(int(np.isnan(fc.gear_angle).sum()) for fc in sides)
            if nan:
                kind += f" +{nan} nan"
        except InputError as exc:
            kind = "refused: " + str(exc).splitlines()[-1].strip()[:160]
        except Exception as exc:  # noqa: BLE001 - the point of a stress test
            kind = "FAILED: " + repr(exc)[:200]
        seconds.append(time.perf_counter() - t0)
        outcomes[kind] += 1
    for kind, count in outcomes.most_common():
        print(f"{count:4d}  {kind}")
    print(
        f"seed {args.seed}: {n} designs; TCA median {statistics.median(seconds):.2f} s, "
        f"largest {max(seconds):.2f} s ({args.positions} positions, both flanks)"
    )


if __name__ == "__main__":
    sys.exit(main())

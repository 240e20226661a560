"""Benchmark: full unloaded TCA of case 03 (drive and coast, 61 positions).

Prints the median wall time of ``run_tca`` (surfaces generated on the fly, both
flanks, 61 pinion positions x 9 tooth pairs each, batched Newton) and, as the
baseline measured in the same run, the same contact problems solved one at a time
with ``scipy.optimize.fsolve`` (finite-difference Jacobian, one call per problem) on
a subset, scaled per problem. Also the cost of a surface grid, and of a TCA with edge
contact (the paper's case 01 under a 0.02 deg shaft-angle error) against the same pair
without errors.

    python3 benchmarks/bench_tca.py
"""

from __future__ import annotations

import math
import statistics
import time
from pathlib import Path

import numpy as np
from scipy.optimize import fsolve

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair
from gearbox.surface import blanks_from_design, tooth_grid
from gearbox.tca import Assembly, TCASettings, run_tca
from gearbox.tca.assembly import AssemblyErrors
from gearbox.tca.contact import contact_residual

SCENE = Path(__file__).parents[1] / "models" / "case03.toml"


def timed(fn, repeats):
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def main():
    scene = load_scene(SCENE)
    design = design_pair(PairSpec.from_scene(scene))
    settings = TCASettings(positions=61)
    t_tca, res = timed(lambda: run_tca(design, settings=settings), 7)
    n_problems = sum(fc.active.size for fc in (res.drive, res.coast))

    # baseline: the same drive-side problems, one fsolve call each, same start values
    pinion, gear = blanks_from_design(design)
    asm = Assembly.from_design(design)
    fc = res.drive
    N1 = pinion.teeth
    phis = (fc.pinion_angle[:, None] + 2 * np.pi * fc.pair[None, :] / N1).ravel()
    x_sol = np.concatenate(
        [
            fc.pinion_zu,
            fc.gear_zu,
            (fc.gear_angle_pairs - 2 * np.pi * fc.pair / gear.teeth)[..., None],
        ],
        axis=-1,
    ).reshape(-1, 5)
    rng = np.random.default_rng(1)
    subset = rng.choice(len(phis), 40, replace=False)
    perturb = np.array([1e-3, 1e-3, 1e-3, 1e-3, 1e-3])  # start 1 mm / 1 mrad off the solution

    def one_by_one():
        errs = []
        for k in subset:
            f = lambda x, k=k: contact_residual(pinion, gear, asm, "R", [phis[k]], x[None, :])[0][0]  # noqa: E731
            x = fsolve(f, x_sol[k] + perturb, xtol=1e-13)
            errs.append(np.max(np.abs(x - x_sol[k])))
        return max(errs)

    t_base, err = timed(one_by_one, 3)
    t_base_per = t_base / len(subset)

    # batched solver on the same perturbed starts (all drive problems at once)
    from gearbox.tca.contact import solve_contact

    t_batch, sol = timed(lambda: solve_contact(pinion, gear, asm, "R", phis, x_sol + perturb), 7)
    t_grid, _ = timed(lambda: tooth_grid(pinion, 41, 61), 7)
    low = (x_sol[:, 1] < -pinion.normal_module) | (x_sol[:, 3] < -gear.normal_module)
    n_far = int(np.sum(~sol.converged & low))

    print("unloaded TCA, case 03 (median wall times)")
    print(
        f"  full run_tca (drive + coast, 61 positions, {n_problems} contact problems): {t_tca * 1e3:8.1f} ms"
    )
    print(
        f"  batched Newton, {len(phis)} drive problems from 1 mm / 1 mrad off:  {t_batch * 1e3:8.1f} ms "
        f"(converged {int(sol.converged.sum())} of {len(phis)}; not converged with the solution more than "
        f"one module below a form circle: {n_far})"
    )
    print(
        f"  baseline fsolve one problem at a time:                    {t_base_per * 1e3:8.2f} ms per problem "
        f"(max deviation from the batched solution {err:.1e})"
    )
    print(
        f"  baseline scaled to {len(phis)} problems:                          {t_base_per * len(phis) * 1e3:8.1f} ms"
    )
    print(
        f"  ratio baseline / batched (same problems):               {t_base_per * len(phis) / t_batch:8.1f}"
    )
    print(f"  tooth surface grid 41 x 61 (+ fillet), both flanks:    {t_grid * 1e3:8.1f} ms")
    # edge contact (gearbox.tca.edge): the paper's case 01 under a 0.02 deg shaft-angle
    # error, whose drive flank has no surface contact on the real flanks at any
    # position, against case 01 without errors in the same run
    d01 = design_pair(PairSpec.from_scene(load_scene(SCENE.parent / "case01.toml")))
    t01, _ = timed(lambda: run_tca(d01, settings=settings), 5)
    tilt = AssemblyErrors(shaft_angle=math.radians(0.02))
    t01e, r01e = timed(lambda: run_tca(d01, errors=tilt, settings=settings), 3)
    n_edge = int(np.sum(r01e.drive.edge != ""))
    print(
        f"  case 01, no errors:                                     {t01 * 1e3:8.1f} ms\n"
        f"  case 01, 0.02 deg shaft-angle error (edge contact at {n_edge} of 61 drive positions, "
        f"32 candidates): {t01e * 1e3:8.1f} ms, {t01e / t01:.1f} x"
    )
    print(f"  target < 1 s for the full TCA: {'met' if t_tca < 1.0 else 'NOT met'}")


if __name__ == "__main__":
    main()

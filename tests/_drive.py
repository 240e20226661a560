"""The default scene's drive flank at a few positions, for tests of the loaded TCA's
hunting record (pitch and form deviations) that share its set-up; the order spectrum
of a drive's run against the pinion's own angle; and the check that a record's added
lines lie at gear orders."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca import LTCAOptions, compliance_for, ltca_cycle
from gearbox.ltca.beveloid import scene_grids

ROOT = Path(__file__).resolve().parents[1]


def default_drive(positions: int, torques=(300.0, 802.0)):
    """(scene, design, grids, compliance, loaded TCA) of models/marine_drive.toml's
    drive flank at ``positions`` per mesh cycle, the fast level, ``torques`` (N m)."""
    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    design = design_pair(PairSpec.from_scene(scene))
    grids, _, _ = scene_grids(design, scene, "R", positions)
    comp = compliance_for("fast")
    res = ltca_cycle(
        lambda f: grids[round(f * positions)],
        list(torques),
        options=LTCAOptions(positions=positions),
        compliance=comp,
    )
    return scene, design, grids, comp, res


def parallel_drive(pair, positions: int, n_face: int, torques=(200.0, 400.0)):
    """(grids, compliance, loaded TCA) of a parallel pair's drive flank
    (:class:`gearbox.ltca.ParallelPair`) at ``positions`` per mesh cycle, the
    closed-form grid of ``n_face`` slices, the fast level, ``torques`` (N m)."""
    from gearbox.ltca.parallel import parallel_grid

    grids = [parallel_grid(pair, j / positions, n_face) for j in range(positions)]
    comp = compliance_for("fast")
    res = ltca_cycle(
        lambda f: grids[round(f * positions) % positions],
        list(torques),
        options=LTCAOptions(positions=positions),
        compliance=comp,
    )
    return grids, comp, res


def angle_spectrum(ts, channel: str, revs: int = 45):
    """Order spectrum (single-sided peak amplitudes, bins of 1 / revs pinion order) of a
    run's ``channel`` against the pinion's own angle: uniform resampling over the
    record's whole hunting period of ``revs`` pinion revolutions."""
    th = ts.channels["pinion_angle_rad"]
    n = ts.time.size
    grid = th[0] + np.arange(n) * (2 * math.pi * revs / n)
    x = np.interp(grid, th, ts.channels[channel])
    return np.abs(np.fft.rfft(x)) / n * 2


def added_lines_at_gear_orders(rec):
    """Assert that every line the deviations add to a hunting record's TE (against the
    nominal teeth's) lies at a gear order, to 1e-9 of the largest; return the record's
    (orders, amplitudes)."""
    z1, z2 = rec.teeth
    orders, amp = rec.order_spectrum()
    added = np.abs(amp - rec.order_spectrum("lte_nominal")[1])
    gear_order = np.isclose(orders * z2 / z1, np.round(orders * z2 / z1), atol=1e-9)
    assert added[~gear_order].max() < 1e-9 * added.max()
    return orders, amp

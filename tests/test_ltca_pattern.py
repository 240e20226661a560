"""The contact pattern's raster (gearbox.ltca.analysis._pattern): a tooth's contact swept
between positions, and the pattern of few positions against one of many."""

from pathlib import Path

import numpy as np
import pytest

from gearbox.ltca.analysis import _pattern

ROOT = Path(__file__).resolve().parents[1]

#: 10 profile cells of 1 mm over [0, 10] mm, 2 face cells of 1 mm over [0, 2] mm
PROFILE = (0.0, 0.010)
FACE = (0.0, 0.002)


def _samples(age, profile_mm, pressure, loaded, edge=None, slot=0, half_mm=0.1):
    n = len(age)
    return {
        "age": np.asarray(age, float),
        "profile": 1e-3 * np.asarray(profile_mm, float),
        "face": np.full(n, 0.0005 + 0.001 * slot),
        "half": np.full(n, 1e-3 * half_mm),
        "width": np.full(n, 0.001),
        "pressure": np.asarray(pressure, float),
        "loaded": np.asarray(loaded, bool),
        "edge": np.zeros(n, bool) if edge is None else np.asarray(edge, bool),
        "slot": np.full(n, slot),
    }


def test_contact_is_swept_between_positions():
    # one tooth in one slice at four positions 0.25 cycles apart, 2.5 mm up the profile
    # each: every cell from the first to the last loaded height is met, the pressure
    # interpolated linearly between the positions (cell centres at 0.5, 1.5, ... mm)
    raster = np.zeros((10, 2))
    s = _samples(
        [0.0, 0.25, 0.5, 0.75], [1.0, 3.5, 6.0, 8.5], [100.0, 200.0, 300.0, 400.0], [1] * 4
    )
    _pattern(raster, PROFILE, FACE, s, 0.25)
    col = raster[:, 0]
    assert np.all(raster[:, 1] == 0.0)  # the other slice
    # 1.0 .. 8.5 mm swept; each end reaches half a step further (1.25 mm) plus its
    # half-width (0.1 mm), extrapolated: the tooth leaves the grid on both sides
    assert np.all(col[0:10] > 0)
    assert col[2] == pytest.approx(100.0 + 100.0 * (2.5 - 1.0) / 2.5)
    assert col[4] == pytest.approx(200.0 + 100.0 * (4.5 - 3.5) / 2.5)
    assert col[9] == pytest.approx(400.0)  # beyond the last position: its pressure

    # the samples' own rectangles alone (a step of more than one cycle: no sweep, no
    # ends) leave the cells between the positions empty
    raster = np.zeros((10, 2))
    s = _samples([0.0, 2.0, 4.0, 6.0], [1.0, 3.5, 6.0, 8.5], [100.0] * 4, [1] * 4)
    _pattern(raster, PROFILE, FACE, s, 0.25)
    assert np.flatnonzero(raster[:, 0]).tolist() == [1, 3, 6, 8]


def test_contact_ends_half_way_to_an_unloaded_position_and_does_not_jump():
    # loaded at 2.0 and 4.0 mm, unloaded at 6.0 mm: the contact ends half way (5.0 mm,
    # plus the half-width 0.1 mm), so the cell at 5.5 mm stays empty; a loaded point on
    # a border at 9.0 mm (edge) is not swept to from the flank (the contact jumps)
    raster = np.zeros((10, 2))
    s = _samples(
        [0.0, 0.25, 0.5, 0.75],
        [2.0, 4.0, 6.0, 9.0],
        [100.0, 100.0, 0.0, 500.0],
        [1, 1, 0, 1],
        edge=[0, 0, 0, 1],
    )
    _pattern(raster, PROFILE, FACE, s, 0.25)
    col = raster[:, 0]
    assert np.flatnonzero(col).tolist() == [1, 2, 3, 4, 9]
    assert col[9] == 500.0 and col[4] == 100.0


@pytest.mark.slow
def test_pattern_of_24_positions_reads_the_pattern_of_192():
    # case 03, drive flank, 300 N m: the pattern of the default 24 positions against
    # 192 positions. Measured: 31 cells of 1600 differ, area 0.677 against 0.695; the
    # samples' rectangles alone (before the sweep) missed 52 cells, area 0.663
    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.analysis import LTCAOptions
    from gearbox.ltca.table import scene_ltca

    scene = load_scene(ROOT / "models" / "case03.toml")
    scene = scene.replaced(load={"torques_Nm": [300.0]}, ltca={"flanks": ["drive"]})
    design = design_pair(PairSpec.from_scene(scene))
    pat = {
        p: scene_ltca(design, scene, options=LTCAOptions(positions=p)).flanks["drive"]
        for p in (24, 192)
    }
    few, many = (pat[p].pattern_pressure[0] > 0 for p in (24, 192))
    assert int((few ^ many).sum()) <= 40
    assert many.mean() - few.mean() < 0.025
    assert pat[24].pattern_area_fraction[0] == pytest.approx(few.mean())

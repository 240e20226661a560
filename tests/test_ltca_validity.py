"""The fast level's notes for pairs outside the range it was checked on
(gearbox.ltca.validity): each limit is a checked geometry's, so a pair on the checked
side gets no note and one past it gets a note naming the gear, its value and the
limit; the loaded TCA, its summary, the CLI and the report carry them."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from dataclasses import replace
from pathlib import Path
from types import SimpleNamespace

import pytest

from gearbox import load_scene
from gearbox.ltca import ParallelPair, parallel_grid
from gearbox.ltca.compliance import body_tilt
from gearbox.ltca.validity import BODY_TILT_MAX, fast_level_notes

DATA = Path(__file__).parent / "data"

#: the FE level's whole-gear pair BODY_TILT was fitted on (z 20 / 40, m_n 4, b 30 mm)
FITTED = ParallelPair(4e-3, math.radians(20.0), 0.0, (20, 40), face_width=0.03)


def _notes(pair: ParallelPair) -> tuple[str, ...]:
    return fast_level_notes(parallel_grid(pair, 0.0, 12))


def test_inside_the_checked_range_there_are_no_notes():
    """Spur, 15 and 25 deg on faces of 7.5 m_n: nothing to say."""
    for deg in (0.0, 15.0, 25.0):
        assert _notes(replace(FITTED, helix_angle=math.radians(deg))) == (), deg


def test_a_helix_angle_above_the_papers_names_both_gears():
    notes = _notes(replace(FITTED, helix_angle=math.radians(30.0)))
    assert len(notes) == 1  # the body's tilt at 30 deg is the fitted one (1.39 < 1.41)
    (note,) = notes
    assert note.startswith("helix angle above the 25 deg")
    assert "pinion 30.0 deg" in note and "gear 30.0 deg" in note
    assert 'ltca.fidelity = "fe"' in note
    assert _notes(replace(FITTED, helix_angle=math.radians(-26.0)))  # either hand


def test_a_narrow_face_is_named_in_normal_modules():
    """b = 4.9 m_n is below the 5 m_n the face load distribution holds to; 5.1 is not."""
    (note,) = _notes(replace(FITTED, face_width=4.9 * FITTED.normal_module))
    assert note.startswith("face narrower than the 5 m_n")
    assert "pinion 19.6 mm = 4.90 m_n" in note and "gear 19.6 mm = 4.90 m_n" in note
    assert _notes(replace(FITTED, face_width=5.1 * FITTED.normal_module)) == ()


def test_the_body_tilt_note_starts_past_the_fitted_gear():
    """The fitted gear z 40 at 30 deg sits at 1.39 / E, inside; a gear of 200 teeth on
    the same face is 34 times past it, and the note says by how much; a spur gear's
    body does not tilt (no axial load), however large."""
    fitted = replace(FITTED, helix_angle=math.radians(30.0))
    g = parallel_grid(fitted, 0.0, 12)
    assert body_tilt(g, 1) == pytest.approx(1.39, abs=0.01)
    assert body_tilt(g, 1) < BODY_TILT_MAX
    large = replace(FITTED, helix_angle=math.radians(30.0), teeth=(20, 200))
    tilt = body_tilt(parallel_grid(large, 0.0, 12), 1)
    notes = _notes(large)
    (note,) = [n for n in notes if n.startswith("gear body tilt")]
    assert f"gear {tilt:.2f} / E: {tilt / BODY_TILT_MAX:.1f} times" in note
    assert "pinion" not in note  # the pinion z 20 is the fitted one
    assert _notes(replace(FITTED, teeth=(20, 200))) == ()


def test_the_papers_cases_lie_inside_the_checked_range():
    """The paper's pairs are where the fast level was checked: case 01's pinion at
    25 deg is the edge, and neither flank of it or of the default scene's case 03
    gets a note."""
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import scene_grids

    for case in ("case01", "case03"):
        scene = load_scene(Path(__file__).parents[1] / "models" / f"{case}.toml")
        design = design_pair(PairSpec.from_scene(scene))
        for side in ("R", "L"):
            grids, _, _ = scene_grids(design, scene, side, 4)
            assert fast_level_notes(grids[0]) == (), (case, side)


def _scene_30_deg():
    return load_scene(DATA / "ltca_parallel_helical.toml").replaced(
        pinion={"helix_angle_deg": 30.0},
        pair={"offset_mm": 74 * 6.0 / 2 / math.cos(math.radians(30.0))},
        ltca={"positions": 6, "flanks": ["drive"]},
        load={"torques_Nm": [300.0]},
    )


def test_the_loaded_tca_and_its_report_carry_the_notes():
    """scene_ltca puts the notes in the result and its summary; the report's LTCA
    section lists each among its warnings; a pair inside the range gets none."""
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.table import scene_ltca
    from gearbox.report.loaded import render_ltca

    scene = _scene_30_deg()
    design = design_pair(PairSpec.from_scene(scene))
    res = scene_ltca(design, scene)
    # the helix angle, and the gear z 45's body (r_f / b 3.7 at 30 deg: 1.6 times the
    # fitted tilt)
    assert len(res.notes) == 2 and "pinion 30.0 deg" in res.notes[0]
    assert res.notes[1].startswith("gear body tilt") and "r_f / b 3.7" in res.notes[1]
    assert res.summary()["notes"] == list(res.notes)

    section = render_ltca(res, SimpleNamespace(scene=scene))
    texts = [w.text for w in section.warnings if w.source == "ltca"]
    assert all(note in texts for note in res.notes)
    scene = load_scene(DATA / "ltca_parallel_helical.toml").replaced(
        ltca={"positions": 6, "flanks": ["drive"]}, load={"torques_Nm": [300.0]}
    )
    plain = scene_ltca(design_pair(PairSpec.from_scene(scene)), scene)
    assert plain.notes == () and plain.summary()["notes"] == []


def test_gearbox_ltca_prints_the_notes(tmp_path):
    from gearbox.report.build import scene_toml

    path = tmp_path / "helical30.toml"
    path.write_text(scene_toml(_scene_30_deg()))
    cmd = [sys.executable, "-m", "gearbox", "ltca", str(path), "--out", str(tmp_path / "o")]
    out = subprocess.run([*cmd, "--no-figures"], capture_output=True, text=True, check=True)
    assert "  note: helix angle above the 25 deg" in out.stdout
    summary = json.loads((tmp_path / "o" / "ltca_summary.json").read_text())
    assert summary["notes"] and "gear 30.0 deg" in summary["notes"][0]

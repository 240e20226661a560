"""The active-root design check (the mating tip's contact ends above the root form
circle, ISO 21771 d_Nf >= d_Ff) against the unloaded TCA on the generated surfaces,
and undercut flanks: the TCA keeps to the regular involute, the loaded TCA notes
the interference of a tip that reaches below the form circle.

Variants of case 03's pair with a 12-tooth pinion: the backlash-free gear shift
follows the offset, and the pinion's shift moves its form circle. Measured on these
(2026-12): the check fails for x_t1 <= 0.84 and passes from 0.85; the TCA's paths end
at the pinion's form circle for x_t1 <= 0.76 and at the gear's tip from 0.78 (at 41
and 121 positions alike): the sectional check is the conservative side (its worst
face section against the path's own end)."""

import math

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.errors import InputError
from gearbox.geometry import PairSpec, design_pair
from gearbox.surface import blanks_from_design, flank_points, fold_parameter, involute_start
from gearbox.tca import TCASettings, run_tca

SETTINGS = TCASettings(positions=41, mesh_cycles=2.0)


def _variant(teeth: int, xt: float, offset_mm: float):
    scene = load_scene("models/case03.toml")
    scene = scene.replaced(
        pinion={"teeth": teeth, "profile_shift_xt": xt, "helix_angle_deg": 20.0},
        pair={"offset_mm": offset_mm},
    )
    return scene, design_pair(PairSpec.from_scene(scene))


def _roots(design) -> dict[str, bool]:
    return {k: c.ok for k, c in design.checks.items() if "_active_root_" in k}


@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_paper_cases_pass_and_their_paths_end_at_the_tips(case):
    scene = load_scene(f"models/case{case}.toml")
    design = design_pair(PairSpec.from_scene(scene))
    assert all(_roots(design).values()) and len(_roots(design)) == 4
    res = run_tca(design, scene, settings=SETTINGS)
    for fc in (res.drive, res.coast):
        assert sorted(fc.path_limits) == ["gear tip", "pinion tip"]
    assert not any("root form circle" in m for m in res.messages)


def test_a_small_pinion_fails_where_the_tca_path_ends_at_its_form_circle():
    scene, design = _variant(12, 0.35, 165.0)
    ok = _roots(design)
    assert not ok["pinion_active_root_right"] and not ok["pinion_active_root_left"]
    assert ok["gear_active_root_right"] and ok["gear_active_root_left"]
    assert "below the base circle" in design.checks["pinion_active_root_right"].detail
    res = run_tca(design, scene, settings=SETTINGS)
    assert "pinion root" in res.drive.path_limits and "pinion root" in res.coast.path_limits
    notes = [m for m in res.messages if "root form circle" in m]
    assert len(notes) == 2 and "pinion_active_root_right" in notes[0]
    # a larger shift (and the offset that keeps x_t2 in range): both pass
    scene, design = _variant(12, 0.9, 169.5)
    assert all(_roots(design).values())
    res = run_tca(design, scene, settings=SETTINGS)
    assert sorted(res.drive.path_limits) == ["gear tip", "pinion tip"]


def test_the_check_is_conservative_against_the_surfaces():
    """x_t1 = 0.80: the TCA's paths still end at the gear's tip; the check fails. The
    path's end is named by the limit nearest to its refined end: the first limit that
    the next position outside violates named the pinion's root here at 41 positions."""
    scene, design = _variant(12, 0.80, 168.5)
    assert not design.checks["pinion_active_root_right"].ok
    margin = design.checks["pinion_active_root_right"].margin
    assert -1e-3 < margin < 0  # 0.53 mm of path measured
    res = run_tca(design, scene, settings=SETTINGS)
    assert sorted(res.drive.path_limits) == ["gear tip", "pinion tip"]
    assert sorted(res.coast.path_limits) == ["gear tip", "pinion tip"]


def test_undercut_pinion_tca_keeps_to_the_involute_and_ltca_notes_interference():
    from gearbox.ltca.beveloid import beveloid_ltca

    scene, design = _variant(12, 0.16, 165.0)
    assert not design.checks["pinion_undercut_right"].ok
    pinion, gear = blanks_from_design(design)
    for side in "RL":
        z = np.array([pinion.z_toe, 0.0, pinion.z_heel])
        u = fold_parameter(pinion, side, z)
        assert np.all(u > 0)
        # the fold lies on the base cylinder (docs/surface.md)
        r = flank_points(pinion, side, z, u, involute_only=True).radius
        assert np.allclose(r, design.pinion.base_radius["RL".index(side)], rtol=0, atol=1e-9)
        # the fillet cuts the regular involute above the fold
        assert np.all(involute_start(pinion, side, z) > u)
        assert np.all(involute_start(gear, side, z) == 0)
    res = run_tca(design, scene, settings=SETTINGS)
    s = res.summary()
    # contacts on the folded branch gave a mean of 7.1 deg with an 89 deg spread
    for flank, k in (("right", 0), ("left", 1)):
        assert abs(s[f"measured_fpd_angle_{flank}_deg"] - math.degrees(res.designed_fpd[k])) < 1e-6
        assert s[f"measured_fpd_angle_{flank}_spread_deg"] < 1e-6
    # the loaded TCA takes the undercut pinion from where its fillet cuts the involute
    # (tests/test_ltca_undercut.py); here the gear's tip reaches 10.2 mm of path below
    # the pinion's form circle, meshing interference, which it names
    res = beveloid_ltca(design, scene.replaced(ltca={"positions": 8}))
    notes = [n for n in res.notes if "meshing interference" in n]
    assert len(notes) == 2
    assert "pinion_active_root_right" in notes[0] and "pinion_active_root_left" in notes[1]


def test_ltca_refuses_flanks_that_do_not_overlap():
    """Case 04 with x_t2 = -1.5 (no backlash-free shift): transverse contact ratio below
    0, the TCA finds no contact; the loaded TCA gave a table of tip-edge contact."""
    from gearbox.ltca.beveloid import beveloid_ltca

    scene = load_scene("models/case04.toml").replaced(
        pair={"offset_mm": 232.435, "backlash_free": False},
        gear={"profile_shift_xt": -1.5},
        ltca={"flanks": ["coast"], "positions": 4},
    )
    design = design_pair(PairSpec.from_scene(scene))
    assert design.checks["transverse_contact_ratio_left"].margin < -1.0
    with pytest.raises(
        InputError, match=r"ltca.flanks\[coast\] = 'coast': the transverse contact ratio is -0.0"
    ):
        beveloid_ltca(design, scene)


def test_ltca_refuses_pointed_teeth():
    """Gear teeth pointed by their profile shift (an 8-tooth pinion's solved x_t2 gave
    tip thickness -0.94 mm): RuntimeWarnings and a 'moment image decay' error before."""
    from gearbox.ltca.beveloid import beveloid_ltca

    scene = load_scene("models/case03.toml").replaced(
        pair={"backlash_free": False}, gear={"profile_shift_xt": 2.5}
    )
    design = design_pair(PairSpec.from_scene(scene))
    assert design.checks["gear_topping"].margin + 0.25 * design.spec.normal_module < 0
    with pytest.raises(
        InputError, match=r"gear.profile_shift_xt = 2.5: the gear's teeth are pointed"
    ):
        beveloid_ltca(design, scene)

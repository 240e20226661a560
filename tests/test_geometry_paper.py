"""Tier (b): the paper's Table 2 from its printed inputs.

Source: "Geometry Design and Tooth Contact Analysis of Crossed Beveloid Gears for
Marine Transmissions", Tables 1 and 2 (tests/data/paper_tables.toml). Tolerances are
half a unit of the last printed digit or tighter: xi_n 1e-4 (printed 4 decimals),
beta_2 0.01 deg (printed 2), xi_R / xi_L 1e-3 deg (printed 4), x_t2 1e-3 (printed 4).
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import least_squares

from gearbox import load_scene
from gearbox.geometry import GearSpec, PairSpec, design_pair, solve_pair_arrays

DATA = tomllib.loads((Path(__file__).parent / "data" / "paper_tables.toml").read_text())
T1 = DATA["table1"]
ROWS = {row["case"]: row for row in DATA["table2"]}
MODELS = Path(__file__).parents[1] / "models"


def spec_from_table(case: str, offset_mm: float = T1["offset_mm"]) -> PairSpec:
    row = ROWS[case]
    d = math.radians
    return PairSpec(
        normal_module=T1["normal_module_mm"] * 1e-3,
        normal_pressure_angle=d(T1["normal_pressure_angle_deg"]),
        shaft_angle=d(T1["shaft_angle_deg"]),
        offset=offset_mm * 1e-3,
        pinion=GearSpec(
            T1["teeth"][0],
            d(row["helix_angle_deg"][0]),
            d(row["cone_angle_deg"][0]),
            row["profile_shift_xt"][0],
        ),
        gear=GearSpec(T1["teeth"][1], None, d(row["cone_angle_deg"][1]), None),
    )


@pytest.mark.parametrize("case", ["01", "02", "03"])
def test_table2_reproduced_from_printed_inputs(case):
    row = ROWS[case]
    d = design_pair(spec_from_table(case))
    msg = f"paper Table 2, case {case}"
    assert abs(d.normal_angular_factor - row["normal_angular_factor"]) < 1e-4, msg
    assert abs(math.degrees(d.gear.helix_angle) - row["helix_angle_deg"][1]) < 0.01, msg
    assert abs(math.degrees(d.fpd_angle_right) - row["fpd_angle_right_deg"]) < 1e-3, msg
    assert abs(math.degrees(d.fpd_angle_left) - row["fpd_angle_left_deg"]) < 1e-3, msg
    assert abs(d.gear.profile_shift_xt - row["profile_shift_xt"][1]) < 1e-3, msg


@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_scene_files_carry_table2_and_reproduce_it(case):
    """The scene files hold the printed inputs; designing them gives the printed outputs."""
    scene = load_scene(MODELS / f"case{case}.toml")
    row = ROWS[case]
    assert scene["pinion"]["helix_angle_deg"] == row["helix_angle_deg"][0]
    assert [scene["pinion"]["cone_angle_deg"], scene["gear"]["cone_angle_deg"]] == row[
        "cone_angle_deg"
    ]
    d = design_pair(PairSpec.from_scene(scene))
    assert abs(d.normal_angular_factor - row["normal_angular_factor"]) < 1e-4
    assert abs(math.degrees(d.fpd_angle_right) - row["fpd_angle_right_deg"]) < 1e-3
    assert abs(math.degrees(d.fpd_angle_left) - row["fpd_angle_left_deg"]) < 1e-3
    # case 04 prints x_t2 with two decimals only ("0.15"): half a unit is 5e-3
    tol = 5e-3 if case == "04" else 1e-3
    assert abs(d.gear.profile_shift_xt - row["profile_shift_xt"][1]) < tol
    assert d.checks["gear_helix_angle_given"].ok


def test_case04_does_not_reproduce_with_printed_offset():
    """With Table 1's E = 229 mm, case 04's printed outputs are far off (not rounding)."""
    row = ROWS["04"]
    d = design_pair(spec_from_table("04"))
    assert abs(d.normal_angular_factor - row["normal_angular_factor"]) > 50 * 1e-4
    assert abs(math.degrees(d.fpd_angle_right) - row["fpd_angle_right_deg"]) > 0.4
    assert abs(d.gear.profile_shift_xt - row["profile_shift_xt"][1]) > 0.3


def _fit_single_input(name: str):
    """Least-squares fit of one printed input of case 04 to its four printed outputs.

    Residuals are scaled by half a unit of each output's last printed digit, so a
    residual norm below ~1 per output means 'consistent with the printed rounding'.
    """
    row = ROWS["04"]
    target = np.array(
        [
            row["normal_angular_factor"],
            row["helix_angle_deg"][1],
            row["fpd_angle_right_deg"],
            row["fpd_angle_left_deg"],
        ]
    )
    scale = np.array([0.5e-4, 0.5e-2, 0.5e-4, 0.5e-4])
    base = dict(
        gamma1=row["cone_angle_deg"][0],
        gamma2=row["cone_angle_deg"][1],
        beta1=row["helix_angle_deg"][0],
        offset=T1["offset_mm"],
        delta=T1["shaft_angle_deg"],
        alpha_n=T1["normal_pressure_angle_deg"],
    )

    def outputs(v):
        p = dict(base, **{name: v})
        r = math.radians
        s = solve_pair_arrays(
            T1["normal_module_mm"] * 1e-3,
            r(p["alpha_n"]),
            r(p["delta"]),
            p["offset"] * 1e-3,
            T1["teeth"][0],
            T1["teeth"][1],
            r(p["beta1"]),
            r(p["gamma1"]),
            r(p["gamma2"]),
        )
        return np.array(
            [
                float(s["xi_n"]),
                math.degrees(float(s["beta2"])),
                math.degrees(float(s["fpd_right"])),
                math.degrees(float(s["fpd_left"])),
            ]
        )

    def resid(v):
        out = outputs(v[0])
        return np.where(np.isfinite(out), (out - target) / scale, 1e6)

    best = None
    for f in np.linspace(0.5, 1.5, 11):
        x0 = base[name] * f if base[name] else f - 0.5
        sol = least_squares(resid, [x0])
        if best is None or sol.cost < best.cost:
            best = sol
    return best.x[0], np.abs(resid(best.x)).max(), lambda v: np.abs(resid([v])).max()


def test_case04_offset_is_the_inconsistent_input():
    """Of all printed inputs, only the offset explains case 04's printed outputs.

    Fitting each input alone: the offset lands on 232.0 mm with every output within
    one unit of its last printed digit; every other input leaves residuals of more
    than ten units.
    """
    fitted_E, _, worst_at = _fit_single_input("offset")
    assert abs(fitted_E - 232.0) < 0.05, fitted_E
    # at the round value E = 232 mm every output is within one unit of its last printed
    # digit (measured worst: 0.84 units, xi_R); every other input misses by > 10 units
    assert worst_at(232.0) < 2.0, worst_at(232.0)
    for name in ("gamma1", "gamma2", "beta1", "delta", "alpha_n"):
        _, worst, _ = _fit_single_input(name)
        assert worst > 20.0, (name, worst)
    # and with E = 232 mm the whole printed row follows
    row = ROWS["04"]
    d = design_pair(spec_from_table("04", offset_mm=232.0))
    assert abs(d.normal_angular_factor - row["normal_angular_factor"]) < 1e-4
    assert abs(math.degrees(d.gear.helix_angle) - row["helix_angle_deg"][1]) < 0.01
    assert abs(math.degrees(d.fpd_angle_right) - row["fpd_angle_right_deg"]) < 1e-3
    assert abs(math.degrees(d.fpd_angle_left) - row["fpd_angle_left_deg"]) < 1e-3


def test_target_fpd_mode_recovers_case03_cone_angle():
    """Designing case 03 for its own printed xi_R gives back its printed gamma_1 = 1.0 deg."""
    spec = replace(
        spec_from_table("03"),
        design_mode="target_fpd",
        target_fpd_angle=math.radians(ROWS["03"]["fpd_angle_right_deg"]),
    )
    d = design_pair(spec)
    # xi_R printed to 1e-4 deg; d(xi_R)/d(gamma_1) ~ -0.8, so gamma_1 is known to ~1e-4 deg
    assert abs(math.degrees(d.spec.pinion.cone_angle) - 1.0) < 2e-4
    assert abs(math.degrees(d.fpd_angle_right) - ROWS["03"]["fpd_angle_right_deg"]) < 1e-9


@pytest.mark.parametrize("i, case", list(enumerate(["01", "02", "03", "04"])))
def test_line_of_action_and_pitch_point_against_table3(i, case):
    """Paper Table 3: line of action n and mesh point P (loaded, at 300 N m) in Sf.

    The design's right-flank line of action at the pitch point, with z negated (the
    paper's Sf is ours mirrored in z, see docs/geometry.md), agrees with the printed
    n to 0.002 per component (printed to 3 decimals; the loaded mesh point is not
    exactly the pitch point). The mesh point's x, y agree to 2 mm; its z depends on
    where the paper put the origin along the pinion axis, which it does not say.
    """
    row = DATA["table3"][i]
    d = design_pair(PairSpec.from_scene(load_scene(MODELS / f"case{case}.toml")))
    n = np.array(d.line_of_action[0]) * [1, 1, -1]
    assert np.abs(n - row["line_of_action"]).max() < 2e-3, (n, row["line_of_action"])
    assert np.abs(np.array(d.pitch_point[:2]) - row["mesh_point_m"][:2]).max() < 2e-3
    assert abs(np.linalg.norm(d.line_of_action[1]) - 1) < 1e-14


def test_a_given_gear_profile_shift_is_checked_against_the_backlash_free_one():
    """With pair.backlash_free = true x_t2 is solved; a scene that also gives it has it
    checked (it was ignored without a word), as the gear helix angle is."""
    scene = load_scene("models/case03.toml")
    solved = design_pair(PairSpec.from_scene(scene)).gear.profile_shift_xt
    assert "gear_profile_shift_given" not in design_pair(PairSpec.from_scene(scene)).checks
    for given, ok in ((round(solved, 4), True), (0.5, False)):
        d = design_pair(PairSpec.from_scene(scene.replaced(gear={"profile_shift_xt": given})))
        c = d.checks["gear_profile_shift_given"]
        assert c.ok is ok and c.margin == pytest.approx(1e-3 - abs(given - solved))
        assert d.gear.profile_shift_xt == solved  # the solved one is used


def test_the_reference_section_lies_on_the_face():
    """pinion.reference_section_mm far off the face gave a transverse contact ratio of
    59 reported as passing; it must lie within half the face width of the middle."""
    from gearbox.errors import InputError

    scene = load_scene("models/case03.toml")
    for v, ok in ((20.0, True), (-20.0, True), (20.5, False), (1e6, False)):
        s = scene.replaced(pinion={"reference_section_mm": v})
        if ok:
            assert design_pair(PairSpec.from_scene(s)).spec.pinion.reference_section == v * 1e-3
        else:
            with pytest.raises(InputError, match=r"pinion.reference_section_mm = .*\[-20, 20\]"):
                PairSpec.from_scene(s)

"""Unloaded TCA of crossed beveloid pairs: conjugacy, FPD angles, path, bad input.

Independent references:
- involute helicoids on crossed axes are conjugate: the contact moves along one fixed
  straight line (the intersection of the two planes of action), along the common
  normal, with a constant gear ratio (Litvin & Fuentes, Gear Geometry and Applied
  Theory, 2nd ed. 2004, ch. 16 "Involute Helical Gears with Crossed Axes");
- the paper's Table 2 FPD angles (tests/data/paper_tables.toml, decoded from the
  paper's text) and the design stage's eqs (1), (8), (9);
- the contact ellipse against the gap measured directly between the surfaces.
"""

import json
import math
import tomllib
import warnings
from pathlib import Path

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.errors import InputError
from gearbox.geometry import PairSpec, design_pair
from gearbox.surface import blanks_from_design
from gearbox.tca import Assembly, AssemblyErrors, TCASettings, run_tca, tca_of_blanks
from gearbox.tca.contact import flank_frames

DATA = Path(__file__).parent / "data"
ARCSEC = 180 / math.pi * 3600


def design(case="03", **pinion):
    sc = load_scene(f"models/case{case}.toml")
    if pinion:
        sc = sc.replaced(pinion=pinion)
    return design_pair(PairSpec.from_scene(sc))


@pytest.fixture(scope="module")
def des03():
    return design("03")


@pytest.fixture(scope="module")
def tca03(des03):
    return run_tca(des03)


def paper_table2():
    # copied from the paper's Table 2 (see the file's header for the decoding)
    return {
        row["case"]: row
        for row in tomllib.loads((DATA / "paper_tables.toml").read_text())["table2"]
    }


@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_fpd_angles_measured_on_surfaces_equal_design_and_paper(case):
    des = design(case)
    res = run_tca(des, settings=TCASettings(positions=15, mesh_cycles=1.0))
    s = res.summary()
    for key, designed in (("right", des.fpd_angle_right), ("left", des.fpd_angle_left)):
        measured = s[f"measured_fpd_angle_{key}_deg"]
        # the issue's bound; the two routes agree to ~4e-10 deg in fact (solve tolerance)
        assert abs(measured - math.degrees(designed)) < 1e-3, (
            case,
            key,
            measured,
            math.degrees(designed),
        )
        # constant along the path (rulings and normal are fixed directions in Sf)
        assert s[f"measured_fpd_angle_{key}_spread_deg"] < 1e-9
        # the paper prints 4 decimals: half a unit of the last digit; case 04's offset is
        # not the printed one but inferred from its outputs (models/case04.toml, 232 mm),
        # which limits the agreement to about 1e-4 deg there
        printed = paper_table2()[case][f"fpd_angle_{key}_deg"]
        tol = 2e-4 if case == "04" else 5e-5 + 1e-9
        assert abs(measured - printed) < tol, f"paper Table 2 case {case} xi_{key[0].upper()}"


def test_contact_passes_design_pitch_point(des03, tca03):
    """The unloaded contact line passes through the design's pitch point P."""
    fc = tca03.drive
    pts = fc.active_points
    P = np.array(des03.pitch_point)
    d = np.linalg.norm(np.cross(pts - P, fc.normal[fc.active][0]), axis=1)
    assert d.max() < 1e-9  # P lies on the contact line (solver tolerance 1e-11 m)


@pytest.mark.parametrize("i, case", list(enumerate(["01", "02", "03", "04"])))
def test_line_of_action_matches_paper_table3(i, case):
    """The common normal of the drive side is the paper's Table 3 line of action
    (printed to 3 decimals, with the opposite sign: the force on the pinion)."""
    row = tomllib.loads((DATA / "paper_tables.toml").read_text())["table3"][i]
    res = run_tca(design(case), settings=TCASettings(positions=5, mesh_cycles=0.5))
    n = res.drive.normal[res.drive.active][0]
    assert np.allclose(-n, row["line_of_action"], atol=1.5e-3), (
        f"paper Table 3, FPD {row['fpd_angle_right_deg']}"
    )


def _assert_conjugate(res):
    for fc in (res.drive, res.coast):
        assert fc.converged.all()
        assert (fc.pairs_in_contact >= 1).all()
        # TE zero to solver tolerance: 1e-11 m on radii ~0.1 m is ~2e-5 arcsec
        assert fc.te_peak_to_peak() * ARCSEC < 1e-4
        # straight path along the (constant) common normal
        assert fc.straightness() < 1e-9
        pts = fc.active_points
        _, _, vt = np.linalg.svd(pts - pts.mean(0))
        n = fc.normal[fc.active]
        # normals collinear to the solve tolerance (1e-11 on the tangent projections)
        assert np.ptp(n, axis=0).max() < 1e-10
        assert abs(abs(vt[0] @ n[0]) - 1) < 1e-10


def test_drive_side_convention(tca03):
    """Pinion turning +phi_1 about z_f pushes its R flank into the gear (drive), its L
    flank away (coast); a larger phi_2 than the contact's moves the gear's R flank into
    the pinion, so the drive side's gear angle is the smallest over the pairs. The
    ratio of the normal velocities is N_1/N_2 (base-circle rolling)."""
    asm = tca03.assembly
    for fc, sign in ((tca03.drive, 1), (tca03.coast, -1)):
        p, n = fc.point[fc.active], fc.normal[fc.active]
        v_pinion = np.einsum("ni,ni->n", np.cross([0, 0, 1.0], p - asm.pinion_origin), n)
        v_gear = np.einsum("ni,ni->n", np.cross(asm.gear_axis, p - asm.gear_origin), n)
        assert (sign * v_pinion > 0).all() and (sign * v_gear < 0).all()
        assert np.allclose(-v_pinion / v_gear, tca03.pinion.teeth / tca03.gear.teeth, rtol=1e-9)


def test_perfect_design_is_conjugate_and_backlash_free(tca03):
    _assert_conjugate(tca03)
    # eq. (20) and the designed positions: drive and coast flanks touch together
    r2 = tca03.gear.reference_pitch_radius
    assert np.max(np.abs(tca03.backlash_angle)) * r2 < 1e-9
    assert tca03.status == "ok"


@pytest.mark.parametrize(
    "err",
    [
        AssemblyErrors(offset=30e-6),
        AssemblyErrors(shaft_angle=math.radians(0.02)),
        AssemblyErrors(pinion_axial=0.5e-3, offset=30e-6),
        AssemblyErrors(gear_axial=-0.5e-3, offset=30e-6),
        AssemblyErrors(
            offset=20e-6, shaft_angle=math.radians(-0.015), pinion_axial=-0.3e-3, gear_axial=0.4e-3
        ),
    ],
)
def test_te_stays_zero_under_assembly_errors_while_path_moves(des03, tca03, err):
    res = run_tca(des03, errors=err)
    _assert_conjugate(res)
    for fc, fc0 in ((res.drive, tca03.drive), (res.coast, tca03.coast)):
        moved = np.linalg.norm(fc.active_points.mean(0) - fc0.active_points.mean(0))
        assert moved > 1e-6, "the contact path moves with the assembly"
    if err.shaft_angle:
        # the FPD angle follows the shaft angle (it depends on delta, not on E or axial shifts)
        assert (
            abs(res.summary()["measured_fpd_angle_right_deg"] - math.degrees(des03.fpd_angle_right))
            > 1e-3
        )


def test_parallel_helical_pair_is_line_contact():
    """Cone angles 0 and shaft angle 0: ISO helical gears, conjugate with line contact.

    The contact conditions then have a line of solutions (rank-deficient Jacobian); the
    minimum-norm Newton step picks one point of it. FPD angle 0, no finite ellipse.
    """
    sc = load_scene("models/case03.toml").replaced(
        pair={"shaft_angle_deg": 0.0, "offset_mm": 230.0},
        pinion={"cone_angle_deg": 0.0},
        gear={"cone_angle_deg": 0.0, "helix_angle_deg": -20.0},
    )
    res = run_tca(design_pair(PairSpec.from_scene(sc)), settings=TCASettings(positions=21))
    for fc in (res.drive, res.coast):
        assert fc.converged[fc.active].all() and (fc.pairs_in_contact >= 1).all()
        assert fc.te_peak_to_peak() * ARCSEC < 1e-4
        assert np.degrees(fc.fpd_angle[fc.active]).max() < 1e-5
        assert np.isinf(fc.ellipse_axes[fc.active][:, 0]).all()
        assert any(m.startswith(f"{fc.name}: line contact") for m in res.messages)
    assert json.dumps(res.summary(), allow_nan=False)


def test_backlash_sign_follows_offset_error(des03):
    loose = run_tca(des03, errors=AssemblyErrors(offset=50e-6))
    tight = run_tca(des03, errors=AssemblyErrors(offset=-50e-6))
    assert loose.status == "ok" and np.nanmin(loose.backlash_angle) > 0
    assert tight.status == "interference" and np.nanmax(tight.backlash_angle) < 0
    assert any("interfere" in m for m in tight.messages)
    # first order: the play is odd in the offset error
    assert np.allclose(loose.backlash_angle, -tight.backlash_angle, rtol=1e-2)


def test_case03_path_in_middle_of_flanks(tca03):
    s = tca03.summary()["path_position"]
    for side in ("drive", "coast"):
        for who in ("pinion", "gear"):
            pp = s[side][who]
            # within 5 % of the half face width from the middle (measured: below 1 %)
            assert abs(pp["face_centroid"]) < 0.05, (side, who, pp)
            assert 0.4 < pp["profile_centroid"] < 0.6, (side, who, pp)
            assert pp["region"] == "middle"


def test_fig10_profile_shift_moves_pinion_path_towards_heel():
    """Paper Fig. 10: x_t1 from 0.2 to 0.1 moves the pinion's path from toe to heel.

    With the designed assembly the contact line is fixed in space (it depends on the
    base cylinders and the axes only); x_t1 and the backlash-free x_t2 (eq. (20)) move
    only the tip cones, so the active segment slides along that line: the pinion's
    centroid moves towards its heel (+z_f) on the drive side, the gear's as well
    (towards +z_f, the gear's heel in Sf). See docs/tca.md for the size of the shift.
    """
    res = {
        xt: run_tca(design("03", profile_shift_xt=xt), settings=TCASettings(positions=41))
        for xt in (0.2, 0.1)
    }
    pin = {xt: r.drive.path_position("pinion")["z_centroid_mm"] for xt, r in res.items()}
    gear = {xt: r.drive.path_position("gear")["z_centroid_mm"] for xt, r in res.items()}
    assert pin[0.1] > pin[0.2]
    assert gear[0.1] > gear[0.2]


def _gap_along(res, side_contact, k, direction, dist):
    """Gap between the two surfaces along the normal through P + dist * direction."""
    fc = side_contact
    i, j = np.argwhere(fc.active)[k]
    n = fc.normal[i, j]
    Q = fc.point[i, j] + dist * direction
    e1 = direction
    e2 = np.cross(n, e1)
    asm, N1 = res.assembly, res.pinion.teeth
    phi1 = fc.pinion_angle[i] + 2 * np.pi * fc.pair[j] / N1
    phi2 = fc.gear_angle_pairs[i, j] - 2 * np.pi * fc.pair[j] / res.gear.teeth
    heights = []
    for blank, zu, M, O in (
        (res.pinion, fc.pinion_zu[i, j], asm.pinion_matrix(np.array([phi1])), asm.pinion_origin),
        (res.gear, fc.gear_zu[i, j], asm.gear_matrix(np.array([phi2])), asm.gear_origin),
    ):
        x = np.array(zu, dtype=float)
        for _ in range(30):  # Newton: the surface point on the line Q + t n
            f = flank_frames(blank, fc.side, x[:1], x[1:], M, O)
            d = f["r"][0] - Q
            F = np.array([d @ e1, d @ e2])
            Jm = np.array([[f["rz"][0] @ e1, f["ru"][0] @ e1], [f["rz"][0] @ e2, f["ru"][0] @ e2]])
            x = x - np.linalg.solve(Jm, F)
            if np.max(np.abs(F)) < 1e-14:
                break
        heights.append((f["r"][0] - Q) @ n)
    return heights[1] - heights[0]


def test_contact_ellipse_matches_gap_between_surfaces(des03):
    """Semi-axes from the curvatures reproduce the separation measured directly."""
    delta = 0.1e-6  # small, so that the quadratic approximation holds to ~1e-3
    res = run_tca(des03, settings=TCASettings(positions=9, mesh_cycles=1.0, marking_compound=delta))
    for fc in (res.drive, res.coast):
        k = int(fc.active.sum() // 2)
        i, j = np.argwhere(fc.active)[k]
        a, b = fc.ellipse_axes[i, j]
        major = fc.ellipse_direction[i, j]
        minor = np.cross(fc.normal[i, j], major)
        for d, length in ((major, a), (minor, b)):
            for sgn in (1, -1):
                gap = _gap_along(res, fc, k, sgn * d, length)
                assert abs(gap / delta - 1) < 0.02, (fc.name, length, gap)
    # a larger FPD angle gives a shorter ellipse (paper section 3.2)
    assert np.median(res.drive.ellipse_axes[res.drive.active][:, 0]) > np.median(
        res.coast.ellipse_axes[res.coast.active][:, 0]
    )


@pytest.mark.parametrize("case", ["01", "03", "04"])
def test_ellipse_major_axis_lies_between_the_rulings(case):
    """The relative curvature is the sum of two rank-one tensors (developable flanks),
    so the major axis lies in the acute angle between the two rulings: between the
    pinion's face-width direction (its ruling) and the gear's ruling at the FPD angle."""
    res = run_tca(design(case), settings=TCASettings(positions=15))
    for fc in (res.drive, res.coast):
        a = fc.active
        p, n = fc.point[a], fc.normal[a]
        e_face = np.array([0.0, 0.0, 1.0]) - n[:, 2:3] * n
        e_prof = np.cross(n, e_face)
        radial = p - res.assembly.pinion_origin
        radial[:, 2] = 0.0
        about_n = fc.ellipse_angle[a] * np.sign(np.einsum("ni,ni->n", e_prof, radial))
        f = fc.fpd_angle_signed[a]
        assert (np.minimum(0, f) - 1e-12 <= about_n).all() and (
            about_n <= np.maximum(0, f) + 1e-12
        ).all()
        assert (np.abs(about_n) > 1e-3 * np.abs(f)).all()  # strictly inside, not on a ruling


def test_no_contact_in_range_is_an_error(des03):
    p, g = blanks_from_design(des03)
    asm = Assembly.from_design(des03)
    N1 = p.teeth
    # one tooth pair examined (J = 1) and angles 6 pitches away: nothing can touch
    far = np.linspace(6, 6.5, 5) * 2 * np.pi / N1
    with pytest.raises(InputError, match="no tooth pair is in contact"):
        tca_of_blanks(
            p, g, asm, TCASettings(pairs=1), pitch_point=des03.pitch_point, pinion_angles=far
        )


def test_separating_assembly_is_an_error(des03):
    """15 mm further apart: the tip cylinders no longer overlap (working depth 12 mm).
    At 3 mm, which this test had taken, the gears still mesh, at their face ends
    (tests/test_tca_edge.py)."""
    with pytest.raises(InputError, match="no tooth pair is in contact on the real flanks"):
        run_tca(des03, errors=AssemblyErrors(offset=15e-3))


def test_iteration_bound_is_reported_not_hidden(des03, monkeypatch):
    """With one iteration allowed, contacts that need more are flagged and excluded.
    (The sweep's solves start from the tangent predictor at the pitch point's solution,
    which on these conjugate flanks is exact even under assembly errors: here it is
    switched off, so that every start needs iterations.)"""
    import gearbox.tca.analysis as analysis

    monkeypatch.setattr(analysis, "tangent_predictor", lambda *a: np.zeros((1, 5)))
    err = AssemblyErrors(offset=30e-6, shaft_angle=math.radians(0.01))
    with np.errstate(all="ignore"), warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN slices of the play
        res = run_tca(des03, errors=err, settings=TCASettings(max_iter=4))
    s = res.summary()
    assert sum(s["not_converged"].values()) > 0
    assert res.drive.active.any()  # those the bound let converge are kept
    for fc in (res.drive, res.coast):
        assert not (fc.active & ~fc.converged).any()
        assert all("not converged" in lim for lim in fc.limit[~fc.converged])
    assert any("did not converge" in m for m in res.messages)


def test_pitch_point_solve_that_fails_says_so(des03, monkeypatch):
    import gearbox.tca.analysis as analysis
    import gearbox.tca.edge as edge

    monkeypatch.setattr(analysis, "CENTRE_MAX_ITER", 1)
    monkeypatch.setattr(edge, "START_MAX_ITER", 1)  # no border found there either
    with pytest.raises(InputError, match=r"within 1 iterations .*with no assembly errors"):
        run_tca(des03, settings=TCASettings(max_iter=1))
    err = AssemblyErrors(offset=30e-6)
    with pytest.raises(InputError, match=r"check the assembly errors"):
        run_tca(des03, errors=err, settings=TCASettings(max_iter=1))


@pytest.mark.parametrize(
    "change",
    [{"pinion": {"cone_angle_deg": 3.5}}, {"pair": {"design_mode": "target_fpd"}}],
    ids=["cone-3.5", "target-fpd-2"],
)
def test_designs_far_from_the_rack_reference_find_their_pitch_point(change, tmp_path):
    """Valid designs whose working pitch radius lies well off the rack's reference
    plane: the pitch-point solve starts at that radius on both flanks (it started at the
    rack's reference point, and a 3.5 deg pinion cone needed 44 iterations against the
    bound 30, the target-FPD design of 2 deg did not converge in 200). Conjugate: the
    TE is rounding, the contact ratio above 1."""
    text = Path("models/case03.toml").read_text()  # the gear's helix angle solved
    lines = [ln for ln in text.splitlines() if not ln.startswith("helix_angle_deg = -")]
    (tmp_path / "s.toml").write_text("\n".join(lines) + "\n")
    sc = load_scene(tmp_path / "s.toml").replaced(**change)
    if "pair" in change:
        sc = sc.replaced(pair={"target_fpd_angle_deg": 2.0})
    des = design_pair(PairSpec.from_scene(sc))
    res = run_tca(des)
    for fc in (res.drive, res.coast):
        assert np.ptp(fc.transmission_error) * ARCSEC < 1e-6 and fc.contact_ratio > 1.2
    if "pair" in change:  # the FPD angle measured on the surfaces is the target
        assert math.degrees(res.drive.fpd_angle[res.drive.active].mean()) == pytest.approx(
            2.0, abs=1e-6
        )


def test_result_round_trips_through_dict(tca03):
    back = type(tca03).from_dict(json.loads(json.dumps(tca03.to_dict())))
    assert back.summary() == tca03.summary()
    assert np.array_equal(back.drive.limit, tca03.drive.limit)
    assert back.drive.active.dtype == bool and np.array_equal(back.drive.active, tca03.drive.active)


def test_summary_is_json_with_issue_keys(tca03):
    s = json.loads(json.dumps(tca03.summary(), allow_nan=False))
    for key in (
        "measured_fpd_angle_right_deg",
        "measured_fpd_angle_left_deg",
        "unloaded_te_peak_to_peak_arcsec",
        "contact_path_straightness_um",
        "path_position",
    ):
        assert key in s
    assert set(s["unloaded_te_peak_to_peak_arcsec"]) == {"drive", "coast"}
    assert s["max_iterations"]["drive"] <= TCASettings().max_iter


def test_te_plot_of_conjugate_flanks_is_not_drawn_to_the_noise_scale(tca03):
    """Conjugate flanks' TE is the solver's rounding (~1e-11 arcsec): the axis keeps a
    least span and says the flanks are conjugate; a real TE is drawn to its own scale."""
    import dataclasses

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from gearbox.tca.plot import TE_AXIS_MIN_SPAN_ARCSEC, plot_transmission_error

    ax = plot_transmission_error(tca03)
    lo, hi = ax.get_ylim()
    assert hi - lo >= TE_AXIS_MIN_SPAN_ARCSEC
    assert any("conjugate" in t.get_text() for t in ax.texts)
    plt.close(ax.figure)

    def wavy(fc):  # 3 arcsec of TE, as a mismatched pair would have
        phi = fc.pinion_angle - fc.pinion_angle[0]
        te = 3.0 / ARCSEC * np.sin(2 * np.pi * phi / np.ptp(phi))
        return dataclasses.replace(fc, transmission_error=te)

    real = dataclasses.replace(tca03, drive=wavy(tca03.drive), coast=wavy(tca03.coast))
    ax = plot_transmission_error(real)
    lo, hi = ax.get_ylim()
    assert 5.9 < hi - lo < 8.0  # autoscaled about the 6 arcsec swing
    assert not ax.texts
    plt.close(ax.figure)


def test_a_sweep_of_many_mesh_cycles_finds_contact_at_every_position(des03, tca03):
    """tca.mesh_cycles up to its bound 20: every position has its pairs examined (a
    sweep of 10 cycles once read 5 of 121 positions as without contact, 20 cycles 104
    of 200, as the examined pairs stayed those about the pitch point)."""
    for cycles, positions in ((10.0, 121), (20.0, 200)):
        res = run_tca(des03, settings=TCASettings(positions=positions, mesh_cycles=cycles))
        for fc, ref in ((res.drive, tca03.drive), (res.coast, tca03.coast)):
            assert np.all(fc.pairs_in_contact >= 1), (cycles, fc.name)
            te = fc.transmission_error
            assert np.all(np.isfinite(te)) and np.ptp(te) * ARCSEC < 1e-6
            # the path's ends are refined by bisection: the same ratio as the default
            assert fc.contact_ratio == pytest.approx(ref.contact_ratio, abs=1e-6)

"""Edge contact in the unloaded TCA (gearbox.tca.edge): where the flanks' surfaces do
not touch on the real flanks, a border of one flank (face end, tip, form circle)
touches the mate's flank.

Checked against the definition of the gear angle, the rigid rotation to first touch,
by brute force over the pinion's real flank (tests/_rigid.py: no contact conditions,
no normals, no edge tangents). The brute force samples: its first touch can only come
later than the true one (on the drive side a larger gear angle, on the coast side a
smaller one), so the TCA's gear angle must not come later than it by more than the
solves' tolerance (1e-10 rad), and may come earlier only by what the grid misses
(ZOOM_TOL)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from _rigid import rigid_first_contact

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair
from gearbox.surface import blanks_from_design
from gearbox.tca import TCASettings, run_tca
from gearbox.tca.assembly import Assembly, AssemblyErrors
from gearbox.tca.edge import CANDIDATES, EDGES, edge_residual, edge_unknowns, solve_candidate
from gearbox.tca.local import centre_start

#: How much earlier than the brute force's sampled first touch the TCA's may lie
#: (rad): the zoomed grid (61 x 61, six zooms about six starts) missed a narrow basin by
#: up to 1.5e-7 rad in trials at 41 and 81 points; 0.04 um on a 136 mm pitch radius.
ZOOM_TOL = 3e-7

#: A crossed beveloid pair designed near line contact on its drive flank (FPD angle
#: 0.755 deg; coast 10.19 deg), drawn by the first version of
#: benchmarks/pipeline_random_scenes.py (seed 1, scene 3, before it drew the solver),
#: where a shaft-angle error of 0.005 deg had made the TCA fail.
NEAR_LINE = dict(
    pinion={
        "teeth": 29,
        "profile_shift_xt": -0.2816048962010852,
        "helix_angle_deg": 14.871431198867924,
        "cone_angle_deg": 3.886393653787552,
    },
    gear={"teeth": 45, "cone_angle_deg": 1.1418609151423138},
    pair={"offset_mm": 215.01513148339032, "shaft_angle_deg": 16.223269386149184},
)


@pytest.fixture(scope="module")
def near_line():
    sc = load_scene("models/case03.toml").replaced(**NEAR_LINE)
    return design_pair(PairSpec.from_scene(sc))


def _parallel_design(shaft_error_deg: float):
    from gearbox.scene import scene_from_dict

    scene = load_scene("models/case03.toml").to_dict()
    scene["pair"]["shaft_angle_deg"] = 0.0
    scene["pinion"]["cone_angle_deg"] = 0.0
    scene["gear"]["cone_angle_deg"] = 0.0
    scene["gear"].pop("helix_angle_deg", None)
    scene["assembly"] = {"shaft_angle_error_deg": shaft_error_deg}
    sc = scene_from_dict(scene)
    return design_pair(PairSpec.from_scene(sc)), sc


def test_the_near_line_pair_meshes_at_its_face_ends_under_a_shaft_angle_error(near_line):
    assert math.degrees(near_line.fpd_angle_right) == pytest.approx(0.7554, abs=1e-3)
    err = AssemblyErrors(offset=50e-6, shaft_angle=math.radians(-0.02))
    res = run_tca(near_line, errors=err, settings=TCASettings(positions=21))
    fc = res.drive
    assert not fc.active.any(), "no point of the surfaces' contact on the real flanks"
    assert np.isfinite(fc.gear_angle).all() and (fc.edge != "").all()
    assert set(fc.edge) <= {"pinion heel", "gear heel"}  # the misalignment's end
    assert res.status == "edge contact"
    assert any("a border of a real flank" in m for m in res.messages)
    tally = res.summary()["edge_contact_positions"]["drive"]
    assert sum(tally.values()) == 21
    # the coast flank (FPD 10.2 deg) keeps its surface contact
    assert res.coast.pairs_in_contact.min() >= 1 and (res.coast.edge == "").all()
    # TE grows with the error (24 positions: 0.163 arcsec at 0.005 deg, 0.909 at 0.02 deg)
    te = res.drive.te_peak_to_peak()
    small = run_tca(
        near_line, errors=AssemblyErrors(offset=50e-6, shaft_angle=math.radians(-0.005))
    )
    assert 0 < small.drive.te_peak_to_peak() < te


def _check_against_brute_force(design, errors, positions):
    res = run_tca(design, errors=errors, settings=TCASettings(positions=positions))
    p, g = blanks_from_design(design)
    asm = Assembly.from_design(design, errors)
    checked = 0
    for fc in (res.drive, res.coast):
        for i in np.flatnonzero(fc.edge != ""):
            # the touching pair's tooth: the brute force searches it and its neighbours
            shift = int(fc.edge_pair[i])
            firsts = []
            for k in (shift - 1, shift, shift + 1):
                phi1 = fc.pinion_angle[i] + 2 * math.pi * k / p.teeth
                guess = fc.gear_angle[i] - 2 * math.pi * k / g.teeth
                b = rigid_first_contact(p, g, asm, fc.side, phi1, guess)
                firsts.append(b + 2 * math.pi * k / g.teeth)
            brute = np.nanmin(firsts) if fc.side == "R" else np.nanmax(firsts)
            later = (fc.gear_angle[i] - brute) * (1 if fc.side == "R" else -1)
            assert -ZOOM_TOL < later < 1e-10, (fc.name, i, fc.edge[i], later)
            checked += 1
    return res, checked


@pytest.mark.slow
def test_edge_contacts_are_the_rigid_first_touch_near_line_contact(near_line):
    err = AssemblyErrors(offset=50e-6, shaft_angle=math.radians(-0.02))
    res, checked = _check_against_brute_force(near_line, err, 5)
    assert checked == 5


@pytest.mark.slow
def test_a_parallel_pair_with_a_shaft_angle_error_touches_at_its_borders():
    """Parallel helical gears (no cones) are in line contact: a shaft-angle error of
    0.01 deg sends the surfaces' point of contact along the line, off the face, and the
    teeth touch at a face end or the form circle (the TCA had refused the pair, with a
    message saying why). Both flanks, against the brute force."""
    design, sc = _parallel_design(0.01)
    err = AssemblyErrors.from_scene(sc)
    res, checked = _check_against_brute_force(design, err, 3)
    assert checked == 6
    for fc in (res.drive, res.coast):
        assert (fc.edge != "").all() and fc.te_peak_to_peak() > 0


def test_candidate_jacobians_match_central_differences(near_line):
    """The analytic Jacobian of every candidate's conditions (borders, corners,
    crossings, one batched system) against central differences, at its touch near the
    pitch point under a shaft-angle error."""
    p, g = blanks_from_design(near_line)
    asm = Assembly.from_design(near_line, AssemblyErrors(shaft_angle=math.radians(-0.02)))
    kinds = {e: kind for e, _member, kind in EDGES}
    checked = 0
    for side in ("R", "L"):
        phi1c, x0 = centre_start(p, g, asm, side, np.asarray(near_line.pitch_point))
        for edge in CANDIDATES:
            s = solve_candidate(p, g, asm, side, [phi1c], x0[None, :], edge, max_iter=100)
            if not s.converged[0]:  # a line that does not touch near here
                assert kinds.get(edge, "tip") in ("tip", "root"), (side, edge)
                continue
            y = edge_unknowns(p, g, asm, side, s.x, edge)
            F, J = edge_residual(p, g, asm, side, [phi1c], y, edge)
            assert np.max(np.abs(F[:, :3])) < 1e-10
            Jn = np.empty_like(J)
            for k in range(4):
                h = 1e-7
                yp, ym = y.copy(), y.copy()
                yp[0, k] += h
                ym[0, k] -= h
                Fp = edge_residual(p, g, asm, side, [phi1c], yp, edge)[0]
                Fm = edge_residual(p, g, asm, side, [phi1c], ym, edge)[0]
                Jn[:, :, k] = (Fp - Fm) / (2 * h)
            assert np.max(np.abs(J - Jn)) < 1e-5 * np.max(np.abs(J)), (side, edge)
            checked += 1
    assert checked >= 40  # 46 of the 64 touch near the pitch point on this pair
    for bad in ("pinion tip x pinion heel", "gear toe/middle", "gear flank"):
        with pytest.raises(ValueError, match="must be one of"):
            solve_candidate(p, g, asm, "R", [phi1c], x0[None, :], bad)


def test_pairs_in_surface_contact_have_no_edge_entries():
    """Without assembly errors case 03 keeps its surface contact at every position: no
    border is taken, nothing flagged."""
    res = run_tca(design_pair(PairSpec.from_scene(load_scene("models/case03.toml"))))
    for fc in (res.drive, res.coast):
        assert (fc.edge == "").all() and not fc.edge_corner.any()
        assert np.isnan(fc.edge_point).all()
    assert res.summary()["edge_contact_positions"] == {"drive": {}, "coast": {}}


def test_an_offset_error_moves_case03_to_its_face_ends():
    """A 3 mm larger offset (half a module): the cones put the surfaces' contact 3 mm /
    tan(1 deg) = 172 mm along the face, far off it; the gears mesh at their face ends
    with a backlash of about 2 Delta E tan(alpha) (2.3 mm). The TCA had called this a
    separating assembly."""
    design = design_pair(PairSpec.from_scene(load_scene("models/case03.toml")))
    res = run_tca(design, errors=AssemblyErrors(offset=3e-3), settings=TCASettings(positions=21))
    for fc in (res.drive, res.coast):
        assert np.isfinite(fc.gear_angle).sum() >= 19
    bl = res.summary()["backlash_um"]
    assert 1.5e3 < bl["max"] < 3.0e3


def test_the_tip_and_root_lines_splines_follow_the_exact_lines(near_line):
    """The splines through LINE_NODES points against the exact tip and root lines, on
    the face and half a face beyond it, also on an undercut pinion (case 03 with 14
    teeth at x_t1 0.1, undercut 0.56 mm: its root line is the fillet's cut). The tip
    lines to 1e-9 m; the root line where the undercut sets in along the face has a
    kink (u = max(0, cut)), which the spline rounds off by up to 8.5e-7 m of rack
    profile (measured; the form line meets the fillet tangentially, no material edge
    moves)."""
    from gearbox.surface import involute_start, tip_parameter
    from gearbox.tca.edge import _line_spline

    undercut = design_pair(
        PairSpec.from_scene(
            load_scene("models/case03.toml").replaced(
                pinion={"teeth": 14, "profile_shift_xt": 0.1}, pair={"offset_mm": 181.0}
            )
        )
    )
    for design in (near_line, undercut):
        for blank in blanks_from_design(design):
            z = np.linspace(
                blank.z_toe - 0.5 * blank.face_width, blank.z_heel + 0.5 * blank.face_width, 57
            )
            for side in ("R", "L"):
                tip = _line_spline(blank, side, "tip")(z)
                root = _line_spline(blank, side, "root")(z)
                assert np.max(np.abs(tip - tip_parameter(blank, side, z)[0])) < 1e-9
                assert np.max(np.abs(root - involute_start(blank, side, z))) < 1e-6


def test_the_loaded_tca_takes_its_touching_phase_from_the_first_border():
    """A near-line pair (drive FPD 0.659 deg) under the misalignment that scene 5 of the
    first benchmarks/pipeline_random_scenes.py (seed 1) drew: its loaded TCA had stopped with
    'the assembly does not mesh' (no surface contact near the pitch point, and the phase
    search found none). Its touching phase now comes from the border that touches
    first, as the TCA's sweep starts (gearbox.tca.edge.edge_start)."""
    from gearbox.ltca.beveloid import beveloid_ltca

    sc = load_scene("models/case03.toml").replaced(
        pinion={
            "teeth": 33,
            "profile_shift_xt": 0.3053500768708159,
            "helix_angle_deg": 16.1481776018182,
            "cone_angle_deg": 1.9959458092280595,
        },
        gear={"teeth": 38, "cone_angle_deg": 1.6978543385283102},
        pair={"offset_mm": 207.0664204449603, "shaft_angle_deg": 13.63557740508648},
        assembly={"offset_error_mm": 0.0557, "shaft_angle_error_deg": -0.0222},
        ltca={"positions": 6, "flanks": ["drive"]},
        load={"torques_Nm": [300.0]},
    )
    design = design_pair(PairSpec.from_scene(sc))
    assert math.degrees(design.fpd_angle_right) == pytest.approx(0.659, abs=1e-3)
    tca = run_tca(design, sc, settings=TCASettings(positions=11))
    assert set(tca.drive.edge) == {"gear heel"}
    res = beveloid_ltca(design, sc)
    k = float(res.flanks["drive"].stiffness[0].mean())
    assert 1e8 < k < 2e9


def test_no_border_touches_before_the_surfaces_of_conjugate_flanks():
    """Borders are taken only where no pair's surfaces touch. That loses nothing on the
    TCA's flanks, which are conjugate (zero TE under assembly errors, tests/test_tca.py):
    a border of a pair touches no earlier than its own pair's surfaces would, and those
    all touch at the one gear angle. Case 03 under assembly errors, every border at every
    position of both flanks: none comes first (they come 2.5e-7 rad or more later)."""
    from gearbox.tca.contact import solve_contact
    from gearbox.tca.edge import edge_contacts

    design = design_pair(PairSpec.from_scene(load_scene("models/case03.toml")))
    err = AssemblyErrors(offset=30e-6, shaft_angle=math.radians(0.02))
    settings = TCASettings(positions=15)
    res = run_tca(design, errors=err, settings=settings)
    p, g = blanks_from_design(design)
    asm = Assembly.from_design(design, err)
    for fc in (res.drive, res.coast):
        assert (fc.pairs_in_contact > 0).all()
        phi1c, x0 = centre_start(p, g, asm, fc.side, np.asarray(design.pitch_point))
        c = solve_contact(p, g, asm, fc.side, [phi1c], x0[None, :], max_iter=200)
        angle, *_ = edge_contacts(
            p, g, asm, fc.side, fc.pinion_angle, fc.pair, phi1c, c.x[0], settings
        )
        later = (angle - fc.gear_angle) * (1 if fc.side == "R" else -1)
        assert np.isfinite(later).any() and np.nanmin(later) > 0, fc.name


@pytest.mark.slow
def test_paper_case01_under_a_shaft_angle_error_touches_at_its_toe():
    """The paper's case 01 (drive FPD angle 1.66 deg) under a shaft-angle error of 0.02
    deg: the TCA had refused it ("no tooth pair is in contact on the real flanks
    anywhere"). Its drive flank now touches at borders at every position (toe edges
    mostly), with TE; positions not flagged as corners against the brute force."""
    design = design_pair(PairSpec.from_scene(load_scene("models/case01.toml")))
    err = AssemblyErrors(shaft_angle=math.radians(0.02))
    res = run_tca(design, errors=err, settings=TCASettings(positions=9))
    fc = res.drive
    assert (fc.pairs_in_contact == 0).all() and (fc.edge != "").all()
    assert fc.te_peak_to_peak() > 0
    p, g = blanks_from_design(design)
    asm = Assembly.from_design(design, err)
    checked = 0
    for i in np.flatnonzero(~fc.edge_corner)[:3]:
        k = int(fc.edge_pair[i])
        firsts = []
        for j in (k - 1, k, k + 1):
            phi1 = fc.pinion_angle[i] + 2 * math.pi * j / p.teeth
            b = rigid_first_contact(
                p, g, asm, "R", phi1, fc.gear_angle[i] - 2 * math.pi * j / g.teeth
            )
            firsts.append(b + 2 * math.pi * j / g.teeth)
        later = fc.gear_angle[i] - np.nanmin(firsts)
        assert -ZOOM_TOL < later < 1e-10, (i, fc.edge[i], later)
        checked += 1
    assert checked == 3


@pytest.mark.slow
def test_tips_that_barely_overlap_touch_at_corners_and_crossings():
    """Case 03 on axes 12 mm apart beyond the design (the working depth is 12 mm): only
    the tips' regions overlap, and the teeth touch where a tip line crosses the mate's
    tip line or face end, or at a corner. Against the brute force at every position
    where the TCA finds a touch (the face ends, tip and form lines alone had missed
    these by up to 3.7e-3 rad)."""
    design = design_pair(PairSpec.from_scene(load_scene("models/case03.toml")))
    err = AssemblyErrors(offset=12e-3)
    res, checked = _check_against_brute_force(design, err, 5)
    names = {str(e) for fc in (res.drive, res.coast) for e in fc.edge if e}
    assert any(" x " in e for e in names), names
    assert checked >= 6


def test_a_surface_contact_off_the_flanks_near_the_pitch_point_is_not_the_start():
    """A random valid design (drive FPD 0.861 deg) under -53 um, -0.0213 deg and -29 um
    of pinion axial error (benchmark stress draw): the surfaces' contact near the pitch
    point converges 0.53 m along the continued flanks. Taken as the sweep's start, the
    borders tracked from there found nothing and the TCA called the gears separated;
    the sweep now starts from what touches first on the real flanks."""
    sc = load_scene("models/case03.toml").replaced(
        pinion={
            "teeth": 25,
            "profile_shift_xt": -0.18532203801750796,
            "helix_angle_deg": 12.797780984269263,
            "cone_angle_deg": 3.0524136654569776,
        },
        gear={"teeth": 32, "cone_angle_deg": 1.1276500937279677},
        pair={"offset_mm": 165.41061866853033, "shaft_angle_deg": 16.127095178910984},
    )
    design = design_pair(PairSpec.from_scene(sc))
    assert math.degrees(design.fpd_angle_right) == pytest.approx(0.861, abs=1e-3)
    err = AssemblyErrors(offset=-53.3e-6, shaft_angle=-3.7138e-4, pinion_axial=-28.6e-6)
    res = run_tca(design, errors=err, settings=TCASettings(positions=11))
    assert np.isfinite(res.drive.gear_angle).all() and (res.drive.edge != "").all()

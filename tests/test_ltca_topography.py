"""Profile slope, flank twist and flank topographies (gearbox.ltca.modification): their
laws, the topography's coordinates against the grids' own flank coordinates, and
topographies sampled from the other modifications, which must act exactly as those do
on the separations and in the loaded TCA of both paths."""

from __future__ import annotations

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from _benchmarks import benchmark

from gearbox import load_scene
from gearbox.errors import InputError
from gearbox.ltca import FlankModification, LTCAOptions
from gearbox.ltca.modification import Topography
from gearbox.ltca.parallel import parallel_grid
from gearbox.ltca.table import parallel_ltca

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"

#: spur, m 4 mm, z 30/45, b 30 mm: the pair of benchmarks/ltca_misalignment.py
SPUR = benchmark("ltca_misalignment").SPUR
HELICAL = replace(SPUR, helix_angle=math.radians(15.0))

RB, RF, RA, B = 0.09, 0.092, 0.1, 0.04  # radii (m) and face width of the law checks


def removal(mod, r, w, **kw):
    base = {
        "tip_radius": RA,
        "base_radius": RB,
        "face_width": B,
        "form_radius": RF,
        "reference_radius": 0.095,
    }
    return mod.removal(r, w, **(base | kw))


def _place(t):
    """Radius at the place t of the form-to-tip range of the roll length."""
    xF, xa = math.sqrt(RF**2 - RB**2), math.sqrt(RA**2 - RB**2)
    return np.sqrt(RB**2 + (xF + np.asarray(t) * (xa - xF)) ** 2)


def test_profile_slope_and_flank_twist_follow_their_laws():
    t = np.linspace(0.0, 1.0, 11)
    r, w0 = _place(t), np.zeros_like(t)
    slope = removal(FlankModification(profile_slope=6e-6), r, w0)
    assert slope == pytest.approx(6e-6 * (t - 0.5), abs=1e-18)
    assert slope[[0, 5, 10]] == pytest.approx([-3e-6, 0.0, 3e-6], abs=1e-18)
    twist = FlankModification(flank_twist=8e-6)
    for w in (-0.5 * B, 0.0, 0.25 * B, 0.5 * B):
        got = removal(twist, r, np.full_like(t, w))
        # the profile slope at face position w is S w / b: -S/2 .. +S/2 end to end
        assert got == pytest.approx(8e-6 * (w / B) * (t - 0.5), abs=1e-18), w
    both = FlankModification(profile_slope=-4e-6, flank_twist=8e-6, lead_crowning=3e-6)
    w = np.linspace(-0.5 * B, 0.5 * B, 11)
    got = removal(both, r, w)
    want = (-4e-6 + 8e-6 * w / B) * (t - 0.5) + 3e-6 * (2 * w / B) ** 2
    assert got == pytest.approx(want, abs=1e-18)
    assert both.describe() == "lead crowning 3 um, profile slope -4 um, flank twist 8 um"
    with pytest.raises(ValueError, match="form_radius"):
        FlankModification(profile_slope=1e-6).removal(
            r, w0, tip_radius=RA, base_radius=RB, face_width=B
        )


def _roll(r, rb=RB, r_ref=0.095):
    return np.sqrt(r**2 - rb**2) - math.sqrt(r_ref**2 - rb**2)


def test_a_topography_sampled_from_polynomial_terms_is_exact():
    """Profile crowning, lead crowning, helix slope, profile slope and flank twist are
    polynomials of degree <= 2 in the roll length and the face position: a bicubic
    topography sampled from them at 5 x 6 points gives them back everywhere on the flank
    (round-off, 1e-18 m against micrometres); a bilinear one gives back the bilinear
    terms (slopes and twist) exactly and the crownings within their h^2 / 8 bound."""
    terms = FlankModification(
        profile_crowning=4e-6, lead_crowning=6e-6, helix_slope=-5e-6, profile_slope=3e-6
    )
    terms = replace(terms, flank_twist=7e-6)
    bilinear = FlankModification(helix_slope=-5e-6, profile_slope=3e-6, flank_twist=7e-6)
    rng = np.random.default_rng(3)
    t, w = rng.uniform(0, 1, 400), rng.uniform(-0.5 * B, 0.5 * B, 400)
    r = _place(t)
    lo, hi = _roll(_place(0.0)), _roll(_place(1.0))
    for mod, method, nx, ny in ((terms, "cubic", 5, 6), (bilinear, "linear", 2, 2)):
        x = np.linspace(lo, hi, nx)
        y = np.linspace(-0.5 * B, 0.5 * B, ny)
        X, Y = np.meshgrid(x, y, indexing="ij")
        R = np.sqrt(RB**2 + (X + math.sqrt(0.095**2 - RB**2)) ** 2)
        topo = Topography(x, y, removal(mod, R, Y), method)
        got = removal(FlankModification(topography=topo), r, w)
        np.testing.assert_allclose(got, removal(mod, r, w), rtol=0, atol=2e-18)
    # bilinear on the crowned terms: the error of linear interpolation is at most
    # h^2 / 8 times the second derivative on each axis
    x, y = np.linspace(lo, hi, 9), np.linspace(-0.5 * B, 0.5 * B, 9)
    X, Y = np.meshgrid(x, y, indexing="ij")
    R = np.sqrt(RB**2 + (X + math.sqrt(0.095**2 - RB**2)) ** 2)
    topo = Topography(x, y, removal(terms, R, Y), "linear")
    err = removal(FlankModification(topography=topo), r, w) - removal(terms, r, w)
    hx, hy = x[1] - x[0], y[1] - y[0]
    bound = hx**2 / 8 * 8 * 4e-6 / (hi - lo) ** 2 + hy**2 / 8 * 8 * 6e-6 / B**2
    assert np.max(np.abs(err)) <= bound * (1 + 1e-9)
    assert np.max(np.abs(err)) > 0.2 * bound  # the bound is reached, not idle


def test_a_topography_is_held_beyond_its_grid_and_turns_with_the_face():
    x, y = (-2e-3, 0.0, 1e-3, 3e-3), (-0.01, 0.0, 0.005, 0.02)
    rng = np.random.default_rng(5)
    topo = Topography(x, y, rng.uniform(-5e-6, 5e-6, (4, 4)))
    corner = topo(np.array([-1.0, 1.0]), np.array([-1.0, 1.0]))
    assert corner == pytest.approx([topo.removal[0][0], topo.removal[-1][-1]], abs=1e-18)
    grid = topo(np.array(x)[:, None], np.array(y)[None, :])
    np.testing.assert_allclose(grid, topo.removal, rtol=0, atol=1e-18)  # it interpolates
    turned = topo.reflected()
    xi, wi = rng.uniform(-3e-3, 4e-3, 50), rng.uniform(-0.03, 0.03, 50)
    np.testing.assert_allclose(turned(xi, -wi), topo(xi, wi), rtol=0, atol=1e-18)
    mod = FlankModification(helix_slope=2e-6, flank_twist=-1e-6, topography=topo)
    assert mod.reflected().reflected() == mod
    assert not mod.face_symmetric
    even = Topography(x, (-0.01, 0.0, 0.01, 0.02), [[1e-6, 0, 1e-6, 5e-6]] * 4)
    assert not FlankModification(topography=even).face_symmetric
    even = Topography(x, (-0.01, -0.005, 0.005, 0.01), [[1e-6, 0, 0, 1e-6]] * 4)
    assert FlankModification(topography=even, lead_crowning=1e-6).face_symmetric


def test_bad_topographies_name_their_part():
    with pytest.raises(InputError) as err:
        Topography((0.0, 1e-3, 2e-3), (0.0, 1e-3), [[0, 0], [0, 0], [0, 0]])
    assert [p.path for p in err.value.problems] == ["profile", "face"]
    assert "at least 4 points for cubic" in str(err.value)
    with pytest.raises(InputError) as err:
        Topography((0.0, 1e-3), (1e-3, 0.0), [[0, 0], [0, math.nan]], "linear")
    assert [p.path for p in err.value.problems] == ["face", "removal"]
    with pytest.raises(InputError, match="removal\\[1\\]"):
        Topography((0.0, 1e-3), (0.0, 1e-3), [[0, 0], [0]], "linear")
    with pytest.raises(InputError, match="method"):
        Topography((0.0, 1e-3), (0.0, 1e-3), [[0, 0], [0, 0]], "quintic")


def _grid_topography():
    """A random 6 x 7 bicubic topography over the spur pair's flank (0 to 6 um)."""
    x = np.linspace(-9e-3, 9e-3, 6)
    y = np.linspace(-0.5 * SPUR.face_width, 0.5 * SPUR.face_width, 7)
    return Topography(x, y, np.random.default_rng(11).uniform(0, 6e-6, (6, 7)))


@pytest.mark.parametrize("pair", [SPUR, HELICAL], ids=["spur", "helical"])
def test_topographies_act_at_the_grids_own_flank_coordinates(pair):
    """The grids carry where each point lies on both flanks (roll length from each
    gear's reference circle, axial position; built for the form deviations): a
    topography on each gear adds exactly its value there to every separation."""
    topo_p = _grid_topography()
    topo_g = replace(topo_p.reflected(), method="linear")
    mods = (FlankModification(topography=topo_p), FlankModification(topography=topo_g))
    for f in (0.0, 0.37, 0.8):
        plain = parallel_grid(pair, f, 20)
        g = parallel_grid(pair, f, 20, relief=mods)
        c = g.flank_coordinates
        want = topo_p(c[:, 0], c[:, 1]) + topo_g(c[:, 2], c[:, 3])
        assert np.ptp(want) > 1e-6
        np.testing.assert_allclose(g.separation - plain.separation, want, rtol=0, atol=1e-18)


def test_a_linear_topography_is_the_linear_tip_relief():
    """Tip relief, linear in the roll length from its start to the tip, is a bilinear
    topography with profile points at the relief's start and at the tip (roll lengths
    from the reference circle): the loaded TCA of both flanks is the same to round-off.
    This checks the topography's profile coordinate against the tip relief's own law."""
    ca, la = 12e-6, 1.2e-3
    tip = FlankModification(tip_relief=ca, tip_relief_length=la)
    rb, ra, rp = HELICAL.base_radius(0), HELICAL.tip_radius(0), HELICAL.pitch_radius(0)
    xr = math.sqrt(rp**2 - rb**2)
    xs, xa = math.sqrt((ra - la) ** 2 - rb**2) - xr, math.sqrt(ra**2 - rb**2) - xr
    x = (xs - 5e-3, xs, xa)
    # beyond the tip the relief's law is continued and the topography held: move the
    # last point out so that the grids' continuation (the edge test) reads the same
    x_out = x[:2] + (xa + 2e-3,)
    c_out = ca * (x_out[2] - xs) / (xa - xs)
    topo = Topography(x_out, (-0.02, 0.02), [[0, 0], [0, 0], [c_out, c_out]], "linear")
    opts = LTCAOptions(positions=8)
    a = parallel_ltca(HELICAL, [300.0], options=opts, relief=(tip, None), n_face=12)
    b = parallel_ltca(
        HELICAL,
        [300.0],
        options=opts,
        relief=(FlankModification(topography=topo), None),
        n_face=12,
    )
    for flank in ("drive", "coast"):
        fa, fb = a.flanks[flank], b.flanks[flank]
        assert np.ptp(fa.lte) > 0
        for name in ("lte", "stiffness", "lte_unloaded"):
            np.testing.assert_allclose(
                getattr(fb, name), getattr(fa, name), rtol=1e-9, atol=1e-18, err_msg=name
            )
    assert "topography 3 x 2 (linear, 0 to" in b.attrs["flank_modifications"]


def test_an_uneven_topography_is_the_helix_slope_on_both_flanks_and_hands():
    """A topography equal to a helix slope plus a flank twist (bicubic, exact for
    them) gives the loaded TCA of those terms: drive and coast (the coast is the drive
    flank with the modifications turned end for end), right and left hand (the left
    hand is the right hand's mirror image)."""
    terms = FlankModification(helix_slope=10e-6, flank_twist=-6e-6)
    opts = LTCAOptions(positions=8)
    for beta in (15.0, -15.0):
        pair = replace(SPUR, helix_angle=math.radians(beta))
        rb, ra, rp = pair.base_radius(0), pair.tip_radius(0), pair.pitch_radius(0)
        rF = pair.form_radius(0)
        xr = math.sqrt(rp**2 - rb**2)
        x = np.linspace(math.sqrt(rF**2 - rb**2) - xr, math.sqrt(ra**2 - rb**2) - xr, 4)
        y = np.linspace(-0.5 * pair.face_width, 0.5 * pair.face_width, 4)
        X, Y = np.meshgrid(x, y, indexing="ij")
        R = np.sqrt(rb**2 + (X + xr) ** 2)
        kw = {"tip_radius": ra, "base_radius": rb, "face_width": pair.face_width}
        values = terms.removal(R, Y, form_radius=rF, **kw)
        topo = FlankModification(topography=Topography(x, y, values))
        a = parallel_ltca(pair, [300.0], options=opts, relief=(terms, None), n_face=16)
        b = parallel_ltca(pair, [300.0], options=opts, relief=(topo, None), n_face=16)
        for flank in ("drive", "coast"):
            fa, fb = a.flanks[flank], b.flanks[flank]
            np.testing.assert_allclose(fb.lte, fa.lte, rtol=1e-9, atol=1e-15)
            np.testing.assert_allclose(fb.stiffness, fa.stiffness, rtol=1e-9)
            np.testing.assert_allclose(fb.mesh_point, fa.mesh_point, rtol=0, atol=1e-12)
        # the slope moves the load towards -w on both flanks, as the helix slope does
        for flank in ("drive", "coast"):
            assert np.all(b.flanks[flank].mesh_point[..., 2] < -1e-3), (beta, flank)


@pytest.fixture(scope="module")
def case03():
    from gearbox.geometry import PairSpec, design_pair

    scene = load_scene(ROOT / "models" / "case03.toml")
    return design_pair(PairSpec.from_scene(scene)), scene


def _topography_keys(member, x_mm, y_mm, rows_um):
    return {
        f"{member}_topography_profile_mm": list(map(float, x_mm)),
        f"{member}_topography_face_mm": list(map(float, y_mm)),
        f"{member}_topography_um": [list(map(float, r)) for r in rows_um],
    }


def test_beveloid_separations_take_the_topography(case03):
    """Case 03 (beveloid, whose base radii differ between the flanks): a pinion
    topography adds its value at each sampled flank point's roll length (from the
    reference circle, with that flank's base radius) and face position, on both
    flanks; a gear topography sampled from a lead crowning adds the crowning's
    removal at the gear's partner points (exact: bicubic in w)."""
    from gearbox.ltca.beveloid import modifications_from_scene, separation_field
    from gearbox.surface import blanks_from_design

    design, scene = case03
    pinion = blanks_from_design(design)[0]
    x = np.linspace(-14.0, 16.0, 6)
    y = np.linspace(-20.0, 20.0, 5)
    rng = np.random.default_rng(2)
    rows = rng.uniform(0, 5, (6, 5))
    gy = np.linspace(-20.0, 20.0, 5)
    crowned = 8.0 * (2 * gy / 40.0) ** 2
    keys = _topography_keys("pinion", x, y, rows) | _topography_keys(
        "gear", (-10, 0, 10, 20), gy, [crowned] * 4
    )
    mods = modifications_from_scene(design, scene.replaced(ltca=keys))
    assert mods[0].topography.method == "cubic"
    kw = {"n_profile": 8, "n_face": 10, "positions": 6}
    for k, side in enumerate(("R", "L")):
        f0 = separation_field(design, scene, side, relief=(None, None), **kw)
        only_p = separation_field(design, scene, side, relief=(mods[0], None), **kw)
        only_g = separation_field(design, scene, side, relief=(None, mods[1]), **kw)
        rb = design.pinion.base_radius[k]
        radius = np.hypot(only_p.point[..., 0], only_p.point[..., 1])
        roll = np.sqrt(radius**2 - rb**2) - math.sqrt(
            design.pinion.reference_pitch_radius**2 - rb**2
        )
        w = only_p.point[..., 2] - 0.5 * (pinion.z_toe + pinion.z_heel)
        want = mods[0].topography(roll, np.broadcast_to(w, roll.shape))
        d = only_p.separation - f0.separation
        ok = np.isfinite(d)
        assert ok.sum() > 100
        np.testing.assert_allclose(d[ok], np.broadcast_to(want, d.shape)[ok], atol=1e-12)
        # the gear's: its partner points' axial position from the gear's face middle
        gear = blanks_from_design(design)[1]
        wg = only_g.gear_z - 0.5 * (gear.z_toe + gear.z_heel)
        dg = only_g.separation - f0.separation
        ok = np.isfinite(dg)
        want_g = 8e-6 * (2 * np.clip(wg, -0.02, 0.02) / 0.04) ** 2
        np.testing.assert_allclose(dg[ok], want_g[ok], atol=1e-12)


def test_scene_topography_errors_name_their_keys(case03, tmp_path):
    from gearbox.ltca.beveloid import modifications_from_scene

    design, scene = case03
    x, y = [-10.0, 0.0, 10.0, 20.0], [-20.0, 0.0, 20.0, 30.0]
    cases = {
        "ltca.pinion_topography_face_mm": {"pinion_topography_profile_mm": x},
        "ltca.gear_topography_profile_mm": _topography_keys(
            "gear", [40, 50, 60, 70], y, [[0] * 4] * 4
        ),
        "ltca.pinion_topography_um[1]": _topography_keys(
            "pinion", x, y, [[0] * 4, [0] * 3, [0] * 4, [0] * 4]
        ),
    }
    for path, keys in cases.items():
        with pytest.raises(InputError) as err:
            modifications_from_scene(design, scene.replaced(ltca=keys))
        assert path in {p.path for p in err.value.problems}, (path, str(err.value))
    few = _topography_keys("pinion", x[:3], y, [[0] * 4] * 3)
    with pytest.raises(InputError, match="at least 4 points for cubic") as err:
        modifications_from_scene(design, scene.replaced(ltca=few))
    assert err.value.problems[0].path == "ltca.pinion_topography_profile_mm"
    linear = scene.replaced(ltca=few | {"topography_interpolation": "linear"})
    assert modifications_from_scene(design, linear)[0].topography.method == "linear"
    # a CSV file beside the scene, as for the measured traces
    text = (ROOT / "models" / "case03.toml").read_text()
    (tmp_path / "topo.csv").write_text("# removal (um)\n0,1,2,3\n0,1,2,3\n1,1,1,1\n2,2,2,2\n")
    extra = (
        "\n[ltca]\npinion_topography_profile_mm = [-10.0, 0.0, 10.0, 20.0]\n"
        "pinion_topography_face_mm = [-20.0, 0.0, 10.0, 20.0]\n"
        'pinion_topography_um = "topo.csv"\n'
    )
    (tmp_path / "s.toml").write_text(_with_ltca(text, extra))
    s = load_scene(tmp_path / "s.toml")
    assert s["ltca"]["pinion_topography_um"][2] == [1.0, 1.0, 1.0, 1.0]
    mods = modifications_from_scene(design, s)
    assert mods[0].topography.removal[3] == pytest.approx((2e-6,) * 4)


def _with_ltca(text: str, extra: str) -> str:
    """The scene text with the keys of ``extra``'s [ltca] added to its own [ltca]."""
    if "\n[ltca]" not in text:
        return text + extra
    head, _, tail = text.partition("\n[ltca]\n")
    return head + extra.rstrip("\n") + "\n" + tail


def test_the_topography_enters_the_loaded_tca_stage_key(case03, tmp_path):
    """A changed value in a topography's CSV file changes the loaded TCA's cache key
    (the file's numbers take its name's place in the scene)."""
    from gearbox.pipeline import preview

    design, scene = case03
    keys = _topography_keys("pinion", [-10, 0, 10, 20], [-20, 0, 10, 20], [[0, 1, 2, 3]] * 4)
    a = dict((n, k) for n, k, _ in preview(scene.replaced(ltca=keys), ["ltca"], cache=None))
    keys["pinion_topography_um"][2] = [0, 1, 2, 4]
    b = dict((n, k) for n, k, _ in preview(scene.replaced(ltca=keys), ["ltca"], cache=None))
    assert a["design"] == b["design"] and a["ltca"] != b["ltca"]


@pytest.mark.slow
@pytest.mark.parametrize("beta_deg", [20.0, -20.0])
def test_both_paths_take_an_uneven_topography_alike(beta_deg):
    """The 29/45 parallel pair (m 6, b 40 mm) with a pinion topography that rises
    across the face and up the profile, and a gear flank twist, through the scene keys:
    the surface path (generated flanks, the beveloid machinery) and the closed form
    move the load the same way on both flanks and both hands. The paths' own
    difference without modifications (stiffness within 2.5 %, mesh point within
    0.5 mm, test_ltca_modifications) bounds the comparison; the topography moves the
    mesh point by more than 5 mm."""
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import beveloid_ltca
    from gearbox.ltca.table import scene_ltca

    x = np.linspace(-15.0, 15.0, 5)
    y = np.linspace(-20.0, 20.0, 5)
    rows = [[12.0 * (v + 20) / 40 + 2.0 * (u + 15) / 30 for v in y] for u in x]
    lt = {"positions": 12, "grid_profile": 40, "grid_face": 20}
    keys = _topography_keys("pinion", x, y, rows) | {"gear_flank_twist_um": 6.0}
    base = load_scene(DATA / "ltca_parallel_helical.toml").replaced(
        pinion={"helix_angle_deg": beta_deg},
        pair={"offset_mm": 74 * 6.0 / 2 / math.cos(math.radians(beta_deg))},
        load={"torques_Nm": [300.0]},
    )
    design = design_pair(PairSpec.from_scene(base))
    out = {}
    for label, extra in (("plain", {}), ("topo", keys)):
        scene = base.replaced(ltca=lt | extra)
        out[label] = (beveloid_ltca(design, scene), scene_ltca(design, scene))
    for flank in ("drive", "coast"):
        z = {
            (label, path): out[label][i].flanks[flank].mesh_point[0][:, 2].mean()
            for label in out
            for i, path in enumerate(("surface", "closed"))
        }
        moved = z[("topo", "surface")] - z[("plain", "surface")]
        assert abs(moved) > 5e-3, (flank, moved)
        assert z[("topo", "closed")] - z[("plain", "closed")] == pytest.approx(moved, abs=0.5e-3)
        k_s = out["topo"][0].flanks[flank].stiffness[0].mean()
        k_c = out["topo"][1].flanks[flank].stiffness[0].mean()
        assert k_c == pytest.approx(k_s, rel=0.025), flank
        assert "topography 5 x 5" in out["topo"][0].attrs["flank_modifications"]


def test_the_result_carries_a_map_of_each_modified_gear_and_the_report_draws_it(case03):
    """Case 03 with a pinion topography and a gear profile slope and twist: the loaded
    TCA keeps per modified gear and analysed flank the removal over that flank (form
    circle to tip at each face position, with the flank's own base and form radii:
    the beveloid's drive and coast flanks differ), which equals the modification's own
    removal there; the report's loaded-TCA section draws one panel per gear and flank,
    its layout checked."""
    from gearbox.ltca.beveloid import _form_radius, modification_maps, modifications_from_scene
    from gearbox.ltca.table import scene_ltca
    from gearbox.report import html
    from gearbox.report.loaded import render_ltca
    from gearbox.surface import blanks_from_design

    design, scene = case03
    keys = _topography_keys(
        "pinion", [-15, -5, 5, 15], [-20, -5, 5, 20], [[0, 1, 2, 6], [1, 1, 1, 1]] * 2
    ) | {"gear_profile_slope_um": 4.0, "gear_flank_twist_um": 5.0}
    s = scene.replaced(
        ltca=keys | {"positions": 6, "flanks": ["drive"]}, load={"torques_Nm": [300.0]}
    )
    mods = modifications_from_scene(design, s)
    maps = modification_maps(design, mods, flanks=("drive", "coast"))
    assert list(maps) == [
        "pinion, drive flank",
        "gear, drive flank",
        "pinion, coast flank",
        "gear, coast flank",
    ]
    blanks = blanks_from_design(design)
    for flank, side in (("drive", 0), ("coast", 1)):
        for k, (name, gd) in enumerate((("pinion", design.pinion), ("gear", design.gear))):
            m, blank = maps[f"{name}, {flank} flank"], blanks[k]
            z = m["face_m"] + 0.5 * (blank.z_toe + blank.z_heel)
            rb = gd.base_radius[side]
            roll = m["roll_m"] + math.sqrt(gd.reference_pitch_radius**2 - rb**2)
            r = np.sqrt(rb**2 + roll**2)
            # from the form circle to the tip circle of each section
            np.testing.assert_allclose(r[:, 0], _form_radius(blank, gd, z)[side], rtol=1e-12)
            np.testing.assert_allclose(r[:, -1], blank.tip_radius(z), rtol=1e-12)
            want = mods[k].removal(
                r,
                np.broadcast_to(m["face_m"][:, None], r.shape),
                tip_radius=blank.tip_radius(z)[:, None],
                base_radius=rb,
                face_width=blank.face_width,
                form_radius=_form_radius(blank, gd, z)[side][:, None],
                reference_radius=gd.reference_pitch_radius,
            )
            np.testing.assert_allclose(m["removal_m"], want, rtol=0, atol=1e-18)
    # the flanks' form circles differ on this pair, so do the maps' roll ranges
    d, c = maps["pinion, drive flank"]["roll_m"], maps["pinion, coast flank"]["roll_m"]
    assert abs(d[:, 0] - c[:, 0]).max() > 1e-5
    # the gear's profile slope and twist: -/+ (f + S w / b) / 2 at the form circle / tip
    g = maps["gear, drive flank"]
    slope = 4e-6 + 5e-6 * g["face_m"] / blanks[1].face_width
    np.testing.assert_allclose(g["removal_m"][:, -1] - g["removal_m"][:, 0], slope, atol=1e-18)
    res = scene_ltca(design, s)
    assert set(res.modification_maps) == {"pinion, drive flank", "gear, drive flank"}

    class Run:
        scene = s

    old = html.CHECK_LAYOUT
    html.CHECK_LAYOUT = True  # every figure's texts inside the canvas, no overlaps
    try:
        section = render_ltca(res, Run())
        both = scene_ltca(design, s.replaced(ltca={"flanks": ["drive", "coast"]}))
        assert len(both.modification_maps) == 4
        two_rows = render_ltca(both, Run())
    finally:
        html.CHECK_LAYOUT = old
    assert "Flank modifications: material removed normal to the flank" in section.body
    assert section.body.count("<img") == 3
    assert two_rows.body.count("<img") == 3  # the four maps in one figure
    plain = scene_ltca(design, scene.replaced(ltca={"positions": 6, "flanks": ["drive"]}))
    assert plain.modification_maps == {}
    assert render_ltca(plain, Run()).body.count("<img") == 2


def test_a_ringing_bicubic_topography_earns_a_note():
    """A 10 um end relief given as a step between two face points of a 5 mm grid: the
    bicubic spline overshoots it by 3.0 um and undershoots the unrelieved face by 0.9
    um (material added where the grid says none). Topography.overshoot measures the
    ringing only where the grid's values run one way, so a smooth crowning whose
    vertex lies between the points reads 0; the loaded TCA's notes name the gear and
    the remedy; the bilinear grid does not ring."""
    y = np.linspace(-0.02, 0.02, 9)
    x = np.linspace(-0.015, 0.015, 4)
    step = Topography(x, y, [np.where(y >= 0.015, 10e-6, 0.0)] * 4)
    w = np.linspace(-0.02, 0.02, 4001)
    v = step(np.zeros_like(w), w)
    assert v.min() < -0.8e-6 and v.max() > 12.9e-6  # the ringing itself
    assert step.overshoot() == pytest.approx(v.max() - 10e-6, rel=0.02)
    assert step.overshoot() > 3.0e-6
    crown = Topography(x, y, [10e-6 * ((y - 0.0025) / 0.02) ** 2] * 4)
    assert crown.overshoot() < 1e-12
    assert replace(step, method="linear").overshoot() == 0.0
    pair = replace(SPUR, face_width=0.04)
    mods = (FlankModification(topography=step), FlankModification(topography=crown))
    res = parallel_ltca(pair, [300.0], options=LTCAOptions(positions=4), relief=mods, n_face=12)
    notes = [n for n in res.notes if "topography" in n]
    assert len(notes) == 1 and notes[0].startswith("pinion's topography")
    assert "3 um" in notes[0] and "'linear'" in notes[0]
    calm = (FlankModification(topography=replace(step, method="linear")), None)
    res = parallel_ltca(pair, [300.0], options=LTCAOptions(positions=4), relief=calm, n_face=12)
    assert not [n for n in res.notes if "topography" in n]


def test_a_pchip_topography_is_smooth_without_overshoot():
    """'pchip': the step that makes the bicubic spline ring stays within its values;
    data linear on each axis come back exactly (PCHIP is exact for them); on a random
    grid the refined evaluation lies within 0.05 um of PCHIP taken point by point with
    scipy (along the face, then up the profile; measured 0.039 um on 0-5 um); turned
    end for end it reads the same at -w."""
    from scipy.interpolate import PchipInterpolator

    y = np.linspace(-0.02, 0.02, 9)
    x = np.linspace(-0.015, 0.015, 4)
    step = Topography(x, y, [np.where(y >= 0.015, 10e-6, 0.0)] * 4, "pchip")
    w = np.linspace(-0.02, 0.02, 4001)
    v = step(np.zeros_like(w), w)
    assert v.min() >= -1e-18 and v.max() <= 10e-6 + 1e-18
    assert np.all(np.diff(v) >= -1e-18)  # monotone data, monotone removal
    assert step.overshoot() == 0.0
    bilinear = FlankModification(helix_slope=-5e-6, profile_slope=3e-6, flank_twist=7e-6)
    lo, hi = _roll(_place(0.0)), _roll(_place(1.0))
    gx, gy = np.linspace(lo, hi, 3), np.linspace(-0.5 * B, 0.5 * B, 5)
    X, Y = np.meshgrid(gx, gy, indexing="ij")
    R = np.sqrt(RB**2 + (X + math.sqrt(0.095**2 - RB**2)) ** 2)
    topo = Topography(gx, gy, removal(bilinear, R, Y), "pchip")
    rng = np.random.default_rng(8)
    t, wq = rng.uniform(0, 1, 300), rng.uniform(-0.5 * B, 0.5 * B, 300)
    got = removal(FlankModification(topography=topo), _place(t), wq)
    np.testing.assert_allclose(got, removal(bilinear, _place(t), wq), rtol=0, atol=1e-18)
    V = rng.uniform(0, 5e-6, (4, 9))
    rand = Topography(x, y, V, "pchip")
    px, py = rng.uniform(-0.015, 0.015, 500), rng.uniform(-0.02, 0.02, 500)
    along = PchipInterpolator(y, V, axis=1)(py)  # (4, 500): each profile row at py
    want = np.array([PchipInterpolator(x, along[:, i])(px[i]) for i in range(px.size)])
    assert np.max(np.abs(rand(px, py) - want)) < 0.05e-6
    np.testing.assert_allclose(rand.reflected()(px, -py), rand(px, py), rtol=0, atol=1e-18)


def test_any_malformed_grid_is_refused_by_name():
    """Random grids, shapes and values (hypothesis): a Topography either builds and
    evaluates to finite removals held within reach of its values, or raises InputError
    naming one of its parts; nothing else escapes."""
    from hypothesis import given, settings
    from hypothesis import strategies as st

    nums = st.one_of(
        st.floats(-1e-4, 1e-4),
        st.sampled_from([math.nan, math.inf, 0.0]),
    )
    axis = st.lists(nums, min_size=0, max_size=6)
    rows = st.lists(st.lists(nums, min_size=0, max_size=6), min_size=0, max_size=6)

    @settings(max_examples=300, deadline=None)
    @given(axis, axis, rows, st.sampled_from(["cubic", "pchip", "linear", "spline"]))
    def check(x, y, r, method):
        try:
            topo = Topography(x, y, r, method)
        except InputError as err:
            parts = {p.path.partition("[")[0] for p in err.problems}
            assert parts and parts <= {"profile", "face", "removal", "method"}
            return
        v = topo(np.linspace(-2e-4, 2e-4, 7), np.linspace(-2e-4, 2e-4, 7))
        assert np.all(np.isfinite(v))
        values = np.asarray(topo.removal)
        span = np.ptp(values) + 1e-18
        # a cubic may ring (topo.overshoot), but within a few spans of its values
        assert v.min() >= values.min() - 4 * span and v.max() <= values.max() + 4 * span
        assert topo.overshoot() >= 0.0

    check()

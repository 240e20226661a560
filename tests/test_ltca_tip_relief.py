"""Tip relief (profile modification) in the loaded TCA.

The relief is material removed normal to the flank near the tip; it enters the
separation field of the beveloid pair (gearbox.ltca.beveloid) and the parallel-pair
grid (gearbox.ltca.parallel). Case 03 at 300 N m is the paper's tested case; its
unmodified flanks put about 20 % of the load on tip edges at some positions.
"""

from pathlib import Path

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca import LTCAOptions, compliance_for, ltca_cycle
from gearbox.ltca.beveloid import (
    TipRelief,
    beveloid_ltca,
    separation_field,
    tip_relief_from_scene,
)
from gearbox.ltca.parallel import parallel_grid
from gearbox.ltca.table import parallel_pair_from_design, scene_ltca
from gearbox.scene import load_scene
from gearbox.surface import blanks_from_design

ROOT = Path(__file__).resolve().parents[1]
DATA = Path(__file__).parent / "data"
EDGE_FLAG = 0.05  # the edge_contact threshold of gearbox.ltca.analysis


def _relief_keys(amount_um, length_mm, shape="linear", gears=("pinion", "gear")):
    out = {}
    for g in gears:
        out[f"{g}_tip_relief_um"] = amount_um
        out[f"{g}_tip_relief_length_mm"] = length_mm
        out[f"{g}_tip_relief_shape"] = shape
    return out


@pytest.fixture(scope="module")
def case03():
    scene = load_scene(ROOT / "models" / "case03.toml")
    return scene, design_pair(PairSpec.from_scene(scene))


def _summary(scene, **ltca):
    s = scene.replaced(ltca={"flanks": ["drive"], **ltca}, load={"torques_Nm": [300.0]})
    res = beveloid_ltca(design_pair(PairSpec.from_scene(s)), s)
    return res.summary()["flanks"]["drive"]["300"], res


# ----------------------------------------------------------------- the relief law
def test_relief_law_zero_below_start_and_ca_at_the_tip():
    rb, ra = 0.08, 0.1
    for shape, half in (("linear", 0.5), ("parabolic", 0.25)):
        rel = TipRelief(15e-6, 2e-3, shape)
        rs = ra - 2e-3
        xs, xa = np.sqrt(rs**2 - rb**2), np.sqrt(ra**2 - rb**2)
        r_mid = np.sqrt((0.5 * (xs + xa)) ** 2 + rb**2)  # half the roll length
        c = rel.removal(np.array([0.09, rs - 1e-9, rs, r_mid, ra]), ra, rb)
        assert np.all(c[:3] == 0.0)
        assert c[3] == pytest.approx(half * 15e-6, rel=1e-12)
        assert c[4] == pytest.approx(15e-6, rel=1e-12)
    assert np.all(TipRelief().removal(np.linspace(0.08, 0.1, 5), ra, rb) == 0.0)


def test_relief_on_the_field_is_the_removal_at_each_gears_radius(case03):
    # pinion-only and gear-only reliefs: the Newton projections do not depend on the
    # relief, so the field's change is exactly the removal at the pinion point's
    # radius (resp. the gear partner's radius): zero below the start, C_a at the tip
    scene, design = case03
    pinion, gear = blanks_from_design(design)
    kw = dict(n_profile=12, n_face=8, positions=4)
    rel = TipRelief(20e-6, 1.8e-3, "linear")
    base = separation_field(design, scene, "R", relief=(TipRelief(), TipRelief()), **kw)
    f1 = separation_field(design, scene, "R", relief=(rel, TipRelief()), **kw)
    f2 = separation_field(design, scene, "R", relief=(TipRelief(), rel), **kw)
    # pinion
    r1 = np.hypot(base.point[..., 0], base.point[..., 1])  # (S, U)
    ra1 = pinion.tip_radius(base.point[..., 2])
    expect1 = rel.removal(r1, ra1, design.pinion.base_radius[0])
    d1 = f1.separation - base.separation
    ok = np.isfinite(d1)
    assert np.allclose(d1[ok], np.broadcast_to(expect1, d1.shape)[ok], rtol=0, atol=1e-13)
    below = np.broadcast_to(r1 < ra1 - rel.length, d1.shape) & ok
    assert below.sum() > 0.5 * ok.sum() and np.all(d1[below] == 0.0)
    assert rel.removal(ra1, ra1, design.pinion.base_radius[0]) == pytest.approx(20e-6)
    # the topmost contacting profile points lie well inside the relief (12.9 um of
    # the 20 um measured with this grid)
    assert 0.5 * 20e-6 < np.nanmax(d1) < 20e-6
    # gear
    ra2 = gear.tip_radius(base.gear_z)
    expect2 = rel.removal(base.gear_radius, ra2, design.gear.base_radius[0])
    d2 = f2.separation - base.separation
    ok2 = np.isfinite(d2)
    assert np.allclose(d2[ok2], expect2[ok2], rtol=0, atol=1e-13)
    assert np.any(d2[ok2] == 0.0) and np.nanmax(d2) > 0.5 * 20e-6


# ------------------------------------------------------- zero relief: no change
# sums of the separation field of case 03 (drive, 12 x 12 grid, 8 positions) without
# modifications, recorded at the touching gear phase (2026-12; the first recording, of
# the code before tip relief existed, commit 4c9b88f, had the phase searched at
# phi_1 = 0, 0.44 mrad off: separation 3.0940, edge points 212)
_REFERENCE_FIELD = {
    "separation": 3.256186950425084,
    "line_separation": 0.42724160740731454,
    "line_curvature": 27475.984287026324,
    "line_u": 2.8976428225130344,
    "line_gear_radius": 88.6340099590852,
}
#: The curvature's sum, of second differences, carries the last bits of the math
#: library: with numpy 2.4.6 it reads 3.9e-12 off the recording, the other sums 3e-16.
_REFERENCE_RTOL = {"line_curvature": 1e-10}


def test_zero_relief_reproduces_the_unmodified_field_and_tables(case03):
    scene, design = case03
    kw = dict(n_profile=12, n_face=12, positions=8)
    # the recording has the edge points on the last profile samples
    f0 = separation_field(design, scene, "R", edge_borders=False, **kw)
    for key, ref in _REFERENCE_FIELD.items():
        rel = _REFERENCE_RTOL.get(key, 1e-12)
        assert float(np.nansum(getattr(f0, key))) == pytest.approx(ref, rel=rel), key
    assert int(f0.line_edge.sum()) == 213
    # zero amount with a length and shape given: bit for bit the default scene, with
    # the edge points on the last samples and on the flank borders (where the zero
    # removal is added to the projected separation)
    zero = scene.replaced(ltca=_relief_keys(0.0, 1.5, "parabolic"))
    for borders in (False, True):
        f0 = separation_field(design, scene, "R", edge_borders=borders, **kw)
        fz = separation_field(design, zero, "R", edge_borders=borders, **kw)
        for key in ("separation", "line_separation", "line_curvature", "line_point"):
            assert np.array_equal(getattr(f0, key), getattr(fz, key), equal_nan=True), key
    small = dict(positions=8, grid_profile=12, grid_face=12)
    _, r0 = _summary(scene, **small)
    _, rz = _summary(zero, **small)
    for key in ("stiffness", "lte", "lte_unloaded", "edge_load_fraction"):
        a, b = getattr(r0.flanks["drive"], key), getattr(rz.flanks["drive"], key)
        assert np.array_equal(a, b), key


# ------------------------------------------------------------- case 03, 300 N m
@pytest.fixture(scope="module")
def case03_runs(case03):
    scene, _ = case03
    # C_a by the rule of thumb (ISO 6336 / Niemann): about the mesh deflection at the
    # load, F_n / k = 3.7 kN / 468 MN/m = 8 um; short relief 0.2 m_n = 1.2 mm
    # (measured: max edge load 19.6 % -> 1.6 %, docs/ltca.md "Tip relief")
    return {
        "none": _summary(scene)[0],
        "short": _summary(scene, **_relief_keys(8.0, 1.2))[0],
        "parabolic": _summary(scene, **_relief_keys(20.0, 1.8, "parabolic"))[0],
        "long": _summary(scene, **_relief_keys(30.0, 3.0))[0],
    }


def test_relief_takes_the_load_off_the_tip_edges(case03_runs):
    r = case03_runs
    assert r["none"]["edge_contact"] and r["none"]["max_edge_load_fraction"] > 0.15
    for name in ("short", "parabolic", "long"):
        assert r[name]["max_edge_load_fraction"] < EDGE_FLAG, name
        assert not r[name]["edge_contact"], name
        # less flank in contact: softer mesh, smaller pattern
        assert r[name]["mean_mesh_stiffness_N_per_m"] < r["none"]["mean_mesh_stiffness_N_per_m"]
        assert r[name]["contact_pattern_area_fraction"] < r["none"]["contact_pattern_area_fraction"]


def test_unloaded_te_grows_with_the_relief(case03_runs):
    # case 03's contact ratio keeps an unrelieved part of some contact line in
    # contact at every position under a short relief, so its unloaded TE barely moves
    # (measured 4.4 -> 5.4 nm); a long relief (0.5 m_n) opens the flanks at the start
    # and end of engagement at every face position and the rigid rotation to first
    # contact varies over the cycle (measured 481 nm)
    te = {k: v["unloaded_te_peak_to_peak_m"] for k, v in case03_runs.items()}
    assert te["short"] >= te["none"] - 1e-10
    assert te["long"] > 50 * te["none"]
    assert te["long"] > 1e-7
    # and the long relief evens out the loaded TE: its p-p falls below the unmodified
    assert case03_runs["long"]["lte_peak_to_peak_m"] < case03_runs["none"]["lte_peak_to_peak_m"]


# --------------------------------------------------------------- parallel pairs
def test_parallel_grid_relief_matches_the_surface_path():
    # the parallel helical pair through the generated flanks (beveloid path) and in
    # closed form (plane of action) with the same relief: measured 0.1 % apart on
    # mean stiffness and LTE (40 profile points), hence 1 %
    scene = load_scene(DATA / "ltca_parallel_helical.toml")
    s = scene.replaced(
        ltca={"positions": 12, "grid_profile": 40, "grid_face": 20, "flanks": ["drive"]},
        load={"torques_Nm": [300.0]},
    )
    design = design_pair(PairSpec.from_scene(s))
    pair = parallel_pair_from_design(design, s)
    rel = (TipRelief(10e-6, 1.2e-3), TipRelief(10e-6, 1.2e-3))
    g0 = parallel_grid(pair, 0.3, 20)
    assert np.array_equal(g0.separation, parallel_grid(pair, 0.3, 20, relief=None).separation)
    assert np.any(parallel_grid(pair, 0.3, 20, relief=rel).separation > 0)
    b = beveloid_ltca(design, s, relief=rel).flanks["drive"]
    p = ltca_cycle(
        lambda f: parallel_grid(pair, f, 20, relief=rel),
        [300.0],
        options=LTCAOptions(positions=12),
        compliance=compliance_for("fast"),
    )
    p0 = ltca_cycle(
        lambda f: parallel_grid(pair, f, 20),
        [300.0],
        options=LTCAOptions(positions=12),
        compliance=compliance_for("fast"),
    )
    assert b.stiffness[0].mean() == pytest.approx(p.stiffness[0].mean(), rel=0.01)
    assert b.lte[0].mean() == pytest.approx(p.lte[0].mean(), rel=0.01)
    assert p.stiffness[0].mean() < 0.95 * p0.stiffness[0].mean()  # the relief matters


# ------------------------------------------------------------------ bad input
@pytest.mark.parametrize(
    ("keys", "path"),
    [
        ({"pinion_tip_relief_um": -1.0}, "ltca.pinion_tip_relief_um"),
        ({"gear_tip_relief_um": 500.0}, "ltca.gear_tip_relief_um"),
        ({"gear_tip_relief_length_mm": -0.5}, "ltca.gear_tip_relief_length_mm"),
        ({"pinion_tip_relief_shape": "cubic"}, "ltca.pinion_tip_relief_shape"),
        ({"pinion_tip_relief_um": 10.0}, "ltca.pinion_tip_relief_length_mm"),
    ],
)
def test_bad_relief_keys_name_the_key(case03, keys, path):
    scene, _ = case03
    with pytest.raises(InputError) as e:
        scene.replaced(ltca=keys)
    assert path in str(e.value)


def test_relief_starting_below_the_base_circle_is_an_error(case03):
    scene, design = case03
    # case 03's pinion: tip radius 99.3-100.0 mm, base radius 86.5 mm
    s = scene.replaced(ltca=_relief_keys(10.0, 20.0, gears=("pinion",)))
    with pytest.raises(InputError) as e:
        tip_relief_from_scene(design, s)
    assert "ltca.pinion_tip_relief_length_mm" in str(e.value)
    assert "20" in str(e.value)
    with pytest.raises(InputError, match="amount"):
        TipRelief(-1e-6, 1e-3)
    with pytest.raises(InputError, match="length"):
        TipRelief(1e-6, 0.0)


def test_relief_on_a_parallel_scene_reaches_the_tables():
    # the scene path of a parallel-axis pair passes the relief to the closed-form grid:
    # the same relief given to parallel_grid directly gives the same table
    scene = load_scene(DATA / "ltca_parallel_helical.toml")
    relieved = scene.replaced(ltca=_relief_keys(10.0, 1.2))
    design = design_pair(PairSpec.from_scene(relieved))
    opts = LTCAOptions(positions=8)
    plain = scene_ltca(design, scene, options=opts).flanks["drive"]
    res = scene_ltca(design, relieved, options=opts).flanks["drive"]
    assert not np.allclose(res.lte, plain.lte)
    pair = parallel_pair_from_design(design, relieved)
    relief = tip_relief_from_scene(design, relieved)
    direct = ltca_cycle(
        lambda f: parallel_grid(pair, f, relieved["ltca"]["grid_face"], relief=relief),
        relieved["load"]["torques_Nm"],
        options=opts,
    )
    assert np.allclose(res.lte, direct.lte, rtol=1e-12, atol=0)

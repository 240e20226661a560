"""The flanks' sliding and the mesh loss factor of the loaded TCA
(:meth:`ContactGrid.sliding_velocity`, ``CycleResult.loss_factor``).

References, none written here:

- parallel pairs: the sliding velocity at a point of the plane of action is
  ``v_g = (omega_1 + omega_2) g`` with ``g`` its transverse distance from the pitch
  line (Niemann / Winter, Maschinenelemente II, eq. 21/58; ISO/TR 14179-2 uses it
  for the tooth losses);
- crossed helical gears at the pitch point: ``v_g = v_w1 sin(Sigma) / cos(beta_w2)``
  (Niemann / Winter, Maschinenelemente III, crossed helical gears);
- the tooth loss factor of a spur pair with the load shared in halves wherever two
  pairs touch: ``H_V = pi (u + 1) / (z_1 u) (1 - eps_a + eps_1^2 + eps_2^2)``
  (Ohlendorf 1958, ISO/TR 14179-2:2001 eq. 8), with eps_1 / eps_2 the addendum
  contact ratios of pinion / gear;
- a helical pair whose load is spread evenly over its contact lines: the loss
  factor is the mean transverse distance from the pitch line over the path,
  ``pi (u + 1) / (z_1 u cos(beta_b)) (eps_1^2 + eps_2^2) / eps_a`` (the same
  integral with an even load instead of halves).
"""

import math
from pathlib import Path

import numpy as np
import pytest
from _textbook import loss_factor

from gearbox.ltca import LTCAOptions, ParallelPair, ltca_cycle, parallel_grid

ROOT = Path(__file__).resolve().parents[1]


def _pair(helix_deg, face_mm=40.0):
    return ParallelPair(
        normal_module=4e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=math.radians(helix_deg),
        teeth=(20, 40),
        face_width=face_mm * 1e-3,
    )


def _pitch_roll(p):
    """Roll distance of the pitch point from T1, and the addendum contact ratios of
    pinion and gear (path from the pitch point to the pinion's / gear's tip)."""
    xa, xe = p.roll_limits
    xc = p.base_radius(0) * math.tan(p.working_pressure_angle)
    return xc, (xe - xc) / p.base_pitch, (xc - xa) / p.base_pitch


@pytest.mark.parametrize("helix_deg", [0.0, 15.0, 30.0])
def test_sliding_speed_is_the_textbook_profile_sliding(helix_deg):
    p = _pair(helix_deg)
    xc, _, _ = _pitch_roll(p)
    u = p.teeth[1] / p.teeth[0]
    for f in (0.0, 0.3, 0.7):
        g = parallel_grid(p, f, n_face=10)
        v = g.sliding_velocity()
        xi = g.profile + p.roll_limits[0]
        # (omega_1 + omega_2) g per unit omega_1; exact, to round-off
        expect = (1 + 1 / u) * np.abs(xi - xc)
        assert np.allclose(np.linalg.norm(v, axis=1), expect, rtol=0, atol=1e-12)
        # in the tangent plane, along the profile: normal to the contact lines'
        # direction in the plane of action (the pitch line's)
        assert np.allclose(v @ np.array([0.0, 0.0, 1.0]), 0.0, atol=1e-15)
        # conjugate flanks at the gear's speed z1/z2: no approach, to round-off
        assert np.max(np.abs(g.approach_rate())) < 1e-12


def test_crossed_helical_pitch_point_sliding():
    # case 03 with both cone angles 0: a crossed helical pair (shaft angle 13 deg,
    # beta_w1 + beta_w2 = Sigma). The slowest sliding of all contact points over the
    # cycle is the pitch point's v_w1 sin(Sigma) / cos(beta_w2) within 1 % (measured
    # 0.44 % below: the grid's points sample the flanks with a finite spacing, and the
    # slowest relative velocity lies on the instantaneous screw axis, near but not at
    # the pitch point)
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import scene_grids
    from gearbox.scene import load_scene

    s = load_scene(ROOT / "models" / "case03.toml")
    s = s.replaced(pinion={"cone_angle_deg": 0.0}, gear={"cone_angle_deg": 0.0})
    d = design_pair(PairSpec.from_scene(s))
    grids, _, _ = scene_grids(d, s, "R", 8)
    slowest = min(np.linalg.norm(g.sliding_velocity(), axis=1).min() for g in grids)
    pitch = d.pinion.working_pitch_radius * math.sin(d.shaft_angle)
    pitch /= math.cos(d.gear.working_helix_angle)
    assert slowest == pytest.approx(pitch, rel=0.01)
    # the gear turns in the sense that keeps the touching points in contact: where the
    # flanks touch (gap under 1 um at the position's first contact) inside the flanks
    # they do not approach (measured 5.0e-5 of the pinion's normal speed). An edge point
    # on a flank border is not conjugate: its contact runs over the border's corner
    # (measured up to 1.5e-3 there, 9.6e-4 on the last profile sample)
    for g in grids:
        gap = g.separation - np.min(g.separation / g.arm) * g.arm
        near = gap < 1e-6
        assert (near & ~g.edge).sum() >= 5
        assert np.max(np.abs(g.approach_rate()[near & ~g.edge])) < 1e-4
        assert np.max(np.abs(g.approach_rate()[near])) < 5e-3


def _cycle(p, torques, positions=48):
    return ltca_cycle(
        lambda f: parallel_grid(p, f, n_face=20), torques, options=LTCAOptions(positions=positions)
    )


def test_spur_loss_factor_from_the_load_shares_and_against_ohlendorf():
    p = _pair(0.0)
    res = _cycle(p, [100.0, 1000.0])
    xc, e1, e2 = _pitch_roll(p)
    u = p.teeth[1] / p.teeth[0]
    rb1 = p.base_radius(0)
    # per position, exactly: each tooth pair's share of the load times its textbook
    # sliding speed (a spur pair's points of one pair share their roll distance)
    xa = p.roll_limits[0]
    for t in range(res.torque.size):
        for j, f in enumerate(res.fraction):
            xi = xa + (f + res.pair_index) * p.base_pitch
            h = np.sum(res.pair_share[t, j] * (1 + 1 / u) * np.abs(xi - xc)) / rb1
            assert res.loss_factor[t, j] == pytest.approx(h, rel=1e-9)
    # over the cycle against Ohlendorf's H_V: its halves in double contact are the
    # rigid teeth's sharing; elastic teeth give the entering and leaving pair less
    # than half (load ramps at the path's ends, where the sliding is fastest), so
    # the LTCA reads below H_V, measured 0.972 / 0.969 at 100 / 1000 N m: within 5 %
    eps = p.transverse_contact_ratio
    hv = math.pi * (u + 1) / (p.teeth[0] * u) * (1 - eps + e1**2 + e2**2)
    ratio = res.loss_factor.mean(axis=1) / hv
    assert np.all((ratio > 0.95) & (ratio < 1.0)), ratio
    # friction power at most where the sliding is fastest, the path's ends
    assert np.all(res.sliding_speed <= (1 + 1 / u) * max(e1, e2) * p.base_pitch * (1 + 1e-9))


def test_helical_loss_factor_against_the_even_load():
    # 30 deg, overlap ratio 1.59: the load lies nearly evenly along the contact lines;
    # the loss factor reads the even load's within 3 % (measured +1.3 / +1.9 % at
    # 100 / 1000 N m)
    p = _pair(30.0)
    res = _cycle(p, [100.0, 1000.0])
    _, e1, e2 = _pitch_roll(p)
    u = p.teeth[1] / p.teeth[0]
    eps = p.transverse_contact_ratio
    even = math.pi * (u + 1) / (p.teeth[0] * u * math.cos(p.base_helix_angle))
    even *= (e1**2 + e2**2) / eps
    assert res.loss_factor.mean(axis=1) == pytest.approx([even, even], rel=0.03)
    # the ripple over the cycle is small where the overlap is large (spur: the
    # loss factor swings with the single / double contact)
    spur = _cycle(_pair(0.0), [400.0])
    assert np.ptp(res.loss_factor[0]) < 0.3 * np.ptp(spur.loss_factor[0])


def test_cycle_without_axes_has_no_loss_factor():
    import dataclasses

    p = _pair(0.0)

    def bare(f):
        return dataclasses.replace(parallel_grid(p, f, n_face=8), pinion_axis=None, gear_axis=None)

    res = ltca_cycle(bare, [100.0], options=LTCAOptions(positions=4))
    assert res.loss_factor is None and res.sliding_speed is None
    again = type(res).from_dict(res.to_dict())
    assert again.loss_factor is None
    from gearbox.ltca.analysis import cycle_summary

    assert "mesh_loss_factor" not in cycle_summary(res)["torques"][0]


def test_one_axis_alone_is_a_clear_error():
    import dataclasses

    from gearbox.errors import InputError

    g = parallel_grid(_pair(0.0), 0.0, n_face=8)
    with pytest.raises(InputError, match="gear_axis"):
        dataclasses.replace(g, gear_axis=None)
    with pytest.raises(InputError, match=r"pinion_axis\[0\]"):
        dataclasses.replace(g, pinion_axis=np.zeros((2, 3)))


def test_case03_report_shows_loss_factor_and_sliding_speed():
    # crossed axes add sliding along the teeth to the profile's: case 03's loss
    # factor is well above a parallel helical pair's (0.15 - 0.19 above), and its
    # slowest sliding is the pitch point's lengthwise one, never zero
    from types import SimpleNamespace

    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import beveloid_ltca
    from gearbox.report.loaded import _MU, render_ltca
    from gearbox.scene import load_scene

    s = load_scene(ROOT / "models" / "marine_drive.toml")
    s = s.replaced(ltca={"positions": 8, "flanks": ["drive"]}, load={"torques_Nm": [300.0, 900.0]})
    lt = beveloid_ltca(design_pair(PairSpec.from_scene(s)), s)
    res = lt.flanks["drive"]
    assert np.all(res.loss_factor > 0.25)
    assert lt.table.extra["mesh_loss_factor"].shape == (1, 2, 8)
    assert np.array_equal(lt.table.extra["mesh_loss_factor"][0], res.loss_factor)
    html = render_ltca(lt, SimpleNamespace(scene=s)).body
    assert "mesh loss factor H" in html and "max sliding (m/s at 3500 rpm)" in html
    t = 1  # 900 N m, nearest to the operating 802 N m
    h = float(res.loss_factor[t].mean())
    assert f"{h:.4f}" in html
    assert f"drive flank {100 * (1 - _MU * h):.2f} % mesh efficiency" in html
    power = 900.0 * 3500 * math.pi / 30
    assert f"{_MU * h * power / 1e3:.2f} kW (drive flank)" in html
    assert f"of the {power / 1e3:.1f} kW into heat" in html
    omega = 3500 * math.pi / 30
    assert f"{res.sliding_speed[t].max() * omega:.2f}" in html


@pytest.mark.parametrize("side", ["R", "L"])
def test_case03_flanks_touch_without_approaching(side):
    # the generated beveloid flanks of the line-contact design are conjugate where they
    # touch inside the flanks: the points within 1 um of first contact approach at under
    # 1e-4 of the pinion's normal speed (measured 4.2e-5 drive, 5.9e-5 coast). The edge
    # points on the flank borders are not conjugate, their contact runs over the
    # border: under 1 % (measured 0.53 % drive, 0.12 % coast; on the last profile
    # samples 0.19 % and 0.07 %)
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca.beveloid import scene_grids
    from gearbox.scene import load_scene

    s = load_scene(ROOT / "models" / "case03.toml")
    d = design_pair(PairSpec.from_scene(s))
    grids, _, _ = scene_grids(d, s, side, 8)
    worst, inner = 0.0, 0.0
    for g in grids:
        near = g.separation - np.min(g.separation / g.arm) * g.arm < 1e-6
        rate = np.abs(g.approach_rate())
        worst = max(worst, float(np.max(rate[near])))
        inner = max(inner, float(np.max(rate[near & ~g.edge])))
    assert 0.0 < inner < 1e-4
    assert inner < worst < 0.01


def test_spur_friction_arms_are_the_textbook_arms():
    # Friction at roll distance x from T_1 acts at the arm x about the pinion's axis and
    # T_1T_2 - x about the gear's, reversed at the pitch point (Vaishya & Singh, J.
    # Sound Vib. 243 (2001); the sliding velocity's sense flips there): per point
    # exactly, and per position the load shares times each pair's arms (rel 1e-9,
    # round-off: a spur pair's points of one pair share their roll distance).
    p = _pair(0.0)
    xc, _, _ = _pitch_roll(p)
    line = (p.base_radius(0) + p.base_radius(1)) * math.tan(p.working_pressure_angle)  # T_1T_2
    xa = p.roll_limits[0]
    for f in (0.1, 0.6):
        g = parallel_grid(p, f, n_face=6)
        x = g.profile + xa
        sg = np.sign(x - xc)
        np.testing.assert_allclose(g.friction_arms()[:, 0], sg * x, rtol=0, atol=1e-12)
        np.testing.assert_allclose(g.friction_arms()[:, 1], sg * (line - x), rtol=0, atol=1e-12)
    res = _cycle(p, [100.0, 1000.0], positions=24)
    for t in range(res.torque.size):
        for j, f in enumerate(res.fraction):
            x = xa + (f + res.pair_index) * p.base_pitch
            sg = np.sign(x - xc)
            share = res.pair_share[t, j]
            want = np.sum(share * sg * x), np.sum(share * sg * (line - x))
            np.testing.assert_allclose(res.friction_arm[t, j], want, rtol=1e-9, atol=1e-15)


@pytest.mark.parametrize("helix_deg", [0.0, 30.0])
def test_friction_arms_carry_the_loss_factor(helix_deg):
    # The torques of the friction on the two bodies lose what the sliding loses: per
    # position arm_1 - (z1 / z2) arm_2 = H T / F_n, the loss factor computed from the
    # sliding speeds; to round-off (measured 7e-18 / 4e-18 m)
    p = _pair(helix_deg)
    res = _cycle(p, [100.0, 1000.0], positions=24)
    u = p.teeth[1] / p.teeth[0]
    arm = res.friction_arm
    loss = res.loss_factor * res.torque[:, None] / res.normal_load
    np.testing.assert_allclose(arm[..., 0] - arm[..., 1] / u, loss, rtol=0, atol=1e-15)


@pytest.mark.parametrize("helix_deg", [0.0, 15.0, 30.0])
def test_analytical_table_friction_arms_against_the_textbook_loss_factor(helix_deg):
    # The analytical table spreads the load evenly along the contact lines. Over the
    # cycle its arms lose (arm_1 - arm_2 / u) / lambda_1 per unit friction
    # coefficient, which for a spur pair is Ohlendorf's H_V (halves in double contact,
    # ISO/TR 14179-2 eq. 8; measured 8e-5 off, the sampling of 4096 angles) and for a
    # helical pair the even-load factor of the path (measured -0.46 / -0.59 % at 15 /
    # 30 deg: the cycle's mean of a ratio, since the total contact length varies over
    # the cycle unless the overlap ratio is whole). Tolerance 1e-3 and 1 %.
    from gearbox.mesh_analytical import HelicalPair, friction_arms

    h = HelicalPair(
        teeth=(20, 40),
        normal_module=4e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=math.radians(helix_deg),
        face_width=40e-3,
    )
    u, z1 = 2.0, 20
    arms = friction_arms(h, np.arange(4096) * (2 * math.pi / z1 / 4096))
    lam1 = h.base_radius(0) * math.cos(h.base_helix_angle)
    got = float(np.mean(arms[:, 0] - arms[:, 1] / u)) / lam1
    assert got == pytest.approx(loss_factor(h), rel=1e-3 if helix_deg == 0.0 else 0.01)
    # the coast flank runs its path the other way: the same loss over the cycle, to the
    # sampling of the spur pair's jumps (measured 4e-5)
    coast = friction_arms(h, np.arange(4096) * (2 * math.pi / z1 / 4096), "coast")
    assert float(np.mean(coast[:, 0] - coast[:, 1] / u)) / lam1 == pytest.approx(got, rel=1e-4)

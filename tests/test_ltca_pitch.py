"""Pitch deviations in the loaded TCA (gearbox.ltca.pitch): the pair weights against
finite differences of the contact solve, the textbook base-pitch relation on a spur
pair, the linear method against the exact re-solve, and the hunting record's spectrum."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from _drive import default_drive

from gearbox.errors import InputError
from gearbox.ltca import LTCAOptions, ParallelPair, compliance_for, ltca_cycle
from gearbox.ltca.parallel import parallel_grid
from gearbox.ltca.pitch import (
    HuntingRecord,
    PitchDeviations,
    exact_rotation,
    hunting_lte,
    pair_angles,
)
from gearbox.ltca.solver import pair_sensitivities, rotation_sensitivity, solve_contact

ROOT = Path(__file__).resolve().parents[1]
P = 12  # positions per mesh cycle: enough to cross every pair's entry and exit


@pytest.fixture(scope="module")
def drive():
    """The default scene's drive flank: design, grids, compliance, loaded TCA."""
    return default_drive(P)[1:]


def _random_deviations(design, scale, seed=1):
    """Cumulative deviations from uniform single pitch deviations within +-scale."""
    rng = np.random.default_rng(seed)
    out = []
    for g in (design.pinion, design.gear):
        f = rng.uniform(-scale, scale, g.teeth)
        out.append(np.cumsum(f - f.mean()))
    r = (design.pinion.reference_pitch_radius, design.gear.reference_pitch_radius)
    return PitchDeviations(out[0], out[1], *r)


def test_pair_weights_are_the_derivative_of_the_contact_solve(drive):
    """Each pair weight against a central difference of the full contact solve (loaded
    set free, contact flattening iterated), offsets of +-1e-8 m: within 2e-5, the
    difference's own error at this step (measured 1e-6)."""
    _, grids, comp, res = drive
    for j in (0, 4, 8):
        g = grids[j]
        for t, torque in enumerate(res.torque):
            sol = solve_contact(g, comp, torque)
            d = rotation_sensitivity(g, comp, sol)
            h = 1e-8 / float(np.mean(g.arm))
            for kk, k in enumerate(res.pair_index):
                on = g.pair == k
                if not on.any():
                    continue
                rot = []
                for sign in (1.0, -1.0):
                    s = g.separation - np.where(on, g.arm * sign * h, 0.0)
                    gg = dataclasses.replace(g, separation=s)
                    rot.append(solve_contact(gg, comp, torque, initial_load=sol.load).rotation)
                fd = -(rot[0] - rot[1]) / (2 * h)
                w = float(g.arm[on] @ d[on])
                assert w == pytest.approx(fd, abs=2e-5)
                assert res.pair_weight[t, j, kk] == pytest.approx(w, abs=1e-8)  # warm start
    np.testing.assert_allclose(res.pair_weight.sum(axis=2), 1.0, atol=1e-12)


def test_pair_load_sensitivities_are_the_derivative_of_the_contact_solve(drive):
    """Each pair's normal load per unit offset angle of each pair against a central
    difference of the full contact solve (offsets +-1e-8 m): within 1e-4 of the largest
    entry (measured 3e-5); symmetric (reciprocity of the compliance) and free of
    torque: m^T dF = 0."""
    _, grids, comp, res = drive
    ks = res.pair_index
    for j in (0, 4, 8):
        g = grids[j]
        sol = solve_contact(g, comp, 802.0)
        w, S = pair_sensitivities(g, comp, sol, ks)
        np.testing.assert_allclose(S, S.T, atol=1e-9 * np.abs(S).max())
        h = 1e-8 / float(np.mean(g.arm))
        for kk, k in enumerate(ks):
            on = g.pair == k
            if not on.any():
                continue
            loads = []
            for sign in (1.0, -1.0):
                gg = dataclasses.replace(
                    g, separation=g.separation - np.where(on, g.arm * sign * h, 0.0)
                )
                s2 = solve_contact(gg, comp, 802.0, initial_load=sol.load)
                loads.append(np.array([s2.load[g.pair == q].sum() for q in ks]))
                assert float(g.arm @ (s2.load - sol.load)) == pytest.approx(0.0, abs=1e-6 * 802)
            fd = (loads[0] - loads[1]) / (2 * h)
            assert np.abs(fd - S[:, kk]).max() < 1e-4 * np.abs(S).max()


def test_a_rigid_turn_moves_the_te_by_its_arc(drive):
    """Every pinion tooth 5 um proud (the pinion turned ahead by 5 um / r_1): the loads
    stay, the rotation drops by the angle. Linear: exact (the weights sum to 1); the
    exact re-solve: within 1e-6 of the shift."""
    design, grids, comp, res = drive
    z1, z2 = design.pinion.teeth, design.gear.teeth
    r1, r2 = design.pinion.reference_pitch_radius, design.gear.reference_pitch_radius
    dev = PitchDeviations(np.full(z1, 5e-6), np.zeros(z2), r1, r2)
    lin = hunting_lte(res, dev, 802.0, teeth=(z1, z2))
    arm = 802.0 / res.normal_load[1]
    shift = np.tile(-arm * 5e-6 / r1, dev.hunting_cycles)
    np.testing.assert_allclose(lin.lte - lin.lte_nominal, shift, rtol=1e-12, atol=0)
    # the loads stay: every tooth's largest load is the nominal teeth's
    F0 = lin.tooth_load_nominal
    for teeth in lin.tooth_loads():
        np.testing.assert_allclose(teeth, F0, rtol=1e-9)
    alpha = pair_angles(dev, res.pair_index, [0, 7])
    for j in (0, 5):
        rot, arm_j = exact_rotation(grids[j], comp, 802.0, alpha, res.pair_index)
        sol = solve_contact(grids[j], comp, 802.0)
        assert np.all(np.abs(sol.rotation - rot - 5e-6 / r1) < 1e-6 * 5e-6 / r1)


def test_spur_single_pair_zone_takes_the_base_pitch_deviation():
    """Spur pair z 20/40 (contact ratio 1.6): in the single-pair zone one pair carries
    the load, its weight is 1, and the TE moves by the pair's pitch deviations on the
    base circle, (F_p1 + F_p2) cos(alpha_t) (ISO 1328: f_pb = f_pt cos alpha_t), to
    1e-9 relative; in the two-pair zone by a weighted mean of the two pairs'."""
    pair = ParallelPair(
        normal_module=4e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=0.0,
        teeth=(20, 40),
        face_width=0.03,
    )
    n = 16
    comp = compliance_for("fast")
    res = ltca_cycle(
        lambda f: parallel_grid(pair, f, 10),
        [500.0],
        options=LTCAOptions(positions=n),
        compliance=comp,
    )
    assert 1.5 < pair.transverse_contact_ratio < 1.7
    rng = np.random.default_rng(3)
    e1, e2 = rng.uniform(-8e-6, 8e-6, 20), rng.uniform(-8e-6, 8e-6, 40)
    dev = PitchDeviations(e1, e2, pair.pitch_radius(0), pair.pitch_radius(1))
    rec = hunting_lte(res, dev, 500.0, teeth=(20, 40))
    d = (rec.lte - rec.lte_nominal).reshape(-1, n)
    k0 = int(np.flatnonzero(res.pair_index == 0)[0])
    single = np.flatnonzero(np.isclose(res.pair_weight[0, :, k0], 1.0, atol=1e-12))
    assert single.size >= 3  # 0.4 of a cycle at 16 positions
    cos_at = math.cos(pair.transverse_pressure_angle)
    c = np.arange(dev.hunting_cycles)
    want = -(e1[c % 20] + e2[c % 40]) * cos_at
    for j in single:
        np.testing.assert_allclose(d[:, j], want, rtol=1e-9, atol=1e-15)
        # one pair carries the whole load whatever the deviations (T / r_b1)
        loads = rec.pair_load.reshape(-1, n, res.pair_index.size)[:, j, k0]
        np.testing.assert_allclose(loads, 500.0 / pair.base_radius(0), rtol=1e-9)
    for j in np.setdiff1d(np.arange(n), single):  # between the loaded pairs' values
        ks = res.pair_index[res.pair_weight[0, j] > 0]
        v = np.stack([-(e1[(c - k) % 20] + e2[(c - k) % 40]) * cos_at for k in ks])
        assert np.all(d[:, j] >= v.min(axis=0) - 1e-15)
        assert np.all(d[:, j] <= v.max(axis=0) + 1e-15)


def test_linear_method_against_the_exact_re_solve(drive):
    """Random single pitch deviations within +-0.5 / +-1 / +-2 um on both members, 802 N m,
    every 29th mesh cycle of the hunting period: the linear method's largest error
    against the exact re-solve stays below 2.5 % of the largest TE change at 1 um
    (measured 1.2 % on 24 positions) and falls faster than the deviations (second
    order: the loaded set's changes)."""
    design, grids, comp, res = drive
    errs = []
    for scale in (0.5e-6, 1e-6, 2e-6):
        dev = _random_deviations(design, scale)
        z = (design.pinion.teeth, design.gear.teeth)
        lin = hunting_lte(res, dev, 802.0, teeth=z)
        cyc = np.arange(0, dev.hunting_cycles, 29)
        alpha = pair_angles(dev, res.pair_index, cyc)
        ex = np.column_stack(
            [np.prod(exact_rotation(g, comp, 802.0, alpha, res.pair_index), axis=0) for g in grids]
        )
        nom = lin.lte_nominal.reshape(-1, P)[cyc]
        dl, de = lin.lte.reshape(-1, P)[cyc] - nom, ex - nom
        errs.append((float(np.abs(dl - de).max()), float(np.abs(de).max())))
    assert errs[1][0] < 0.025 * errs[1][1]
    assert errs[1][0] / errs[0][0] > 2.5 and errs[2][0] / errs[1][0] > 2.5


@pytest.mark.slow
def test_tooth_loads_and_root_stress_linear_against_exact(drive):
    """Random single pitch deviations within +-1 um, 802 N m, the whole hunting period
    at 12 positions: the teeth's largest loads (measured 7831 N nominal, 8126 N exact)
    within 0.25 % of the exact re-solve's tooth by tooth (measured 14.0 N, 0.18 %), the
    largest root stresses within 1 % (measured +3.5 / +3.2 % over the nominal teeth's;
    the linear method's scaled nominal stresses 0.55 / 0.53 % above the exact method's,
    which come from each sample's own loads). (With the edge points on the last
    profile samples: 8694 / 8914 N, 6.2 N apart, root stresses 0.26 % above.)"""
    design, grids, comp, res = drive
    dev = _random_deviations(design, 1e-6)
    z = (design.pinion.teeth, design.gear.teeth)
    lin = hunting_lte(res, dev, 802.0, teeth=z)
    ex = hunting_lte(res, dev, 802.0, teeth=z, method="exact", grids=grids, compliance=comp)
    assert lin.tooth_load_nominal == pytest.approx(ex.tooth_load_nominal, rel=1e-6)
    for a, b in zip(lin.tooth_loads(), ex.tooth_loads(), strict=True):
        np.testing.assert_allclose(a, b, rtol=2.5e-3)
    assert np.max(ex.tooth_loads()[0]) > 1.01 * ex.tooth_load_nominal
    for a, b, c in zip(lin.root_stress(), ex.root_stress(), ex.root_stress_nominal(), strict=True):
        assert a == pytest.approx(b, rel=1e-2) and b > 1.01 * c


def test_order_spectrum_of_a_hunting_record():
    """A record of known sines at pinion order 2 and gear order 3 (pinion order
    3 z1 / z2) over a hunting period: amplitudes exact to 1e-9 at their bins, nothing
    elsewhere (the record is one period)."""
    z1, z2, n = 29, 45, 8
    H = z1 * z2
    theta = np.arange(H * n) * 2 * math.pi / (z1 * n)
    x = 3e-6 * np.sin(2 * theta + 0.3) + 1e-6 * np.cos(3 * z1 / z2 * theta) + 2e-6
    rec = HuntingRecord(theta, x, np.zeros_like(x), 500.0, (z1, z2), H, "linear")
    orders, amp = rec.order_spectrum()
    assert rec.pinion_revolutions == z2
    for order, a in ((2.0, 3e-6), (3 * z1 / z2, 1e-6), (0.0, 2e-6)):
        i = int(np.argmin(np.abs(orders - order)))
        assert orders[i] == pytest.approx(order, abs=1e-12)
        assert amp[i] == pytest.approx(a, rel=1e-9)
    others = np.ones(amp.size, bool)
    others[[0, 2 * z2, 3 * z1]] = False
    assert amp[others].max() < 1e-18


def test_bad_deviations_name_the_parameter(drive):
    design, _, _, res = drive
    r = (design.pinion.reference_pitch_radius, design.gear.reference_pitch_radius)
    with pytest.raises(InputError, match=r"pinion\[3\]"):
        PitchDeviations(np.r_[np.zeros(3), 2e-3, np.zeros(25)], np.zeros(45), *r)
    with pytest.raises(InputError, match="pinion_single"):
        PitchDeviations.from_single(np.ones(29) * 1e-6, np.zeros(45), *r)
    dev = PitchDeviations(np.zeros(30), np.zeros(45), *r)
    with pytest.raises(InputError, match="deviations"):
        hunting_lte(res, dev, 802.0, teeth=(29, 45))
    dev = PitchDeviations(np.zeros(29), np.zeros(45), *r)
    with pytest.raises(InputError, match="torque"):
        hunting_lte(res, dev, 1000.0, teeth=(29, 45))

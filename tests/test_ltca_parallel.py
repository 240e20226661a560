"""Loaded TCA of parallel-axis spur and helical pairs: closed forms, ISO 6336-1,
grid convergence, bad input."""

import math
from dataclasses import dataclass, replace

import numpy as np
import pytest
from _benchmarks import benchmark

from gearbox.errors import InputError
from gearbox.ltca import (
    FastCompliance,
    LTCAOptions,
    ParallelPair,
    ltca_cycle,
    parallel_grid,
    solve_contact,
)
from gearbox.ltca.compliance import CALIBRATED_BEAM, _pasternak_block

SPUR = ParallelPair(
    normal_module=0.004,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(30, 45),
    face_width=0.03,
)
HELICAL = replace(SPUR, helix_angle=math.radians(15))


@dataclass(frozen=True)
class UniformSlices:
    """Test double: independent slices of constant compliance c (m per N/m)."""

    c: float = 5e-11
    name: str = "uniform"
    load_dependent: bool = False

    def tooth_matrix(self, grid):
        return np.diag(self.c / grid.width)

    def matrix(self, grid, line_load=None):
        return self.tooth_matrix(grid)


def _cycle(pair, torques=(400.0,), positions=24, n_face=20, compliance=None):
    return ltca_cycle(
        lambda f: parallel_grid(pair, f, n_face),
        list(torques),
        options=LTCAOptions(positions=positions),
        compliance=compliance,
    )


def test_uniform_slices_give_the_closed_form_stiffness():
    # n pairs of line contacts of length b and compliance c per unit length:
    # k = n b / c exactly; the double-contact share of the cycle is eps_alpha - 1
    c = 5e-11
    r = _cycle(SPUR, positions=48, compliance=UniformSlices(c))
    npairs = (r.pair_share[0] > 0).sum(axis=1)
    assert np.allclose(r.stiffness[0], npairs * SPUR.face_width / c, rtol=1e-10)
    # linear compliance, unchanged active set: tangent = secant
    assert np.allclose(r.tangent_stiffness[0], r.stiffness[0], rtol=1e-8)
    # geometry: fraction of positions with two pairs, within one position step
    assert abs(np.mean(npairs == 2) - (SPUR.transverse_contact_ratio - 1)) <= 1 / 48


@pytest.mark.parametrize("pair", [SPUR, HELICAL], ids=["spur", "helical"])
def test_equilibrium_and_secant_times_lte_is_the_normal_load(pair):
    r = _cycle(pair, torques=(200.0, 400.0))
    arm = pair.base_radius(0) * math.cos(pair.base_helix_angle)
    for t, tq in enumerate(r.torque):
        # the normal load balances the torque on the involute arm r_b1 cos(beta_b)
        assert np.allclose(r.normal_load[t] * arm, tq, rtol=1e-10)
        elastic = r.lte[t] - r.lte_unloaded
        assert np.allclose(r.stiffness[t] * elastic, r.normal_load[t], rtol=1e-12)
    assert r.success
    assert np.all(r.gap_residual < 1e-12)


def test_contact_flattening_stiffens_with_load():
    # Weber's approach grows like q ln(1/sqrt(q)): the tangent stiffness exceeds
    # the secant one and the secant stiffness grows with the torque
    r = _cycle(HELICAL, torques=(100.0, 400.0))
    assert np.all(r.tangent_stiffness >= r.stiffness * (1 - 1e-9))
    assert r.stiffness[1].mean() > r.stiffness[0].mean()


def _iso_ratio(pair, torque):
    """benchmarks/ltca_ripple.py's mean stiffness over ISO 6336-1's c_gamma_alpha (the
    transverse convention), with the cycle result."""
    return benchmark("ltca_ripple").iso_ratio(pair, torque)


def test_mean_mesh_stiffness_against_iso_6336_1_spur():
    ratio, r = _iso_ratio(SPUR, 400.0)
    # measured: 0.875 with the default (plane-strain tooth, far field shared, the
    # plane-strain whole gear between pairs; 0.894 with the even share), which is 2.4 %
    # below the whole-gear FE level on this pair; the whole-gear FE level lies 9 % below
    # ISO's c_gamma_alpha (docs/fe.md). CALIBRATED_BEAM gave 0.734 (0.745 with the
    # torsion in the slices). The band guards that statement.
    assert 0.86 < ratio < 0.89, f"fast / ISO 6336-1 c_gamma_alpha = {ratio:.3f}"
    # shape: ISO's c_gamma_alpha = c' (0.75 eps_alpha + 0.25) relates the cycle mean
    # to the single-pair maximum c'; the slices alone (torsion in the slices, no body
    # term) agree within 3 % (measured 1.503 against ISO's 1.521). The compliances in
    # series common to all pairs flatten it: 1.438 with the body torsion shared, 1.421
    # with the body term as well
    slices = FastCompliance(body_compliance=0.0, shared_torsion=False, foundation="normal")
    r_s = _cycle(SPUR, compliance=slices, n_face=20)
    npairs = (r_s.pair_share[0] > 0).sum(axis=1)
    single_max = r_s.stiffness[0][npairs == 1].max()
    iso_shape = 0.75 * SPUR.transverse_contact_ratio + 0.25
    assert r_s.stiffness[0].mean() / single_max == pytest.approx(iso_shape, rel=0.03)
    # a body term (CALIBRATED_BEAM's): the series compliance of the same size at every
    # position
    r1 = _cycle(SPUR, compliance=CALIBRATED_BEAM, n_face=20)
    r0 = _cycle(SPUR, compliance=replace(CALIBRATED_BEAM, body_compliance=0.0), n_face=20)
    cb = 1.0 / r1.stiffness[0] - 1.0 / r0.stiffness[0]
    assert np.ptp(cb) < 0.02 * cb.mean()


def test_mean_mesh_stiffness_against_iso_6336_1_helical():
    ratio, _ = _iso_ratio(HELICAL, 400.0)
    # measured: 0.866 for this helical pair with the default (+0.2 % against the
    # whole-gear FE level; 0.888 and +2.8 % with the even share between pairs, 0.904
    # and +4.6 % with the earlier growth cos(beta)^-4.5 of the far field);
    # CALIBRATED_BEAM 0.796 (0.807 with the torsion in the slices
    # and the earlier body term, 0.864 without the body term, 0.920 with transverse
    # slices; docs/ltca.md)
    assert 0.85 < ratio < 0.88, f"fast / ISO 6336-1 c_gamma_alpha = {ratio:.3f}"


def test_integer_overlap_ratio_flattens_the_stiffness():
    # with eps_beta = 1 the total contact-line length is constant over the cycle
    # (ISO 21771), so only the compliance along the profile varies: the relative
    # peak-to-peak stiffness falls well below that of eps_beta = 0.5
    def rel_p2p(eps_beta):
        beta = math.asin(eps_beta * math.pi * SPUR.normal_module / SPUR.face_width)
        r = _cycle(replace(SPUR, helix_angle=beta), n_face=40)
        k = r.stiffness[0]
        return (k.max() - k.min()) / k.mean()

    assert rel_p2p(1.0) < 0.5 * rel_p2p(0.5)


def test_grid_convergence_of_the_contact_solution():
    # face slices 10 / 20 / 40 / 80: the mean stiffness settles; the change from
    # 40 to 80 slices is below 0.5 % and below the change from 10 to 20
    means = [_cycle(HELICAL, n_face=n, positions=8).stiffness[0].mean() for n in (10, 20, 40, 80)]
    d1 = abs(means[1] - means[0]) / means[3]
    d3 = abs(means[3] - means[2]) / means[3]
    assert d3 < 5e-3
    assert d3 < d1
    # the load distribution converges too: peak slice line load within 3 %
    peaks = []
    for n in (40, 80):
        g = parallel_grid(HELICAL, 0.3, n)
        s = solve_contact(g, FastCompliance(), 400.0)
        peaks.append(float(np.max(s.load / g.line_length)))
    assert peaks[0] == pytest.approx(peaks[1], rel=0.03)


def test_shear_layer_coupling_is_the_exponential_influence_function():
    # a point load in the middle of a long uniform tooth: deflections decay like
    # exp(-|y| / lambda) (Pasternak foundation Green's function)
    m, width, c, lam = 401, 1e-4, 5e-11, 4e-3
    C = _pasternak_block(np.full(m, c), width, lam)
    col = C[:, m // 2]
    y = (np.arange(m) - m // 2) * width
    sel = np.abs(y) < 3 * lam
    expected = col[m // 2] * np.exp(-np.abs(y[sel]) / lam)
    # discretisation h / lambda = 0.025: 1 % of the peak
    assert np.max(np.abs(col[sel] - expected)) < 0.01 * col[m // 2]
    # a uniform line load gives the uncoupled slice deflection everywhere
    w = C @ np.full(m, 1000.0 * width)
    assert np.allclose(w, c * 1000.0, rtol=1e-9)


def test_bad_input_is_refused_or_flagged():
    with pytest.raises(InputError, match="positions"):
        LTCAOptions(positions=3)
    with pytest.raises(InputError, match="torques"):
        _cycle(SPUR, torques=(0.0,))
    with pytest.raises(InputError, match="torque"):
        solve_contact(parallel_grid(SPUR, 0.1, 10), FastCompliance(), -5.0)
    # a grid whose load points leave the flank (above the tip) is refused by name
    g = parallel_grid(SPUR, 0.1, 10)
    t1 = replace(g.tooth1, radius=g.tooth1.radius + 0.01)
    with pytest.raises(InputError, match="leaves the flank"):
        replace(g, tooth1=t1)
    # a grid that does not reach the active flank at all
    with pytest.raises(InputError, match="empty"):
        g.take(np.arange(0))
    # loads on points where the grid cannot see the true contact are flagged
    r = _cycle(SPUR)
    assert not r.edge_contact[0]

    def edged(f):
        g = parallel_grid(SPUR, f, 10)
        return replace(g, edge=g.pair == g.pair.max())

    r = ltca_cycle(edged, [400.0], options=LTCAOptions(positions=6))
    assert r.edge_contact[0] and r.edge_load_fraction.max() > 0.3


def test_slice_compliance_physics():
    # a load nearer the tip bends the tooth more; all parts scale with 1/E except
    # shear (1/G, same ratio at fixed nu); the fillet-foundation part is positive
    from gearbox.ltca.slice_model import slice_compliance

    g = parallel_grid(SPUR, 0.0, 10)
    xi = np.linspace(0.2, 0.8, 7)
    teeth = replace(
        g.tooth1,
        **{f: getattr(g.tooth1, f)[:1].repeat(7) for f in g.tooth1.__dataclass_fields__},
    )
    rb, ra = float(teeth.base_radius[0]), float(teeth.tip_radius[0])
    radii = np.sqrt(rb**2 + (xi * np.sqrt(ra**2 - rb**2)) ** 2)
    teeth = replace(teeth, radius=radii)
    c = slice_compliance(teeth, 206e9, 0.3)
    assert np.all(np.diff(c.total) > 0)
    assert np.all(np.diff(c[0]) > 0)  # bending
    assert np.all(c[3] > 0)
    c2 = slice_compliance(teeth, 2 * 206e9, 0.3)
    assert np.allclose(c2.total, 0.5 * c.total, rtol=1e-12)


def test_line_contact_sweeps_the_whole_active_flank():
    # perfect involute line contact: over a mesh cycle the loaded lines of all pairs
    # cover the active flank (pattern raster 40 x 40: one cell row of tolerance)
    r = _cycle(HELICAL, n_face=20)
    assert r.pattern_area_fraction[0] > 0.97


def test_spur_root_stress_is_iso_6336_3_nominal_stress_at_the_hpstc():
    # ISO 6336-3 method B: sigma_F0 = F_t / (b m_n) Y_F Y_S with the load at the outer
    # point of single pair contact, ISO's d_en: pinion roll distance
    # xi_tip - p_bt (eps_alpha - 1) = xi_A + p_bt along the path of contact. With the
    # whole load on one pair there, the largest slice root stress of
    # the pinion over the cycle is that stress; 96 positions put a position within
    # 1/96 of a base pitch of the point: 1 % tolerance
    from gearbox.ltca import iso_root_section

    T = 400.0
    r = _cycle(SPUR, torques=(T,), positions=96, n_face=10)
    rb1 = SPUR.base_radius(0)
    xa, xe = SPUR.roll_limits
    eps = SPUR.transverse_contact_ratio
    d_en = 2 * math.sqrt(rb1**2 + (xe - SPUR.base_pitch * (eps - 1)) ** 2)
    sec = iso_root_section(
        zn=SPUR.teeth[0],
        normal_module=SPUR.normal_module,
        normal_pressure_angle=SPUR.normal_pressure_angle,
        profile_shift=0.0,
        rack_dedendum=SPUR.dedendum_coefficient,
        rack_root_radius=SPUR.root_radius_coefficient,
        load_diameter=d_en,
    )
    Ft = T / SPUR.pitch_radius(0)
    sigma_iso = Ft / (SPUR.face_width * SPUR.normal_module) * float(sec.Y_F * sec.Y_S)
    assert r.root_stress_pinion[0].max() == pytest.approx(sigma_iso, rel=0.01)


def test_cycle_result_round_trips_through_a_dict():
    import json

    from gearbox.ltca import CycleResult

    r = _cycle(SPUR, positions=4, n_face=6)
    back = CycleResult.from_dict(json.loads(json.dumps(r.to_dict())))
    for name in ("stiffness", "lte", "pair_share", "pattern_pressure", "converged", "iterations"):
        a, b = getattr(r, name), getattr(back, name)
        assert a.dtype == b.dtype and np.array_equal(a, b), name
    assert back.profile_range == r.profile_range and back.meta == r.meta


def test_grid_take_indexes_every_per_point_field_and_keeps_the_axes():
    """ContactGrid.take: every field with one entry per point is indexed (PER_POINT
    names them; a new per-point field left out of it would fail here), the grid-wide
    fields, the axes among them, are kept."""
    import dataclasses

    from gearbox.ltca.grid import ContactGrid, ToothSections

    g = parallel_grid(HELICAL, 0.3)
    n = g.size
    for f in dataclasses.fields(g):
        v = getattr(g, f.name)
        per_point = isinstance(v, ToothSections) or (
            isinstance(v, np.ndarray)
            and v.shape[:1] == (n,)
            and f.name not in ("pinion_axis", "gear_axis")
        )
        assert per_point == (f.name in ContactGrid.PER_POINT), f.name
    keep = np.flatnonzero(g.pair == g.pair.min())
    part = g.take(keep)
    assert part.size == keep.size
    np.testing.assert_array_equal(part.position, g.position[keep])
    np.testing.assert_array_equal(part.tooth2.radius, g.tooth2.radius[keep])
    np.testing.assert_array_equal(part.pinion_axis, g.pinion_axis)
    np.testing.assert_array_equal(part.sliding_velocity(), g.sliding_velocity()[keep])

"""Tier (a): exact limits of the beveloid design.

- shaft angle 0 and cone angles 0: a parallel helical (or spur) pair, which must
  reduce to ISO 21771 (working transverse pressure angle from the profile-shift sum,
  centre distance);
- cone angles 0 with a shaft angle: a crossed helical pair (r_w1 + r_w2 = E,
  beta_w1 + beta_w2 = delta);
- no NaN, no warning and no loss of digits approaching either limit.

Worked examples:
- helical: z = 31 / 30, m_n = 3.5 mm, alpha_n = 20 deg, reference centre distance
  114.3447280708 mm (so beta = 21 deg), working centre distance 116.5 mm:
  alpha_wt = 23.8707609654 deg, sum of profile shifts 0.6518771312 (ISO 21771:2007
  eq. (62), as evaluated in the published calculation sheet "Gear Generating Profile
  Shift Calculations"). Printed to 10 digits: tolerance 1e-9.
- spur: m = 3 mm, alpha = 20 deg, z = 12 / 24, a_w = 56.5 mm: x_1 + x_2 = 0.960,
  alpha_w = 26.0888 deg (bolsover.com, "Profile Shifted External Spur Gears", table
  rows 6 and 10). Printed to 3 and 4 decimals: tolerances 5e-4 and 5e-5 deg.
"""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

from gearbox.geometry import GearSpec, PairSpec, design_pair, inv
from gearbox.geometry.design import solve_pair_arrays

D = math.radians


def helical_pair(z1, z2, m_n, alpha_deg, beta_deg, a_w, x_n1, delta_deg=0.0, gamma=(0.0, 0.0)):
    beta = D(beta_deg)
    return PairSpec(
        normal_module=m_n * 1e-3,
        normal_pressure_angle=D(alpha_deg),
        shaft_angle=D(delta_deg),
        offset=a_w * 1e-3,
        pinion=GearSpec(z1, beta, D(gamma[0]), x_n1 * math.cos(beta) / math.cos(D(gamma[0]))),
        gear=GearSpec(z2, None, D(gamma[1]), None),
    )


def test_iso21771_helical_worked_example():
    beta_deg = math.degrees(math.acos(3.5 * 61 / (2 * 114.3447280708)))
    d = design_pair(helical_pair(31, 30, 3.5, 20.0, beta_deg, 116.5, 0.291), with_checks=False)
    for g in d.gears:
        for a in g.working_transverse_pressure_angle:
            assert abs(math.degrees(a) - 23.8707609654) < 1e-9
        for a in g.transverse_pressure_angle:
            assert abs(math.degrees(a) - 21.2990642859) < 1e-9
    assert abs(d.pinion.normal_profile_shift + d.gear.normal_profile_shift - 0.6518771312) < 1e-9
    assert abs(d.gear.helix_angle + d.pinion.helix_angle) < 1e-14  # opposite hands
    assert abs(d.pinion.working_pitch_radius + d.gear.working_pitch_radius - 0.1165) < 1e-15
    assert d.fpd_angle_right == pytest.approx(0.0, abs=1e-15)
    assert d.fpd_angle_left == pytest.approx(0.0, abs=1e-15)


def test_spur_worked_example():
    d = design_pair(helical_pair(12, 24, 3.0, 20.0, 0.0, 56.5, 0.6), with_checks=False)
    assert abs(d.pinion.normal_profile_shift + d.gear.normal_profile_shift - 0.960) < 5e-4
    assert abs(math.degrees(d.pinion.working_transverse_pressure_angle[0]) - 26.0888) < 5e-5
    assert d.pinion.working_pitch_radius * 2e3 == pytest.approx(37.667, abs=5e-4)


def test_a_spur_pair_takes_its_own_total_contact_aim():
    """A spur pair's eps_gamma is its transverse contact ratio (no overlap), so the
    default aim of 2 always fails; pair.min_total_contact_ratio sets the aim, and a
    value outside [1, 4] is named."""
    from dataclasses import replace

    from gearbox.errors import InputError

    # z 30/60, m 3, standard centre distance 135 mm: eps_alpha about 1.7
    spec = helical_pair(30, 60, 3.0, 20.0, 0.0, 135.0, 0.0)
    d = design_pair(spec)
    chk = d.checks["total_contact_ratio_right"]
    eps = d.checks["transverse_contact_ratio_right"].margin + 1.0
    assert 1.5 < eps < 1.9
    assert not chk.ok and chk.margin == pytest.approx(eps - 2.0, abs=1e-12)
    low = design_pair(replace(spec, min_total_contact_ratio=1.4))
    chk = low.checks["total_contact_ratio_right"]
    assert chk.ok and chk.margin == pytest.approx(eps - 1.4, abs=1e-12)
    assert "pair.min_total_contact_ratio" in chk.detail
    with pytest.raises(InputError, match=r"pair\.min_total_contact_ratio"):
        replace(spec, min_total_contact_ratio=0.5).validate()


def test_parallel_limit_matches_iso_formula_over_many_pairs():
    """ISO 21771: inv a_wt = inv a_t + 2 tan a_n (x1 + x2) / (z1 + z2), cos a_wt = a_0 cos a_t / a."""
    rng = np.random.default_rng(1)
    for _ in range(50):
        z1, z2 = int(rng.integers(12, 60)), int(rng.integers(12, 120))
        beta = rng.uniform(0, 35)
        m_n = rng.uniform(1, 10)
        a0 = m_n * (z1 + z2) / (2 * math.cos(D(beta)))
        a_w = a0 * rng.uniform(0.99, 1.04)
        d = design_pair(helical_pair(z1, z2, m_n, 20.0, beta, a_w, 0.1), with_checks=False)
        a_t = math.atan(math.tan(D(20.0)) / math.cos(D(beta)))
        a_wt = math.acos(a0 * math.cos(a_t) / a_w)
        x_sum = (z1 + z2) * (inv(a_wt) - inv(a_t)) / (2 * math.tan(D(20.0)))
        assert d.pinion.normal_profile_shift + d.gear.normal_profile_shift == pytest.approx(
            x_sum, abs=1e-11
        )
        assert d.gear.working_transverse_pressure_angle[1] == pytest.approx(a_wt, abs=1e-13)


def test_crossed_helical_limit():
    """Cone angles 0: pitch cylinders touch on the common perpendicular."""
    d = design_pair(
        helical_pair(29, 45, 6.0, 20.0, 20.0, 229.0, 0.16, delta_deg=13.0), with_checks=False
    )
    assert d.pinion.working_helix_angle + d.gear.working_helix_angle == pytest.approx(
        D(13.0), abs=1e-14
    )
    assert d.pinion.working_pitch_radius + d.gear.working_pitch_radius == pytest.approx(
        0.229, abs=1e-15
    )
    assert d.pitch_point[1] == 0.0 and d.pitch_point[2] == 0.0
    assert math.isinf(d.pinion.mounting_distance) and math.isinf(d.gear.mounting_distance)
    # crossed helical gears have no common plane of action: the FPD angle is the shaft
    # angle projected into the common rack, xi_R = xi_L = 2 atan(...) > 0, equal flanks
    assert d.fpd_angle_right == pytest.approx(d.fpd_angle_left, abs=1e-15)


@pytest.mark.parametrize("which", ["shaft_and_cones", "cones_only"])
def test_no_nan_no_warning_no_lost_digits_near_the_limits(which):
    """Approach the limit along eps -> 0; the result converges smoothly to the limit."""
    eps = np.logspace(-12, -2, 41)
    if which == "shaft_and_cones":
        delta, g1, g2 = D(13.0) * eps, D(1.0) * eps, D(0.8) * eps
    else:
        delta, g1, g2 = D(13.0) * np.ones_like(eps), D(1.0) * eps, D(0.8) * eps
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        sol = solve_pair_arrays(6e-3, D(20.0), delta, 0.229, 29, 45, D(20.0), g1, g2)
    assert sol["ok"].all()
    for key in ("xi_n", "beta2", "fpd_right", "fpd_left"):
        v = sol[key]
        assert np.all(np.isfinite(v))
        # smooth approach: |v(eps) - v(eps_min)| <= C eps (C = 10 rad or 1 per unit eps is
        # generous for these O(1) quantities), and no noise floor above 1e-12 near eps_min
        err = np.abs(v - v[0])
        assert np.all(err <= 1e-12 + 10 * eps), (key, err.max())
    if which == "cones_only":
        lim = solve_pair_arrays(6e-3, D(20.0), D(13.0), 0.229, 29, 45, D(20.0), 0.0, 0.0)
        for key in ("xi_n", "beta2", "fpd_right", "fpd_left"):
            assert abs(sol[key][0] - float(lim[key])) < 1e-11

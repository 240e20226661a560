"""Tier (a): invariants of the design over random valid inputs (hypothesis)."""

from __future__ import annotations

import math

import numpy as np
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st

from gearbox.errors import InputError
from gearbox.geometry import GearSpec, PairSpec, design_pair
from gearbox.geometry.design import solve_pair_arrays

D = math.radians


@st.composite
def pair_specs(draw):
    m_n = draw(st.floats(1.0, 12.0)) * 1e-3
    a_n = D(draw(st.floats(14.0, 25.0)))
    delta = D(draw(st.floats(0.5, 30.0)))
    z1, z2 = draw(st.integers(12, 60)), draw(st.integers(12, 120))
    beta1 = D(draw(st.floats(5.0, 35.0)))
    g1 = D(draw(st.floats(0.0, 3.0)))
    g2 = D(draw(st.floats(0.0, 3.0)))
    xt1 = draw(st.floats(-0.3, 0.6))
    # an offset near the sum of the reference pitch radii (the design exists there)
    a0 = m_n * (z1 / math.cos(beta1) + z2 / math.cos(delta - beta1)) / 2
    E = a0 * draw(st.floats(0.995, 1.03))
    return PairSpec(m_n, a_n, delta, E, GearSpec(z1, beta1, g1, xt1), GearSpec(z2, None, g2, None))


SETTINGS = settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.too_slow])


@SETTINGS
@given(pair_specs())
def test_design_invariants(spec):
    try:
        d = design_pair(spec, with_checks=False)
    except InputError:
        assume(False)
    # eq. (15): xi_n = cos a_nw / cos a_n and m_n / m_nw
    assert math.isclose(
        d.normal_angular_factor,
        math.cos(d.working_normal_pressure_angle) / math.cos(spec.normal_pressure_angle),
        rel_tol=1e-13,
    )
    # eq. (1): FPD angles are the sums of the parts; eqs (8), (9): xi_L - xi_R depends on the cones only
    for j, total in ((0, d.fpd_angle_right), (1, d.fpd_angle_left)):
        assert math.isclose(d.pinion.fpd_part[j] + d.gear.fpd_part[j], total, abs_tol=1e-14)
    if spec.pinion.cone_angle == 0 and spec.gear.cone_angle == 0:  # equal flanks exactly
        assert math.isclose(d.fpd_angle_right, d.fpd_angle_left, abs_tol=1e-14)
    else:
        assert d.fpd_angle_left >= d.fpd_angle_right
    # base radii and normal base pitch are conserved (eqs (11), (12))
    for g in d.gears:
        for j in range(2):
            assert math.isclose(
                g.working_pitch_radius * math.cos(g.working_transverse_pressure_angle[j]),
                g.base_radius[j],
                rel_tol=1e-12,
            )
    # the gear's solved helix angle regenerates the same working helix (inverse of eqs (13)-(15))
    sol = solve_pair_arrays(
        spec.normal_module,
        spec.normal_pressure_angle,
        spec.shaft_angle,
        spec.offset,
        spec.pinion.teeth,
        spec.gear.teeth,
        spec.pinion.helix_angle,
        spec.pinion.cone_angle,
        spec.gear.cone_angle,
    )
    assert np.isclose(float(sol["beta2"]), d.gear.helix_angle, atol=1e-14)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(pair_specs(), st.floats(0.9, 1.1))
def test_offset_scales_with_module(spec, k):
    """The design is scale-free: scaling module and offset together keeps every angle."""
    try:
        d1 = design_pair(spec, with_checks=False)
    except InputError:
        assume(False)
    from dataclasses import replace

    d2 = design_pair(
        replace(spec, normal_module=spec.normal_module * k, offset=spec.offset * k),
        with_checks=False,
    )
    assert math.isclose(d1.normal_angular_factor, d2.normal_angular_factor, rel_tol=1e-12)
    assert math.isclose(d1.fpd_angle_right, d2.fpd_angle_right, abs_tol=1e-12)
    assert math.isclose(
        d2.gear.working_pitch_radius, k * d1.gear.working_pitch_radius, rel_tol=1e-12
    )


def test_vectorised_solve_equals_scalar_designs():
    """A batched solve gives the same numbers as one design at a time."""
    g1 = np.linspace(0.0, D(3.0), 25)
    sol = solve_pair_arrays(6e-3, D(20.0), D(13.0), 0.229, 29, 45, D(20.0), g1, D(0.8))
    for i in (0, 7, 24):
        d = design_pair(
            PairSpec(
                6e-3,
                D(20.0),
                D(13.0),
                0.229,
                GearSpec(29, D(20.0), g1[i], 0.16),
                GearSpec(45, None, D(0.8), None),
            ),
            with_checks=False,
        )
        assert sol["xi_n"][i] == d.normal_angular_factor
        assert sol["fpd_right"][i] == d.fpd_angle_right

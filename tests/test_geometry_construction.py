"""Independent checks of the printed equations by 3-D construction.

The working pitch cones of both gears must touch one plane (the common rack's pitch
plane) at one point P. Built here with plain vector algebra (least squares, no formula
from gearbox.geometry.design): unit normal m with m.a1 = -sin g_w1, m.a2 = sin g_w2,
pinion cone radius r_w1 at P, gear cone radius r_w2 at P. The construction closes
(eq. (19)), the angle between the cone generators in the plane is beta_w1 + beta_w2
(eq. (18)), and the apex positions give the mounting distances: the corrected
eqs (16), (17) agree, the printed ones do not.

Also: the backlash-free condition eq. (20) against tooth thicknesses: the normal tooth
thicknesses at the working pitch cylinders, computed flank by flank from the
involutes, add up to the working normal pitch pi m_nw.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair, inv

MODELS = Path(__file__).parents[1] / "models"
CASES = ["01", "02", "03", "04"]


def construct(d):
    delta, E = d.shaft_angle, d.offset
    a1 = np.array([0.0, 0.0, 1.0])
    a2 = np.array([0.0, math.sin(delta), math.cos(delta)])
    s1, s2 = math.sin(d.pinion.working_cone_angle), math.sin(d.gear.working_cone_angle)
    c1, c2 = math.cos(d.pinion.working_cone_angle), math.cos(d.gear.working_cone_angle)
    # m: m.a1 = -s1, m.a2 = s2, |m| = 1, m_x > 0: solve the two linear conditions for (m_y, m_z)
    A = np.array([[a1[1], a1[2]], [a2[1], a2[2]]])
    my, mz = np.linalg.solve(A, [-s1, s2])
    m = np.array([math.sqrt(1 - my**2 - mz**2), my, mz])
    e1 = (m + s1 * a1) / c1
    e2 = (-m + s2 * a2) / c2
    rhs = (
        np.array([E, 0, 0]) + d.gear.working_pitch_radius * e2 - d.pinion.working_pitch_radius * e1
    )
    M = np.column_stack([a1, -a2])
    (h1, h2), *_ = np.linalg.lstsq(M, rhs, rcond=None)
    closure = np.linalg.norm(M @ [h1, h2] - rhs)
    g1 = (a1 - (a1 @ m) * m) / np.linalg.norm(a1 - (a1 @ m) * m)
    g2 = (a2 - (a2 @ m) * m) / np.linalg.norm(a2 - (a2 @ m) * m)
    angle = math.acos(np.clip(g1 @ g2, -1, 1))
    apex1 = h1 - d.pinion.working_pitch_radius * c1 / s1
    apex2 = h2 - d.gear.working_pitch_radius * c2 / s2
    P = h1 * a1 + d.pinion.working_pitch_radius * e1
    return dict(closure=closure, angle=angle, d1=-apex1, d2=-apex2, h1=h1, h2=h2, P=P, m=m)


def design(case):
    return design_pair(PairSpec.from_scene(load_scene(MODELS / f"case{case}.toml")))


@pytest.mark.parametrize("case", CASES)
def test_eqs_18_19_close_the_construction(case):
    d = design(case)
    c = construct(d)
    assert c["closure"] < 1e-12  # m; eq. (19) solved to ~1e-16 relative
    assert c["angle"] == pytest.approx(
        d.pinion.working_helix_angle + d.gear.working_helix_angle, abs=1e-12
    )
    assert np.allclose(c["P"], d.pitch_point, atol=1e-12)
    assert np.allclose(c["m"], d.pitch_plane_normal, atol=1e-14)


@pytest.mark.parametrize("case", CASES)
def test_corrected_mounting_distances_match_construction_printed_do_not(case):
    d = design(case)
    c = construct(d)
    # corrected eqs (16), (17) (implemented) vs the construction: rounding only
    assert d.pinion.mounting_distance == pytest.approx(c["d1"], rel=1e-10)
    assert d.gear.mounting_distance == pytest.approx(c["d2"], rel=1e-10)
    # the printed forms put the apex elsewhere by millimetres to tens of millimetres
    sd, cd, E = math.sin(d.shaft_angle), math.cos(d.shaft_angle), d.offset
    s1, s2 = math.sin(d.pinion.working_cone_angle), math.sin(d.gear.working_cone_angle)
    c2 = math.cos(d.gear.working_cone_angle)
    rw2 = d.gear.working_pitch_radius
    rD = math.sqrt(sd**2 - s1**2 - s2**2 - 2 * s1 * s2 * cd)
    d1_printed = -rw2 / (s1 * c2) + E * (sd**2 - s1**2 - s1**2 * cd) / (s1 * sd * rD)
    d2_printed = rw2 / (s2 * c2) - E * (s1 * cd + s2**2) / (sd * rD)
    assert abs(d1_printed - c["d1"]) > 1e-3
    assert abs(d2_printed - c["d2"]) > 1e-3


@pytest.mark.parametrize("case", CASES)
def test_eq20_against_tooth_thicknesses(case):
    d = design(case)
    total = 0.0
    for g in d.gears:
        X = g.profile_shift_xt * g.transverse_module  # radial rack shift at the reference section
        (aR, aL), (wR, wL) = g.transverse_pressure_angle, g.working_transverse_pressure_angle
        psi = math.pi / g.teeth + X * (math.tan(aR) + math.tan(aL)) / g.reference_pitch_radius
        psi += inv(aR) - inv(wR) + inv(aL) - inv(wL)
        total += g.working_pitch_radius * psi * math.cos(g.working_helix_angle)
    assert total == pytest.approx(math.pi * d.working_normal_module, rel=1e-13)


@pytest.mark.parametrize("case", CASES)
def test_base_pitch_conservation(case):
    """Paper eqs (11), (12): working rack and tool give the same base circles and normal base pitch."""
    d = design(case)
    for g in d.gears:
        for j in range(2):
            rb_working = g.working_pitch_radius * math.cos(g.working_transverse_pressure_angle[j])
            assert rb_working == pytest.approx(g.base_radius[j], rel=1e-13)
    assert d.working_normal_module * math.cos(d.working_normal_pressure_angle) == pytest.approx(
        d.normal_module * math.cos(d.normal_pressure_angle), rel=1e-14
    )

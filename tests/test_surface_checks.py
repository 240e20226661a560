"""The design stage's undercut and topping checks, measured on the generated flanks.

gearbox.geometry.checks evaluates closed forms (interference point per flank, tip
thickness from involute functions); here the same quantities come from the surfaces
of simulated generation: the cuspidal edge of the envelope (undercut) and the
transverse arc thickness between the two generated flanks on the tip cone (topping).
"""

import math

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.geometry import PairSpec, design_pair
from gearbox.geometry.checks import TOPPING_MIN_SAN, sections
from gearbox.surface import (
    ToothBlank,
    blanks_from_design,
    flank_jets,
    flank_points,
    tip_parameter,
    undercut_margin,
)


@pytest.fixture(scope="module", params=["01", "03"])
def design(request):
    return design_pair(PairSpec.from_scene(load_scene(f"models/case{request.param}.toml")))


def test_undercut_margin_from_surface_equals_design_check(design):
    for b, gd, name in zip(
        blanks_from_design(design), design.gears, ("pinion", "gear"), strict=True
    ):
        z = sections(gd)
        for side, flank in (("R", "right"), ("L", "left")):
            measured = undercut_margin(b, side, z).min()
            # both are exact for the straight tool flank: agreement to rounding
            assert abs(measured - design.checks[f"{name}_undercut_{flank}"].margin) < 1e-12


def test_tip_thickness_from_surfaces_equals_topping_check(design):
    for b, gd, name in zip(
        blanks_from_design(design), design.gears, ("pinion", "gear"), strict=True
    ):
        z = sections(gd)
        theta = {}
        for side in "RL":
            u, _ = tip_parameter(b, side, z)
            p = flank_points(b, side, z, u).position
            theta[side] = np.arctan2(-p[:, 0], p[:, 1])
        s_an = b.tip_radius(z) * (theta["R"] - theta["L"]) * math.cos(b.helix_angle)
        expected = design.checks[f"{name}_topping"].margin + TOPPING_MIN_SAN * b.normal_module
        assert abs(s_an.min() - expected) < 1e-12


@pytest.mark.parametrize("teeth,xt", [(10, -0.2), (12, 0.0), (14, -0.4)])
def test_undercut_detected_on_small_pinions(teeth, xt):
    """Few teeth and negative shift: the straight flank ends below the interference
    point, so the generated envelope folds (its orientation reverses at u = 0)."""
    b = ToothBlank(
        teeth, 0.006, math.radians(20), math.radians(15), math.radians(2), xt, 0.03
    ).validate()
    for side in "RL":
        z = np.array([b.z_toe, 0.0, b.z_heel])
        m = undercut_margin(b, side, z)
        # textbook condition per flank in the transverse section (Niemann-Winter I, 21.4)
        a_n, g = b.normal_pressure_angle, b.cone_angle
        at = math.atan(
            math.tan(a_n) * math.cos(g) / math.cos(b.helix_angle)
            + (-1 if side == "R" else 1) * math.tan(b.helix_angle) * math.sin(g)
        )
        h_lim = (b.tool_addendum - b.tool_tip_radius * (1 - math.sin(a_n))) / math.cos(g)
        expected = b.reference_pitch_radius * math.sin(at) ** 2 - (h_lim - b.rack_shift(z))
        assert np.allclose(m, expected, atol=1e-12)
        assert (m < 0).any()
        r, n, _ = flank_jets(b, side, z, np.zeros_like(z), involute_only=True)
        R = np.stack([c.d for c in r], axis=-1)
        orient = np.einsum("ni,in->n", np.cross(R[1], R[2]), n)
        r_mid, n_mid, _ = flank_jets(
            b, side, z, np.full_like(z, 4 * b.normal_module), involute_only=True
        )
        R_mid = np.stack([c.d for c in r_mid], axis=-1)
        orient_mid = np.einsum("ni,in->n", np.cross(R_mid[1], R_mid[2]), n_mid)
        assert np.array_equal(np.sign(orient) != np.sign(orient_mid), m < 0)

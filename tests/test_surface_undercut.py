"""Undercut flanks: where the root fillet cuts the regular involute (form_point),
against a brute-force cut by the rack as a solid (tests/_rack.py: no equation of
meshing), and the tooth outline that the loaded TCA's slices take."""

import math

import numpy as np
import pytest
from _rack import deepest
from hypothesis import given, settings
from hypothesis import strategies as st

from gearbox.surface import (
    ToothBlank,
    flank_points,
    fold_parameter,
    form_point,
    involute_start,
    profile_range,
)

D = math.radians


def small(teeth, xt, beta=15.0, gamma=2.0):
    return ToothBlank(teeth, 0.006, D(20.0), D(beta), D(gamma), xt, 0.03).validate()


# undercut pinions (test_surface_checks.py) and one free of undercut
UNDERCUT = {"z10": small(10, -0.2), "z12": small(12, 0.0), "z14": small(14, -0.4)}
FREE = small(29, 0.16, 20.0, 1.0)


@pytest.mark.parametrize("name", sorted(UNDERCUT))
def test_form_point_is_where_the_rack_cuts_the_involute(name):
    """Below the form point the regular involute lies inside the rack at some roll
    angle (the tip rounding cuts it away); above it the rack only touches it. Likewise
    the fillet: touched up to the crossing, cut beyond it towards its end u = 0. The
    brute-force depth resolves 1e-8 m (a fine roll step of 1e-7 rad, second order),
    so the points are taken 3 um of profile either side, where the cut is deeper."""
    b = UNDERCUT[name]
    for side, sigma in (("R", -1), ("L", 1)):
        z = np.array([b.z_toe, 0.0])
        ustar = fold_parameter(b, side, z)
        uf, ui = form_point(b, side, z)
        assert np.all(ustar > 0) and np.all(ui > ustar) and np.all(uf < 0)
        assert np.all(uf > profile_range(b)[0])
        d = 3e-6
        for k in range(z.size):
            zk = np.full(2, z[k])
            inv = flank_points(b, side, zk, ui[k] + np.array([-d, d]), involute_only=True)
            below, above = (deepest(b, sigma, p, span=1.2) for p in inv.position)
            assert below > 1e-8 and above < 1e-8, (below, above)
            if uf[k] < -d:
                fil = flank_points(b, side, zk, uf[k] + np.array([-d, d]))
                under, over = (deepest(b, sigma, p, span=1.2) for p in fil.position)
                assert under < 1e-8 and over > 1e-8, (under, over)


def test_fillet_and_involute_meet_at_the_form_point():
    for b in UNDERCUT.values():
        for side in "RL":
            z = np.linspace(b.z_toe, b.z_heel, 7)
            uf, ui = form_point(b, side, z)
            pf = flank_points(b, side, z, uf).position
            pi = flank_points(b, side, z, ui).position
            assert np.abs(pf - pi).max() < 1e-12
            assert np.array_equal(involute_start(b, side, z), ui)


def test_a_flank_free_of_undercut_starts_at_the_fillets_end():
    for side in "RL":
        z = np.linspace(FREE.z_toe, FREE.z_heel, 5)
        assert np.all(fold_parameter(FREE, side, z) == 0)
        uf, ui = form_point(FREE, side, z)
        assert np.all(uf == 0) and np.all(ui == 0)


@settings(max_examples=60, deadline=None)
@given(
    teeth=st.integers(6, 22),
    xt=st.floats(-0.6, 0.4),
    beta=st.floats(-30.0, 30.0),
    gamma=st.floats(-6.0, 6.0),
    rho=st.floats(0.05, 0.38),
)
def test_form_point_holds_on_random_blanks(teeth, xt, beta, gamma, rho):
    """Random small gears (undercut or not): where the blank is valid, the cut is found
    in every section of the face, the fillet's and the involute's points agree to 1e-11
    m, the cut lies above the fold and on the fillet, and a flank free of undercut
    starts at 0."""
    from gearbox.errors import InputError

    try:
        b = ToothBlank(
            teeth, 0.006, D(20.0), D(beta), D(gamma), xt, 0.03, tool_tip_radius=rho * 0.006
        ).validate()
    except InputError:
        return
    z = np.linspace(b.z_toe, b.z_heel, 5)
    for side in "RL":
        ustar = fold_parameter(b, side, z)
        uf, ui = form_point(b, side, z)
        assert np.all(np.isfinite(uf)) and np.all(np.isfinite(ui))
        cut = ustar > 0
        assert np.all(uf[~cut] == 0) and np.all(ui[~cut] == 0)
        # above 1.1 u*, where the loaded TCA's projection keeps an undercut gear's u_2
        # (beveloid._project); measured 1.29 .. 1.50 u* on 1180 sections of such blanks
        assert np.all(ui[cut] > 1.1 * ustar[cut]) and np.all(uf[cut] <= 0)
        assert np.all(uf > profile_range(b)[0])
        gap = flank_points(b, side, z, uf).position - flank_points(b, side, z, ui).position
        assert np.abs(gap).max() < 1e-11

"""Root stress of the loaded TCA: the moment image along the face and ISO 6336-3.

The slice root stress (ISO 6336-3 method B section at each slice's load) is spread
along the face with the cantilever-plate moment image of Wellauer & Seireg (1960)
(gearbox.ltca.stress). Tested here: the image's exact properties (uniform load
unchanged, no root moment lost, symmetry), its closed-form peak for one loaded cell,
and the whole chain on a parallel helical pair against ISO 6336-3 with Y_beta.
"""

import math

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.ltca import (
    FastCompliance,
    LTCAOptions,
    ParallelPair,
    ltca_cycle,
    parallel_grid,
    solve_contact,
)
from gearbox.ltca.compliance import CALIBRATED_BEAM
from gearbox.ltca.stress import (
    HelixEnds,
    RootStressModel,
    acute_end,
    grid_root_stress,
    helix_end_factor,
    iso_pair_root_stress,
    moment_image,
    root_stress_profile,
    slice_root_stress,
)

FACE = (-0.02, 0.02)
S = 40
W = (FACE[1] - FACE[0]) / S
Y = FACE[0] + (np.arange(S) + 0.5) * W


@pytest.mark.parametrize("decay", [0.2e-3, 5e-3, 60e-3], ids=["narrow", "tooth", "wide"])
def test_uniform_load_is_unchanged(decay):
    # cells tiling the face: the weights at every point add up to 1 (Neumann images
    # of the free ends keep the moment that a long plate would carry beyond them)
    A = moment_image(Y, Y, W, decay, FACE)
    np.testing.assert_allclose(A.sum(axis=1), 1.0, atol=1e-12)


@pytest.mark.parametrize("decay", [1e-3, 5e-3, 60e-3])
@pytest.mark.parametrize("cell", [0, 3, 20, 39])
def test_a_point_load_integrates_back(decay, cell):
    # the root moment of one loaded cell, integrated over the face, is the cell's own
    # (statics of the cantilever plate); trapezoid rule on 8001 points
    yf = np.linspace(*FACE, 8001)
    a = moment_image(yf, [Y[cell]], W, decay, FACE)[:, 0]
    assert np.trapezoid(a, yf) == pytest.approx(W, rel=1e-6)


def test_without_free_ends_the_moment_beyond_the_face_is_lost():
    yf = np.linspace(*FACE, 8001)
    a = moment_image(yf, [Y[0]], W, 5e-3, FACE, free_ends=False)[:, 0]
    assert np.trapezoid(a, yf) < 0.7 * W


def test_kernel_is_symmetric_and_decays():
    A = moment_image(Y, Y, W, 4e-3, FACE)
    np.testing.assert_allclose(A, A.T, atol=1e-15)
    mid = A[S // 2]
    assert np.all(np.diff(mid[S // 2 :]) < 0)  # decays away from the load
    assert np.all(np.diff(mid[: S // 2 + 1]) > 0)


def test_one_loaded_cell_far_from_the_ends_has_the_closed_form_peak():
    # integral of sech(s/c)/(pi c) over the cell [-w/2, w/2]: (2/pi) gd(w / 2c),
    # gd(t) = 2 arctan(tanh(t/2)); the ends are 20 c away
    c = 1e-3
    A = moment_image([0.0], [0.0], W, c, FACE)
    gd = 2 * math.atan(math.tanh(W / (4 * c)))
    assert A[0, 0] == pytest.approx(2 / math.pi * gd, rel=1e-9)


def test_invalid_model_and_image_are_named():
    with pytest.raises(InputError, match="spread_height"):
        RootStressModel(spread_height=-1.0)
    with pytest.raises(InputError, match="face_range"):
        moment_image(Y, Y, W, 1e-3, (0.02, -0.02))
    with pytest.raises(InputError, match="decay"):
        moment_image(Y, Y, W, 0.0, FACE)
    with pytest.raises(InputError, match=r"helix_ends\.height = \(0\.6, 0\.3, 0\.9\)"):
        HelixEnds(height=(0.6, 0.3, 0.9))
    with pytest.raises(InputError, match=r"helix_ends\.acute_decay .* must be > 0"):
        HelixEnds(acute_decay=(0.7, 0.0, 1.7))


SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(30, 45),
    face_width=30e-3,
)
HELICAL = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=math.radians(15),
    teeth=(30, 45),
    face_width=30e-3,
)


def test_spur_line_load_gives_the_slice_stress():
    # a spur pair's contact line lies at one height: its uniform line load keeps the
    # independent slice stress (the spread only moves moment along the face)
    g = parallel_grid(SPUR, 0.3, n_face=20)
    sol = solve_contact(g, FastCompliance(), 400.0)
    s1, s2 = grid_root_stress(g, sol.load)
    np.testing.assert_allclose(s1, slice_root_stress(g.tooth1, sol.load / g.width), rtol=1e-9)
    np.testing.assert_allclose(s2, slice_root_stress(g.tooth2, sol.load / g.width), rtol=1e-9)


def test_no_spread_is_the_slice_model():
    g = parallel_grid(HELICAL, 0.7, n_face=20)
    sol = solve_contact(g, FastCompliance(), 400.0)
    s1, _ = grid_root_stress(
        g, sol.load, RootStressModel(spread_height=0, spread_module=0, helix_ends=None)
    )
    np.testing.assert_allclose(s1, slice_root_stress(g.tooth1, sol.load / g.width))


def test_acute_end_follows_the_contact_lines():
    # the pinion's contact lines climb towards +face, the gear's towards -face; the FE
    # level puts the helical tooth's rise at those ends (bench_root_stress.py
    # --helix-ends); a spur pair's lines stay at one height: no factor
    g = parallel_grid(HELICAL, 0.3, n_face=20)
    assert acute_end(g, g.tooth1) == 1.0
    assert acute_end(g, g.tooth2) == -1.0
    s = parallel_grid(SPUR, 0.3, n_face=20)
    np.testing.assert_allclose(helix_end_factor(s, s.tooth1, RootStressModel()), 1.0)


def test_helix_end_factor_rises_towards_the_acute_end():
    ends = HelixEnds()
    u = np.linspace(0.1, 5.9, 30)  # a 6 m_n face, acute end at u = 0
    for eta in (0.2, 0.6, 0.95):
        np.testing.assert_allclose(ends.factor(0.0, eta, u, 6.0 - u), 1.0)
        f20 = ends.factor(math.tan(math.radians(20)), eta, u, 6.0 - u)
        f30 = ends.factor(math.tan(math.radians(30)), eta, u, 6.0 - u)
        assert np.all(np.diff(f20) < 0) and f20[0] > 1.1 and f20[-1] < 0.95
        assert f30[0] > f20[0] and f30[-1] < f20[-1]
    g = parallel_grid(HELICAL, 0.3, n_face=20)
    f = helix_end_factor(g, g.tooth1, RootStressModel())
    near = g.face > g.face_range[1] - 2 * HELICAL.normal_module
    far = g.face < g.face_range[0] + 2 * HELICAL.normal_module
    assert f[near].min() > f[far].max()
    np.testing.assert_allclose(helix_end_factor(g, g.tooth1, RootStressModel(helix_ends=None)), 1.0)


def test_profile_covers_every_slot_and_matches_the_grid_points():
    g = parallel_grid(HELICAL, 0.7, n_face=20)
    sol = solve_contact(g, FastCompliance(), 400.0)
    s1, _ = grid_root_stress(g, sol.load)
    prof = root_stress_profile(g, sol.load, 0)
    assert prof.stress.shape == (prof.pairs.size, 20)
    for kk, k in enumerate(prof.pairs):
        on = g.pair == k
        np.testing.assert_allclose(prof.stress[kk, g.slot[on]], s1[on], rtol=1e-12)


HELICAL_WIDE = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=math.radians(30),
    teeth=(20, 40),
    face_width=60e-3,
)


# ISO 6336-3 method B nominal stress sigma_F0 = F_t/(b m_n) Y_F Y_S Y_beta against the
# largest root stress over a mesh cycle of the loaded TCA. ISO loads the virtual spur
# gear's outer point of single pair contact with the whole F_t and corrects for the
# oblique contact line with the empirical, linear Y_beta; the loaded TCA finds the
# load sharing and the line-end concentrations itself, and its helical face-end
# factor (HelixEnds, fitted on the FE level) raises loads near the acute face end.
# Measured (bench_root_stress.py --iso and this test), loaded TCA / ISO - 1, pinion /
# gear, default / CALIBRATED_BEAM compliance: 15 deg b 30 (eps_beta 0.62) -3.3 / -5.6 %
# and -8.7 / -8.1 %; 30 deg b 60 (eps_beta 2.4, Y_beta 0.75) +48.1 / +42.0 % and
# +37.9 / +34.5 % (+13.8 / +10.3 % and +8.7 / +9.1 % without the face-end factor).
# The 15 deg pair: within 12 %. The 30 deg pair: the FE level (three teeth at a time,
# elements 0.5 m_n along the face; tests/data/ltca_root_stress_fe_three_teeth.json)
# reads +45 / +50 % above ISO under the fast level's loads, and under its own +59 /
# +84 %, but there from a peak within 2 mm of the acute face end (the pinion's
# envelope 75.5 MPa 3 mm from the end, +7 % over ISO, 112 MPa 1 mm from it); the
# default mesh, which does not resolve that corner, +15 / +17 %. The loaded TCA's
# +48 / +42 % lies between: at or above ISO and within +60 %.
# The independent slices (no spread) give 2.7 to 3.2 times ISO on these pairs.
@pytest.mark.parametrize("gear", [0, 1], ids=["pinion", "gear"])
@pytest.mark.parametrize(
    "pair, low, high",
    [(HELICAL, -0.12, 0.12), (HELICAL_WIDE, 0.0, 0.60)],
    ids=["15deg_b30", "30deg_b60"],
)
def test_helical_pair_root_stress_against_iso_6336_3(pair, low, high, gear):
    T = 400.0
    iso = iso_pair_root_stress(pair, T, gear)
    eps_b = min(pair.overlap_ratio, 1.0)
    assert iso.Y_beta == pytest.approx(1 - eps_b * min(math.degrees(pair.helix_angle), 30) / 120)
    for comp in (None, CALIBRATED_BEAM):
        r = ltca_cycle(
            lambda f: parallel_grid(pair, f, n_face=40),
            [T],
            options=LTCAOptions(48),
            compliance=comp,
        )
        got = (r.root_stress_pinion if gear == 0 else r.root_stress_gear)[0].max()
        assert low <= got / iso.sigma_F0 - 1 <= high, (
            f"loaded TCA {got / 1e6:.1f} MPa, ISO 6336-3 {iso.sigma_F0 / 1e6:.1f} MPa"
        )

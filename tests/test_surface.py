"""Generated flanks against independent geometry (involute helicoid, ISO 21771).

The surfaces come from the envelope of the tilted rack (gearbox.surface.generation).
The references below are written from textbook geometry, not from that code:
- an involute helicoid's transverse sections are involutes of one base circle, and
  its lead 2 pi r_b / tan(beta_b) is constant (Litvin & Fuentes, Gear Geometry and
  Applied Theory, 2nd ed. 2004, ch. 14 "Involute Helical Gears with Parallel Axes");
- the transverse pressure angle of a tilted rack flank, tan a_t = tan a_n cos g / cos b
  -+ tan b sin g, from the flank plane's normal;
- ISO 21771:2007 helical flanks (eqs for s_t, inv) for gamma = 0.
"""

import math

import numpy as np
import pytest
from _rack import deepest
from scipy.optimize import least_squares

from gearbox.surface import (
    ToothBlank,
    flank_points,
    parameter_at_radius,
    profile_range,
    tip_parameter,
)

D = math.radians


def blank(gamma_deg=1.0, beta_deg=20.0, xt=0.16, teeth=29, rho=0.25):
    return ToothBlank(
        teeth, 0.006, D(20.0), D(beta_deg), D(gamma_deg), xt, 0.040, tool_tip_radius=rho * 0.006
    ).validate()


BLANKS = {
    "case03-pinion": blank(),
    "case01-pinion": blank(3.0, 25.0, 0.29),
    "case03-gear": blank(0.8, -7.235859, 0.219102, 45),
    "steep": blank(6.0, -30.0, 0.3, 23),
}


def rack_angles(b: ToothBlank, side):
    """Transverse pressure angle and |sin base helix| of the tilted rack flank plane."""
    a, be, g = b.normal_pressure_angle, b.helix_angle, b.cone_angle
    sign = -1 if side == "R" else 1
    at = math.atan(math.tan(a) * math.cos(g) / math.cos(be) + sign * math.tan(be) * math.sin(g))
    sbb = abs(math.cos(a) * math.sin(be) * math.cos(g) - sign * math.sin(a) * math.sin(g))
    return at, math.asin(sbb)


def involute_points(b, side, z, n=25):
    """Points of the involute part at section z, and their polar coordinates."""
    ut, _ = tip_parameter(b, side, np.array([z]))
    u = np.linspace(0.05 * ut[0], ut[0], n)
    fp = flank_points(b, side, z, u)
    x, y = fp.position[:, 0], fp.position[:, 1]
    return np.hypot(x, y), np.arctan2(-x, y), fp


def fit_involute(r, theta):
    """Least-squares involute theta = theta0 +- inv(arccos(rb / r)): returns rb, theta0, rms."""
    best = None
    for sgn in (1, -1):

        def res(p, sgn=sgn):
            return theta - (p[1] + sgn * (np.tan(np.arccos(p[0] / r)) - np.arccos(p[0] / r)))

        sol = least_squares(
            res,
            [0.9 * r.min(), theta.mean()],
            xtol=1e-15,
            ftol=1e-15,
            gtol=1e-15,
            bounds=([0.5 * r.min(), -4], [r.min() * (1 - 1e-12), 4]),
        )
        rms = np.sqrt(np.mean(sol.fun**2))
        if best is None or rms < best[2]:
            best = (sol.x[0], sol.x[1], rms, sgn)
    return best


@pytest.mark.parametrize("name", list(BLANKS))
@pytest.mark.parametrize("side", ["R", "L"])
def test_flank_is_involute_helicoid_constant_base_radius_and_lead(name, side):
    b = BLANKS[name]
    at, bb = rack_angles(b, side)
    rb_expected = b.reference_pitch_radius * math.cos(at)
    zs = np.linspace(b.z_toe, b.z_heel, 5)
    rbs, th0 = [], []
    for z in zs:
        r, th, _ = involute_points(b, side, z)
        rb, t0, rms, _ = fit_involute(r, th)
        # an exact involute: residual at rounding level (angles ~1 rad, 1e-12 is ~1e-13 m)
        assert rms < 1e-11, (name, side, z, rms)
        rbs.append(rb)
        th0.append(t0)
    # base radius the same in every section and equal to r_p cos(alpha_t) of the rack
    # flank: 1e-9 m is far below any manufacturing tolerance and far above rounding
    assert np.ptp(rbs) < 1e-9
    assert abs(np.mean(rbs) - rb_expected) < 1e-9
    # constant lead: theta0 linear in z, slope tan(beta_b) / r_b
    slope, icpt = np.polyfit(zs, th0, 1)
    assert np.max(np.abs(np.polyval([slope, icpt], zs) - th0)) < 1e-10
    assert abs(abs(slope) - math.tan(bb) / rb_expected) < 1e-9 * abs(slope) + 1e-12
    # the tooth turns in the positive sense towards +z for a right-hand tool (beta > 0)
    assert np.sign(slope) == np.sign(b.helix_angle)


def test_base_data_agree_with_geometry_design():
    """Surfaces (simulated generation) vs the design's closed forms, case 03."""
    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.surface import blanks_from_design

    des = design_pair(PairSpec.from_scene(load_scene("models/case03.toml")))
    for b, gd in zip(blanks_from_design(des), des.gears, strict=True):
        for k, side in enumerate("RL"):
            zs = [b.z_toe, 0.0, b.z_heel]
            rbs = []
            for z in zs:
                r, th, fp = involute_points(b, side, z)
                rbs.append(fit_involute(r, th)[0])
                # |normal's axial component| = sin(base helix) of the design
                assert np.allclose(
                    np.abs(fp.normal[:, 2]), abs(math.sin(gd.base_helix_angle[k])), atol=1e-12
                )
            assert np.allclose(rbs, gd.base_radius[k], atol=1e-9), (side, rbs, gd.base_radius)


def pitch_circle_angle(b, side, z):
    """Polar angle of the flank at r = r_p in section z (bisection on the involute)."""
    lo, hi = 0.0, tip_parameter(b, side, np.array([z]))[0][0]
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        p = flank_points(b, side, z, mid).position
        if math.hypot(p[0], p[1]) < b.reference_pitch_radius:
            lo = mid
        else:
            hi = mid
        if hi - lo < 1e-15:
            break
    p = flank_points(b, side, z, 0.5 * (lo + hi)).position
    return math.atan2(-p[0], p[1])


@pytest.mark.parametrize("name", ["case03-pinion", "case01-pinion", "steep"])
def test_transverse_tooth_thickness_is_linear_along_face(name):
    """Arc thickness on r_p: s(z) = pi m_t / 2 + X(z) (tan a_tR + tan a_tL).

    The rack's space width on the rolling line y = r_p, X(z) below its reference line
    (transverse section: the flanks move by X tan(alpha_t) each).
    """
    b = BLANKS[name]
    aR, _ = rack_angles(b, "R")
    aL, _ = rack_angles(b, "L")
    for z in np.linspace(b.z_toe, b.z_heel, 5):
        s = b.reference_pitch_radius * (
            pitch_circle_angle(b, "R", z) - pitch_circle_angle(b, "L", z)
        )
        expected = math.pi * b.transverse_module / 2 + b.rack_shift(z) * (
            math.tan(aR) + math.tan(aL)
        )
        assert abs(s - expected) < 1e-10, (z, s, expected)


@pytest.mark.parametrize("beta_deg,xt", [(20.0, 0.16), (-12.0, -0.3), (0.0, 0.5)])
def test_cone_angle_zero_gives_iso_21771_helical_flanks(beta_deg, xt):
    b = blank(0.0, beta_deg, xt)
    a_n, be = b.normal_pressure_angle, b.helix_angle
    at = math.atan(math.tan(a_n) / math.cos(be))
    rb = b.reference_pitch_radius * math.cos(at)
    x = xt / math.cos(be)  # normal profile-shift coefficient: X = x_t m_t = x m_n
    st = b.transverse_module * (math.pi / 2 + 2 * x * math.tan(a_n))  # ISO 21771 s_t
    inv = lambda a: math.tan(a) - a  # noqa: E731
    for side, sgn in (("R", 1), ("L", -1)):
        zg, ug = np.meshgrid(np.linspace(-0.02, 0.02, 5), np.linspace(0.0, 0.008, 7))
        fp = flank_points(b, side, zg, ug)
        r = fp.radius
        th = np.arctan2(-fp.position[..., 0], fp.position[..., 1])
        ay = np.arccos(rb / r)
        expected = zg * math.tan(be) / b.reference_pitch_radius + sgn * (
            st / (2 * b.reference_pitch_radius) + inv(at) - (np.tan(ay) - ay)
        )
        # polar angle to 1e-12 rad, i.e. ~1e-13 m on the flank
        assert np.max(np.abs(th - expected)) < 1e-12


@pytest.mark.parametrize("name", list(BLANKS))
@pytest.mark.parametrize("side", ["R", "L"])
def test_principal_curvatures_of_involute_helicoid(name, side):
    """k_min = 0 along the ruling, k_max = cos(beta_b) / sqrt(r^2 - r_b^2)."""
    b = BLANKS[name]
    at, bb = rack_angles(b, side)
    rb = b.reference_pitch_radius * math.cos(at)
    zg, ug = np.meshgrid(np.linspace(b.z_toe, b.z_heel, 4), np.linspace(0.5e-3, 8e-3, 6))
    fp = flank_points(b, side, zg, ug)
    kmax = math.cos(bb) / np.sqrt(fp.radius**2 - rb**2)
    assert np.max(np.abs(fp.curvatures[..., 0])) < 1e-9 * np.max(kmax)
    assert np.max(np.abs(fp.curvatures[..., 1] / kmax - 1)) < 1e-9
    # the zero-curvature direction is a ruling: a straight line of the surface, tangent
    # to the base cylinder (distance from the axis of the line's point closest to the
    # axis equals r_b) and inclined by beta_b to the axis
    d0 = fp.directions[..., 0, :]
    assert np.allclose(np.abs(d0[..., 2]), math.cos(bb), atol=1e-12)
    p = fp.position
    t = -(p[..., 0] * d0[..., 0] + p[..., 1] * d0[..., 1]) / (d0[..., 0] ** 2 + d0[..., 1] ** 2)
    q = p + t[..., None] * d0
    assert np.allclose(np.hypot(q[..., 0], q[..., 1]), rb, atol=1e-10)


@pytest.mark.parametrize("name", list(BLANKS))
def test_fillet_joins_involute_smoothly_and_reaches_root_cone(name):
    b = BLANKS[name]
    u_min, _ = profile_range(b)
    for side in "RL":
        z = np.array([b.z_toe, 0.0, b.z_heel])
        a = flank_points(b, side, z, -1e-12)
        c = flank_points(b, side, z, 1e-12)
        assert np.allclose(a.position, c.position, atol=1e-12)
        assert np.allclose(a.normal, c.normal, atol=1e-9)
        bottom = flank_points(b, side, z, u_min)
        assert np.allclose(bottom.radius, b.root_radius(z), atol=1e-10)
        # radius grows monotonically from the root to the tip: no undercut here
        ut, _ = tip_parameter(b, side, z)
        u = np.linspace(u_min, ut.min(), 200)
        r = flank_points(b, side, z[:, None], u[None, :]).radius
        assert np.all(np.diff(r, axis=1) > 0)
        # the tip parameter lands on the tip cone, and any radius on the flank is found
        assert np.allclose(flank_points(b, side, z, ut).radius, b.tip_radius(z), atol=1e-12)
        r_target = np.linspace(r[:, 0].max() + 1e-4, b.tip_radius(z).min(), 7)
        ur, _ = parameter_at_radius(b, side, z[:, None], r_target[None, :])
        assert np.allclose(
            flank_points(b, side, z[:, None], ur).radius, r_target[None, :], atol=1e-12
        )


@pytest.mark.parametrize("name", ["case03-pinion", "steep"])
def test_rack_never_cuts_into_generated_flank(name):
    """Envelope check without the equation of meshing: over a sweep of rack positions
    the rack tooth's flank plane and tip rounding touch each generated point once and
    never pass through it (a point inside the rack tooth would be cut away)."""
    b = BLANKS[name]
    for side, sigma in (("R", -1), ("L", 1)):
        zg, ug = np.meshgrid([b.z_toe, 0.0, b.z_heel], np.linspace(profile_range(b)[0], 6e-3, 9))
        pts = flank_points(b, side, zg, ug).position.reshape(-1, 3)
        worst = [deepest(b, sigma, p) for p in pts]
        worst = np.array(worst)
        # touches (max depth ~ 0 to within the fine phi step 1e-7 rad, second order)
        # and never penetrates by more than that
        assert np.all(worst < 1e-8), worst.max()
        assert np.all(worst > -1e-9), worst.min()

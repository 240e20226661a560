"""Flank surfaces by simulated generation with a tilted rack cutter.

Method (the envelope of the tool surface family and its equation of meshing, Litvin &
Fuentes, *Gear Geometry and Applied Theory*, 2nd ed. 2004, ch. 6 "Conjugated Surfaces
and Curves"):

1. Rack profile in its normal section (coordinates s along the rack's normal pitch,
   v outward, i.e. away from the gear axis): a straight flank through the reference
   line point ``s0 = sigma pi m_n / 4`` with normal ``(sigma cos a_n, sin a_n)`` and, below
   it, the tip rounding of radius rho_a0 tangent to the flank and to the tip line
   ``v = -h_a0``. ``sigma = -1`` for the right flank R, ``+1`` for the left flank L.
   The profile parameter ``u`` is the arc length along this profile, 0 at the
   tangency of rounding and flank, > 0 up the straight flank (the involute part of
   the gear), < 0 on the rounding (the gear's root fillet), down to
   ``u_min = -rho_a0 (pi/2 - a_n)`` on the tip line.
2. The rack tooth runs at the helix angle beta in its pitch plane (tooth line
   ``e1 = (-sin b, 0, cos b)`` in rack axes u, v, w), and the rack is tilted about its
   direction of motion u by the cone angle gamma so that its reference plane rises
   towards +z: rack (u, v, w) -> gear (x, v cos g + w sin g + r_p + x_t m_t,
   -v sin g + w cos g). Each transverse section z therefore sees the rack shifted
   radially by X(z) = x_t m_t + z tan(gamma).
3. Generation: the gear turns by phi about +z while the rack moves by -r_p phi along x
   (rolling of the pitch circle r_p on the rack). The equation of meshing
   ``n . v_rel = 0`` is linear in phi for a rack point P (fixed frame) with normal n:
   ``phi = (n_y P_x - n_x (P_y - r_p)) / (n_y r_p)``, so the envelope is closed form.
   The gear point is ``Rz(-phi) (P - r_p phi e_x)`` and its normal ``Rz(-phi) n``.

Every quantity is written with :class:`gearbox.surface._jet.Jet`, so the first and
second derivatives in (z, u) are exact; the principal curvatures follow from the
fundamental forms (:func:`principal_curvatures`). Nothing here uses the closed-form
involute-helicoid relations of :mod:`gearbox.geometry`: the tests compare the two.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ._jet import Jet, jet_variable, where
from .blank import SIDES, ToothBlank

__all__ = [
    "FlankPoints",
    "flank_points",
    "flank_jets",
    "principal_curvatures",
    "profile_range",
    "side_sign",
    "fold_parameter",
    "form_point",
    "involute_start",
    "undercut_margin",
]


def side_sign(side: str) -> int:
    """sigma of a flank: -1 for "R", +1 for "L"."""
    if side not in SIDES:
        raise ValueError(f"side must be one of {SIDES}, got {side!r}")
    return -1 if side == "R" else 1


def profile_range(blank: ToothBlank) -> tuple[float, float]:
    """``(u_min, 0)``: the rack-profile arc length of the rounding (m).

    ``u_min = -rho_a0 (pi/2 - a_n)`` is the rack tip line, ``0`` the start of the
    straight flank (the gear's form circle). The upper end of the involute is set
    by the tip cone; see :func:`tip_parameter`.
    """
    return -blank.tool_tip_radius * (0.5 * math.pi - blank.normal_pressure_angle), 0.0


def _rack_profile(blank: ToothBlank, sigma: int, u: Jet, involute_only: bool = False):
    """Normal-section rack profile (s, v, m_s, m_v) as jets in u (m, unit normal)."""
    a = blank.normal_pressure_angle
    m = blank.normal_module
    rho = blank.tool_tip_radius
    sa, ca = math.sin(a), math.cos(a)
    s0 = sigma * math.pi * m / 4
    vc = -blank.tool_addendum + rho
    sc = s0 + sigma * (rho - sa * vc) / ca
    st, vt = sc - rho * sigma * ca, vc - rho * sa
    # straight flank
    s_f = st - sigma * sa * u
    v_f = vt + ca * u
    ms_f = 0.0 * u + sigma * ca
    mv_f = 0.0 * u + sa
    if rho <= 0.0 or involute_only:
        return s_f, v_f, ms_f, mv_f
    th = u / rho + (0.5 * math.pi - a)
    sth, cth = th.sin(), th.cos()
    s_r = sc - rho * sigma * sth
    v_r = vc - rho * cth
    ms_r = sigma * sth
    mv_r = cth
    on_flank = u.val >= 0.0
    return (
        where(on_flank, s_f, s_r),
        where(on_flank, v_f, v_r),
        where(on_flank, ms_f, ms_r),
        where(on_flank, mv_f, mv_r),
    )


def flank_jets(
    blank: ToothBlank, side: str, z, u, *, normal_jets: bool = False, involute_only: bool = False
):
    """Generated flank point of tooth 0 as jets, and its unit normal.

    Args:
        blank: the gear's :class:`ToothBlank`.
        side: ``"R"`` or ``"L"``.
        z: axial position in the gear frame (m), array.
        u: rack-profile arc length (m), array broadcastable with z.
        normal_jets: return the normal as 3 jets too (its derivatives are exact).
        involute_only: continue the involute part (straight rack flank) for u < 0
            instead of switching to the root fillet; the contact solver iterates on
            this smooth continuation and checks the limits afterwards.

    Returns:
        ``(r, n, phi)``: ``r`` a list of 3 :class:`Jet` (x, y, z of the point, with
        derivatives in (z, u)); ``n`` ndarray shape ``(3,) + shape``, the unit normal
        pointing out of the tooth material (a list of 3 jets with ``normal_jets``);
        ``phi`` the generating roll angle (rad).
    """
    sigma = side_sign(side)
    z, u = np.broadcast_arrays(np.asarray(z, dtype=float), np.asarray(u, dtype=float))
    Z, U = jet_variable(z, 0), jet_variable(u, 1)
    b, g = blank.helix_angle, blank.cone_angle
    sb, cb, sg, cg = math.sin(b), math.cos(b), math.sin(g), math.cos(g)
    rp = blank.reference_pitch_radius
    y0 = rp + blank.profile_shift_xt * blank.transverse_module

    s, v, ms, mv = _rack_profile(blank, sigma, U, involute_only)
    # position along the tooth line so that the point lies in section z (step 2)
    e = (Z + v * sg - s * (sb * cg)) / (cb * cg)
    pu = s * cb - e * sb
    pv = v
    pw = s * sb + e * cb
    nu = ms * cb
    nv = mv
    nw = ms * sb
    # tilt and shift into the fixed frame (= gear frame at phi = 0)
    px = pu
    py = pv * cg + pw * sg + y0
    pz = -pv * sg + pw * cg
    nx = nu
    ny = nv * cg + nw * sg
    nz = -nv * sg + nw * cg
    # equation of meshing n . v_rel = 0 (step 3)
    phi = (ny * px - nx * (py - rp)) / (ny * rp)
    qx = px - rp * phi
    cphi, sphi = phi.cos(), phi.sin()
    rx = cphi * qx + sphi * py
    ry = cphi * py - sphi * qx
    if normal_jets:
        return [rx, ry, pz], [cphi * nx + sphi * ny, cphi * ny - sphi * nx, nz + 0.0 * Z], phi.val
    c0, s0 = cphi.val, sphi.val
    n = np.stack([c0 * nx.val + s0 * ny.val, c0 * ny.val - s0 * nx.val, nz.val])
    return [rx, ry, pz], n, phi.val


@dataclass(frozen=True)
class FlankPoints:
    """Points of a generated flank (gear frame, SI); arrays of one common shape S.

    Attributes:
        side: ``"R"`` or ``"L"``.
        z, u: surface parameters (m), shape S.
        position: ndarray shape S + (3,), the point (m).
        normal: unit normal out of the material, shape S + (3,).
        dr_dz, dr_du: tangent vectors (-, -), shape S + (3,).
        curvatures: principal curvatures (k_min, k_max) (1/m), shape S + (2,); positive
            where the flank is convex.
        directions: principal directions, shape S + (2, 3), unit, in the tangent plane.
        roll_angle: generating roll angle phi (rad), shape S.
        on_fillet: True where the point lies on the root fillet (u < 0), shape S.
    """

    side: str
    z: np.ndarray
    u: np.ndarray
    position: np.ndarray
    normal: np.ndarray
    dr_dz: np.ndarray
    dr_du: np.ndarray
    curvatures: np.ndarray
    directions: np.ndarray
    roll_angle: np.ndarray
    on_fillet: np.ndarray

    @property
    def radius(self) -> np.ndarray:
        """Distance from the gear axis (m), shape S."""
        return np.hypot(self.position[..., 0], self.position[..., 1])


def principal_curvatures(r: list[Jet], n: np.ndarray):
    """Principal curvatures and directions from the fundamental forms.

    Args:
        r: 3 jets of the position (derivatives in two parameters).
        n: unit normal out of the material, shape ``(3,) + S``.

    Returns:
        ``(k, d)``: k shape ``S + (2,)`` (k_min, k_max), positive for a convex surface
        (centre of curvature inside the material); d shape ``S + (2, 3)`` unit
        principal directions. Weingarten map ``I^-1 II`` (do Carmo, *Differential
        Geometry of Curves and Surfaces*, section 3-3).
    """
    R = np.stack([c.d for c in r], axis=-1)  # (6, S..., 3)
    rz, ru, rzz, rzu, ruu = R[1], R[2], R[3], R[4], R[5]
    nn = np.moveaxis(n, 0, -1)
    E = np.sum(rz * rz, -1)
    F = np.sum(rz * ru, -1)
    G = np.sum(ru * ru, -1)
    # second form with the sign that makes convex positive (normal points outwards)
    L = -np.sum(rzz * nn, -1)
    M = -np.sum(rzu * nn, -1)
    N = -np.sum(ruu * nn, -1)
    det = E * G - F * F
    H = 0.5 * (E * N - 2 * F * M + G * L) / det
    K = (L * N - M * M) / det
    disc = np.sqrt(np.maximum(H * H - K, 0.0))
    k = np.stack([H - disc, H + disc], axis=-1)
    dirs = []
    for i in range(2):
        lam = k[..., i]
        a1, b1 = M - lam * F, -(L - lam * E)
        a2, b2 = N - lam * G, -(M - lam * F)
        use1 = (a1 * a1 + b1 * b1) >= (a2 * a2 + b2 * b2)
        a = np.where(use1, a1, a2)
        b = np.where(use1, b1, b2)
        d = a[..., None] * rz + b[..., None] * ru
        norm = np.linalg.norm(d, axis=-1, keepdims=True)
        dirs.append(d / np.where(norm > 0, norm, 1.0))
    d = np.stack(dirs, axis=-2)
    # umbilic / flat points: any orthonormal pair of the tangent plane
    flat = disc < 1e-12 * np.maximum(np.abs(H), 1e-300)
    if np.any(flat):
        t1 = rz / np.linalg.norm(rz, axis=-1, keepdims=True)
        t2 = np.cross(nn, t1)
        d = np.where(flat[..., None, None], np.stack([t1, t2], axis=-2), d)
    return k, d


def flank_points(blank: ToothBlank, side: str, z, u, *, involute_only: bool = False) -> FlankPoints:
    """Generated flank of tooth 0 at parameters (z, u): points, normals, curvatures.

    Args:
        blank: the gear's :class:`ToothBlank`.
        side: ``"R"`` (drive) or ``"L"`` (coast).
        z: axial positions in the gear frame (m), array.
        u: rack-profile arc length (m), array broadcastable with z; see
            :func:`profile_range`.
        involute_only: continue the involute for u < 0 (see :func:`flank_jets`).

    Returns:
        :class:`FlankPoints`; tooth k is tooth 0 turned by ``2 pi k / N`` about z.
    """
    r, n, phi = flank_jets(blank, side, z, u, involute_only=involute_only)
    k, d = principal_curvatures(r, n)
    R = np.stack([c.d for c in r], axis=-1)
    zz, uu = np.broadcast_arrays(np.asarray(z, dtype=float), np.asarray(u, dtype=float))
    return FlankPoints(
        side=side,
        z=zz,
        u=uu,
        position=R[0],
        normal=np.moveaxis(n, 0, -1),
        dr_dz=R[1],
        dr_du=R[2],
        curvatures=k,
        directions=d,
        roll_angle=phi,
        on_fillet=(uu < 0.0) & (not involute_only),
    )


def fold_parameter(blank: ToothBlank, side: str, z) -> np.ndarray:
    """Rack profile parameter u* (m) of the cuspidal edge where an undercut flank's
    envelope folds (on the base cylinder, :func:`undercut_margin`), 0 where the flank
    is free of undercut: points with 0 <= u < u* lie on the folded branch."""
    z = np.atleast_1d(np.asarray(z, dtype=float))
    (z0, z1), (u0, u1) = _fold_ends(blank, side)
    if max(u0, u1) <= 0.0:
        return np.zeros_like(z)
    # the radial rack shift, and so u*, is linear in z
    return np.maximum(u0 + (z - z0) * (u1 - u0) / (z1 - z0), 0.0)


def involute_start(blank: ToothBlank, side: str, z) -> np.ndarray:
    """Lowest rack profile parameter u (m) of the flank's regular involute in sections
    z: 0 (the tool's straight flank ends there, the form circle) or, on an undercut
    flank, where the root fillet cuts the regular involute (:func:`form_point`), above
    the fold u* (:func:`fold_parameter`): the folded branch and the involute between
    the fold and the cut are removed by the tool's tip rounding."""
    return form_point(blank, side, z)[1]


def form_point(blank: ToothBlank, side: str, z, *, tol: float = 1e-14) -> tuple:
    """Where the flank's material boundary passes from the root fillet to the involute
    in sections z: ``(u_fillet, u_involute)``, rack profile parameters (m) of the same
    point on the fillet (u <= 0) and on the regular involute (u >= u*). Both 0 on a
    flank free of undercut (the fillet joins the involute at u = 0); on an undercut
    flank the fillet, generated by the tool's tip rounding, cuts the regular involute
    above the base cylinder, and the boundary is the fillet up to ``u_fillet`` and the
    involute from ``u_involute``.

    In each transverse section the crossing is the root of ``g(u_f) = s (theta_f(u_f) -
    theta_i(r_f(u_f)))`` (polar angle of the fillet point less the regular involute's
    at the same radius, ``s`` the side of the material): below 0 where the fillet
    lies inside the involute, bracketed between the fillet's point on the base
    cylinder and its end u = 0, and refined by the Illinois method to ``tol`` (m) in
    u_f. Checked against a brute-force cut by the rack's positions in
    ``tests/test_surface_undercut.py``."""
    z = np.atleast_1d(np.asarray(z, dtype=float))
    ustar = fold_parameter(blank, side, z)
    uf = np.zeros_like(z)
    ui = np.zeros_like(z)
    cut = ustar > 0.0
    if np.any(cut) and blank.tool_tip_radius > 0.0:
        uf[cut], ui[cut] = _fillet_cut(blank, side, z[cut], ustar[cut], tol)
    return uf, ui


def _section_polar(blank, side, z, u, involute_only=False):
    r, n, _ = flank_jets(blank, side, z, u, involute_only=involute_only)
    x, y = r[0].val, r[1].val
    return np.hypot(x, y), np.arctan2(x, y), n, (x, y, r[0].d[2], r[1].d[2])


def _at_radius(blank, side, z, radius, lo, hi, tol, involute_only=False):
    """u in [lo, hi] where the profile reaches ``radius`` (safeguarded Newton; the
    radius grows with u in the bracket)."""
    lo, hi = lo.copy(), hi.copy()
    u = 0.5 * (lo + hi)
    for _ in range(100):
        rad, _, _, (x, y, dx, dy) = _section_polar(blank, side, z, u, involute_only)
        f = rad - radius
        lo = np.where(f < 0, u, lo)
        hi = np.where(f > 0, u, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = u - f * rad / (x * dx + y * dy)
        inside = np.isfinite(newton) & (newton > lo) & (newton < hi)
        u_new = np.where(inside, newton, 0.5 * (lo + hi))
        if np.all((np.abs(u_new - u) <= tol) | (f == 0)):
            return u_new
        u = u_new
    return u


def _fillet_cut(blank, side, z, ustar, tol):
    # the regular involute of each section is the involute of the base circle through
    # the fold (each transverse section of the generated flank is an involute,
    # tests/test_surface.py): its polar angle at radius r is theta_b + w inv(acos(r_b / r)),
    # w the way it unwinds, read off a point of the regular branch
    rb, th_b, n_b, _ = _section_polar(blank, side, z, ustar, True)
    r2, th2, _, _ = _section_polar(blank, side, z, 2.0 * ustar + 0.1 * blank.normal_module, True)
    a2 = np.arccos(rb / r2)
    w = np.sign(np.angle(np.exp(1j * (th2 - th_b))) / (np.tan(a2) - a2))
    # the side of the material: the outward normal's turn about the gear axis
    s = np.sign(n_b[0] * np.cos(th_b) - n_b[1] * np.sin(th_b))

    def g(u):
        rad, th, _, _ = _section_polar(blank, side, z, u)
        a = np.arccos(np.clip(rb / rad, -1.0, 1.0))
        return s * np.angle(np.exp(1j * (th - th_b - w * (np.tan(a) - a)))), rad

    # the bracket: the fillet's point on the base cylinder (inside the involute's cusp,
    # g < 0) and its end u = 0 (on the folded branch, outside: g > 0)
    u_min = np.full(z.shape, profile_range(blank)[0])
    lo = _at_radius(blank, side, z, rb, u_min, np.zeros_like(z), tol)
    hi = np.zeros_like(z)
    glo, _ = g(lo)
    ghi, _ = g(hi)
    last = np.zeros(z.shape)
    for _ in range(200):
        with np.errstate(divide="ignore", invalid="ignore"):
            u = (lo * ghi - hi * glo) / (ghi - glo)
        u = np.where(np.isfinite(u) & (u > lo) & (u < hi), u, 0.5 * (lo + hi))
        gu, _ = g(u)
        left = gu < 0  # the root lies above u
        lo, glo = np.where(left, u, lo), np.where(left, gu, glo)
        hi, ghi = np.where(left, hi, u), np.where(left, ghi, gu)
        # Illinois: halve the kept end's value when the same end moved last time too
        glo = np.where(~left & (last < 0), 0.5 * glo, glo)
        ghi = np.where(left & (last > 0), 0.5 * ghi, ghi)
        last = np.where(left, 1.0, -1.0)
        if np.all((hi - lo <= tol) | (gu == 0)):
            break
    uf = np.where(gu == 0, u, 0.5 * (lo + hi))
    _, rad = g(uf)
    top = ustar + 4.0 * blank.normal_module
    ui = _at_radius(blank, side, z, rad, ustar, top, tol, involute_only=True)
    return uf, ui


@lru_cache(maxsize=64)
def _fold_ends(blank: ToothBlank, side: str) -> tuple[tuple[float, float], tuple[float, float]]:
    ends = np.array([blank.z_toe, blank.z_heel])
    u = -undercut_margin(blank, side, ends) * math.cos(blank.cone_angle)
    u = u / math.cos(blank.normal_pressure_angle)
    return (float(ends[0]), float(ends[1])), (float(u[0]), float(u[1]))


def undercut_margin(blank: ToothBlank, side: str, z) -> np.ndarray:
    """Undercut margin of a flank in sections z (m), from the generated surface.

    The envelope of the straight rack flank is regular where ``(r_z x r_u) . n`` keeps
    its sign and has a cuspidal edge (on the base cylinder) where it vanishes, at rack
    profile parameter ``u*`` (found by secant steps; the function is linear in u for a
    straight tool flank). The straight flank ends at u = 0, so the flank is free of
    undercut when ``u* < 0``. Returned as the transverse radial distance
    ``-u* cos(alpha_n) / cos(gamma)`` (> 0: no undercut), comparable with the classic
    interference-point condition written per flank in :mod:`gearbox.geometry.checks`.
    """
    z = np.atleast_1d(np.asarray(z, dtype=float))

    def g(u):
        r, n, _ = flank_jets(blank, side, z, u, involute_only=True)
        R = np.stack([c.d for c in r], axis=-1)
        return np.einsum("ni,in->n", np.cross(R[1], R[2]), n)

    m = blank.normal_module
    u0, u1 = np.zeros_like(z), np.full_like(z, m)
    g0, g1 = g(u0), g(u1)
    for _ in range(4):
        u2 = u1 - g1 * (u1 - u0) / (g1 - g0)
        u0, g0 = u1, g1
        u1, g1 = u2, g(u2)
        if np.all(np.abs(u1 - u0) < 1e-15):
            break
    return -u1 * math.cos(blank.normal_pressure_angle) / math.cos(blank.cone_angle)

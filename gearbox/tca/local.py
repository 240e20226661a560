"""Local geometry along the contact path: flank limits, path ends, contact ellipse."""

from __future__ import annotations

import math

import numpy as np

from ..surface import ToothBlank, flank_jets, flank_points, involute_start
from .contact import solve_contact

__all__ = [
    "centre_start",
    "contact_ellipse",
    "far_outside",
    "flank_limits",
    "limit_margins",
    "margin_to_limits",
    "nearest_limit",
    "refine_path_ends",
]


def _pitch_profile_parameter(b: ToothBlank) -> float:
    """u of the rack point on its reference plane (v = 0) (m)."""
    sa, ca = math.sin(b.normal_pressure_angle), math.cos(b.normal_pressure_angle)
    vt = -b.tool_addendum + b.tool_tip_radius * (1 - sa)
    return -vt / ca


def _angle_about(v, axis, ref):
    """Angle of v about a unit axis, measured from ref (both projected)."""
    v = v - (v @ axis) * axis
    e1 = ref - (ref @ axis) * axis
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    return math.atan2(v @ e2, v @ e1)


def _profile_parameter_at(b: ToothBlank, side: str, radius: float) -> float:
    """u of the flank point at radius ``radius`` in the reference section (z = 0),
    interpolated in the involute's radius from the form circle to beyond the tip; the
    rack's reference-plane point (:func:`_pitch_profile_parameter`) where ``radius`` is
    not on the flank."""
    u = np.linspace(0.0, 3.0 * b.normal_module, 121)
    r = flank_points(b, side, np.zeros_like(u), u, involute_only=True).radius
    ok = np.isfinite(r)
    u, r = u[ok], r[ok]
    if u.size < 2 or np.any(np.diff(r) <= 0) or not r[0] <= radius <= r[-1]:
        return _pitch_profile_parameter(b)
    return float(np.interp(radius, r, u))


def centre_start(pinion, gear, asm, side, target):
    """Pinion angle and starting values that put both flanks' points at target: in
    each member's reference section, at the target's distance from its axis (the
    working pitch radius, which a profile shift and the cone move off the rack's
    reference plane)."""
    target = np.asarray(target, dtype=float)
    r_1 = math.hypot(*(target - asm.pinion_origin)[:2])
    d2 = target - asm.gear_origin
    r_2 = float(np.linalg.norm(d2 - (d2 @ asm.gear_axis) * asm.gear_axis))
    u1, u2 = _profile_parameter_at(pinion, side, r_1), _profile_parameter_at(gear, side, r_2)
    q1 = flank_points(pinion, side, 0.0, u1).position
    p10 = asm.pinion_matrix(0.0) @ q1
    phi1 = math.atan2(target[1], target[0]) - math.atan2(p10[1], p10[0])
    p1 = asm.pinion_matrix(phi1) @ q1 + asm.pinion_origin
    q2 = flank_points(gear, side, 0.0, u2).position
    g0 = asm.gear_matrix(0.0) @ q2
    a2 = asm.gear_axis
    phi2 = _angle_about(p1 - asm.gear_origin, a2, np.array([-1.0, 0, 0])) - _angle_about(
        g0, a2, np.array([-1.0, 0, 0])
    )
    return phi1, np.array([0.0, u1, 0.0, u2, phi2])


def flank_limits(blank: ToothBlank, side: str, z, u, radius, who: str):
    """First violated limit per point ("" if on the flank) and (face, profile) fractions."""
    z = np.asarray(z)
    form = flank_points(blank, side, z, np.zeros_like(z)).radius
    tip = blank.tip_radius(z)
    lim = np.full(z.shape, "", dtype=object)
    tol = 1e-12
    # an undercut flank starts at its envelope's fold (involute_start), not at u = 0
    lim = np.where(u < involute_start(blank, side, z) - tol, f"{who} root", lim)
    lim = np.where(radius > tip + tol, f"{who} tip", lim)
    lim = np.where(z > blank.z_heel + tol, f"{who} heel", lim)
    lim = np.where(z < blank.z_toe - tol, f"{who} toe", lim)
    zmid = -blank.reference_section
    face = (z - zmid) / (0.5 * blank.face_width)
    prof = (radius - form) / (tip - form)
    return lim, np.stack([face, prof], axis=-1)


def limit_margins(pinion, gear, side, x) -> np.ndarray:
    """Signed distances (m) of contacts x (N, 5) from each flank limit, shape (N, 8) in
    the order of :data:`gearbox.tca.result.LIMITS` (pinion toe, heel, root, tip, then
    the gear's); >= 0 on the flank. Root: rack-profile length above the involute's start
    (:func:`gearbox.surface.involute_start`); tip: radial."""
    cols = []
    for blank, z, u in ((pinion, x[:, 0], x[:, 1]), (gear, x[:, 2], x[:, 3])):
        r, _, _ = flank_jets(blank, side, z, u, involute_only=True)
        radius = np.hypot(r[0].val, r[1].val)
        start = involute_start(blank, side, z)
        cols += [z - blank.z_toe, blank.z_heel - z, u - start, blank.tip_radius(z) - radius]
    return np.stack(cols, axis=-1)


def margin_to_limits(pinion, gear, side, x):
    """Signed distance (m) of contacts x (N, 5) from the nearest flank limit (>= 0 on
    both real flanks): face ends, the involute's start (u = 0 or an undercut's fold, in
    rack-profile length) and tip cone."""
    return limit_margins(pinion, gear, side, x).min(axis=-1)


def nearest_limit(pinion, gear, side, x) -> np.ndarray:
    """Name (:data:`gearbox.tca.result.LIMITS`) of the limit nearest to each contact x
    (N, 5): at a path's refined end, the limit the contact leaves the flanks by (the
    first one a point beyond the end violates need not be it where two limits come
    close: a gear tip just before the pinion's root form circle)."""
    from .result import LIMITS

    return np.asarray(LIMITS, dtype=object)[
        np.argmin(limit_margins(pinion, gear, side, x), axis=-1)
    ]


def refine_path_ends(
    pinion, gear, asm, side, phi_in, x_in, phi_out, x_out, settings, tan, steps: int = 12
):
    """Where the reference pair's contact leaves the flanks, by regula falsi in phi_1.

    ``phi_in``/``x_in``: active solutions next to each end, ``phi_out``/``x_out`` the
    inactive neighbours (arrays of 2). The limit margin (:func:`margin_to_limits`) is smooth in
    phi_1 along the path; the Illinois variant of regula falsi keeps the bracket and
    converges superlinearly. Returns the two end angles (rad) and the limits the path
    leaves the flanks by there (:func:`nearest_limit` of the last solutions inside).
    """
    a, b = np.array(phi_in, float), np.array(phi_out, float)
    xa = np.array(x_in, float)
    fa, fb = (
        margin_to_limits(pinion, gear, side, xa),
        margin_to_limits(pinion, gear, side, np.array(x_out, float)),
    )
    side_kept = np.zeros(2, dtype=int)
    for _ in range(steps):
        c = b - fb * (b - a) / (fb - fa)
        c = np.where(np.isfinite(c), c, 0.5 * (a + b))
        sol = solve_contact(
            pinion, gear, asm, side, c, xa + np.outer(c - a, tan), max_iter=settings.max_iter
        )
        fc = np.where(
            sol.converged & sol.opposed, margin_to_limits(pinion, gear, side, sol.x), -np.inf
        )
        fc = np.where(np.isfinite(fc), fc, -abs(fb))
        inside = fc >= 0
        # Illinois: halve the function value at the end that stays
        fb = np.where(inside & (side_kept == 1), 0.5 * fb, fb)
        fa = np.where(~inside & (side_kept == -1), 0.5 * fa, fa)
        side_kept = np.where(inside, 1, -1)
        a, fa = np.where(inside, c, a), np.where(inside, fc, fa)
        xa = np.where(inside[:, None], sol.x, xa)
        b, fb = np.where(inside, b, c), np.where(inside, fb, fc)
        if np.all(np.abs(b - a) < 1e-12):
            break
    return np.where(np.abs(fa) < np.abs(fb), a, b), nearest_limit(pinion, gear, side, xa)


def far_outside(blank: ToothBlank, z, u, radius):
    """True where (z, u) lies more than one module outside the flank's limits."""
    m = blank.normal_module
    return (
        (z < blank.z_toe - m)
        | (z > blank.z_heel + m)
        | (u < -m)
        | (radius > blank.tip_radius(z) + m)
        | ~np.isfinite(radius)
    )


def contact_ellipse(k1, d1, k2, d2, n, delta):
    """Contact ellipse from both surfaces' principal curvatures (convex-positive).

    k_i (N, 2), d_i (N, 2, 3) in Sf, n (N, 3). Returns semi-axes (N, 2) (major,
    minor) and the major-axis direction (N, 3).
    """
    e1 = d1[:, 0, :]
    e1 = e1 - np.einsum("ni,ni->n", e1, n)[:, None] * n
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(n, e1)
    C = np.zeros((len(n), 2, 2))
    for k, d in ((k1, d1), (k2, d2)):
        for i in range(2):
            a = np.stack(
                [np.einsum("ni,ni->n", d[:, i], e1), np.einsum("ni,ni->n", d[:, i], e2)], axis=1
            )
            C += k[:, i, None, None] * a[:, :, None] * a[:, None, :]
    lam, vec = np.linalg.eigh(C)
    with np.errstate(divide="ignore", invalid="ignore"):
        axes = np.sqrt(2 * delta / lam)
    # relative curvature below 1e-9 of the largest: line contact, no finite ellipse
    axes = np.where(lam > 1e-9 * np.abs(lam[:, 1:]), axes, np.inf)
    major = vec[:, 0, 0, None] * e1 + vec[:, 1, 0, None] * e2
    return np.stack([axes[:, 0], axes[:, 1]], axis=1), major

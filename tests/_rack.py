"""The generating rack as a solid, without the equation of meshing: how deep a gear
point lies inside the rack tooth at each generating roll angle (tests of the
generated flanks: the envelope touches each point once and never passes through it;
an undercut flank's cut-away part is passed through)."""

import math

import numpy as np


def rack_depth(b, sigma: int, p, phis) -> np.ndarray:
    """Signed depth (m) of gear point ``p`` (gear frame) inside the rack tooth of flank
    ``sigma`` (-1 R, +1 L) of blank ``b`` at roll angles ``phis``: positive inside.

    The gear point in the fixed frame when the gear has turned by phi, then in rack axes
    relative to the moved rack (rack moved by -r_p phi along x); the depth is the
    smallest of the distances to the rack tooth's two flank planes, its tip plane and,
    in the corners, its tip rounding."""
    a, be, g = b.normal_pressure_angle, b.helix_angle, b.cone_angle
    m, rho, rp = b.normal_module, b.tool_tip_radius, b.reference_pitch_radius
    # rack axes in the fixed frame (x: motion, v: tilted outward, w: tilted axial)
    V = np.array([0, math.cos(g), -math.sin(g)])
    W = np.array([0, math.sin(g), math.cos(g)])
    tn = np.array([math.cos(be), 0, math.sin(be)])  # normal-section pitch direction, rack axes
    R = np.stack([np.array([1.0, 0, 0]), V, W], axis=1)  # rack axes -> fixed frame
    o = np.array([0, rp + b.profile_shift_xt * b.transverse_module, 0])
    c, s = np.cos(phis), np.sin(phis)
    f = np.stack([c * p[0] - s * p[1], s * p[0] + c * p[1], np.full_like(c, p[2])], 1)
    f[:, 0] += rp * phis
    q = (f - o) @ R  # rack axes (u, v, w)
    sn, vv = q @ tn, q[:, 1]  # normal-section coordinates
    s0 = sigma * math.pi * m / 4
    s1 = sigma * 3 * math.pi * m / 4  # the same rack tooth's other flank
    d_this = sigma * math.cos(a) * (sn - s0) + math.sin(a) * vv
    d_other = -sigma * math.cos(a) * (sn - s1) + math.sin(a) * vv
    d_tip = vv + b.tool_addendum
    vc = -b.tool_addendum + rho
    sc = s0 + sigma * (rho - math.sin(a) * vc) / math.cos(a)
    # the arc is the nearest boundary in the sector between its two tangency normals
    corner = (sigma * (sn - sc) <= 0) & (
        (sn - sc) * (-sigma * math.sin(a)) + (vv - vc) * math.cos(a) < 0
    )
    d_round = np.where(corner, rho - np.hypot(sn - sc, vv - vc), np.inf)
    return np.minimum(np.minimum(d_this, d_other), np.minimum(d_tip, d_round))


def deepest(b, sigma: int, p, span: float = 0.6, n: int = 24001) -> float:
    """Largest depth of ``p`` inside the rack over roll angles -span..span: a coarse
    sweep, then a fine one (4001 angles) about its largest."""
    phis = np.linspace(-span, span, n)
    coarse = rack_depth(b, sigma, p, phis)
    i = int(np.argmax(coarse))
    fine = rack_depth(b, sigma, p, np.linspace(phis[max(i - 2, 0)], phis[min(i + 2, n - 1)], 4001))
    return max(float(coarse.max()), float(fine.max()))

"""Rigid first contact by brute force: for every point of a grid over the pinion's real
flank, the gear angle at which the gear's real flank passes through it (Newton on
``r_f2(z_2, u_2, phi_2) = p``, 3 equations in 3 unknowns, seeded from the nearest point
of a grid over the gear's flank), and the first of these over the flank (least on the
drive side, largest on the coast side), zoomed in about the best grid points.

This is the definition of the unloaded TCA's gear angle (the rigid rotation to first
touch) without its contact conditions: no normals, no edge tangents. Shared by
tests/test_tca_edge.py."""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from gearbox.surface import flank_points, involute_start, tip_parameter
from gearbox.tca.contact import flank_frames


def _first(side, g, ok):
    g = np.where(ok, g, np.inf if side == "R" else -np.inf)
    i = int(np.argmin(g) if side == "R" else np.argmax(g))
    return i, g


def _touch_angles(p, g, asm, side, phi1, Z, F, phi2_guess):
    """Gear angle of the reference tooth at which each pinion point (z, profile
    fraction F between the involute's start and the tip) lies on the gear's real flank;
    and whether it does."""
    ut, _ = tip_parameter(p, side, Z)
    uf = involute_start(p, side, Z)
    U = uf + (ut - uf) * F
    P = flank_frames(p, side, Z, U, asm.pinion_matrix(np.full(Z.size, phi1)), asm.pinion_origin)[
        "r"
    ]
    zs2 = np.linspace(g.z_toe - 0.2 * g.face_width, g.z_heel + 0.2 * g.face_width, 121)
    ut2, _ = tip_parameter(g, side, zs2)
    uf2 = involute_start(g, side, zs2)
    U2 = (uf2[:, None] + (ut2 - uf2)[:, None] * np.linspace(-0.2, 1.2, 57)[None, :]).ravel()
    Z2 = np.repeat(zs2, 57)
    q = flank_frames(
        g, side, Z2, U2, asm.gear_matrix(np.full(Z2.size, phi2_guess)), asm.gear_origin
    )
    _, nn = cKDTree(q["r"]).query(P)
    x = np.stack([Z2[nn], U2[nn], np.full(Z.size, phi2_guess)], axis=1)
    a2, O2 = asm.gear_axis, asm.gear_origin
    for _ in range(60):
        f2 = flank_frames(g, side, x[:, 0], x[:, 1], asm.gear_matrix(x[:, 2]), O2)
        res = f2["r"] - P
        if np.max(np.abs(res)) < 1e-12:
            break
        J = np.stack([f2["rz"], f2["ru"], np.cross(a2, f2["r"] - O2)], axis=-1)
        dx = np.linalg.solve(J, -res[..., None])[..., 0]
        x += np.clip(dx, [-5e-3, -5e-3, -0.05], [5e-3, 5e-3, 0.05])
    ok = np.linalg.norm(res, axis=1) < 1e-10
    r2 = flank_points(g, side, x[:, 0], x[:, 1], involute_only=True).radius
    ok &= (x[:, 0] >= g.z_toe - 1e-12) & (x[:, 0] <= g.z_heel + 1e-12)
    ok &= x[:, 1] >= involute_start(g, side, x[:, 0]) - 1e-12
    ok &= r2 <= g.tip_radius(x[:, 0]) + 1e-12
    return x[:, 2], ok


def rigid_first_contact(p, g, asm, side, phi1, phi2_guess, *, n=61, starts=6, zooms=6):
    """First touch (gear angle of the reference tooth, rad) of pinion tooth 0 at pinion
    angle ``phi1`` with the gear tooth near ``phi2_guess``; NaN where none touches."""

    def grid(box, nz, nf):
        z0, z1, f0, f1 = box
        zs, fs = np.linspace(z0, z1, nz), np.linspace(f0, f1, nf)
        return np.repeat(zs, nf), np.tile(fs, nz), (z1 - z0) / (nz - 1), (f1 - f0) / (nf - 1)

    Z, F, hz, hf = grid((p.z_toe, p.z_heel, 0.0, 1.0), 4 * n, n)
    ang, ok = _touch_angles(p, g, asm, side, phi1, Z, F, phi2_guess)
    if not ok.any():
        return float("nan")
    _, gg = _first(side, ang, ok)
    picks = []
    for i in np.argsort(gg if side == "R" else -gg):
        if not np.isfinite(gg[i]) or len(picks) == starts:
            break
        if all(abs(Z[i] - Z[j]) > 3 * hz or abs(F[i] - F[j]) > 3 * hf for j in picks):
            picks.append(i)
    best = []
    for i in picks:
        z, f, dz, df, val = Z[i], F[i], hz, hf, gg[i]
        for _ in range(zooms):
            box = (
                max(p.z_toe, z - 2 * dz),
                min(p.z_heel, z + 2 * dz),
                max(0.0, f - 2 * df),
                min(1.0, f + 2 * df),
            )
            Zb, Fb, dz, df = grid(box, n, n)
            a, o = _touch_angles(p, g, asm, side, phi1, Zb, Fb, phi2_guess)
            if not o.any():
                break
            k, gb = _first(side, a, o)
            z, f, val = Zb[k], Fb[k], gb[k]
        best.append(val)
    return float(np.min(best) if side == "R" else np.max(best))

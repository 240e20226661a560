"""The tooth of one slice as a plane-strain finite-element model (a check and an
option for the beam of :mod:`gearbox.ltca.slice_model`).

The beam of the slice model (Timoshenko bending, shear with the factor 1.2, axial
compression) reads a tooth loaded near its root as a short cantilever; the
finite-element tooth clamped at the root circle is 1.3 to 3 times stiffer there
(``benchmarks/ltca_slice_vs_fe.py``): a beam's shear strain is spread evenly over
its length, while a load close to a clamp is carried straight into it. This module
solves the same slice, the tooth alone, as a 2-D elastic body: the generated
section (trochoidal fillet of the rack's tip round from the root circle, involute
above it up to the tip circle; :func:`~gearbox.ltca.slice_model.fillet_root`),
clamped along the root circle between the fillets' ends, plane strain, a unit
line load along the transverse line of action at the flank point of each radius,
and the displacement along the load read where the load's line crosses the tooth's
centre line (as ``slice_compliance(beam_at="centre_line")`` and the FE level's
``centre`` reading).

Mesh: biquadratic (9-node) isoparametric quadrilaterals on the map ``(s, t) ->
(rho(s), t psi(rho))`` in polar coordinates (rho the radius, psi(rho) the half
tooth-thickness angle of the section, t in [-1, 1] across the tooth), graded towards
the root (``rho = r_f + (r_a - r_f) s^2``); 3 x 3 Gauss points. One sparse
factorisation per section, one solve per load radius.
"""

from __future__ import annotations

import numpy as np

from .slice_model import _fillet_points, _half_angle, fillet_root

__all__ = ["fe_tooth_compliance", "section_outline"]

_G3 = np.array([-np.sqrt(0.6), 0.0, np.sqrt(0.6)])
_W3 = np.array([5.0, 8.0, 5.0]) / 9.0


def _lagrange3(x):
    """Quadratic Lagrange functions on nodes -1, 0, 1 and their derivatives."""
    n = np.stack([0.5 * x * (x - 1.0), 1.0 - x**2, 0.5 * x * (x + 1.0)], axis=-1)
    d = np.stack([x - 0.5, -2.0 * x, x + 0.5], axis=-1)
    return n, d


def section_outline(sections, i: int = 0, *, normal: bool = True, samples: int = 400):
    """The flank of section ``i`` as ``(rho, psi)``: radius from the root circle
    (where the fillet ends) to the tip circle, increasing, and the half
    tooth-thickness angle at it (fillet below the fillet's top, involute above)."""
    theta_f, rg, sc, yc, rr, alpha = (np.atleast_1d(v)[i] for v in fillet_root(sections, normal))
    rb = float(sections.base_radius[i])
    psi_b = float(sections.base_half_angle[i])
    ra = float(sections.tip_radius[i])
    phi0 = sc / rg
    phi1 = (sc + yc / np.tan(alpha)) / rg
    phi = np.linspace(phi0, phi1, samples)
    rho_f, psi_f = _fillet_points(phi, rg, sc, yc, rr)
    top = max(float(rho_f[-1]), rb)
    keep = rho_f < top
    rho_i = np.linspace(top, ra, samples)
    psi_i = _half_angle(rho_i, rb, psi_b)
    rho = np.concatenate([rho_f[keep], rho_i])
    psi = np.concatenate([psi_f[keep], psi_i])
    order = np.argsort(rho, kind="stable")
    rho, psi = rho[order], psi[order]
    ok = np.concatenate([[True], np.diff(rho) > 0])
    return rho[ok], psi[ok]


def _mesh(rho_o, psi_o, n_along: int, n_across: int):
    """Node coordinates (x across, y along the centre line) on a (2 n_along + 1) x
    (2 n_across + 1) grid, and the element connectivity (9 nodes each)."""
    rf, ra = rho_o[0], rho_o[-1]
    s = np.linspace(0.0, 1.0, 2 * n_along + 1)
    rho = rf + (ra - rf) * s**2
    psi = np.interp(rho, rho_o, psi_o)
    t = np.linspace(-1.0, 1.0, 2 * n_across + 1)
    ang = t[None, :] * psi[:, None]
    x = rho[:, None] * np.sin(ang)
    y = rho[:, None] * np.cos(ang)
    nt = t.size
    idx = np.arange(rho.size * nt).reshape(rho.size, nt)
    ea, ec = np.meshgrid(np.arange(n_along), np.arange(n_across), indexing="ij")
    ea, ec = ea.ravel(), ec.ravel()
    # node order: (i, j) with i along s (0, 1, 2), j across (0, 1, 2), i major
    conn = np.stack([idx[2 * ea + i, 2 * ec + j] for i in range(3) for j in range(3)], axis=1)
    return np.column_stack([x.ravel(), y.ravel()]), conn, idx, rho


def _stiffness(xy, conn, E, nu):
    from scipy.sparse import coo_matrix

    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    D = np.array([[lam + 2 * mu, lam, 0.0], [lam, lam + 2 * mu, 0.0], [0.0, 0.0, mu]])
    Xe = xy[conn]  # (ne, 9, 2)
    ne = conn.shape[0]
    Ke = np.zeros((ne, 18, 18))
    for a, wa in zip(_G3, _W3, strict=True):
        na, da = _lagrange3(a)
        for b, wb in zip(_G3, _W3, strict=True):
            nb, db = _lagrange3(b)
            dNs = np.outer(da, nb).ravel()  # d/ds, node order i major
            dNt = np.outer(na, db).ravel()
            J = np.stack([dNs @ Xe, dNt @ Xe], axis=1)  # (ne, 2, 2): rows s, t
            det = J[:, 0, 0] * J[:, 1, 1] - J[:, 0, 1] * J[:, 1, 0]
            inv = (
                np.stack(
                    [
                        np.stack([J[:, 1, 1], -J[:, 0, 1]], axis=1),
                        np.stack([-J[:, 1, 0], J[:, 0, 0]], axis=1),
                    ],
                    axis=1,
                )
                / det[:, None, None]
            )
            # dN/dx, dN/dy: inv(J) @ [dNs; dNt]
            dN = np.einsum("eij,jn->ein", inv, np.stack([dNs, dNt]))
            B = np.zeros((ne, 3, 18))
            B[:, 0, 0::2] = dN[:, 0]
            B[:, 1, 1::2] = dN[:, 1]
            B[:, 2, 0::2] = dN[:, 1]
            B[:, 2, 1::2] = dN[:, 0]
            Ke += np.einsum("eki,kl,elj->eij", B, D, B) * (np.abs(det) * wa * wb)[:, None, None]
    dofs = np.stack([2 * conn, 2 * conn + 1], axis=2).reshape(ne, 18)
    rows = np.repeat(dofs, 18, axis=1).ravel()
    cols = np.tile(dofs, (1, 18)).ravel()
    n = 2 * xy.shape[0]
    return coo_matrix((Ke.ravel(), (rows, cols)), shape=(n, n)).tocsc()


def fe_tooth_compliance(
    sections,
    youngs_modulus: float,
    poisson_ratio: float,
    *,
    normal: bool = True,
    n_along: int = 48,
    n_across: int = 10,
) -> np.ndarray:
    """Tooth compliance of slices (m per N/m of transverse line load, along the load),
    the tooth alone clamped at the root circle, read where the load's line of action
    crosses the centre line; shape (n,), one value per point of ``sections``.

    ``sections``: :class:`~gearbox.ltca.grid.ToothSections` (use
    :func:`~gearbox.ltca.slice_model.normal_section` for helical slices, as the beam
    does). Points whose section (everything but the load radius) is the same share
    one model. ``n_along`` / ``n_across``: elements along and across the tooth.
    """
    from scipy.sparse.linalg import splu

    n = np.asarray(sections.radius).size
    keys = np.column_stack(
        [
            sections.base_radius,
            sections.base_half_angle,
            sections.tip_radius,
            sections.profile_shift,
            sections.normal_module,
            sections.normal_pressure_angle,
            sections.helix_angle,
            sections.rack_dedendum,
            sections.rack_root_radius,
            sections.teeth,
        ]
    )
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    out = np.empty(n)
    for g, i0 in enumerate(first):
        pts = np.flatnonzero(inverse.ravel() == g)
        rho_o, psi_o = section_outline(sections, int(i0), normal=normal)
        xy, conn, idx, rho_nodes = _mesh(rho_o, psi_o, n_along, n_across)
        K = _stiffness(xy, conn, youngs_modulus, poisson_ratio)
        fixed = np.concatenate([2 * idx[0], 2 * idx[0] + 1])  # the root circle
        free = np.setdiff1d(np.arange(K.shape[0]), fixed)
        lu = splu(K[free][:, free])
        rb = float(sections.base_radius[i0])
        psi_b = float(sections.base_half_angle[i0])
        rL = np.asarray(sections.radius, float)[pts]
        psi_L = _half_angle(rL, rb, psi_b)
        a1 = np.arccos(np.clip(rb / rL, -1.0, 1.0)) - psi_L
        xR = rL * np.cos(psi_L) - rL * np.sin(psi_L) * np.tan(a1)  # on the centre line
        F = np.zeros((K.shape[0], pts.size))
        edge = idx[:, -1]  # the flank t = +1, nodes along s
        s_L = np.sqrt((rL - rho_nodes[0]) / (rho_nodes[-1] - rho_nodes[0]))
        for k, (sl, a) in enumerate(zip(s_L, a1, strict=True)):
            e = min(int(sl * n_along), n_along - 1)
            loc = 2.0 * (sl * n_along - e) - 1.0
            w, _ = _lagrange3(np.array(loc))
            nodes = edge[2 * e : 2 * e + 3]
            F[2 * nodes, k] = -np.cos(a) * w
            F[2 * nodes + 1, k] = -np.sin(a) * w
        U = np.zeros_like(F)
        U[free] = lu.solve(F[free])
        centre = idx[:, idx.shape[1] // 2]  # t = 0: x = 0, y = rho
        for k, (xr, a) in enumerate(zip(xR, a1, strict=True)):
            ux = np.interp(xr, rho_nodes, U[2 * centre, k])
            uy = np.interp(xr, rho_nodes, U[2 * centre + 1, k])
            out[pts[k]] = -(ux * np.cos(a) + uy * np.sin(a))
    return out

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

from dataclasses import replace

import numpy as np

from ..geometry.involute import inv
from .grid import ToothSections
from .slice_model import _fillet_points, _half_angle, fillet_root, fillet_top

__all__ = [
    "fe_tooth_compliance",
    "neighbour_influence",
    "section_outline",
    "whole_gear_compliance",
    "whole_gear_influence",
]

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
    rb = float(np.atleast_1d(sections.base_radius)[i])
    psi_b = float(np.atleast_1d(sections.base_half_angle)[i])
    ra = float(np.atleast_1d(sections.tip_radius)[i])
    phi0 = sc / rg
    phi1, top = (float(np.atleast_1d(v)[i]) for v in fillet_top(sections, normal))
    phi = np.linspace(phi0, phi1, samples)
    rho_f, psi_f = _fillet_points(phi, rg, sc, yc, rr)
    keep = rho_f < top
    rho_i = np.linspace(top, ra, samples)
    psi_i = _half_angle(rho_i, rb, psi_b)
    rho = np.concatenate([rho_f[keep], rho_i])
    psi = np.concatenate([psi_f[keep], psi_i])
    order = np.argsort(rho, kind="stable")
    rho, psi = rho[order], psi[order]
    ok = np.concatenate([[True], np.diff(rho) > 0])
    return rho[ok], psi[ok]


def _mesh(rho_o, psi_o, n_along: int, n_across: int, grade: float = 1.0):
    """Node coordinates (x across, y along the centre line) on a (2 n_along + 1) x
    (2 n_across + 1) grid, the element connectivity (9 nodes each), the node grid, the
    nodes' radii, across-coordinates ``t`` and half-angles at the radii. ``grade`` > 1
    makes the elements finer towards the loaded flank ``t = +1`` (``t = 1 - 2 (1 -
    u)^grade``, u even)."""
    rf, ra = rho_o[0], rho_o[-1]
    s = np.linspace(0.0, 1.0, 2 * n_along + 1)
    rho = rf + (ra - rf) * s**2
    psi = np.interp(rho, rho_o, psi_o)
    t = 1.0 - 2.0 * (1.0 - np.linspace(0.0, 1.0, 2 * n_across + 1)) ** grade
    t[-1] = 1.0
    ang = t[None, :] * psi[:, None]
    x = rho[:, None] * np.sin(ang)
    y = rho[:, None] * np.cos(ang)
    nt = t.size
    idx = np.arange(rho.size * nt).reshape(rho.size, nt)
    ea, ec = np.meshgrid(np.arange(n_along), np.arange(n_across), indexing="ij")
    ea, ec = ea.ravel(), ec.ravel()
    # node order: (i, j) with i along s (0, 1, 2), j across (0, 1, 2), i major
    conn = np.stack([idx[2 * ea + i, 2 * ec + j] for i in range(3) for j in range(3)], axis=1)
    return np.column_stack([x.ravel(), y.ravel()]), conn, idx, rho, t, psi


def _value_at(xy, idx, rho_nodes, t_nodes, psi_nodes, u, point) -> tuple[float, float]:
    """Displacement ``(ux, uy)`` of the solution ``u`` (shape (n_dofs,)) at ``point``
    inside the tooth of node grid ``idx``: the element found from the point's polar
    coordinates, its local coordinates by Newton's method on the isoparametric map."""
    n_along = (idx.shape[0] - 1) // 2
    n_across = (idx.shape[1] - 1) // 2
    rho = float(np.hypot(*point))
    s = np.sqrt(np.clip((rho - rho_nodes[0]) / (rho_nodes[-1] - rho_nodes[0]), 0.0, 1.0))
    t = np.arctan2(point[0], point[1]) / np.interp(rho, rho_nodes, psi_nodes)
    ea = min(int(s * n_along), n_along - 1)
    ec = int(np.clip(np.searchsorted(t_nodes[::2], t) - 1, 0, n_across - 1))
    for _ in range(3):  # the element, moved once or twice where the guess was off
        nodes = idx[2 * ea : 2 * ea + 3, 2 * ec : 2 * ec + 3].ravel()
        X = xy[nodes]
        xi = np.array([2.0 * (s * n_along - ea) - 1.0, 0.0])
        lo, hi = t_nodes[2 * ec], t_nodes[2 * ec + 2]
        xi[1] = np.clip(2.0 * (t - lo) / (hi - lo) - 1.0, -1.0, 1.0)
        for _ in range(20):
            na, da = _lagrange3(np.array(xi[0]))
            nb, db = _lagrange3(np.array(xi[1]))
            r = np.outer(na, nb).ravel() @ X - point
            J = np.column_stack([np.outer(da, nb).ravel() @ X, np.outer(na, db).ravel() @ X])
            step = np.linalg.solve(J, r)
            xi = xi - step
            if np.max(np.abs(step)) < 1e-12:
                break
        move = np.where(xi > 1.0 + 1e-9, 1, np.where(xi < -1.0 - 1e-9, -1, 0))
        if not move.any():
            break
        ea = int(np.clip(ea + move[0], 0, n_along - 1))
        ec = int(np.clip(ec + move[1], 0, n_across - 1))
    na, _ = _lagrange3(np.array(xi[0]))
    nb, _ = _lagrange3(np.array(xi[1]))
    w = np.outer(na, nb).ravel()
    return float(w @ u[2 * nodes]), float(w @ u[2 * nodes + 1])


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


def _line_loads(n_dofs, tooth, rho_nodes, sections, i0, radii):
    """Unit line loads on the flank ``t = +1`` of the tooth whose node grid is
    ``tooth``, along the transverse line of action at ``radii`` (clipped to the tooth):
    the load vectors, shape (n_dofs, n), the radii, the half-angles there and the
    loads' angles to the centre line's normal."""
    n_along = (tooth.shape[0] - 1) // 2
    rb = float(sections.base_radius[i0])
    psi_b = float(sections.base_half_angle[i0])
    rL = np.clip(np.asarray(radii, float), rho_nodes[0], rho_nodes[-1])
    psi_L = _half_angle(rL, rb, psi_b)
    a1 = np.arccos(np.clip(rb / rL, -1.0, 1.0)) - psi_L
    F = np.zeros((n_dofs, rL.size))
    edge = tooth[:, -1]  # the flank t = +1, nodes along s
    s_L = np.sqrt((rL - rho_nodes[0]) / (rho_nodes[-1] - rho_nodes[0]))
    for k, (sl, a) in enumerate(zip(s_L, a1, strict=True)):
        e = min(int(sl * n_along), n_along - 1)
        w, _ = _lagrange3(np.array(2.0 * (sl * n_along - e) - 1.0))
        nodes = edge[2 * e : 2 * e + 3]
        F[2 * nodes, k] = -np.cos(a) * w
        F[2 * nodes + 1, k] = -np.sin(a) * w
    return F, rL, psi_L, a1


def _read_loads(K, fixed, xy, tooth, grid, sections, i0, radii, depth=None) -> np.ndarray:
    """Unit line loads on the flank ``t = +1`` of the tooth whose node grid (rows along
    s, columns across t) is ``tooth``, along the transverse line of action at
    ``radii``, and the displacement along each load (m per N/m) where its line crosses
    the tooth's centre line (``depth`` None) or at ``depth`` (m, scalar or per
    radius) below the flank along the load's line, at most the centre line's
    distance: one factorisation of ``K`` with ``fixed`` dofs held. ``grid``: the
    tooth mesh's node radii, across-coordinates and half-angles (:func:`_mesh`)."""
    from scipy.sparse.linalg import splu

    rho_nodes, t_nodes, psi_nodes = grid
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    lu = splu(K[free][:, free].tocsc())
    F, rL, psi_L, a1 = _line_loads(K.shape[0], tooth, rho_nodes, sections, i0, radii)
    U = np.zeros_like(F)
    U[free] = lu.solve(F[free])
    px, py = rL * np.sin(psi_L), rL * np.cos(psi_L)  # the loaded flank points
    to_centre = px / np.cos(a1)  # along the load's line to the centre line
    reach = to_centre
    if depth is not None:
        # and not below the root circle (near it the load's line points into the root)
        b = px * np.cos(a1) + py * np.sin(a1)
        disc = b**2 - (rL**2 - rho_nodes[0] ** 2)
        to_root = np.where(disc > 0.0, b - np.sqrt(np.maximum(disc, 0.0)), np.inf)
        to_root = np.where(to_root > 0.0, to_root, np.inf)
        reach = np.minimum(np.minimum(np.broadcast_to(depth, rL.shape), to_centre), to_root)
    out = np.empty(rL.size)
    centre = tooth[:, tooth.shape[1] // 2]  # the node column t = 0, on the centre line
    for k, (a, d) in enumerate(zip(a1, reach, strict=True)):
        ca, sa = np.cos(a), np.sin(a)
        point = np.array([px[k] - d * ca, py[k] - d * sa])
        if depth is None:  # on the centre line, at radius point[1]
            ux = np.interp(point[1], rho_nodes, U[2 * centre, k])
            uy = np.interp(point[1], rho_nodes, U[2 * centre + 1, k])
        else:
            ux, uy = _value_at(xy, tooth, rho_nodes, t_nodes, psi_nodes, U[:, k], point)
        out[k] = -(ux * ca + uy * sa)
    # a point held on the clamped root circle reads zero, up to the interpolation's noise
    return out if depth is None else np.maximum(out, 0.0)


def _solve_section(
    sections, i0, radii, E, nu, normal, n_along, n_across, depth=None, grade=1.0
) -> np.ndarray:
    """Compliance of section ``i0``'s tooth clamped at the root circle (along the load,
    read at the centre line or at ``depth``: :func:`_read_loads`) for unit line loads
    at ``radii``."""
    rho_o, psi_o = section_outline(sections, int(i0), normal=normal)
    xy, conn, idx, rho_nodes, t_nodes, psi_nodes = _mesh(rho_o, psi_o, n_along, n_across, grade)
    K = _stiffness(xy, conn, E, nu)
    fixed = np.concatenate([2 * idx[0], 2 * idx[0] + 1])  # the root circle
    grid = (rho_nodes, t_nodes, psi_nodes)
    return _read_loads(K, fixed, xy, idx, grid, sections, i0, radii, depth)


def _whole_gear(sections, E, nu, teeth, normal, i0, n_along=24, n_across=6, n_gap=6, n_rim=8):
    """The plane-strain whole gear of section ``i0`` (:func:`whole_gear_compliance`):
    its stiffness, the fixed dofs (the bore), the nodes, the node grid of every tooth
    (tooth k turned by ``k`` pitches towards ``+x``, the side the loaded flank ``t = +1``
    of tooth 0 faces) and the tooth mesh's node radii, across-coordinates and
    half-angles."""
    rho_o, psi_o = section_outline(sections, int(i0), normal=normal)
    xy_t, conn_t, idx_t, rho_nodes, t_nodes, psi_nodes = _mesh(rho_o, psi_o, n_along, n_across)
    rf, theta_f = float(rho_o[0]), float(psi_o[0])
    z = int(teeth)
    nt = 2 * n_across + 1
    pitch = 2.0 * np.pi / z
    # rim: per pitch the tooth's root nodes (uniform in angle) and the gap to the next
    per = np.concatenate(
        [
            np.linspace(-theta_f, theta_f, nt)[:-1],
            np.linspace(theta_f, pitch - theta_f, 2 * n_gap + 1)[:-1],
        ]
    )
    ang = (per[None, :] + pitch * np.arange(z)[:, None]).ravel()
    na = ang.size
    u = np.linspace(0.0, 1.0, 2 * n_rim + 1)
    bore = float(np.asarray(sections.bore_radius, float).ravel()[i0])
    rr = bore + (rf - bore) * (1.0 - (1.0 - u) ** 2)  # finer towards the root circle
    ridx = np.arange(rr.size * na).reshape(rr.size, na)
    xy = [
        np.column_stack([(rr[:, None] * np.sin(ang)).ravel(), (rr[:, None] * np.cos(ang)).ravel()])
    ]
    ii, jj = np.meshgrid(np.arange(n_rim), np.arange(na // 2), indexing="ij")
    ii, jj = ii.ravel(), jj.ravel()
    conn = [
        np.stack([ridx[2 * ii + a, (2 * jj + b) % na] for a in range(3) for b in range(3)], axis=1)
    ]
    count = ridx.size
    tooth_ids = []
    for k in range(z):
        gid = np.empty_like(idx_t)
        gid[0] = ridx[-1, (k * per.size + np.arange(nt)) % na]  # on the rim's root circle
        gid[1:] = count + np.arange(idx_t[1:].size).reshape(idx_t.shape[0] - 1, nt)
        count += idx_t[1:].size
        c, s = np.cos(pitch * k), np.sin(pitch * k)
        q = xy_t[idx_t[1:].ravel()]
        xy.append(np.column_stack([c * q[:, 0] + s * q[:, 1], -s * q[:, 0] + c * q[:, 1]]))
        local = np.empty(xy_t.shape[0], int)
        local[idx_t.ravel()] = gid.ravel()
        conn.append(local[conn_t])
        tooth_ids.append(gid)
    xy = np.concatenate(xy)
    K = _stiffness(xy, np.concatenate(conn), E, nu)
    fixed = np.concatenate([2 * ridx[0], 2 * ridx[0] + 1])  # the bore
    return K, fixed, xy, tooth_ids, (rho_nodes, t_nodes, psi_nodes)


def whole_gear_compliance(
    sections,
    youngs_modulus: float,
    poisson_ratio: float,
    teeth: int,
    *,
    normal: bool = True,
    i0: int = 0,
    n_along: int = 24,
    n_across: int = 6,
    n_gap: int = 6,
    n_rim: int = 8,
) -> np.ndarray:
    """The whole gear of section ``i0`` as a plane-strain FE body: ``teeth`` teeth on a
    rim from the bore (clamped) to the root circle, tooth 0 loaded at each of
    ``sections.radius`` in turn, read as :func:`fe_tooth_compliance` (m per N/m),
    shape (n,). For checks of the foundation (the slices' Sainsot term) against the
    3-D FE level (``benchmarks/ltca_slice_vs_fe.py``); ``teeth`` must be an integer,
    so a helical gear's virtual spur gear is rounded by the caller."""
    K, fixed, xy, tooth_ids, grid = _whole_gear(
        sections, youngs_modulus, poisson_ratio, teeth, normal, i0, n_along, n_across, n_gap, n_rim
    )
    return _read_loads(K, fixed, xy, tooth_ids[0], grid, sections, i0, sections.radius)


def whole_gear_influence(
    sections,
    youngs_modulus: float,
    poisson_ratio: float,
    teeth: int,
    radii,
    offsets=(-2, -1, 0, 1, 2),
    *,
    normal: bool = True,
    i0: int = 0,
    **mesh,
) -> np.ndarray:
    """Influence of a unit line load on tooth 0 of the plane-strain whole gear
    (:func:`whole_gear_compliance`) on the same flank of its neighbours (m per N/m),
    shape ``(len(offsets), n_read, n_load)``: entry ``[o, i, j]`` is the displacement of
    tooth ``offsets[o]`` along its own load line at ``radii[i]``, read where that line
    crosses its centre line, under the load on tooth 0 at ``radii[j]``. Offset +1 is
    the tooth the loaded flank faces (across the tooth space its outward normal points
    into); offset 0 is :func:`whole_gear_compliance`'s reading. ``mesh``: its
    ``n_along``, ``n_across``, ``n_gap`` and ``n_rim`` (the same defaults)."""
    from scipy.sparse.linalg import splu

    E, nu = float(youngs_modulus), float(poisson_ratio)
    K, fixed, xy, tooth_ids, (rho_nodes, _, _) = _whole_gear(
        sections, E, nu, teeth, normal, i0, **mesh
    )
    z = len(tooth_ids)
    pitch = 2.0 * np.pi / z
    F, rL, psi_L, a1 = _line_loads(K.shape[0], tooth_ids[0], rho_nodes, sections, i0, radii)
    free = np.setdiff1d(np.arange(K.shape[0]), fixed)
    U = np.zeros_like(F)
    U[free] = splu(K[free][:, free].tocsc()).solve(F[free])
    ca, sa = np.cos(a1), np.sin(a1)
    # where each load's line crosses the centre line (the radius there)
    centre_radius = rL * np.cos(psi_L) - rL * np.sin(psi_L) / ca * sa
    out = np.empty((len(offsets), rL.size, rL.size))
    for o, off in enumerate(offsets):
        gid = tooth_ids[int(off) % z]
        centre = gid[:, gid.shape[1] // 2]
        c, s = np.cos(pitch * off), np.sin(pitch * off)
        for j in range(rL.size):  # the load; read at every radius of tooth off
            ux = np.interp(centre_radius, rho_nodes, U[2 * centre, j])
            uy = np.interp(centre_radius, rho_nodes, U[2 * centre + 1, j])
            lx, ly = c * ux - s * uy, s * ux + c * uy  # into the tooth's own frame
            out[o, :, j] = -(lx * ca + ly * sa)
    return out


#: Tooth offsets of :func:`neighbour_influence` (beyond them, the outermost one's).
NEIGHBOURS = (1, 2, 3)

#: Load and reading radii of :func:`neighbour_influence`: fractions of the roll length
#: from the root (or base) circle to the tip circle.
NEIGHBOUR_ROLL = (0.05, 0.236, 0.422, 0.608, 0.794, 0.98)

#: The plane-strain whole gear's mesh for :func:`neighbour_influence` (``n_along``,
#: ``n_across``, ``n_gap``, ``n_rim``): against :func:`whole_gear_influence`'s default
#: mesh (24, 6, 6, 8) its couplings between teeth one to three pitches apart read within
#: 1.9 / 2.0 % (mean 0.3 / 0.4 %) on case 03's pinion / gear (z_v 34 / 46), the two
#: Maxwell-Betti readings averaged on both, in 0.07 / 0.10 s against 1.1 / 1.0 s
#: (tested).
NEIGHBOUR_MESH = (8, 2, 2, 3)

_NEIGHBOURS: dict[tuple, tuple] = {}


def neighbour_influence(section, poisson_ratio: float, mesh=NEIGHBOUR_MESH):
    """What a line load on one tooth of the plane-strain whole gear moves its
    neighbours by, for the couplings between tooth pairs: ``(radii, c)`` with the
    :data:`NEIGHBOUR_ROLL` radii of ``section`` (the one-row normal section of a tooth,
    m) and ``c`` of shape ``(len(NEIGHBOURS), n, n)``: Young's modulus times the
    displacement of the tooth ``d`` pitches in front of the loaded flank
    (:data:`NEIGHBOURS`; :func:`whole_gear_influence`'s offset +d) along its own load
    line at radius ``i`` under a unit line load at radius ``j`` on the loaded tooth,
    averaged with what Maxwell-Betti makes the same entry: the tooth ``d`` pitches
    behind, read at ``j`` under the load at ``i`` (the two readings, taken where the
    load lines cross the centre lines, agree within 1.4 % at contact points on the
    tested gears). Per unit width and times E it depends on the section's shape and
    Poisson's ratio only: kept per shape (rounded as the tooth tables', with the bore
    and Poisson's ratio) for the process, solved for the key's own gear
    (:func:`key_section`), so that what a process ran before does not change it. The
    profile shift is taken at its cell's centre, not read between lattice steps as the
    tooth tables do: moving case 03's pinion by one step (0.02) moves its couplings by
    0.4 % of the largest, against the -5.3 .. +8.3 % by which they meet the FE level's."""
    one = section.take(np.array([0]))
    m = float(np.asarray(one.normal_module, float).ravel()[0])
    bore = float(np.asarray(one.bore_radius, float).ravel()[0])
    shape = _shape_keys(one)[0]
    key = (
        tuple(shape.tolist()),
        round(bore / m / 0.02),
        round(float(poisson_ratio), 4),
        tuple(mesh),
    )
    got = _NEIGHBOURS.get(key)
    if got is None:
        # the key's own gear, not the first one met that rounds to it (module doc)
        one = replace(key_section(shape), bore_radius=np.array([key[1] * 0.02 * _KEY_MODULE]))
        rb, rf, ra = (
            float(np.ravel(a)[0]) for a in (one.base_radius, one.root_radius, one.tip_radius)
        )
        x0, x1 = np.sqrt(max(rf**2 - rb**2, 0.0)), np.sqrt(ra**2 - rb**2)
        radii = np.sqrt(rb**2 + (x0 + (x1 - x0) * np.asarray(NEIGHBOUR_ROLL)) ** 2)
        rows = replace(one.take(np.zeros(radii.size, int)), radius=radii)
        z = int(round(float(np.ravel(one.teeth)[0])))
        offsets = [d for k in NEIGHBOURS for d in (k, -k)]
        n_along, n_across, n_gap, n_rim = mesh
        # E = 1: the displacement times E
        u = whole_gear_influence(
            rows,
            1.0,
            key[2],
            z,
            radii,
            offsets,
            n_along=n_along,
            n_across=n_across,
            n_gap=n_gap,
            n_rim=n_rim,
        )
        c = 0.5 * (u[0::2] + np.swapaxes(u[1::2], 1, 2))
        got = (radii / _KEY_MODULE, c)
        if len(_NEIGHBOURS) >= _TABLES_MAX:
            _NEIGHBOURS.clear()
        _NEIGHBOURS[key] = got
    return got[0] * m, got[1]


#: Tables of solved sections: key (the section's shape, rounded; Poisson's ratio; mesh) ->
#: (heights, compliance times Young's modulus: a plane-strain body's compliance per
#: unit width times E depends on its shape and Poisson's ratio only; the cubic spline
#: through them, built once).
_TABLES: dict[tuple, tuple] = {}
_TABLES_MAX = 512

#: Load heights per table, spaced evenly in roll length from the involute's start (or
#: the fillet's top, whichever is higher) to the tip; a cubic spline between them.
#: 25 against 13 took the tables' rms error against each section solved alone from
#: 0.17-0.24 % to 0.04-0.11 % on the paper's cases, at 0-10 % more time (one
#: factorisation per table either way; ``benchmarks/ltca_slice_tables.py``).
TABLE_RADII = 25

#: Steps of the section's shape in the table key (:func:`_shape_keys`): the number of
#: teeth; the profile shift coefficient (the tables' lattice along it: a section takes
#: the two tables either side, linearly); the root radius's and the tip radius's
#: departures from the generated tooth and the base radius, over the normal module; the
#: base half-angle's departure (rad); pressure and helix angles (rad) and the basic
#: rack's dedendum and root radius over the module. Along a beveloid's face only the
#: profile shift changes (the tip and root cones follow it), so the other steps can be
#: fine at no cost: a pair's gear meets one cell of them, and its face a few lattice
#: steps of profile shift. Against every section solved on its own (``tabulated=False``)
#: the tables read the paper's cases' slices within 0.7 % (rms 0.11 %; tested), and a
#: lattice four times finer changes that by less than 0.02 points
#: (``benchmarks/ltca_slice_tables.py``).
KEY_STEPS = (1.0, 0.02, 0.002, 0.002, 0.002, 2e-4, 1e-4, 1e-4, 1e-3, 1e-3)

#: The column of :data:`KEY_STEPS` the tables interpolate along (the profile shift).
_LATTICE = 1


def _generated(base_radius, profile_shift, pressure_angle, helix_angle, module, dedendum, normal):
    """Pitch radius and root radius (m) and base half-angle (rad) of the tooth a basic
    rack generates on the base circle ``base_radius``: a virtual spur section of the normal section
    (``normal``, as :func:`~gearbox.ltca.slice_model.normal_section` makes them) or a
    transverse section (helix angle ``helix_angle``), as
    :func:`~gearbox.ltca.slice_model.fillet_root` reads the rack: pitch radius
    ``r = r_b / cos(alpha)``, ``r_f = r - (h_fP - x) m_n``, ``psi_b = (pi / 2 + 2 x
    tan(alpha_n)) / z + inv(alpha)`` with ``z = 2 r / m``."""
    beta = 0.0 if normal else np.abs(helix_angle)
    alpha = np.arctan(np.tan(pressure_angle) / np.cos(beta))
    r = base_radius / np.cos(alpha)
    z = 2.0 * r * np.cos(beta) / module
    psi_b = (0.5 * np.pi + 2.0 * profile_shift * np.tan(pressure_angle)) / z + inv(alpha)
    return r, r - (dedendum - profile_shift) * module, psi_b


def _shape_cells(sections, normal: bool = True) -> np.ndarray:
    """The dimensionless shape of each section (the compliance of a plane-strain body
    per unit width does not depend on its size) in units of :data:`KEY_STEPS`, shape
    (n, 10). The root and tip radii and the base half-angle are taken as their
    departures from the tooth that the basic rack generates (:func:`_generated`; the
    tip from ``r + x m_n``): zero (the root, the half-angle) or the same all along a
    beveloid's face (the tip), and :func:`key_section` a generated tooth whose fillet
    meets its involute as the sections' do."""
    n = np.asarray(sections.radius).size
    m = np.broadcast_to(np.asarray(sections.normal_module, float), (n,))
    rb = np.asarray(sections.base_radius, float)
    x = np.asarray(sections.profile_shift, float)
    an = np.asarray(sections.normal_pressure_angle, float)
    r, rf, psi_b = _generated(
        rb, x, an, np.asarray(sections.helix_angle, float), m, sections.rack_dedendum, normal
    )
    cols = [
        sections.teeth,
        x,
        (np.asarray(sections.root_radius) - rf) / m,
        (np.asarray(sections.tip_radius) - r) / m - x,
        rb / m,
        np.asarray(sections.base_half_angle) - psi_b,
        an,
        sections.helix_angle,
        sections.rack_dedendum,
        sections.rack_root_radius,
    ]
    cols = [np.broadcast_to(np.asarray(c, float), (n,)) for c in cols]
    return np.column_stack([c / st for c, st in zip(cols, KEY_STEPS, strict=True)])


def _shape_keys(sections, normal: bool = True) -> np.ndarray:
    """:func:`_shape_cells` rounded: the key of the cell each section lies in."""
    return np.round(_shape_cells(sections, normal))


#: The normal module of :func:`key_section` (m): a plane-strain body's compliance per
#: unit width times E does not depend on its size.
_KEY_MODULE = 1.0e-3


def key_section(shape, normal: bool = True) -> ToothSections:
    """The one section a table key ``shape`` (a row of :func:`_shape_keys`) stands for:
    the centre of the key's cell, the generated tooth of the cell's base radius,
    profile shift, angles and rack, with the cell's departures of root radius and base
    half-angle (the radii at :data:`_KEY_MODULE`; the load radius at the tip). Tables
    are solved for it, not for the first section a process meets with that key: a
    table kept for the process then gives every later section the same value, whatever
    ran before (with the section that a process had met first, case 03's loaded TE
    moved by 2.7e-5 after another scene had run in the process, and a parallel pair's
    by 3.1e-5 in a test run beside others)."""
    z, x, d_rf, d_ra, rb, d_psi, an, beta, hf, rho = (
        float(k) * st for k, st in zip(np.ravel(shape), KEY_STEPS, strict=True)
    )
    m = _KEY_MODULE
    r, rf, psi_b = _generated(rb * m, x, an, beta, m, hf, normal)
    ra = float(r) + (x + d_ra) * m
    return ToothSections.uniform(
        1,
        radius=ra,
        base_radius=rb * m,
        root_radius=float(rf) + d_rf * m,
        tip_radius=ra,
        bore_radius=0.0,
        base_half_angle=float(psi_b) + d_psi,
        teeth=z,
        normal_module=m,
        normal_pressure_angle=an,
        helix_angle=beta,
        profile_shift=x,
        rack_dedendum=hf,
        rack_root_radius=rho,
    )


def _height(sections, radius) -> np.ndarray:
    """Load height over the tooth's height, ``(r - r_f) / (r_a - r_f)``."""
    rf = np.asarray(sections.root_radius, float)
    return (np.asarray(radius, float) - rf) / (np.asarray(sections.tip_radius, float) - rf)


#: Elements along and across the tooth and the grading towards the loaded flank
#: (:func:`_mesh`) for the centre-line reading and for a reading at a depth below the
#: flank: against meshes two and four times finer the depth reading moves by at most
#: 0.06 % on the spur and case 03 teeth at 0.25 m_n (``tests/test_ltca_slice_fe.py``).
MESH_CENTRE = (24, 6, 1.0)
MESH_DEPTH = (48, 12, 2.0)


def _table(key, E, nu, normal, mesh, depth):
    got = _TABLES.get(key)
    if got is None:
        one = key_section(np.asarray(key[: len(KEY_STEPS)], dtype=float), normal)
        rb = float(one.base_radius[0])
        rho_o, _ = section_outline(one, 0, normal=normal, samples=50)
        lo = max(rb * (1.0 + 1e-9), float(rho_o[0]) + 1e-3 * (rho_o[-1] - rho_o[0]))
        ra = float(rho_o[-1])
        roll = np.linspace(np.sqrt(lo**2 - rb**2), np.sqrt(ra**2 - rb**2), TABLE_RADII)
        radii = np.sqrt(rb**2 + roll**2)
        from scipy.interpolate import CubicSpline

        d = None if depth is None else depth * float(np.asarray(one.normal_module).ravel()[0])
        fe = _solve_section(one, 0, radii, E, nu, normal, *mesh[:2], depth=d, grade=mesh[2])
        h = _height(one, radii)
        got = (h, fe * E, CubicSpline(h, fe * E))
        if len(_TABLES) >= _TABLES_MAX:
            _TABLES.clear()
        _TABLES[key] = got
    return got


def fe_tooth_compliance(
    sections,
    youngs_modulus: float,
    poisson_ratio: float,
    *,
    normal: bool = True,
    depth: float | None = None,
    n_along: int | None = None,
    n_across: int | None = None,
    tabulated: bool = True,
) -> np.ndarray:
    """Tooth compliance of slices (m per N/m of transverse line load, along the load),
    the tooth alone clamped at the root circle, read where the load's line of action
    crosses the centre line (``depth`` None) or at ``depth`` times the normal module
    below the flank along the load's line (at most down to the centre line: the FE
    level's matching depth, :class:`gearbox.fe.FEOptions`); shape (n,), one value per
    point of ``sections``.

    ``sections``: :class:`~gearbox.ltca.grid.ToothSections` (use
    :func:`~gearbox.ltca.slice_model.normal_section` for helical slices, as the beam
    does). ``n_along`` / ``n_across``: elements along and across the tooth (default
    :data:`MESH_CENTRE` or, for a depth, :data:`MESH_DEPTH`, graded towards the flank).
    ``tabulated``: solve one section per shape (:data:`KEY_STEPS`) for
    :data:`TABLE_RADII` load heights and keep the table for the process (a loaded TCA
    meets the same shapes at every mesh position); each point takes the value at its
    height ``(r - r_f) / (r_a - r_f)`` (cubic spline; below the table, its first
    value); else solve every distinct section at the points' own radii.
    """
    from dataclasses import fields

    base = MESH_CENTRE if depth is None else MESH_DEPTH
    mesh = (
        base[0] if n_along is None else int(n_along),
        base[1] if n_across is None else int(n_across),
        base[2],
    )
    n = np.asarray(sections.radius).size
    radius = np.asarray(sections.radius, float)
    E, nu = float(youngs_modulus), float(poisson_ratio)
    module = np.broadcast_to(np.asarray(sections.normal_module, float), (n,))
    out = np.zeros(n)
    if not tabulated:  # one model per distinct section: every field but the radius
        keys = np.column_stack(
            [
                np.broadcast_to(np.asarray(getattr(sections, f.name), float), (n,))
                for f in fields(sections)
                if f.name != "radius"
            ]
        )
        _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
        inverse = inverse.ravel()
        for g, i0 in enumerate(first):
            pts = np.flatnonzero(inverse == g)
            d = None if depth is None else depth * module[i0]
            out[pts] = _solve_section(
                sections, i0, radius[pts], E, nu, normal, *mesh[:2], depth=d, grade=mesh[2]
            )
        return out
    cells = _shape_cells(sections, normal)
    keys = np.round(cells)
    keys[:, _LATTICE] = np.floor(cells[:, _LATTICE])
    weight = cells[:, _LATTICE] - keys[:, _LATTICE]  # towards the lattice's next table
    _, first, inverse = np.unique(keys, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    height = _height(sections, radius)
    for g, i0 in enumerate(first):
        pts = np.flatnonzero(inverse == g)
        for step, w in ((0, 1.0 - weight[pts]), (1, weight[pts])):
            if not np.any(w > 0.0):
                continue
            shape = keys[i0].copy()
            shape[_LATTICE] += step
            key = (*shape.tolist(), nu, bool(normal), mesh, depth)
            h, _, spline = _table(key, E, nu, normal, mesh, depth)
            out[pts] += w * spline(np.clip(height[pts], h[0], h[-1])) / E
    return out

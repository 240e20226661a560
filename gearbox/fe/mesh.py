"""Mapped hexahedral mesh of a segment of a gear: a few teeth and the rim.

The mesh is built from the flank parametrisation of :mod:`gearbox.surface` (simulated
generation, root fillet included), so the same code meshes spur, helical and beveloid
teeth; no hand-made geometry enters.

Each transverse layer ``z_l`` (toe to heel) is a structured quadrilateral section:

- tooth block: rows at rack-profile parameters ``u`` from the rack tip line ``u_min``
  (root circle, end of the fillet) through the fillet (``u < 0``) and the involute
  (``u >= 0``; on an undercut flank the fillet up to where it cuts the regular
  involute and the involute from there, :func:`gearbox.surface.form_point`) to the
  tip cone; each row joins the left-flank point L(u) and the
  right-flank point R(u) by interpolation in polar coordinates (radius and angle), with
  columns graded towards the flanks (cosine spacing), where the contact loads act;
- rim block: the root land on both sides of the tooth down to the middle of the tooth
  spaces, and radial rows from the root circle down to the bore, graded towards the root.

Neighbouring teeth share the tooth-space middle; layers are joined into 27-node
(triquadratic Lagrange) hexahedra whose every node, mid-side nodes included, is a point
of the parametrised geometry (isoparametric elements, curved fillet and flanks).
The bore and the two radial cut faces of the segment are the clamped boundary.

Frames (gear frame S_i of :mod:`gearbox.surface.blank`): z along the gear axis, tooth k
is tooth 0 turned by ``2 pi k / N`` about +z.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, replace

import numpy as np

from ..errors import InputError, Problem, Problems
from ..surface.blank import ToothBlank
from ..surface.generation import flank_points, form_point, profile_range
from ..surface.sample import tip_parameter

__all__ = ["MeshOptions", "ToothMesh", "FEBuildError", "build_tooth_mesh"]


class FEBuildError(InputError):
    """The finite-element model cannot be built or factorised; names the cause."""


@dataclass(frozen=True)
class MeshOptions:
    """Element counts of the mapped mesh (per tooth and layer).

    across: elements across the tooth (flank to flank); profile: along the involute
    (form circle to tip); fillet: along the root fillet; land: along each half root
    land (fillet end to tooth-space middle); rim: radial, root circle to bore;
    face_length: element length along the face width over the normal module (the
    layer count is the face width over it, rounded up); grading: exponent of the
    rim's radial grading (> 1 makes rows finer towards the root).

    The defaults are :meth:`coarse` refined twice (``MeshOptions.coarse().refined(2)``):
    the refinement study of ``tests/test_fe_convergence.py`` puts their mean mesh
    stiffness within 1 % of the Richardson-extrapolated value.
    """

    across: int = 4
    profile: int = 8
    fillet: int = 4
    land: int = 2
    rim: int = 4
    face_length: float = 1.0
    grading: float = 1.6

    def __post_init__(self):
        p = Problems()
        for name in ("across", "profile", "fillet", "land", "rim"):
            p.check(
                isinstance(getattr(self, name), int) and getattr(self, name) >= 1,
                f"fe.mesh.{name}",
                getattr(self, name),
                "must be an integer >= 1 (elements)",
            )
        p.in_range("fe.mesh.face_length", self.face_length, 0.0, 50.0, lo_open=True)
        p.in_range("fe.mesh.grading", self.grading, 1.0, 4.0)
        p.raise_if_any("invalid FE mesh options")

    @classmethod
    def coarse(cls) -> MeshOptions:
        """The coarsest mesh of the refinement study (2 elements across the tooth)."""
        return cls(across=2, profile=4, fillet=2, land=1, rim=2, face_length=2.0)

    def layers(self, face_width: float, normal_module: float) -> int:
        """Element layers along a face width (m) for a normal module (m)."""
        return max(1, int(math.ceil(face_width / (self.face_length * normal_module) - 1e-9)))

    def refined(self, factor: float) -> MeshOptions:
        """Every element count times ``factor`` (rounded, at least 1); the face
        element length divided by it."""

        def s(n):
            return max(1, int(round(n * factor)))

        return replace(
            self,
            across=s(self.across),
            profile=s(self.profile),
            fillet=s(self.fillet),
            land=s(self.land),
            rim=s(self.rim),
            face_length=self.face_length / factor,
        )

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> MeshOptions:
        return cls(**d)


@dataclass(frozen=True)
class ToothMesh:
    """A mapped hexahedral mesh of teeth ``teeth[0] .. teeth[-1]`` and their rim (SI).

    p: node coordinates, shape (3, n_nodes), m; t: 27-node hexahedra, shape
    (27, n_elements), local node ``a = i + 3 j + 9 k`` at reference coordinates
    ``(i, j, k) / 2`` (X0 across the tooth, X1 root to tip / bore to root, X2 toe
    to heel); element_tooth, element_layer: tooth offset and face
    layer of each element, shape (n_elements,); element_block: 0 tooth block, 1 rim;
    element_row, element_col: row (root to tip, bore to root) and column (across,
    from the L side) of each element in its block;
    clamped: node indices of the bore and the two cut faces; z_layers: axial
    positions of the node layers (m), shape (2 layers + 1,); flank_nodes: node indices
    of the fillet and flank surface of every tooth and side, shape (node layers, node
    rows), ``{(tooth, side): array}``; flank_u: rack-profile parameter u of those node
    rows per side, shape (node layers, node rows); blank: the generating data;
    options: the counts.
    """

    p: np.ndarray
    t: np.ndarray
    element_tooth: np.ndarray
    element_layer: np.ndarray
    element_block: np.ndarray
    element_row: np.ndarray
    element_col: np.ndarray
    clamped: np.ndarray
    z_layers: np.ndarray
    flank_nodes: dict
    flank_u: dict
    teeth: tuple[int, ...]
    bore_radius: float
    blank: ToothBlank
    options: MeshOptions

    @property
    def n_nodes(self) -> int:
        return int(self.p.shape[1])

    @property
    def n_elements(self) -> int:
        return int(self.t.shape[1])


def _polar(P):
    return np.hypot(P[..., 0], P[..., 1]), np.arctan2(P[..., 1], P[..., 0])


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def _half_steps(x):
    """Coarse node parameters x (n+1,) -> lattice with the midpoints (2n+1,)."""
    out = np.empty(2 * x.size - 1)
    out[0::2] = x
    out[1::2] = 0.5 * (x[:-1] + x[1:])
    return out


@dataclass(frozen=True)
class _Section:
    """Polar lattice of one tooth's section at one axial position (m, rad)."""

    tooth_r: np.ndarray  # (2 rows + 1, 2 across + 1)
    tooth_th: np.ndarray
    rim_r: np.ndarray  # (2 rim + 1, 2 (2 land + across) + 1), row 0 = bore
    rim_th: np.ndarray
    u: dict  # side -> rack-profile parameters of the tooth-block rows (2 rows + 1,)


def _section(blank, z, opts, u_min, bore, probs, where):
    nf, npf, nc, nl, nr = opts.fillet, opts.profile, opts.across, opts.land, opts.rim
    us = {}
    for side in ("L", "R"):
        u_tip, _ = tip_parameter(blank, side, np.array([z]))
        u_tip = float(u_tip[0])
        # the fillet up to where it meets the involute: u = 0 on both, or on an
        # undercut flank where it cuts the regular involute (form_point)
        # (the mid-side nodes of the row between are the fillet's: each branch is
        # halved on its own)
        uf, ui = (float(v[0]) for v in form_point(blank, side, np.array([z])))
        up = _half_steps(np.linspace(ui, u_tip, npf + 1))
        if u_min < 0:
            up = np.concatenate([_half_steps(np.linspace(u_min, uf, nf + 1))[:-1], up])
        us[side] = up
    pts = {s: flank_points(blank, s, np.full(us[s].shape, z), us[s]).position for s in us}
    rL, thL = _polar(pts["L"])
    rR, thR = _polar(pts["R"])
    thc = thL[0] + 0.5 * _wrap(thR[0] - thL[0])
    thL = thc + _wrap(thL - thc)
    thR = thc + _wrap(thR - thc)
    N = blank.teeth
    sgn = 1.0 if thR[0] > thL[0] else -1.0
    rf = 0.5 * (rL[0] + rR[0])
    ok = probs.check(
        bool(np.all(np.diff(rL) > 0) and np.all(np.diff(rR) > 0)),
        f"{where}.profile",
        "radius not increasing from root to tip",
        "the generated fillet and flank must rise monotonically: the fillet "
        "self-intersects (undercut loop) or the tip cone cuts the fillet",
    )
    width = sgn * (thR - thL)
    ok &= probs.check(
        bool(np.all(width > 0)),
        f"{where}.tooth_thickness",
        float(np.min(width)),
        "must be > 0 at every row: pointed or crossing flanks",
    )
    land = sgn * (thc + sgn * np.pi / N - thR[0])
    ok &= probs.check(
        land > 1e-3 * np.pi / N,
        f"{where}.root_land",
        float(land),
        "angle between fillet end and tooth-space middle must be > 0: the fillets of "
        "neighbouring teeth meet or overlap (tool tip radius too large)",
    )
    ok &= probs.check(
        0 < bore < rf, f"{where}.bore_radius", bore, f"must be in (0, root radius {rf:g} m)"
    )
    if not ok:
        return None
    sc = _half_steps(0.5 * (1.0 - np.cos(np.pi * np.arange(nc + 1) / nc)))
    tr = rL[:, None] + sc[None, :] * (rR - rL)[:, None]
    tt = thL[:, None] + sc[None, :] * (thR - thL)[:, None]
    land_s = _half_steps(np.linspace(0.0, 1.0, nl + 1))
    th_space_L = thc - sgn * np.pi / N
    th_space_R = thc + sgn * np.pi / N
    top_th = np.concatenate(
        [
            th_space_L + land_s[:-1] * (tt[0, 0] - th_space_L),
            tt[0, :],
            tt[0, -1] + land_s[1:] * (th_space_R - tt[0, -1]),
        ]
    )
    g = _half_steps((np.arange(nr + 1) / nr) ** opts.grading)  # 0 at the root
    rows_r = rf - g[::-1] * (rf - bore)  # row 0 = bore, last row = root circle
    rim_r = np.broadcast_to(rows_r[:, None], (rows_r.size, top_th.size)).copy()
    rim_r[-1, 2 * nl : 2 * nl + 2 * nc + 1] = tr[0]
    rim_th = np.broadcast_to(top_th[None, :], rim_r.shape).copy()
    return _Section(tr, tt, rim_r, rim_th, us)


def build_tooth_mesh(
    blank: ToothBlank,
    teeth=(-1, 0, 1),
    *,
    bore_radius: float,
    options: MeshOptions = MeshOptions(),
    clamp_cut_faces: bool = True,
    clamp_root: bool = False,
) -> ToothMesh:
    """Mapped mesh of 27-node hexahedra of consecutive teeth and their rim.

    blank: generating data (:class:`~gearbox.surface.blank.ToothBlank`); teeth:
    consecutive tooth offsets (tooth k turned by 2 pi k / N about +z); bore_radius:
    inner radius of the rim (m); clamp_cut_faces: clamp the two radial cut faces of the
    segment as well as the bore (else they are free); clamp_root: clamp every tooth at
    the root circle as well (the bottom row of the tooth block, the chord between the
    two fillet ends), so that the body below it is rigid: the tooth alone, fillets
    included, as a cantilever on a rigid foundation. Every node, mid-side nodes included, lies on the
    parametrised geometry (isoparametric quadratic elements). Raises
    :class:`FEBuildError` naming the cause for a self-intersecting fillet, pointed
    teeth, overlapping fillets or degenerate (inverted) elements.
    """
    teeth = tuple(int(k) for k in teeth)
    probs = Problems()
    probs.check(
        len(teeth) >= 1 and all(b - a == 1 for a, b in zip(teeth, teeth[1:], strict=False)),
        "fe.teeth",
        teeth,
        "must be consecutive tooth offsets",
    )
    probs.raise_if_any("invalid FE model")
    opts = options
    u_min = profile_range(blank)[0] if blank.tool_tip_radius > 0 else 0.0
    nlay = opts.layers(blank.face_width, blank.normal_module)
    z_layers = _half_steps(np.linspace(blank.z_toe, blank.z_heel, nlay + 1))
    sections = []
    for z in z_layers:
        sec = _section(
            blank, float(z), opts, u_min, bore_radius, probs, f"fe.mesh[z={z * 1e3:.4g} mm]"
        )
        sections.append(sec)
        if probs.items:
            break
    if probs.items:
        raise FEBuildError(probs.items, "the FE model of the teeth cannot be built")
    N = blank.teeth
    ids = []
    pts = []
    count = 0
    nz = z_layers.size
    for k in teeth:
        rot = 2 * np.pi * k / N
        blocks = []
        for rname, thname in (("tooth_r", "tooth_th"), ("rim_r", "rim_th")):
            shape = getattr(sections[0], rname).shape
            arr = count + np.arange(nz * shape[0] * shape[1]).reshape((nz,) + shape)
            count += arr.size
            for li, z in enumerate(z_layers):
                r = getattr(sections[li], rname)
                th = getattr(sections[li], thname) + rot
                pts.append(
                    np.stack([r * np.cos(th), r * np.sin(th), np.full(r.shape, z)], -1).reshape(
                        -1, 3
                    )
                )
            blocks.append(arr)
        ids.append(blocks)
    X = np.concatenate(pts)
    # merge coincident nodes (tooth block / rim interface, shared tooth-space middles)
    from scipy.spatial import cKDTree

    pairs = cKDTree(X).query_pairs(1e-7 * blank.normal_module, output_type="ndarray")
    parent = np.arange(X.shape[0])
    for _ in range(4):
        if not pairs.size:
            break
        a, b = pairs[:, 0], pairs[:, 1]
        m = np.minimum(parent[a], parent[b])
        np.minimum.at(parent, a, m)
        np.minimum.at(parent, b, m)
        parent = parent[parent]
    uniq, inverse = np.unique(parent, return_inverse=True)
    p = X[uniq].T.copy()

    elems, etooth, elayer, eblock, clamped, erow, ecol = [], [], [], [], [], [], []
    flank_nodes = {}
    for ti, (k, blocks) in enumerate(zip(teeth, ids, strict=True)):
        for block, arr in enumerate(blocks):
            nl_, nrow, ncol = (s // 2 for s in arr.shape)
            L, R_, C_ = np.meshgrid(np.arange(nl_), np.arange(nrow), np.arange(ncol), indexing="ij")
            L, R_, C_ = 2 * L.ravel(), 2 * R_.ravel(), 2 * C_.ravel()
            el = np.empty((27, L.size), dtype=np.int64)
            for a, (i, j, kk) in enumerate(_Q2_LOCAL):
                el[a] = inverse[arr[L + kk, R_ + j, C_ + i]]
            elems.append(el)
            etooth.append(np.full(L.size, k))
            elayer.append(L // 2)
            erow.append(R_ // 2)
            ecol.append(C_ // 2)
            eblock.append(np.full(L.size, block))
        tb, rb = blocks
        clamped.append(inverse[rb[:, 0, :].ravel()])
        if clamp_root:
            clamped.append(inverse[tb[:, 0, :].ravel()])
        if ti == 0 and clamp_cut_faces:
            clamped.append(inverse[rb[:, :, 0].ravel()])
        if ti == len(teeth) - 1 and clamp_cut_faces:
            clamped.append(inverse[rb[:, :, -1].ravel()])
        flank_nodes[(k, "L")] = inverse[tb[:, :, 0]]
        flank_nodes[(k, "R")] = inverse[tb[:, :, -1]]
    t27 = np.concatenate(elems, axis=1)
    etooth = np.concatenate(etooth)
    elayer = np.concatenate(elayer)
    eblock = np.concatenate(eblock)
    erow = np.concatenate(erow)
    ecol = np.concatenate(ecol)
    det = _jacobians_at(p, t27, _Q2_CHECK)
    if np.median(det) < 0:
        t27 = t27[_MIRROR0]
        det = _jacobians_at(p, t27, _Q2_CHECK)
    # positive Jacobian at every quadrature point (a fillet meeting the root circle
    # tangentially gives a zero Jacobian at one corner, harmless for the quadrature)
    bad = np.flatnonzero(np.min(det, axis=0) <= 0)
    if bad.size:
        e = int(bad[0])
        raise FEBuildError(
            Problem(
                f"fe.mesh.element[{e}] (tooth {int(etooth[e])}, layer {int(elayer[e])}, "
                f"{'tooth block' if eblock[e] == 0 else 'rim'})",
                f"{bad.size} degenerate element(s), min Jacobian {float(det[:, e].min()):.3g}",
                "every element must have a positive Jacobian: refine the mesh or check "
                "the tooth geometry (fillet, tip, bore)",
            ),
            "the FE model of the teeth cannot be built",
        )
    flank_u = {s: np.array([sec.u[s] for sec in sections]) for s in ("L", "R")}
    return ToothMesh(
        p=p,
        t=t27,
        element_tooth=etooth,
        element_layer=elayer,
        element_block=eblock,
        element_row=erow,
        element_col=ecol,
        clamped=np.unique(np.concatenate(clamped)),
        z_layers=z_layers,
        flank_nodes=flank_nodes,
        flank_u=flank_u,
        teeth=teeth,
        bore_radius=float(bore_radius),
        blank=blank,
        options=options,
    )


# 27-node element: local node a = (i, j, k) along (X0 = across, X1 = rows, X2 = layers)
_Q2_LOCAL = [(i, j, k) for k in range(3) for j in range(3) for i in range(3)]
_MIRROR0 = np.array([_Q2_LOCAL.index((2 - i, j, k)) for (i, j, k) in _Q2_LOCAL])
# 3-point Gauss-Legendre nodes on [0, 1]: the element's quadrature points
_G3 = 0.5 + 0.5 * np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
_G3W = np.array([5.0, 8.0, 5.0]) / 18.0
_Q2_CHECK = np.array([[a, b, c] for c in _G3 for b in _G3 for a in _G3])


def _lagrange2(x):
    """Quadratic Lagrange polynomials on [0, 1] (nodes 0, 1/2, 1) and derivatives."""
    x = np.asarray(x, dtype=float)
    v = np.stack([2 * (x - 0.5) * (x - 1), -4 * x * (x - 1), 2 * x * (x - 0.5)])
    d = np.stack([4 * x - 3, -8 * x + 4, 4 * x - 1])
    return v, d


def shape_functions(X):
    """27-node shape functions and reference gradients at points X (m, 3).

    Returns (N (m, 27), dN (m, 27, 3)).
    """
    X = np.asarray(X, dtype=float)
    v0, d0 = _lagrange2(X[:, 0])
    v1, d1 = _lagrange2(X[:, 1])
    v2, d2 = _lagrange2(X[:, 2])
    idx = np.array(_Q2_LOCAL)
    i, j, k = idx[:, 0], idx[:, 1], idx[:, 2]
    N = (v0[i] * v1[j] * v2[k]).T
    dN = np.stack(
        [(d0[i] * v1[j] * v2[k]).T, (v0[i] * d1[j] * v2[k]).T, (v0[i] * v1[j] * d2[k]).T], -1
    )
    return N, dN


def element_map(p, t, X):
    """Points and Jacobians of the isoparametric map of elements ``t`` at reference points.

    p: (3, n_nodes); t: (27, m) element nodes; X: (m, 3) reference coordinates.
    Returns (x (m, 3), J (m, 3, 3)) with ``J[:, i, j] = dx_i / dX_j``.
    """
    N, dN = shape_functions(X)
    P = p[:, t].transpose(2, 1, 0)  # (m, 27, 3)
    # batched matrix products (BLAS): about twice as fast as the einsums of the same
    # sums (20 000 points: 18 -> 10 ms)
    x = np.matmul(N[:, None, :], P)[:, 0]
    J = np.matmul(P.transpose(0, 2, 1), dN)
    return x, J


def _jacobians_at(p, t, Xs):
    out = np.empty((len(Xs), t.shape[1]))
    for a, X in enumerate(Xs):
        _, J = element_map(p, t, np.broadcast_to(X, (t.shape[1], 3)))
        out[a] = np.linalg.det(J)
    return out


def locate(mesh: ToothMesh, x, candidates, *, iterations: int = 30):
    """Element and reference coordinates of physical points, searching candidates.

    x: (n, 3) points (m); candidates: list of n integer arrays of element indices.
    Newton iteration on the element map of every candidate (bounded by
    ``iterations``); the element whose solution lies nearest the unit cube wins and
    its coordinates are clipped to it. Returns (cells (n,), X (n, 3), miss (n,)) with
    ``miss`` the distance (reference units) outside the cube before clipping.
    """
    x = np.asarray(x, dtype=float)
    lens = np.array([c.size for c in candidates])
    owner = np.repeat(np.arange(x.shape[0]), lens)
    cand = np.concatenate(candidates)
    tc = mesh.t[:, cand]
    X = np.full((cand.size, 3), 0.5)
    target = x[owner]
    active = np.arange(cand.size)
    for _ in range(iterations):
        f, J = element_map(mesh.p, tc[:, active], X[active])
        dX = np.linalg.solve(J, (target[active] - f)[:, :, None])[:, :, 0]
        X[active] = np.clip(X[active] + np.clip(dX, -0.5, 0.5), -1.0, 2.0)
        active = active[np.max(np.abs(dX), axis=1) > 1e-13]
        if active.size == 0:
            break
    f, _ = element_map(mesh.p, tc, X)
    out = np.maximum(np.maximum(-X, X - 1.0), 0.0).max(axis=1)
    out = out + (np.linalg.norm(f - target, axis=1) > 1e-9 * mesh.blank.normal_module)
    start = np.concatenate([[0], np.cumsum(lens)])
    cells = np.empty(x.shape[0], dtype=np.int64)
    Xs = np.empty((x.shape[0], 3))
    miss = np.empty(x.shape[0])
    for i in range(x.shape[0]):
        s = slice(start[i], start[i + 1])
        j = int(np.argmin(out[s]))
        cells[i] = cand[s][j]
        Xs[i] = np.clip(X[s][j], 0.0, 1.0)
        miss[i] = out[s][j]
    return cells, Xs, miss

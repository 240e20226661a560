"""One tooth under a line load spread uniformly along its whole face.

The experiment that compares the fast level's two-dimensional slice model
(:func:`gearbox.ltca.slice_model.slice_compliance`) with the finite-element tooth: a
load spread evenly over the face at one height of the flank makes the 3-D tooth act
like the 2-D slice (every transverse section carries the same line load), so the
slice model's compliance per unit face width can be read off the FE model directly.

:func:`line_load_compliance` loads tooth 0 of a segment (``neighbours`` unloaded
teeth each side, cut faces and bore clamped, as in
:class:`~gearbox.fe.compliance.FECompliance`) with a unit force along the inward
flank normal at a given radius, spread over ``n`` equal strips of the face (each a
square patch of side ``face / n``, consistent nodal loads), and reads the
displacement along the load, averaged over the face (the energy-consistent mean for
a uniform load; on a helical tooth without the reading points that the leaning
normal takes out of the face near its ends), at two points below each load point: at the matching depth (the
FE level's own reading point) and where the normal line through the load point
crosses the tooth's mid-surface (the centre line, where a beam model of the tooth
places its deflection). ``clamp_root`` clamps every tooth at the root circle
(:func:`~gearbox.fe.mesh.build_tooth_mesh`), which takes the body below the root
circle out: the tooth alone as a cantilever on a rigid foundation.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import Problems
from ..surface.blank import ToothBlank
from ..surface.generation import flank_points
from .mesh import MeshOptions, build_tooth_mesh, locate
from .model import build_model

__all__ = ["LineLoadCompliance", "line_load_compliance"]


@dataclass(frozen=True)
class LineLoadCompliance:
    """Compliance of one tooth under uniform line loads along its face (SI).

    radius: load radii (m), shape (n,); depth, centre: displacement along the load
    per unit line load (m per N/m of face width), read at the matching depth and at
    the tooth's mid-surface, shape (n,); centre_depth: distance of the mid-surface
    from the flank along the normal (m), shape (n,); matching_depth (m); n_dofs:
    unknowns of the model; seconds: wall time.
    """

    radius: np.ndarray
    depth: np.ndarray
    centre: np.ndarray
    centre_depth: np.ndarray
    matching_depth: float
    n_dofs: int
    seconds: float


def _centre_angle(blank: ToothBlank, side: str, z, u):
    """Polar angle of the tooth's mid-surface in the sections z at the radius of the
    flank point (z, u): the mean of the two flanks' angles there."""
    from .compliance import _u_at_radius

    P = flank_points(blank, side, z, u).position
    r = np.hypot(P[..., 0], P[..., 1])
    other = "L" if side == "R" else "R"
    Q = flank_points(blank, other, z, _u_at_radius(blank, other, z, r)).position
    a, b = np.arctan2(P[..., 1], P[..., 0]), np.arctan2(Q[..., 1], Q[..., 0])
    return a + 0.5 * ((b - a + np.pi) % (2 * np.pi) - np.pi)


def _centre_points(blank: ToothBlank, side: str, P, m, U):
    """Points where the lines P + t m (inward normals) cross the tooth's mid-surface,
    and t (m): bisection on the polar angle against the mid-surface's angle in the
    section the point reaches (a helical mid-surface turns along the axis)."""
    from .compliance import _u_at_radius

    lo = np.zeros(P.shape[0])
    hi = np.full(P.shape[0], 1.5 * blank.normal_module)

    def side_of(t):
        Q = P + t[:, None] * m
        r = np.hypot(Q[:, 0], Q[:, 1])
        # the flank parameter of the point's radius in its own section
        uq = _u_at_radius(blank, side, Q[:, 2], np.maximum(r, 1e-9))
        c = _centre_angle(blank, side, Q[:, 2], uq)
        d = np.arctan2(Q[:, 1], Q[:, 0]) - c
        return (d + np.pi) % (2 * np.pi) - np.pi

    s0 = np.sign(side_of(lo))
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        same = np.sign(side_of(mid)) == s0
        lo = np.where(same, mid, lo)
        hi = np.where(same, hi, mid)
    t = 0.5 * (lo + hi)
    _ = U
    return P + t[:, None] * m, t


def line_load_compliance(
    blank: ToothBlank,
    side: str,
    radii,
    *,
    bore_radius: float,
    youngs_modulus: float,
    poisson_ratio: float,
    options: MeshOptions | None = None,
    neighbours: int = 1,
    matching_depth: float = 0.25,
    strip: float = 0.25,
    clamp_root: bool = False,
    clamp_cut_faces: bool = True,
) -> LineLoadCompliance:
    """Compliance per unit face width of tooth 0 under uniform line loads (see the
    module docstring).

    blank: generating data of a cylindrical gear; side: loaded flank ("R" or "L");
    radii: load radii (m), on the involute; bore_radius (m); matching_depth and
    strip: depth of the reading point and width of the load strips, over m_n;
    options: the mesh (None: the FE level's default, ``MeshOptions()``);
    clamp_root: clamp the teeth at the root circle; clamp_cut_faces: clamp the
    segment's radial cut faces (else free; the bore is clamped in both). One
    factorisation, one solve per radius.
    """
    import time

    from .compliance import FECompliance, FEOptions, _GearModel, _u_at_radius

    radii = np.atleast_1d(np.asarray(radii, dtype=float))
    p = Problems()
    p.check(side in ("R", "L"), "side", side, "must be 'R' or 'L'")
    p.check(
        abs(blank.cone_angle) < 1e-12,
        "blank.cone_angle",
        blank.cone_angle,
        "must be 0 (a cylindrical gear: the load height is the same along the face)",
    )
    p.in_range("strip", strip, 0.05, 1.0)
    p.raise_if_any("invalid line-load experiment")
    t0 = time.perf_counter()
    options = MeshOptions() if options is None else options
    teeth = tuple(range(-neighbours, neighbours + 1))
    mesh = build_tooth_mesh(
        blank,
        teeth,
        bore_radius=bore_radius,
        options=options,
        clamp_root=clamp_root,
        clamp_cut_faces=clamp_cut_faces,
    )
    model = build_model(mesh, youngs_modulus, poisson_ratio)
    mn = blank.normal_module
    fe = FECompliance(FEOptions(mesh=options, matching_depth=matching_depth, lattice_spacing=strip))
    gm = _GearModel(model=model, key=None, bore=bore_radius)
    nz = max(2, int(round(blank.face_width / (strip * mn))))
    Z = blank.z_toe + (np.arange(nz) + 0.5) * blank.face_width / nz
    depth, centre, tc = [], [], []
    tooth_block = np.flatnonzero((mesh.element_tooth == 0) & (mesh.element_block == 0))
    zl = mesh.z_layers[0::2]
    for r in radii:
        U = _u_at_radius(blank, side, Z, np.full(nz, r))
        F = fe._unit_loads(gm, side, 0, Z, U)
        f = np.asarray(F.sum(axis=1)).ravel() / nz
        u = model.solve(f)
        P, n, _, _ = fe._surface(blank, side, 0, Z, U)
        m = -n
        Qd = P + matching_depth * mn * m
        Qc, t = _centre_points(blank, side, P, m, U)
        out = []
        for Q in (Qd, Qc):
            # a helical flank's normal leans along the axis: reading points that leave
            # the face near its ends are left out of the mean
            inside = (Q[:, 2] > blank.z_toe) & (Q[:, 2] < blank.z_heel)
            Q = Q[inside]
            layer = np.clip(np.searchsorted(zl, Q[:, 2]) - 1, 0, zl.size - 2)
            cands = [tooth_block[np.abs(mesh.element_layer[tooth_block] - ly) <= 1] for ly in layer]
            cells, X, miss = locate(mesh, Q, cands)
            if np.max(miss) > 1e-6:
                raise AssertionError(f"reading point outside the tooth block ({np.max(miss):g})")
            Op = model.point_operator(cells, X)
            w = np.sum((Op @ u).reshape(-1, 3) * m[inside], axis=1)
            out.append(float(np.mean(w)) * blank.face_width)
        depth.append(out[0])
        centre.append(out[1])
        tc.append(float(np.mean(t[inside])))
    return LineLoadCompliance(
        radius=radii,
        depth=np.asarray(depth),
        centre=np.asarray(centre),
        centre_depth=np.asarray(tc),
        matching_depth=matching_depth * mn,
        n_dofs=model.n_dofs,
        seconds=time.perf_counter() - t0,
    )


_ = math

"""The FE level's helical teeth against an independent finite-element model, and the
fast level against the FE level over the helix angle and the face width.

``--check`` (default): one tooth of the pinion of a parallel pair (z 20/40, m_n 4 mm,
alpha_n 20 deg) with its rim sector, bore and radial cut faces clamped (the FE level
with ``neighbours=0``, ``far_field="none"``), loaded by the FE level's own unit loads
(a unit force along the inward normal spread over a square patch of side
``lattice_spacing m_n``, 3 x 3 Gauss points) at the points of one contact line (the
grid's tooth pair on that tooth at mesh position 0.25), read along the inward normal
at the matching depth below each point. Both models give the matrix ``C_ij`` of those
points; printed is ``e^T C e / n^2`` (the approach under a load spread evenly over the
line, per newton) of both and their ratio, for each helix angle. The independent model
shares only the flank geometry (``gearbox.surface.flank_points``, checked on its own
against the involute helicoid to 1e-9 m): gmsh lofts the transverse sections of the
tooth sector (OpenCASCADE ``ThruSections`` through nine sections) and meshes it with
linear tetrahedra graded towards the loaded points; scikit-fem solves it with
quadratic (P2) tetrahedra; pyamg's smoothed aggregation preconditions the conjugate
gradients (to a relative residual of 1e-10).

``--mesh-stiffness``: the mean mesh stiffness of the same pairs (8 positions, 300 N m)
at each helix angle and face width: the FE level's segment (``far_field="none"``),
the fast level without its shared far field (what matches the segment) and with it,
and ISO 6336-1's c_gamma_alpha in the same (normal) convention, N/(mm um).

    python3 -m pip install gmsh pyamg     # for --check only; not needed by gearbox
    python3 benchmarks/fe_independent.py --helix-deg 0 15 30 --face-mm 12
    python3 benchmarks/fe_independent.py --mesh-stiffness --helix-deg 0 15 30 --face-mm 12 30
    python3 benchmarks/fe_independent.py --face-profile --helix-deg 0 10 20 30 --face-mm 12 30

``--face-profile``: where along the face the fast level's helical tooth is too stiff.
Each gear's tooth alone (the FE level's segment built for it, ``far_field="none"``, and
the fast level's coupled slices, read at the same matching depth:
``FastCompliance(contact="matching_depth")``) under a load even along a line of constant
radius over the whole face (a line of the tooth's length, not a contact line: no
climbing load), at 15 / 50 / 85 % of the way from the form to the tip circle. Printed:
FE / fast for the mean deflection, the same over the spur tooth's (same face width, gear
and height), and per slice at the obtuse face end, the middle and the acute face end
(where the flank meets the end face at the acute angle: the end towards which that
gear's contact lines climb). A second table: FE / fast of ``q^T C q`` at mid height for
loads even, linear and quadratic across the face (the last two the tooth's rocking and
bowing, which a uniform load does not show).

``--fit-face-ends``: fits the fast compliance's helical face ends
(``gearbox.ltca.compliance.HELIX_ENDS``, a :class:`~gearbox.ltca.stress.HelixEnds`
factor on each slice's compliance) on the same loads as ``--face-profile`` (1 mm
slices): per set (helix angle over the spur tooth, face width, gear, height) the FE's
deflection along the face over the plain slices', taken over the spur tooth's
(``fe_over_slices``), against the slices with the factor; least squares in ln over all
sets, the coefficients per height and one quadratic. ``--cache FILE.npz`` keeps the FE
blocks (about 6 minutes for b 12 / 24 / 40 mm on this machine, shared with other runs), ``--json`` writes
the sets for ``tests/test_ltca_face_ends.py``. ``--mesh-stiffness --face-ends``: the
fast level with that factor.

    python3 benchmarks/fe_independent.py --fit-face-ends --helix-deg 10 20 30 --face-mm 12 24 40 --json tests/data/fe_face_ends.json

``--root-stress``: the fillet stress of the same one-tooth model under 1 kN on the
contact line (mesh positions ``--positions``), even along the line and rising linearly
towards its upper end: the largest principal stress in the loaded side's fillet from
the FE level (its own sample points, the default mesh and ``MeshOptions().refined(
--refine)``), from the independent model (P2 stress at 16 x (4 n + 1) points of the
fillet, 2 um inside it, the mesh also graded to ``--h-min-mm`` along the fillet) and
from the fast level's stress model (the slices spread by the moment image, and the
independent slices), all over the independent model's.

    python3 benchmarks/fe_independent.py --root-stress --helix-deg 0 15 30 --face-mm 12 --positions 0.25 0.75

``--stress-profile``: the FE level's fillet stress along the face over the fast level's,
each gear's tooth alone (default mesh, ``far_field="none"``) under 1 kN even along a
line of constant radius at 0 / 25 / 50 / 85 % of the way from the form to the tip
circle; the helical rows over the spur tooth's at the same face sample.

    python3 benchmarks/fe_independent.py --stress-profile --helix-deg 0 20 30 --face-mm 24

``--decompose``: the fast level's error split step by step (mean stiffness of the same
pairs, 8 positions, 300 N m, each over the FE level's segment): the FE level with its
couplings between tooth pairs dropped; the fast level with each pair's slices replaced
by one FE tooth (the middle one of three meshed, its lattice responses used for every
pair, the fast level's torsion between pairs, no far field) with the FE level's
half-space contact, then with Weber's contact to the matching depth; the fast level
(matching depth) without its far field. ``--decompose --cases 01:drive 03:drive``: the
same on the paper's cases (300 N m, 24 positions; the FE segment run again and checked
against the stored run).

    python3 benchmarks/fe_independent.py --decompose --helix-deg 0 15 30 --face-mm 12 30
    python3 benchmarks/fe_independent.py --decompose --cases 01:drive 03:drive

``--pair-couplings``: what the FE level shares between tooth pairs, against the fast
level. Each gear's FE level (its segment, cut faces clamped, and the far field it adds
to every entry: ``FECompliance.far_field``) built for five loadable teeth -2 .. 2 and
for three; unit loads on tooth 0's lattice, read on every loadable tooth at its lattice
depth points; per unit face width, E times it, under a load even along the face at each
lattice height (``--heights``: the nearest lattice rows, root circle 0 to tip 1, not
form to tip as for ``--stress-profile``), read as the
face mean at the same height: tooth 0 itself, the tooth in front of its loaded flank
(the side its outward normal points to) and the one behind it, the mean of the two
teeth two pitches away, the front and back teeth of the three-tooth segment, the two
far fields. Beside them what the fast level puts between pairs: the rim torsion
(``FastCompliance.torsion_matrix``), ``FAR_FIELD`` and the body's tilt
(``body_tilt``, :data:`BODY_TILT`), and the plane-strain whole gear's front and back
neighbours (:func:`gearbox.ltca.slice_fe.whole_gear_influence`, the normal section,
bore clamped, read at the centre line). About 3.5 minutes of FE per helix angle on the
2-core machine; ``--json`` keeps the rows (``tests/data/fe_pair_couplings.json``, read
by ``tests/test_ltca_slice_fe.py``).

    python3 benchmarks/fe_independent.py --pair-couplings --helix-deg 0 15 30 --face-mm 30 --heights 0.35 0.55 0.8 --json tests/data/fe_pair_couplings.json

On the z 20 / 40, m_n 4 mm pair unless ``--teeth Z1 Z2`` and ``--module-mm`` say
otherwise; the paper's tooth counts and module (about six minutes here):

    python3 benchmarks/fe_independent.py --pair-couplings --teeth 29 45 --module-mm 6 --helix-deg 0 20 --face-mm 40 --heights 0.35 0.55 0.8 --json tests/data/fe_pair_couplings_paper.json
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from gearbox.fe import FECompliance, FEOptions, MeshOptions  # noqa: E402
from gearbox.fe.compliance import gear_loads  # noqa: E402
from gearbox.fe.stress import fillet_stress  # noqa: E402
from gearbox.ltca import (  # noqa: E402
    FastCompliance,
    LTCAOptions,
    ParallelPair,
    iso_mesh_stiffness,
    ltca_cycle,
    parallel_grid,
)
from gearbox.ltca.compliance import HELIX_ENDS  # noqa: E402
from gearbox.ltca.stress import RootStressModel, root_stress_profile  # noqa: E402
from gearbox.surface.generation import flank_points, profile_range  # noqa: E402
from gearbox.surface.sample import tip_parameter  # noqa: E402

E, NU = 206e9, 0.3
TORQUE = 300.0


def pair_of(
    beta_deg: float, face_mm: float, teeth=(20, 40), module_mm: float = 4.0
) -> ParallelPair:
    return ParallelPair(
        normal_module=module_mm * 1e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=math.radians(beta_deg),
        teeth=tuple(teeth),
        face_width=face_mm * 1e-3,
    )


def n_face(face_mm: float) -> int:
    return max(6, int(round(face_mm / 2)))


# ------------------------------------------------------------------ the FE level
def level_line(pair: ParallelPair, position: float = 0.25, mesh: MeshOptions | None = None):
    """The FE level's one-tooth model: C at the contact line's points on tooth 0 (the
    lattice responses interpolated as ``FECompliance.gear_matrix`` does), the points,
    their frames and what the independent model needs (and, for ``--root-stress``, the
    level itself and a grid of the line's points alone)."""
    grid = parallel_grid(pair, position, n_face=n_face(pair.face_width * 1e3))
    loads = gear_loads(grid, 0)
    opts = FEOptions(far_field="none", neighbours=0)
    fe = FECompliance(opts if mesh is None else dataclasses.replace(opts, mesh=mesh))
    gm = fe._model(dataclasses.replace(loads, tooth=np.zeros_like(loads.tooth)), 0, E, NU)
    lat = fe._lattice(gm, loads.side)
    Clat = fe._responses(gm, loads.side, 0).depth[0]
    on = loads.tooth == 0
    z, u = loads.z[on], loads.u[on]
    W = fe._weights(lat, z, u)
    C = W @ Clat @ W.T
    P, n, t1, t2 = fe._surface(loads.blank, loads.side, 0, z, u)
    return {
        "C": 0.5 * (C + C.T),
        "blank": loads.blank,
        "side": loads.side,
        "bore": gm.model.mesh.bore_radius,
        "z": z,
        "u": u,
        "P": P,
        "n": n,
        "t1": t1,
        "t2": t2,
        "half": 0.5 * fe.options.lattice_spacing * loads.blank.normal_module,
        "depth": fe.options.matching_depth * loads.blank.normal_module,
        "fe": fe,
        "grid": grid.take(np.flatnonzero(on)),
    }


# ------------------------------------------------------------ independent model
def _polar(p):
    return np.hypot(p[:, 0], p[:, 1]), np.arctan2(p[:, 1], p[:, 0])


def _wrap(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


def tooth_sector(gmsh, blank, side, bore, refine_at, h_min, h_max, sections=9):
    """Loft of the transverse sections of tooth 0 and its rim sector (bore to the
    middles of the tooth spaces); a linear tetrahedral mesh graded from ``h_min`` within
    1.5 mm of the points ``refine_at`` to ``h_max`` beyond 8 mm. Returns the nodes
    (3, n), the tetrahedra (4, m) and the cut faces' angles per section ``(z, left,
    right)``."""
    occ = gmsh.model.occ
    N = blank.teeth
    u_min = profile_range(blank)[0]
    zs = np.linspace(blank.z_toe, blank.z_heel, sections)
    wires, cuts = [], []
    for z in zs:
        prof = {}
        for s in ("L", "R"):
            u_tip = float(tip_parameter(blank, s, np.array([z]))[0][0])
            u = np.concatenate([np.linspace(u_min, 0, 12)[:-1], np.linspace(0, u_tip, 40)])
            prof[s] = flank_points(blank, s, np.full(u.shape, z), u).position
        rL, thL = _polar(prof["L"])
        rR, thR = _polar(prof["R"])
        thc = thL[0] + 0.5 * _wrap(thR[0] - thL[0])
        sg = 1.0 if _wrap(thR[0] - thc) > 0 else -1.0
        cut_l, cut_r = thc - sg * np.pi / N, thc + sg * np.pi / N
        cuts.append((z, cut_l, cut_r))
        centre = occ.addPoint(0, 0, z)

        def at(r, th, z=z):
            return occ.addPoint(r * math.cos(th), r * math.sin(th), z)

        pR = [occ.addPoint(*q) for q in prof["R"]]
        pL = [occ.addPoint(*q) for q in prof["L"]]
        a, b = at(bore, cut_r), at(rR[0], cut_r)
        c, d = at(rL[0], cut_l), at(bore, cut_l)
        curves = [
            occ.addLine(a, b),
            occ.addCircleArc(b, centre, pR[0]),
            occ.addBSpline(pR),
            occ.addCircleArc(pR[-1], centre, pL[-1]),
            occ.addBSpline(pL[::-1]),
            occ.addCircleArc(pL[0], centre, c),
            occ.addLine(c, d),
            occ.addCircleArc(d, centre, a),
        ]
        wires.append(occ.addWire(curves))
    occ.addThruSections(wires, makeSolid=True, makeRuled=False)
    marks = [occ.addPoint(*q) for q in refine_at]
    occ.synchronize()
    field = gmsh.model.mesh.field
    field.add("Distance", 1)
    field.setNumbers(1, "PointsList", marks)
    field.add("Threshold", 2)
    for key, value in (
        ("InField", 1),
        ("SizeMin", h_min),
        ("SizeMax", h_max),
        ("DistMin", 1.5e-3),
        ("DistMax", 8e-3),
    ):
        field.setNumber(2, key, value)
    field.setAsBackgroundMesh(2)
    for key in ("MeshSizeExtendFromBoundary", "MeshSizeFromPoints", "MeshSizeFromCurvature"):
        gmsh.option.setNumber(f"Mesh.{key}", 0)
    gmsh.option.setNumber("Mesh.Algorithm3D", 10)
    gmsh.model.mesh.generate(3)
    tags, xyz, _ = gmsh.model.mesh.getNodes()
    _, nodes = gmsh.model.mesh.getElementsByType(4)
    index = np.full(int(tags.max()) + 1, -1)
    index[tags.astype(int)] = np.arange(tags.size)
    p = xyz.reshape(-1, 3).T
    t = index[nodes.astype(int)].reshape(-1, 4).T
    used = np.unique(t)
    remap = np.full(p.shape[1], -1)
    remap[used] = np.arange(used.size)
    return p[:, used], remap[t], np.array(cuts)


def _on_flank(blank, side, z, u, target):
    """The flank point nearest ``target`` (Newton on (z, u) from the given start, with
    the flank's own tangents ``dr_dz``, ``dr_du``)."""
    for _ in range(4):
        fp = flank_points(blank, side, np.array([z]), np.array([u]))
        J = np.column_stack([fp.dr_dz[0], fp.dr_du[0]])
        dz, du = np.linalg.lstsq(J, target - fp.position[0], rcond=None)[0]
        z, u = z + dz, u + du
    return flank_points(blank, side, np.array([z]), np.array([u])).position[0]


def _solve_independent(line, h_min, h_max, also_refine=None):
    """The gmsh / scikit-fem model of tooth 0 under the level's unit load at each point
    of the line: (basis, displacement columns U (N, points), size). The mesh is graded
    to ``h_min`` near the loads and the points ``also_refine`` (n, 3)."""
    import gmsh
    import pyamg
    import skfem
    from scipy.sparse.linalg import cg
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    P, n, t1, t2 = line["P"], line["n"], line["t1"], line["t2"]
    refine = np.concatenate([P, 0.5 * (P[1:] + P[:-1])])
    if also_refine is not None:
        refine = np.concatenate([refine, also_refine])
    gmsh.initialize()
    try:
        gmsh.option.setNumber("General.Verbosity", 1)
        p, t, cuts = tooth_sector(
            gmsh, line["blank"], line["side"], line["bore"], refine, h_min, h_max
        )
    finally:
        gmsh.finalize()
    mesh = skfem.MeshTet(np.ascontiguousarray(p), np.ascontiguousarray(t))
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementTetP2()), intorder=4)
    K = skfem.asm(linear_elasticity(*lame_parameters(E, NU)), basis)
    bore = line["bore"]

    def clamped(x):  # the bore and the two cut faces (angle within 1e-4 rad of the loft's)
        r, th = np.hypot(x[0], x[1]), np.arctan2(x[1], x[0])
        near = np.zeros(r.shape, bool)
        for col in (1, 2):
            near |= np.abs(_wrap(th - np.interp(x[2], cuts[:, 0], cuts[:, col]))) < 1e-4
        return (r < bore * (1 + 1e-6)) | near

    fixed = basis.get_dofs(facets=mesh.facets_satisfying(clamped, boundaries_only=True)).all()
    free = basis.complement_dofs(fixed)
    g = np.array([-math.sqrt(0.6), 0.0, math.sqrt(0.6)])
    w = np.array([5.0, 8.0, 5.0]) / 9.0
    F = np.zeros((basis.N, len(P)))
    for k in range(len(P)):
        pts, wts = [], []
        for i, gi in enumerate(g):
            for j, gj in enumerate(g):
                target = P[k] + line["half"] * (gi * t1[k] + gj * t2[k])
                q = _on_flank(line["blank"], line["side"], line["z"][k], line["u"][k], target)
                pts.append(q - 3e-6 * n[k])  # just inside the faceted surface
                wts.append(0.25 * w[i] * w[j])
        probe = basis.probes(np.array(pts).T).tocsr()  # rows: x of every point, then y, z
        m = len(pts)
        for c in range(3):
            F[:, k] -= probe[c * m : (c + 1) * m].T @ (np.array(wts) * n[k, c])
    # the solve: conjugate gradients, smoothed aggregation with the rigid-body modes
    Kf = K[free][:, free].tocsr()
    comp = np.zeros(basis.N, int)
    for c, ix in enumerate(basis.split_indices()):
        comp[ix] = c
    cf, (x, y, z) = comp[free], basis.doflocs[:, free]
    B = np.zeros((free.size, 6))
    for c in range(3):
        B[cf == c, c] = 1.0
    B[cf == 0, 3], B[cf == 1, 3] = -y[cf == 0], x[cf == 1]
    B[cf == 1, 4], B[cf == 2, 4] = -z[cf == 1], y[cf == 2]
    B[cf == 0, 5], B[cf == 2, 5] = z[cf == 0], -x[cf == 2]
    M = pyamg.smoothed_aggregation_solver(Kf, B=B, max_coarse=500).aspreconditioner()
    U = np.zeros_like(F)
    for k in range(F.shape[1]):
        sol, info = cg(Kf, F[free, k], M=M, rtol=1e-10, maxiter=3000)
        if info != 0:
            raise RuntimeError(f"conjugate gradients did not converge (info {info})")
        U[free, k] = sol
    return basis, U, {"vertices": mesh.p.shape[1], "dofs": int(free.size)}


def independent(line, h_min=0.3e-3, h_max=2.0e-3):
    """C of the same points from the gmsh / scikit-fem model (m/N) and its size."""
    basis, U, size = _solve_independent(line, h_min, h_max)
    P, n = line["P"], line["n"]
    Q = (P - line["depth"] * n).T
    probe = basis.probes(Q).tocsr()
    m = Q.shape[1]
    C = np.zeros((m, len(P)))
    for c in range(3):
        C -= (probe[c * m : (c + 1) * m] @ U) * n[:, c][:, None]
    return 0.5 * (C + C.T), size


def check(helix, faces, h_min, h_max) -> None:
    print(
        "| helix (deg) | face (mm) | points | FE level e'Ce/n^2 (m/N) | independent | "
        "independent / FE level | P2 unknowns | s |"
    )
    print("|---|---|---|---|---|---|---|---|")
    for face in faces:
        for beta in helix:
            t0 = time.perf_counter()
            line = level_line(pair_of(beta, face))
            C_ind, size = independent(line, h_min, h_max)
            e = np.ones(len(line["P"]))
            a, b = e @ line["C"] @ e / e.size**2, e @ C_ind @ e / e.size**2
            print(
                f"| {beta:g} | {face:g} | {e.size} | {a:.4e} | {b:.4e} | {b / a:.4f} | "
                f"{size['dofs']} | {time.perf_counter() - t0:.0f} |",
                flush=True,
            )


# ------------------------------------------------------------------ root stress
def _fillet_points(blank, side, n_z, n_u, inset=0.1e-3):
    """Points of tooth 0's fillet on the loaded side: face samples (n_z,) and the
    points (n_z, n_u, 3) with their outward normals, rack parameter u strictly inside
    ``(u_min, 0)`` and the face ends ``inset`` away."""
    u_min = profile_range(blank)[0]
    z = np.linspace(blank.z_toe + inset, blank.z_heel - inset, n_z)
    u = np.linspace(u_min, 0.0, n_u + 2)[1:-1]
    Z, Uu = np.meshgrid(z, u, indexing="ij")
    fp = flank_points(blank, side, Z, Uu)
    return z, fp.position, fp.normal


def _p2_principal(basis, U, pts, normals, depth=2e-6):
    """Largest principal stress (Pa) of the displacement U at points ``depth`` inside
    the surface (along -normal), each from the P2 element that holds it."""
    import skfem

    mesh = basis.mesh
    finder = mesh.element_finder()
    lam = E * NU / ((1 + NU) * (1 - 2 * NU))
    mu = E / (2 * (1 + NU))
    out = np.empty(len(pts))
    for k, (p, nn) in enumerate(zip(pts, normals, strict=True)):
        q = (p - depth * nn)[:, None]
        try:
            el = finder(*q)
        except ValueError:  # outside the faceted surface: a little deeper
            q = (p - 10 * depth * nn)[:, None]
            el = finder(*q)
        X = mesh.mapping().invF(q[:, :, None], tind=el)
        b = skfem.CellBasis(mesh, basis.elem, elements=el, quadrature=(X[:, 0, :], np.ones(1)))
        g = b.interpolate(U).grad[:, :, 0, 0]
        eps = 0.5 * (g + g.T)
        out[k] = np.linalg.eigvalsh(2 * mu * eps + lam * np.trace(eps) * np.eye(3))[-1]
    return out


def _level_fillet(line, load) -> float:
    """The FE level's largest fillet stress (Pa) under ``load`` (N) at the line's
    points (its one-tooth model, factorised by :func:`level_line`, reused)."""
    return fillet_stress(line["fe"], line["grid"], load, 0).max


def _fast_fillet(line, load):
    """The fast level's largest root stress (Pa): the slices spread by the moment
    image, and the independent slices."""
    spread = root_stress_profile(line["grid"], load, 0)
    slices = root_stress_profile(line["grid"], load, 0, RootStressModel(0.0, 0.0, helix_ends=None))
    return spread.stress.max(), slices.stress.max()


def root_stress(helix, faces, h_min, h_max, positions, refine) -> None:
    """The fillet stress of one tooth under a contact line's load: the FE level, the
    FE level on a finer mesh, the independent model and the fast level's stress model."""
    print(
        "| helix (deg) | face (mm) | position | load | FE level (MPa) | FE level "
        f"x{refine:g} | independent | independent / FE level | fast (spread) / independent "
        "| slices / independent | P2 unknowns | s |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    for face in faces:
        for beta in helix:
            for pos in positions:
                t0 = time.perf_counter()
                pair = pair_of(beta, face)
                line = level_line(pair, pos)
                fine = level_line(pair, pos, MeshOptions().refined(refine))
                _, P_f, n_f = _fillet_points(line["blank"], line["side"], 4 * n_face(face) + 1, 16)
                marks = P_f[:, [4, 8, 12]].reshape(-1, 3)
                basis, U, size = _solve_independent(line, h_min, h_max, marks)
                n = len(line["P"])
                s = np.linspace(-1.0, 1.0, n)
                # a line load even along the line, and one rising towards the line's
                # upper end (the tip side of the flank): 1 kN in all
                for name, w in (("even", np.ones(n)), ("rising", 1.0 + s)):
                    load = 1e3 * w / w.sum()
                    fe = _level_fillet(line, load)
                    fe_fine = _level_fillet(fine, load)
                    ind = _p2_principal(
                        basis, U @ load, P_f.reshape(-1, 3), n_f.reshape(-1, 3)
                    ).reshape(P_f.shape[:2])
                    ind_max = ind.max()
                    fast, slices = _fast_fillet(line, load)
                    print(
                        f"| {beta:g} | {face:g} | {pos:g} | {name} | {fe / 1e6:.2f} | "
                        f"{fe_fine / 1e6:.2f} | {ind_max / 1e6:.2f} | {ind_max / fe:.3f} | "
                        f"{fast / ind_max:.3f} | {slices / ind_max:.3f} | "
                        f"{size['dofs']} | {time.perf_counter() - t0:.0f} |",
                        flush=True,
                    )


@dataclasses.dataclass(frozen=True)
class _WithoutFarField(FastCompliance):
    """The fast level without its shared far field: what the FE segment holds."""

    def body_matrix(self, grid):
        return np.zeros((grid.size, grid.size))


def mesh_stiffness(helix, faces, helix_ends=None) -> None:
    print(
        "| helix (deg) | face (mm) | FE segment | fast without far field | fast / FE | "
        "fast (default) | ISO c_gamma_alpha (normal) |"
    )
    print("|---|---|---|---|---|---|---|")
    for face in faces:
        for beta in helix:
            pair = pair_of(beta, face)
            nf = n_face(face)

            def grid(q, pair=pair, nf=nf):
                return parallel_grid(pair, q, n_face=nf)

            def k(comp, grid=grid, pair=pair):
                res = ltca_cycle(grid, [TORQUE], options=LTCAOptions(positions=8), compliance=comp)
                return float(res.stiffness[0].mean()) / pair.face_width / 1e9

            fe = k(FECompliance(FEOptions(far_field="none")))
            seg = k(_WithoutFarField(helix_ends=helix_ends))
            whole = k(FastCompliance(helix_ends=helix_ends))
            iso = (
                iso_mesh_stiffness(
                    teeth=pair.teeth,
                    helix_angle=pair.helix_angle,
                    normal_pressure_angle=pair.normal_pressure_angle,
                    profile_shift=(0.0, 0.0),
                    transverse_contact_ratio=pair.transverse_contact_ratio,
                ).c_gamma_alpha
                / math.cos(pair.base_helix_angle) ** 2
            )
            print(
                f"| {beta:g} | {face:g} | {fe:.2f} | {seg:.2f} | {seg / fe:.3f} | {whole:.2f} | "
                f"{iso / 1e9:.2f} |",
                flush=True,
            )


class _WithinPairs(FECompliance):
    """The FE level with the couplings between tooth pairs dropped (its blocks within
    each pair kept): what the FE's adjacent teeth add. ``within = False``: the level
    itself (the same factorised models and responses)."""

    within = True

    def gear_matrix(self, grid, gear):
        C = super().gear_matrix(grid, gear)
        if not self.within:
            return C
        same = grid.pair[:, None] == grid.pair[None, :]
        return np.where(same, C, 0.0)


@dataclasses.dataclass(frozen=True)
class _ToothAlone(FastCompliance):
    """The fast level with each tooth pair's slices replaced by one FE tooth (the middle
    one of three meshed, ``neighbours=1``, no far field), the same responses for every
    pair; between pairs only the fast level's shared torsion, no far field. fe_contact:
    the FE level's half-space contact instead of Weber's to the matching depth."""

    fe: FECompliance | None = dataclasses.field(default=None, compare=False)
    fe_contact: bool = False

    def slice_matrix(self, grid, gear, parts=None):
        fe = self.fe
        loads = fe.loads(grid, gear)
        alone = dataclasses.replace(loads, tooth=np.zeros_like(loads.tooth))
        gm = fe._model(alone, gear, grid.youngs_modulus, grid.poisson_ratio)
        lat = fe._lattice(gm, loads.side)
        Clat = fe._responses(gm, loads.side, 0).depth[0]
        C = np.zeros((grid.size, grid.size))
        for k in grid.pairs():
            idx = np.flatnonzero(grid.pair == k)
            W = fe._weights(lat, loads.z[idx], loads.u[idx])
            C[np.ix_(idx, idx)] = W @ Clat @ W.T
        return 0.5 * (C + C.T)

    def torsion_matrix(self, grid):  # the FE tooth holds its own rim: between pairs only
        T = super().torsion_matrix(grid)
        return np.where(grid.pair[:, None] == grid.pair[None, :], 0.0, T)

    def body_matrix(self, grid):
        return np.zeros((grid.size, grid.size))

    def tooth_matrix(self, grid):
        C = super().tooth_matrix(grid)
        return C + self.fe.local_matrix(grid) if self.fe_contact else C

    def contact_diagonal(self, grid, line_load):
        if self.fe_contact:
            return self.fe.contact_diagonal(grid, line_load)
        return super().contact_diagonal(grid, line_load)


def _split(k, blanks=None, grids=None):
    """Mean stiffness ``k(compliance)`` of each level of the split (the module
    docstring): the FE segment, the same within pairs (one instance: the factorised
    models and responses reused), one FE tooth with the FE's contact and with Weber's,
    the fast level (matching depth) without its far field; and the seconds spent on the
    segment and on the one tooth. grids: size the segment for them first
    (``FECompliance.reserve``, as the stored runs of the paper's cases)."""
    t0 = time.perf_counter()
    seg = _WithinPairs(FEOptions(far_field="none"), blanks=blanks)
    if grids is not None:
        seg.reserve(grids)
    seg.within = False
    ks = [k(seg)]
    seg.within = True
    ks.append(k(seg))
    t1 = time.perf_counter()
    tooth = FECompliance(FEOptions(far_field="none", neighbours=1), blanks=blanks)
    ks += [
        k(_ToothAlone(contact="matching_depth", fe=tooth, fe_contact=True)),
        k(_ToothAlone(contact="matching_depth", fe=tooth)),
    ]
    t2 = time.perf_counter()
    ks.append(k(_WithoutFarField(contact="matching_depth")))
    return ks, (t1 - t0, t2 - t1)


def _split_row(lead: str, ks, seconds) -> str:
    """A table row: ``lead`` cells, each level over the FE segment (``ks[0]``), times."""
    ratios = " | ".join(f"{v / ks[0]:.3f}" for v in ks[1:])
    return f"| {lead} | {ratios} | {seconds[0]:.0f} / {seconds[1]:.0f} |"


def _print_table(head: list[str], rows: list[str]) -> None:
    print()
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    print("\n".join(rows))


#: the split's columns after the FE segment
_SPLIT = [
    "FE within pairs",
    "tooth alone, FE contact",
    "tooth alone, Weber",
    "fast (matching depth)",
]


def decompose(helix, faces) -> None:
    rows = []
    for face in faces:
        for beta in helix:
            pair = pair_of(beta, face)
            nf = n_face(face)

            def k(comp, pair=pair, nf=nf):
                grid = lambda q: parallel_grid(pair, q, n_face=nf)  # noqa: E731
                res = ltca_cycle(grid, [TORQUE], options=LTCAOptions(positions=8), compliance=comp)
                return float(res.stiffness[0].mean()) / pair.face_width / 1e9

            ks, seconds = _split(k)
            rows.append(_split_row(f"{beta:g} | {face:g} | {ks[0]:.2f}", ks, seconds))
            print(rows[-1], flush=True)
    head = ["helix (deg)", "face (mm)", "FE segment", *_SPLIT, "FE / tooth alone (s)"]
    _print_table(head, rows)


def decompose_cases(specs) -> None:
    """The same split on the paper's beveloid cases (``CASE:FLANK``), 300 N m, 24
    positions, and the default fast level: the FE level's segment run again (against
    the stored run of ``tests/data/fe_reference_paper_cases.json``), then each level
    over it."""
    from ltca_ripple import case_grids, cycle, stored_fe

    from gearbox.surface import blanks_from_design

    rows = []
    for spec in specs:
        case, flank = spec.split(":")
        _, design, grids = case_grids(case, flank)

        def k(comp, grids=grids):
            return float(cycle(grids, [TORQUE], comp).stiffness[0].mean())

        ks, seconds = _split(k, blanks_from_design(design), grids)
        ks.append(k(_WithoutFarField()))
        stored = stored_fe(case, flank)["mean_stiffness_N_per_m"][1]  # 300 N m
        lead = f"{case} | {flank} | {ks[0] / 1e6:.1f} | {ks[0] / stored:.4f}"
        rows.append(_split_row(lead, ks, seconds))
        print(rows[-1], flush=True)
    head = ["case", "flank", "FE segment (N/um)", "/ stored", *_SPLIT, "fast (default)"]
    _print_table([*head, "FE / tooth alone (s)"], rows)


def line_of_constant_radius(pair: ParallelPair, gear: int, frac: float, n: int, teeth=(0,)):
    """A grid with n slices over the whole face on each of ``teeth`` (tooth-pair
    indices; tooth 0 alone by default), every point of gear ``gear`` at the radius
    ``frac`` of the way from its form to its tip circle."""
    grid = parallel_grid(pair, 0.25, n_face=n)
    m = n * len(teeth)
    kw = grid.fields_at(np.full(m, int(np.flatnonzero(grid.pair == 0)[0])))
    dy = pair.face_width / n
    y = np.tile(-0.5 * pair.face_width + dy * (np.arange(n) + 0.5), len(teeth))
    r = pair.form_radius(gear) + frac * (pair.tip_radius(gear) - pair.form_radius(gear))
    name = "tooth1" if gear == 0 else "tooth2"
    kw[name] = dataclasses.replace(kw[name], radius=np.full(m, r))
    kw["position"] = kw["position"].copy()
    kw["position"][:, 2] = y
    kw.update(pair=np.repeat(np.asarray(teeth, int), n), slot=np.tile(np.arange(n), len(teeth)))
    kw["face"] = y
    return type(grid)(**kw)


def _level_couplings(pair: ParallelPair, gear: int, teeth, n: int) -> dict:
    """The FE level's segment built for ``teeth``: the response of each loadable tooth
    to unit loads on tooth 0's lattice (the segment alone), the lattice's load heights
    (root circle 0, tip 1) and the segment's far field (``FECompliance.far_field``, what the level adds
    to every entry)."""
    fe = FECompliance(FEOptions())
    g = line_of_constant_radius(pair, gear, 0.5, n, teeth=teeth)
    loads = fe.loads(g, gear)
    gm = fe._model(loads, gear, E, NU)
    lat = fe._lattice(gm, loads.side)
    solved = fe._responses(gm, loads.side, 0)
    z, u = (a.ravel() for a in np.meshgrid(lat.z, lat.u, indexing="ij"))
    r = np.hypot(*fe._surface(loads.blank, loads.side, 0, z, u)[0][:, :2].T)
    t = g.tooth1 if gear == 0 else g.tooth2
    eta = (r - t.root_radius[0]) / (t.tip_radius[0] - t.root_radius[0])
    return {
        "depth": solved.depth,
        "shape": (lat.z.size, lat.u.size),
        "dz": float(lat.z[1] - lat.z[0]),
        "height": eta.reshape(lat.z.size, lat.u.size).mean(axis=0),
        "far": fe.far_field(g, gear).compliance,
    }


def _even(level: dict, tooth: int) -> np.ndarray:
    """E times the approach per unit face width of ``tooth`` (the face mean at each
    lattice height) under a load per unit width even along tooth 0's face (at each
    lattice height), the level's far field included: shape (read, load) heights."""
    nz, nu = level["shape"]
    w = np.full(nz, level["dz"])
    w[[0, -1]] *= 0.5  # the trapezoidal rule over the lattice's face positions
    D = level["depth"][tooth].reshape(nz, nu, nz, nu)
    return E * (np.einsum("i,iajb,j->ab", w, D, w) / w.sum() + level["far"] * w.sum())


def pair_couplings(helix, faces, heights, out=None, counts=(20, 40), module_mm=4.0) -> None:
    """What the FE level shares between tooth pairs against the fast level (the module
    docstring), E times m^2/N, on the pair of ``counts`` teeth and ``module_mm``."""
    from gearbox.ltca.compliance import FAR_FIELD, body_tilt
    from gearbox.ltca.slice_fe import whole_gear_influence
    from gearbox.ltca.slice_model import normal_section

    rows, data = [], []
    for face in faces:
        n = n_face(face)
        for beta in helix:
            pair = pair_of(beta, face, counts, module_mm)
            for gear in (0, 1):
                # pair +1 is the tooth ahead in the gear's rotation: in front of the
                # driving pinion's loaded flank, behind the driven gear's
                front = 1 if gear == 0 else -1
                wide = _level_couplings(pair, gear, (-2, -1, 0, 1, 2), n)
                narrow = _level_couplings(pair, gear, (-1, 0, 1), n)
                g = line_of_constant_radius(pair, gear, 0.5, n, teeth=(-1, 0, 1))
                b = pair.face_width
                T = FastCompliance().torsion_matrix(g, gear)
                tors = E * float(T[np.ix_(g.pair == front, g.pair == 0)].sum()) / n**2 * b
                tilt = body_tilt(g, gear)
                teeth = (g.tooth1 if gear == 0 else g.tooth2).take(np.array([0]))
                ev = {k: _even(wide, k) for k in (-2, -1, 0, 1, 2)}
                ev5 = {k: _even(narrow, k) for k in (-1, 1)}
                for h in heights:
                    a = int(np.argmin(np.abs(wide["height"] - h)))
                    r = teeth.root_radius + wide["height"][a] * (
                        teeth.tip_radius - teeth.root_radius
                    )
                    v, factor = normal_section(dataclasses.replace(teeth, radius=r))
                    zv = int(round(float(v.teeth[0])))
                    plane = whole_gear_influence(v, E, NU, zv, v.radius, (-1, 0, 1)).ravel()
                    plane = plane * float(np.ravel(factor)[0]) * E
                    row = {
                        "teeth": list(pair.teeth),
                        "module_mm": module_mm,
                        "helix_deg": beta,
                        "face_mm": face,
                        "gear": gear,
                        "height": float(wide["height"][a]),
                        "own": float(ev[0][a, a]),
                        "front": float(ev[front][a, a]),
                        "back": float(ev[-front][a, a]),
                        "two_away": float(0.5 * (ev[2][a, a] + ev[-2][a, a])),
                        "front_narrow": float(ev5[front][a, a]),
                        "back_narrow": float(ev5[-front][a, a]),
                        "far_wide": float(wide["far"] * E * b),
                        "far_narrow": float(narrow["far"] * E * b),
                        "fast_torsion": tors,
                        "fast_far_field": FAR_FIELD,
                        "fast_tilt": tilt,
                        "plane_front": float(plane[2]),
                        "plane_back": float(plane[0]),
                    }
                    data.append(row)
                    fast = tors + FAR_FIELD + tilt
                    rows.append(
                        f"| {beta:g} | {face:g} | {('pinion', 'gear')[gear]} | "
                        f"{row['height']:.2f} | {row['own']:.2f} | {row['front']:.2f} / "
                        f"{row['back']:.2f} | {row['two_away']:.2f} | "
                        f"{row['front_narrow']:.2f} / {row['back_narrow']:.2f} | "
                        f"{row['far_wide']:.2f} / {row['far_narrow']:.2f} | "
                        f"{tors:.2f} + {FAR_FIELD:.2f} + {tilt:.2f} = {fast:.2f} | "
                        f"{row['plane_front']:.2f} / {row['plane_back']:.2f} |"
                    )
                    print(rows[-1], flush=True)
    head = [
        "helix (deg)",
        "face (mm)",
        "gear",
        "height",
        "FE own",
        "FE front / back",
        "FE two away",
        "FE front / back, 3 loadable",
        "FE far field, 5 / 3 loadable",
        "fast torsion + far field + tilt",
        "2-D front / back",
    ]
    _print_table(head, rows)
    if out:
        Path(out).write_text(json.dumps({"command": " ".join(sys.argv), "rows": data}, indent=1))


def face_profile(helix, faces, heights=(0.15, 0.5, 0.85)) -> None:
    fast = FastCompliance(contact="matching_depth")
    rows, modal, spur = [], [], {}
    for face in faces:
        n = int(round(face))  # slices of 1 mm
        for beta in sorted(helix):
            pair = pair_of(beta, face)
            fe = FECompliance(FEOptions(far_field="none"))
            for gear in (0, 1):
                for h in heights:
                    g = line_of_constant_radius(pair, gear, h, n)
                    C_fe, C_fast = fe.gear_matrix(g, gear), fast.slice_matrix(g, gear)
                    e = np.ones(n)
                    w = (C_fe @ e) / (C_fast @ e)
                    if gear == 1:  # the gear's lines climb towards -face
                        w = w[::-1]
                    mean = (e @ C_fe @ e) / (e @ C_fast @ e)
                    spur.setdefault((face, gear, h), mean if beta == 0 else None)
                    ref = spur[(face, gear, h)]
                    over = f"{mean / ref:.3f}" if ref else "-"
                    rows.append(
                        f"| {beta:g} | {face:g} | {('pinion', 'gear')[gear]} | {h:.2f} | "
                        f"{mean:.3f} | {over} | {w[0]:.2f} | {w[n // 2]:.2f} | {w[-1]:.2f} |"
                    )
                    if h == 0.5:
                        y = g.face / (0.5 * face * 1e-3)
                        q = (e, y, y**2 - np.mean(y**2))
                        modal.append(
                            f"| {beta:g} | {face:g} | {('pinion', 'gear')[gear]} | "
                            + " | ".join(f"{(v @ C_fe @ v) / (v @ C_fast @ v):.3f}" for v in q)
                            + " |"
                        )
                    print(rows[-1], flush=True)
    print()
    print(
        "| helix (deg) | face (mm) | gear | height | FE / fast | over spur | obtuse end | "
        "middle | acute end |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    print("\n".join(rows))
    print()
    print("| helix (deg) | face (mm) | gear | even | linear | quadratic |")
    print("|---|---|---|---|---|---|")
    print("\n".join(modal))


FACE_ENDS_HEIGHTS = (0.15, 0.5, 0.85)


def face_ends_data(helix, faces, cache=None) -> dict:
    """The FE level's one-tooth block (``far_field="none"``) under loads on a line of
    constant radius (1 mm slices over the whole face), per helix angle, face width,
    gear and height of :data:`FACE_ENDS_HEIGHTS`, keyed ``"beta_face_gear_height"``;
    read from / written to the ``.npz`` file ``cache`` where given."""
    data = dict(np.load(cache)) if cache and Path(cache).exists() else {}
    for face in faces:
        n = int(round(face))
        for beta in sorted(helix):
            pair, fe = pair_of(beta, face), None
            for gear in (0, 1):
                for h in FACE_ENDS_HEIGHTS:
                    key = f"{beta:g}_{face:g}_{gear}_{h:g}"
                    if key in data:
                        continue
                    fe = fe or FECompliance(FEOptions(far_field="none"))
                    data[key] = fe.gear_matrix(line_of_constant_radius(pair, gear, h, n), gear)
            if cache:
                np.savez(cache, **data)
    return data


def fit_face_ends(helix, faces, cache=None, out=None) -> None:
    """Fit :data:`gearbox.ltca.compliance.HELIX_ENDS` (the module docstring); ``out``:
    a JSON file of the fitted sets (label, load height, the FE's deflection over the
    plain slices', per slice) for ``tests/test_ltca_face_ends.py``."""
    from scipy.optimize import least_squares

    from gearbox.ltca.stress import HelixEnds, load_height

    t0 = time.perf_counter()
    data = face_ends_data(sorted({0.0, *helix}), faces, cache)
    t_fe = time.perf_counter() - t0
    fast = FastCompliance(contact="matching_depth", helix_ends=None)
    sets = {h: [] for h in FACE_ENDS_HEIGHTS}
    for face in faces:
        n = int(round(face))
        for gear in (0, 1):
            for h in FACE_ENDS_HEIGHTS:
                spur = None
                for beta in sorted({0.0, *helix}):
                    g = line_of_constant_radius(pair_of(beta, face), gear, h, n)
                    parts = fast.slice_parts(g)
                    w = fast.slice_matrix(g, gear, parts).sum(axis=1)
                    ratio = data[f"{beta:g}_{face:g}_{gear}_{h:g}"].sum(axis=1) / w
                    if beta == 0.0:
                        spur = ratio
                        continue
                    teeth = g.tooth1 if gear == 0 else g.tooth2
                    sets[h].append(
                        {
                            "grid": g,
                            "parts": parts,
                            "gear": gear,
                            "acute": 1.0 if gear == 0 else -1.0,  # the lines climb so
                            "target": w * ratio / spur,
                            "eta": float(load_height(teeth)[0]),
                            "label": (beta, face, gear, h),
                        }
                    )
    heights = tuple(float(np.mean([s["eta"] for s in sets[h]])) for h in FACE_ENDS_HEIGHTS)
    names = ("acute", "acute_decay", "obtuse", "obtuse_decay", "middle", "narrow")

    def ends_of(p, digits=None):
        r = (lambda v: float(v)) if digits is None else (lambda v: round(float(v), digits))
        per = np.asarray(p[:-1]).reshape(len(heights), len(names))
        kw = {name: tuple(r(v) for v in per[:, i]) for i, name in enumerate(names)}
        return HelixEnds(
            height=tuple(round(v, 2) for v in heights),
            quadratic=r(p[-1]),
            key="ltca.helix_ends",
            **kw,
        )

    def deflection(ends, s):
        comp = dataclasses.replace(fast, helix_ends=ends)
        return comp.slice_matrix(s["grid"], s["gear"], s["parts"], acute=s["acute"]).sum(axis=1)

    def resid(p, digits=None):
        ends = ends_of(p, digits)
        return np.concatenate(
            [np.log(deflection(ends, s) / s["target"]) for h in sets for s in sets[h]]
        )

    k = len(heights)
    p0 = [1.0, 0.5, 0.5, 0.5, 0.0, 0.5] * k + [1.0]
    lo = [0.0, 0.05, 0.0, 0.05, -2.0, -5.0] * k + [-1.0]
    hi = [20.0, 10.0, 20.0, 10.0, 2.0, 5.0] * k + [5.0]
    fit = least_squares(resid, p0, bounds=(lo, hi))
    ends = ends_of(fit.x, 3)  # the rounded coefficients, as printed
    res = resid(fit.x, 3)
    print(f"FE blocks {t_fe:.0f} s, fit {time.perf_counter() - t0 - t_fe:.0f} s")
    print(ends)
    print(f"rms {np.sqrt(np.mean(res**2)):.4f} in ln, largest {np.abs(res).max():.3f}")
    print()
    print(
        "| helix (deg) | face (mm) | gear | height | FE over spur: obtuse / middle / acute "
        "| fitted | rms in ln | mean |"
    )
    print("|---|---|---|---|---|---|---|---|")
    rows = []
    for h in sets:
        for s in sets[h]:
            beta, face, gear, _ = s["label"]
            plain = deflection(None, s)
            t, w = s["target"] / plain, deflection(ends, s) / plain
            if gear == 1:  # obtuse end first
                t, w = t[::-1], w[::-1]
            m = t.size // 2
            e = np.log(w / t)
            print(
                f"| {beta:g} | {face:g} | {('pinion', 'gear')[gear]} | {h:g} | "
                f"{t[0]:.2f} / {t[m]:.2f} / {t[-1]:.2f} | {w[0]:.2f} / {w[m]:.2f} / {w[-1]:.2f} "
                f"| {np.sqrt(np.mean(e**2)):.3f} | {np.mean(w) / np.mean(t):.3f} |"
            )
            rows.append(
                {
                    "helix_deg": beta,
                    "face_mm": face,
                    "gear": gear,
                    "height": h,
                    "fe_over_slices": (s["target"] / plain).tolist(),
                }
            )
    if out:
        with open(out, "w") as f:
            json.dump({"command": " ".join(sys.argv), "sets": rows}, f, indent=1)


def stress_profile(
    helix, faces, heights=(0.0, 0.25, 0.5, 0.85), refine=1.0, face_length=None, out=None
) -> None:
    """The FE level's fillet stress along the face over the fast level's (the slices
    spread by the moment image), each tooth alone under a load even along a line of
    constant radius: per gear, height and face sample; the helical rows over the spur
    tooth's at the same face width, gear, height and face sample. The fast level here
    has no helical face-end factor: a line of constant radius does not show the acute
    end (``gearbox.ltca.stress.acute_end``), so these rows are what the factor is
    for (``bench_root_stress.py --helix-ends`` fits it). ``refine``: the FE
    mesh refined by this factor; ``face_length``: its element length along the face
    (over m_n) instead; ``out``: a JSON file for the rows."""
    mesh = MeshOptions().refined(refine)
    if face_length is not None:
        mesh = dataclasses.replace(mesh, face_length=face_length)
    fe = FECompliance(FEOptions(far_field="none", mesh=mesh))
    spur, rows = {}, []
    print("| helix (deg) | face (mm) | gear | height | FE / fast along the face (z mm: ratio) |")
    print("|---|---|---|---|---|")
    for face in faces:
        n = int(round(face))  # slices of 1 mm
        for beta in sorted(helix):
            pair = pair_of(beta, face)
            for gear in (0, 1):
                for h in heights:
                    g = line_of_constant_radius(pair, gear, h, n)
                    load = np.full(n, 1e3 / n)
                    fs = fillet_stress(fe, g, load, gear)
                    prof = root_stress_profile(g, load, gear)
                    fast = np.interp(fs.z, prof.face, prof.stress.max(axis=0))
                    ratio = fs.root_stress.max(axis=0) / fast
                    spur.setdefault((face, gear, h), ratio if beta == 0 else None)
                    if beta != 0:
                        ratio = ratio / spur[(face, gear, h)]
                    rows.append(
                        {
                            "helix_deg": beta,
                            "face_mm": face,
                            "gear": gear,
                            "height": h,
                            "z_m": fs.z.tolist(),
                            "fe_Pa": fs.root_stress.max(axis=0).tolist(),
                            "fast_Pa": fast.tolist(),
                            "ratio": ratio.tolist(),
                        }
                    )
                    cells = ", ".join(
                        f"{z * 1e3:.0f}: {v:.2f}" for z, v in zip(fs.z, ratio, strict=True)
                    )
                    kind = "" if beta == 0 else " (over spur)"
                    print(
                        f"| {beta:g} | {face:g} | {('pinion', 'gear')[gear]} | {h:.2f}{kind} "
                        f"| {cells} |",
                        flush=True,
                    )
    if out:
        with open(out, "w") as f:
            json.dump({"mesh": mesh.to_dict(), "rows": rows}, f, indent=1)


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--helix-deg", type=float, nargs="+", default=[0.0, 15.0, 30.0])
    ap.add_argument("--face-mm", type=float, nargs="+", default=[12.0])
    ap.add_argument("--mesh-stiffness", action="store_true", help="the fast level against the FE")
    ap.add_argument(
        "--face-profile", action="store_true", help="FE / fast along the face, constant height"
    )
    ap.add_argument(
        "--fit-face-ends", action="store_true", help="fit the fast compliance's face ends"
    )
    ap.add_argument("--cache", help="--fit-face-ends: .npz file of the FE blocks (read, written)")
    ap.add_argument(
        "--face-ends",
        action="store_true",
        help="--mesh-stiffness: the fast level with its helical face ends (HELIX_ENDS)",
    )
    ap.add_argument(
        "--decompose", action="store_true", help="the FE's pair couplings and one tooth"
    )
    ap.add_argument(
        "--cases", nargs="+", metavar="CASE:FLANK", help="with --decompose: paper cases"
    )
    ap.add_argument(
        "--pair-couplings", action="store_true", help="one tooth's load on its neighbours"
    )
    ap.add_argument(
        "--root-stress", action="store_true", help="fillet stress: FE level, independent, fast"
    )
    ap.add_argument(
        "--stress-profile", action="store_true", help="FE / fast root stress along the face"
    )
    ap.add_argument("--positions", type=float, nargs="+", default=[0.25])
    ap.add_argument(
        "--refine", type=float, default=None, help="finer FE mesh (--root-stress: 2 by default)"
    )
    ap.add_argument(
        "--heights",
        type=float,
        nargs="+",
        default=[0.0, 0.25, 0.5, 0.85],
        help="--stress-profile, --pair-couplings: load heights, form (0) to tip circle (1)",
    )
    ap.add_argument(
        "--face-length-mn", type=float, help="--stress-profile: FE element length along the face"
    )
    ap.add_argument(
        "--json", help="--stress-profile, --fit-face-ends, --pair-couplings: write the rows here"
    )
    ap.add_argument("--teeth", type=int, nargs=2, default=[20, 40], help="--pair-couplings: z1 z2")
    ap.add_argument("--module-mm", type=float, default=4.0, help="--pair-couplings: m_n")
    ap.add_argument("--h-min-mm", type=float, default=0.3, help="tetrahedra near the loads")
    ap.add_argument("--h-max-mm", type=float, default=2.0, help="tetrahedra far from them")
    a = ap.parse_args(argv)
    if a.cases and not a.decompose:
        ap.error("--cases goes with --decompose")
    if (a.teeth != [20, 40] or a.module_mm != 4.0) and not a.pair_couplings:
        ap.error("--teeth and --module-mm go with --pair-couplings")
    if a.mesh_stiffness:
        mesh_stiffness(a.helix_deg, a.face_mm, HELIX_ENDS if a.face_ends else None)
    elif a.face_profile:
        face_profile(a.helix_deg, a.face_mm)
    elif a.fit_face_ends:
        fit_face_ends(a.helix_deg, a.face_mm, a.cache, a.json)
    elif a.stress_profile:
        stress_profile(
            a.helix_deg, a.face_mm, tuple(a.heights), a.refine or 1.0, a.face_length_mn, a.json
        )
    elif a.root_stress:
        root_stress(
            a.helix_deg,
            a.face_mm,
            a.h_min_mm * 1e-3,
            a.h_max_mm * 1e-3,
            a.positions,
            2.0 if a.refine is None else a.refine,
        )
    elif a.pair_couplings:
        pair_couplings(a.helix_deg, a.face_mm, a.heights, a.json, a.teeth, a.module_mm)
    elif a.decompose and a.cases:
        decompose_cases(a.cases)
    elif a.decompose:
        decompose(a.helix_deg, a.face_mm)
    else:
        check(a.helix_deg, a.face_mm, a.h_min_mm * 1e-3, a.h_max_mm * 1e-3)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

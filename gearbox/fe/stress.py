"""Tooth root stress from the finite-element model: fillet stresses per unit load.

The grid loads are carried onto the unit load lattice of :class:`~gearbox.fe.
compliance.FECompliance` (the transpose of its interpolation). Where the lattice
responses are cached (the FE compliance solved for them, one factorisation), the
displacements are those responses weighted by the lattice loads; otherwise the
lattice loads are solved for directly, once (a stress check under given loads, e.g.
the fast level's, then costs one solve per load case, not one per lattice point).
The stress tensor follows at fillet points of the loaded flank's side (the tension
side; mesh rows with ``u < 0``, element middles along the face) from the element's own
displacement gradient (isotropic Hooke's law). The root stress is the largest
principal stress along the fillet profile, per face position.
"""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..ltca.grid import ContactGrid
from .compliance import FECompliance
from .mesh import locate

__all__ = ["FilletStress", "fillet_points", "fillet_stress"]


@dataclass(frozen=True)
class FilletStress:
    """Largest principal stress along the fillet of each loaded tooth of one gear (SI).

    teeth: tooth offsets, shape (K,); z: axial position of the node layers (m), shape
    (Z,); u: rack-profile parameter of the fillet node rows (m, < 0), shape (U,);
    sigma1: largest principal stress (Pa), shape (K, Z, U); root_stress: its largest
    value over the fillet profile, shape (K, Z) (root stress along the face width).
    """

    teeth: np.ndarray
    z: np.ndarray
    u: np.ndarray
    sigma1: np.ndarray

    @property
    def root_stress(self) -> np.ndarray:
        return self.sigma1.max(axis=2)

    @property
    def max(self) -> float:
        return float(self.sigma1.max())


def fillet_points(fe, gm, side: str, tooth: int):
    """Where the fillet stresses of one tooth are evaluated.

    Returns (rows, layers, cells, X): node rows and layers of the points, their
    elements and reference coordinates. Cached on the gear model.
    """
    key = ("fillet", side, tooth)
    if key in gm.responses:
        return gm.responses[key]
    mesh = gm.model.mesh
    nodes = mesh.flank_nodes[(tooth, side)]
    u_rows = mesh.flank_u[side][0]
    # element-middle nodes only (odd node rows and layers): each lies inside one
    # element's face, away from the element edges where the stress of C0 elements
    # jumps and from the fillet's end on the root circle, where the fillet meets it
    # tangentially and the corner element's Jacobian vanishes
    rows = np.flatnonzero((u_rows < 0) & (np.arange(u_rows.size) % 2 == 1))
    if rows.size == 0:
        rows = np.array([1])
    layers = np.arange(1, mesh.z_layers.size, 2)
    ids = nodes[np.ix_(layers, rows)]
    P = mesh.p[:, ids.ravel()].T
    zz = np.repeat(mesh.z_layers[layers], rows.size)
    uu = np.tile(u_rows[rows], layers.size)
    cands = fe._candidates(mesh, tooth, side, zz, uu)
    cells, X, _ = locate(mesh, P, cands)
    gm.responses[key] = (rows, layers, cells, X)
    return gm.responses[key]


def fillet_stress(
    fe: FECompliance, grid: ContactGrid, load, gear: int, *, direct: bool = True
) -> FilletStress:
    """Largest principal fillet stress of gear ``gear`` (0 pinion, 1 gear) under the
    normal loads ``load`` (N, shape (n,)) at the grid points.

    Uses the factorised model cached on ``fe``. The loads are carried onto the unit
    load lattice either way; where the lattice responses of every loaded tooth are
    cached (the FE compliance computed them), they are superposed, otherwise
    (``direct``) the lattice loads are solved for once, which gives the same
    displacements (checked to round-off in tests/test_fe_stress.py) at the cost of
    one solve instead of one per lattice point. ``direct=False`` computes and caches
    the lattice responses.
    """
    load = np.asarray(load, dtype=float)
    loads = fe.loads(grid, gear)
    gm = fe._model(loads, gear, grid.youngs_modulus, grid.poisson_ratio)
    lat = fe._lattice(gm, loads.side)
    lattice_load = {t: W.T @ load[idx] for t, (idx, W) in fe._tooth_weights(lat, loads).items()}
    if all((loads.side, ta) in gm.responses for ta in lattice_load) or not direct:
        # superposed lattice responses (computed once per loaded tooth, then reused)
        U = np.zeros(gm.model.n_dofs)
        for ta, w in lattice_load.items():
            solved = fe._responses(gm, loads.side, ta)
            U[solved.dofs] += solved.fillet @ w
    else:
        # one solve under the same lattice loads: the same displacements without the
        # lattice's solve per point (one every 0.25 m_n over the flank by default: 549
        # per tooth on a 60 mm face at m_n 4 mm)
        t0 = time.perf_counter()
        F = np.zeros(gm.model.n_dofs)
        for ta, w in lattice_load.items():
            F += fe._lattice_unit_loads(gm, loads.side, ta) @ w
        U = gm.model.solve(F)
        fe.stats["solves"] += 1
        fe.stats["solve_s"] += time.perf_counter() - t0
    teeth = np.unique(loads.tooth)
    out = []
    rows = None
    for tb in teeth:
        rows, layers, cells, X = fillet_points(fe, gm, loads.side, int(tb))
        sig = gm.model.stress(cells, X, U[:, None])[:, 0]
        s1 = np.linalg.eigvalsh(sig)[:, -1]
        out.append(s1.reshape(layers.size, rows.size))
    mesh = gm.model.mesh
    return FilletStress(
        teeth=teeth,
        z=mesh.z_layers[layers].copy(),
        u=mesh.flank_u[loads.side][0][rows].copy(),
        sigma1=np.array(out),
    )

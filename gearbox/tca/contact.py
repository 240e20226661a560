"""Contact of two generated flanks on crossed axes: batched, bounded Newton.

Unknowns per problem: pinion flank parameters (z_1, u_1), gear flank parameters
(z_2, u_2) and the gear angle phi_2; the pinion angle phi_1 is given. Conditions
(Litvin & Fuentes, *Gear Geometry and Applied Theory*, 2nd ed. 2004, ch. 9
"Computerized Simulation of Meshing and Contact")::

    r_f1(z_1, u_1, phi_1) - r_f2(z_2, u_2, phi_2) = 0       (3 equations)
    n_f2 . e_1 = 0,   n_f2 . e_2 = 0                        (normals collinear)

with (e_1, e_2) a unit tangent basis built from the pinion's normal n_f1 (projecting on
the surface tangents instead would admit spurious roots on the cuspidal edge of the
involute continuation, where those tangents vanish).

The Jacobian is analytic (exact surface derivatives from the jets of
:func:`gearbox.surface.flank_jets`), the iteration is vectorised over any number of
problems, steps are limited, and every problem reports its iterations and whether it
converged. The flanks are iterated on the smooth continuation of their involute part
(``involute_only``); whether a solution lies on the real flank (inside the face width,
above the form circle, below the tip cone) is checked by the caller.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..surface import ToothBlank, flank_jets
from .assembly import Assembly

__all__ = ["ContactSolution", "solve_contact", "flank_frames", "contact_residual"]

MAX_ITER = 30
TOL_POSITION = 1e-11  # m
TOL_NORMAL = 1e-11  # -
MAX_STEP_LENGTH = 5e-3  # m, per iteration for z and u
MAX_STEP_ANGLE = 0.05  # rad, per iteration for phi_2
RCOND = 1e-7  # relative singular-value cut-off of the Newton step (line contact)
MAX_HALVINGS = 8  # backtracking of a step that raised the residual


def flank_frames(blank: ToothBlank, side: str, z, u, matrix, origin):
    """Point, derivatives and normal of a flank, transformed to Sf.

    Returns a dict with ``r`` (N,3), ``rz``, ``ru``, ``rzz``, ``rzu``, ``ruu`` (N,3), ``n``
    (N,3) and ``nz``, ``nu`` (N,3) (normal derivatives); ``matrix`` (N,3,3), ``origin`` (3,).
    """
    r, n, _ = flank_jets(blank, side, z, u, normal_jets=True, involute_only=True)
    R = np.stack([c.d for c in r], axis=-1)  # (6, N, 3)
    Nn = np.stack([c.d for c in n], axis=-1)
    R = np.einsum("nij,knj->kni", matrix, R)
    Nn = np.einsum("nij,knj->kni", matrix, Nn)
    return dict(
        r=R[0] + origin, rz=R[1], ru=R[2], rzz=R[3], rzu=R[4], ruu=R[5], n=Nn[0], nz=Nn[1], nu=Nn[2]
    )


@dataclass(frozen=True)
class ContactSolution:
    """Result of :func:`solve_contact` for N problems (SI).

    Attributes:
        x: (N, 5) solution (z_1, u_1, z_2, u_2, phi_2).
        converged: (N,) bool; ``iterations``: (N,) iterations used.
        residual_position: (N,) |r_f1 - r_f2| (m); ``residual_normal``: (N,) sine of
            the angle between the normals; ``opposed``: (N,) the outward normals point
            against each other (a real contact, not one flank inside the other).
        point: (N, 3) contact point in Sf (m); ``normal``: (N, 3) pinion's outward unit
            normal in Sf; ``pinion``, ``gear``: dicts of :func:`flank_frames`.
    """

    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    residual_position: np.ndarray
    residual_normal: np.ndarray
    opposed: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    pinion: dict
    gear: dict


def _system(pinion, gear, asm, side, phi1, x):
    M1 = asm.pinion_matrix(phi1)
    M2 = asm.gear_matrix(x[:, 4])
    a2, O2 = asm.gear_axis, asm.gear_origin
    f1 = flank_frames(pinion, side, x[:, 0], x[:, 1], M1, asm.pinion_origin)
    f2 = flank_frames(gear, side, x[:, 2], x[:, 3], M2, O2)
    n2 = f2["n"]
    dot = lambda a, b: np.einsum("ni,ni->n", a, b)  # noqa: E731
    E = _tangent_basis(f1["n"])
    F = np.concatenate(
        [f1["r"] - f2["r"], dot(n2, E["e1"])[:, None], dot(n2, E["e2"])[:, None]], axis=1
    )
    J = np.empty(x.shape[:1] + (5, 5))
    J[:, :3, 0] = f1["rz"]
    J[:, :3, 1] = f1["ru"]
    J[:, :3, 2] = -f2["rz"]
    J[:, :3, 3] = -f2["ru"]
    J[:, :3, 4] = -np.cross(a2, f2["r"] - O2)
    dn2 = np.cross(a2, n2)
    for row, e in ((3, "e1"), (4, "e2")):
        J[:, row, 0] = dot(n2, E["d" + e](f1["nz"]))
        J[:, row, 1] = dot(n2, E["d" + e](f1["nu"]))
        J[:, row, 2] = dot(f2["nz"], E[e])
        J[:, row, 3] = dot(f2["nu"], E[e])
        J[:, row, 4] = dot(dn2, E[e])
    return F, J, f1, f2


def _tangent_basis(n1):
    """Unit tangent basis (e1, e2) of the pinion flank from its unit normal, and the
    maps dn1 -> de1, dn1 -> de2 (derivatives for the Jacobian).

    ``e1 = (z_f x n1) / |z_f x n1|``, ``e2 = n1 x e1``: smooth wherever the normal is not
    axial (|sin beta_b| < 1), including the cuspidal edge of the involute continuation
    on the base cylinder, where the surface tangents vanish but n1 does not.
    """
    c = np.array([0.0, 0.0, 1.0])
    w = np.cross(c, n1)
    norm = np.linalg.norm(w, axis=1, keepdims=True)
    e1 = w / norm
    e2 = np.cross(n1, e1)

    def de1(dn):
        dw = np.cross(c, dn)
        return (dw - np.einsum("ni,ni->n", e1, dw)[:, None] * e1) / norm

    def de2(dn):
        return np.cross(dn, e1) + np.cross(n1, de1(dn))

    return {"e1": e1, "e2": e2, "de1": de1, "de2": de2}


def contact_residual(pinion, gear, asm, side, phi1, x):
    """F(x) and the Jacobian dF/dx, shapes (N, 5) and (N, 5, 5)."""
    F, J, _, _ = _system(pinion, gear, asm, side, np.asarray(phi1, float), np.asarray(x, float))
    return F, J


def _min_norm_solve(J, b):
    """Minimum-norm solutions of J x = b for a stack (N, m, m), (N, m).

    Pseudo-inverse by SVD with singular values below ``RCOND`` times the largest
    dropped: for line contact (FPD angle 0) the contact conditions have a curve of
    solutions, the Jacobian has rank 4, and the minimum-norm step goes to the nearest
    point of that curve (Gauss-Newton with the pseudo-inverse, Ben-Israel 1966).
    """
    return np.einsum("nij,nj->ni", np.linalg.pinv(J, rcond=RCOND), b)


def solve_contact(
    pinion: ToothBlank,
    gear: ToothBlank,
    asm: Assembly,
    side: str,
    phi1,
    x0,
    *,
    max_iter: int = MAX_ITER,
) -> ContactSolution:
    """Solve the contact conditions for N pinion angles at once.

    Args:
        pinion, gear: blanks of both members.
        asm: :class:`Assembly`.
        side: ``"R"`` (drive) or ``"L"`` (coast); pinion R meshes with gear R.
        phi1: pinion angles (rad), shape (N,).
        x0: starting values (N, 5): (z_1, u_1, z_2, u_2, phi_2) in m, m, m, m, rad.
        max_iter: iteration bound; problems not converged by then are reported.
    """
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    x = np.array(x0, dtype=float, copy=True).reshape(-1, 5)
    lim = np.array([MAX_STEP_LENGTH] * 4 + [MAX_STEP_ANGLE])

    def system(act, xa):
        F, J, _, _ = _system(pinion, gear, asm, side, phi1[act], xa)
        return F, J

    x, done, iters = bounded_newton(system, x, lim, max_iter)
    F, J, f1, f2 = _system(pinion, gear, asm, side, phi1, x)
    res_pos = np.linalg.norm(F[:, :3], axis=1)
    res_n = np.linalg.norm(np.cross(f1["n"], f2["n"]), axis=1)
    opposed = np.einsum("ni,ni->n", f1["n"], f2["n"]) < 0
    converged = done & np.all(np.isfinite(x), axis=1)
    return ContactSolution(x, converged, iters, res_pos, res_n, opposed, f1["r"], f1["n"], f1, f2)


def bounded_newton(system, x, lim, max_iter: int):
    """Batched bounded Newton with backtracking, shared by the surface and the edge
    contact solves.

    ``system(act, x[act])`` returns F (k, m) and J (k, m, m) of the active problems
    (``act`` a bool mask over all N); the first three parts of F are positions (m, to
    ``TOL_POSITION``), the rest, if any, unitless (to ``TOL_NORMAL``). ``lim`` (m,): the largest
    move of each unknown per iteration. Backtracking on the merit |F|^2 (each part over
    its tolerance): the step from x_prev that made it grow is halved, up to
    ``MAX_HALVINGS`` times, before a new Newton step. Returns (x, converged, iterations).
    """
    x = np.array(x, dtype=float, copy=True)
    n = x.shape[0]
    iters = np.zeros(n, dtype=int)
    done = np.zeros(n, dtype=bool)
    x_prev = x.copy()
    step_prev = np.zeros_like(x)
    merit_prev = np.full(n, np.inf)
    halvings = np.zeros(n, dtype=int)
    for _ in range(max_iter):
        act = ~done
        if not act.any():
            break
        F, J = system(act, x[act])
        ok_pos = np.max(np.abs(F[:, :3]), axis=1) <= TOL_POSITION
        ok_n = np.max(np.abs(F[:, 3:]), axis=1, initial=0.0) <= TOL_NORMAL
        conv = ok_pos & ok_n
        idx = np.flatnonzero(act)
        done[idx[conv]] = True
        upd = ~conv
        if not upd.any():
            break
        with np.errstate(all="ignore"):
            merit = np.sum((F[:, :3] / TOL_POSITION) ** 2, axis=1) + np.sum(
                (F[:, 3:] / TOL_NORMAL) ** 2, axis=1
            )
        i = idx[upd]
        back = ~(merit[upd] < merit_prev[i]) & (halvings[i] < MAX_HALVINGS)
        if back.any():  # the last step made it worse: go half as far from where it began
            b = i[back]
            step_prev[b] *= 0.5
            x[b] = x_prev[b] + step_prev[b]
            halvings[b] += 1
            iters[b] += 1
        new = ~back
        if new.any():
            k = i[new]
            with np.errstate(all="ignore"):
                step = _min_norm_solve(J[upd][new], -F[upd][new])
            # bounded steps: a limited move in each parameter keeps the iteration on the sheet
            scale = np.max(np.abs(step) / lim, axis=1, initial=1.0)
            step = np.where(np.isfinite(step), step / np.maximum(scale, 1.0)[:, None], 0.0)
            x_prev[k] = x[k]
            merit_prev[k] = merit[upd][new]
            step_prev[k] = step
            halvings[k] = 0
            x[k] += step
            iters[k] += 1
    return x, done, iters


def tangent_predictor(pinion, gear, asm, side, phi1, x):
    """dx/dphi_1 at solutions x (N, 5) (implicit function theorem), shape (N, 5)."""
    F, J, f1, f2 = _system(pinion, gear, asm, side, np.asarray(phi1, float), np.asarray(x, float))
    z = np.array([0.0, 0.0, 1.0])
    dr = np.cross(z, f1["r"] - asm.pinion_origin)
    E = _tangent_basis(f1["n"])
    dn1 = np.cross(z, f1["n"])  # the pinion turns about z_f
    n2 = f2["n"]
    dFp = np.concatenate(
        [
            dr,
            np.einsum("ni,ni->n", n2, E["de1"](dn1))[:, None],
            np.einsum("ni,ni->n", n2, E["de2"](dn1))[:, None],
        ],
        axis=1,
    )
    return _min_norm_solve(J, -dFp)

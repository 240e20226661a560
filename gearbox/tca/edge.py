"""Edge contact: where the flanks' surfaces do not touch on the real flanks.

Near line contact (an FPD angle of a degree or less) a small misalignment moves the
point where the two flank surfaces touch (:mod:`gearbox.tca.contact`) along the
near-line far beyond the face: on a pair designed for an FPD angle of 0.76 deg, a
shaft-angle error of 0.005 deg already leaves no such point on the real flanks. The
teeth then first touch where a border of one member's real flank meets the mate's
flank. The borders (:data:`EDGES`) are the face ends (toe and heel: the profile curve
``z = z_e``), the tip (the flank's line on the tip cone, ``u = u_tip(z)``) and the
root (the line where the involute starts, the form circle, ``u = u_start(z)``, where
the fillet takes over tangentially). A border first touches the mate's flank surface
under the rigid rotation where its tangent ``t`` lies in the mate's tangent plane.

Pinion border, unknowns ``y = (s, z_2, u_2, phi_2)`` with ``s`` the border's
parameter (u_1 on a face end, z_1 on the tip or root line)::

    r_f1(border(s), phi_1) - r_f2(z_2, u_2, phi_2) = 0      (3 equations)
    n_f2 . t_1 = 0                                         (tangent in the mate's plane)

Gear border, unknowns ``y = (z_1, u_1, s, phi_2)``: ``r_f1 - r_f2(border(s)) = 0``,
``n_f1 . t_2 = 0``. Both are solved by the bounded Newton iteration of the surface
contact (:func:`gearbox.tca.contact.bounded_newton`) with the exact surface
derivatives; a tip or root line ``u = c(z)`` is a cubic spline through
:data:`LINE_NODES` exact points (:func:`gearbox.surface.tip_parameter`,
:func:`gearbox.surface.involute_start`). The Jacobian is tested against central
differences (tests/test_tca_edge.py). Solutions are written as the surface contact's
five unknowns ``(z_1, u_1, z_2, u_2, phi_2)``.

Two more kinds of touch complete the candidates (:data:`CANDIDATES`): a **corner**
(:data:`CORNERS`, where a face end meets the tip or root line) is a point that the
mate's flank passes through (:func:`solve_corner_contact`: ``r_f1 = r_f2`` in the
mate's (z, u) and phi_2); a **crossing** (:data:`CROSSINGS`, a pinion border against a
gear border) is where two curves meet (:func:`solve_crossing_contact`: in both border
parameters and phi_2). Where the tips barely overlap (case 03 on axes 12 mm further
apart) the borders alone had missed first touches at crossings by up to 3.7e-3 rad.
:func:`edge_contacts` takes, per position, the candidate that touches first on both
real flanks; checked against the rigid first touch by brute force in
tests/test_tca_edge.py.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..surface import ToothBlank, involute_start, tip_parameter
from .assembly import Assembly
from .contact import MAX_ITER, MAX_STEP_ANGLE, MAX_STEP_LENGTH, bounded_newton, flank_frames

__all__ = [
    "CANDIDATES",
    "CORNERS",
    "CROSSINGS",
    "EDGES",
    "LINE_NODES",
    "EdgeSolution",
    "edge_contacts",
    "edge_residual",
    "edge_start",
    "on_flanks",
    "solve_corner_contact",
    "solve_crossing_contact",
    "solve_edge_contact",
]

#: The borders of the real flanks: (name, member, kind). Names are the flank limits'
#: (:data:`gearbox.tca.result.LIMITS`) on which each border lies.
EDGES = (
    ("pinion toe", "pinion", "toe"),
    ("pinion heel", "pinion", "heel"),
    ("pinion tip", "pinion", "tip"),
    ("pinion root", "pinion", "root"),
    ("gear toe", "gear", "toe"),
    ("gear heel", "gear", "heel"),
    ("gear tip", "gear", "tip"),
    ("gear root", "gear", "root"),
)

#: The corners of the real flanks, where a face end meets the tip or the form line:
#: (name, member, face end, line).
CORNERS = tuple(
    (f"{m} {end}/{line}", m, end, line)
    for m in ("pinion", "gear")
    for end in ("toe", "heel")
    for line in ("tip", "root")
)

#: Nodes of the cubic spline through a tip or root line ``u = c(z)``, over the face
#: and one face width beyond either end (c is smooth, the cone's and the helix's slow
#: change; the spline against the exact line in tests/test_tca_edge.py).
LINE_NODES = 241

#: Index in (z_1, u_1, z_2, u_2, phi_2) of each member's (z, u).
_ZU = {"pinion": (0, 1), "gear": (2, 3)}


@dataclass(frozen=True)
class EdgeSolution:
    """Result of :func:`solve_edge_contact` for N problems (SI).

    ``x``: (N, 5) as the surface contact's unknowns; ``converged``, ``iterations``;
    ``opposed``: the flanks' outward normals point against each other; ``point`` (N, 3)
    in Sf; ``normal`` (N, 3): the unit normal of the flank the border touches, turned
    to point along the pinion's outward normal.
    """

    edge: str
    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    opposed: np.ndarray
    point: np.ndarray
    normal: np.ndarray


class _Border:
    """One border of one member's flank: its parameter s, the member's (z, u) of it and
    their first and second derivatives in s."""

    def __init__(self, blank: ToothBlank, side: str, member: str, kind: str):
        self.blank, self.side, self.member, self.kind = blank, side, member, kind
        self.face = kind in ("toe", "heel")
        if self.face:
            self.z_e = float(blank.z_toe if kind == "toe" else blank.z_heel)
        else:
            self.spline = _line_spline(blank, side, kind)

    def zu(self, s):
        """(z, u, dz/ds, du/ds, d2z/ds2, d2u/ds2), each shape (N,)."""
        s = np.asarray(s, float)
        one, zero = np.ones_like(s), np.zeros_like(s)
        if self.face:
            return np.full_like(s, self.z_e), s, zero, one, zero, zero
        c = self.spline
        return s, c(s), one, c(s, 1), zero, c(s, 2)

    def full(self, y, zu=None):
        """(N, 5) surface-contact unknowns from the border's four (``zu``: their
        :meth:`zu`, when computed already)."""
        y = np.asarray(y, float)
        if zu is None:
            zu = self.zu(y[:, 0] if self.member == "pinion" else y[:, 2])
        z, u = zu[0], zu[1]
        if self.member == "pinion":
            return np.stack([z, u, y[:, 1], y[:, 2], y[:, 3]], axis=1)
        return np.stack([y[:, 0], y[:, 1], z, u, y[:, 3]], axis=1)

    def reduced(self, x):
        """The border's four unknowns from (N, 5) ones (the border's parameter: u on a
        face end, z on a line)."""
        iz, iu = _ZU[self.member]
        s = x[:, iu] if self.face else x[:, iz]
        if self.member == "pinion":
            return np.stack([s, x[:, 2], x[:, 3], x[:, 4]], axis=1)
        return np.stack([x[:, 0], x[:, 1], s, x[:, 4]], axis=1)


@lru_cache(maxsize=64)
def _line_spline(blank: ToothBlank, side: str, kind: str):
    """u = c(z) of a tip or root line as a cubic spline through LINE_NODES exact values
    (kept per blank: building one takes about 23 ms, and a TCA with edge contact asks
    for the lines of every candidate several times)."""
    from scipy.interpolate import CubicSpline

    b = blank.face_width
    z = np.linspace(blank.z_toe - b, blank.z_heel + b, LINE_NODES)
    if kind == "tip":
        c = tip_parameter(blank, side, z)[0]
    else:
        c = np.asarray(involute_start(blank, side, z), float)
    return CubicSpline(z, c)


def _solution(name, x, done, iters, f1, f2, touched) -> EdgeSolution:
    """An :class:`EdgeSolution` from a solve's unknowns x (N, 5) and both flanks' frames
    there; ``touched``: the frames of the flank whose normal is the contact's (turned
    along the pinion's outward normal)."""
    opposed = np.einsum("ni,ni->n", f1["n"], f2["n"]) < 0
    n = touched["n"] * np.sign(np.einsum("ni,ni->n", touched["n"], f1["n"]))[:, None]
    converged = done & np.all(np.isfinite(x), axis=1)
    return EdgeSolution(name, x, converged, iters, opposed, f1["r"], n)


def _member(name: str) -> str:
    """The member a border or corner lies on: its name's first word."""
    return name.split()[0]


def _border(pinion, gear, side, edge: str) -> _Border:
    for name, member, kind in EDGES:
        if name == edge:
            return _Border(pinion if member == "pinion" else gear, side, member, kind)
    raise ValueError(f"edge {edge!r} must be one of {', '.join(e[0] for e in EDGES)}")


def _edge_system(pinion, gear, asm, side, phi1, y, b: _Border):
    """F (N, 4), J (N, 4, 4) of a border's conditions at its unknowns y (N, 4); and x
    (N, 5), the frames f1, f2."""
    zu = b.zu(y[:, 0] if b.member == "pinion" else y[:, 2])
    x = b.full(y, zu)
    M1 = asm.pinion_matrix(phi1)
    M2 = asm.gear_matrix(x[:, 4])
    a2, O2 = asm.gear_axis, asm.gear_origin
    f1 = flank_frames(pinion, side, x[:, 0], x[:, 1], M1, asm.pinion_origin)
    f2 = flank_frames(gear, side, x[:, 2], x[:, 3], M2, O2)
    dot = lambda a, c: np.einsum("ni,ni->n", a, c)  # noqa: E731
    _, _, zs, us, zss, uss = zu
    fe, fm = (f1, f2) if b.member == "pinion" else (f2, f1)
    col = lambda v: v[:, None]  # noqa: E731
    # the border's tangent and its derivative along s
    t = col(zs) * fe["rz"] + col(us) * fe["ru"]
    dt = (
        col(zs**2) * fe["rzz"]
        + col(2 * zs * us) * fe["rzu"]
        + col(us**2) * fe["ruu"]
        + col(zss) * fe["rz"]
        + col(uss) * fe["ru"]
    )
    n = fm["n"]
    J = np.empty(y.shape[:1] + (4, 4))
    J[:, :3, 3] = -np.cross(a2, f2["r"] - O2)
    if b.member == "pinion":  # y = (s, z_2, u_2, phi_2)
        J[:, :3, 0] = t
        J[:, :3, 1] = -f2["rz"]
        J[:, :3, 2] = -f2["ru"]
        J[:, 3, 0] = dot(n, dt)
        J[:, 3, 1] = dot(f2["nz"], t)
        J[:, 3, 2] = dot(f2["nu"], t)
        J[:, 3, 3] = dot(np.cross(a2, n), t)
    else:  # y = (z_1, u_1, s, phi_2); the gear's tangent turns with it
        J[:, :3, 0] = f1["rz"]
        J[:, :3, 1] = f1["ru"]
        J[:, :3, 2] = -t
        J[:, 3, 0] = dot(f1["nz"], t)
        J[:, 3, 1] = dot(f1["nu"], t)
        J[:, 3, 2] = dot(n, dt)
        J[:, 3, 3] = dot(n, np.cross(a2, t))
    F = np.concatenate([f1["r"] - f2["r"], dot(n, t)[:, None]], axis=1)
    return F, J, x, f1, f2


def edge_residual(pinion, gear, asm, side, phi1, y, edge: str):
    """F(y) and dF/dy of one border's conditions, shapes (N, 4) and (N, 4, 4); y (N, 4)
    as in the module doc."""
    b = _border(pinion, gear, side, edge)
    F, J, *_ = _edge_system(pinion, gear, asm, side, np.atleast_1d(phi1), np.atleast_2d(y), b)
    return F, J


def solve_edge_contact(
    pinion: ToothBlank,
    gear: ToothBlank,
    asm: Assembly,
    side: str,
    phi1,
    x0,
    edge: str,
    *,
    max_iter: int = MAX_ITER,
) -> EdgeSolution:
    """Touch of the border ``edge`` (one of :data:`EDGES`) with the mate's flank for N
    pinion angles at once.

    x0: starting values (N, 5) as for :func:`gearbox.tca.contact.solve_contact`; the
    border's own member is put on the border (its z on a face end, its u on a line).
    """
    b = _border(pinion, gear, side, edge)
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    y = b.reduced(np.array(x0, dtype=float).reshape(-1, 5))
    lim = np.array([MAX_STEP_LENGTH] * 3 + [MAX_STEP_ANGLE])

    def system(act, ya):
        F, J, *_ = _edge_system(pinion, gear, asm, side, phi1[act], ya, b)
        return F, J

    y, done, iters = bounded_newton(system, y, lim, max_iter)
    _, _, x, f1, f2 = _edge_system(pinion, gear, asm, side, phi1, y, b)
    return _solution(edge, x, done, iters, f1, f2, f2 if b.member == "pinion" else f1)


def _corner(pinion, gear, side, corner: str):
    for name, member, end, line in CORNERS:
        if name == corner:
            blank = pinion if member == "pinion" else gear
            z = float(blank.z_toe if end == "toe" else blank.z_heel)
            u = float(_line_spline(blank, side, line)(z))
            return member, z, u
    raise ValueError(f"corner {corner!r} must be one of {', '.join(c[0] for c in CORNERS)}")


def solve_corner_contact(
    pinion: ToothBlank,
    gear: ToothBlank,
    asm: Assembly,
    side: str,
    phi1,
    x0,
    corner: str,
    *,
    max_iter: int = MAX_ITER,
) -> EdgeSolution:
    """Touch of the corner ``corner`` (one of :data:`CORNERS`) with the mate's flank for
    N pinion angles at once: the gear angle at which the mate's flank passes through
    the corner point, ``r_f1 = r_f2`` in the mate's (z, u) and phi_2 (3 equations).
    x0 as for :func:`solve_edge_contact`; the corner's member is put on the corner."""
    member, zc, uc = _corner(pinion, gear, side, corner)
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    x = np.array(x0, dtype=float).reshape(-1, 5).copy()
    iz, iu = _ZU[member]
    x[:, iz], x[:, iu] = zc, uc
    free = [2, 3, 4] if member == "pinion" else [0, 1, 4]
    a2, O2 = asm.gear_axis, asm.gear_origin

    def frames(ph, xa):
        f1 = flank_frames(
            pinion, side, xa[:, 0], xa[:, 1], asm.pinion_matrix(ph), asm.pinion_origin
        )
        f2 = flank_frames(gear, side, xa[:, 2], xa[:, 3], asm.gear_matrix(xa[:, 4]), O2)
        return f1, f2

    def full(y):
        xa = np.repeat(x[:1], y.shape[0], axis=0)
        xa[:, free] = y
        return xa

    def system(act, y):
        f1, f2 = frames(phi1[act], full(y))
        J = np.empty(y.shape[:1] + (3, 3))
        if member == "pinion":
            J[:, :, 0], J[:, :, 1] = -f2["rz"], -f2["ru"]
        else:
            J[:, :, 0], J[:, :, 1] = f1["rz"], f1["ru"]
        J[:, :, 2] = -np.cross(a2, f2["r"] - O2)
        return f1["r"] - f2["r"], J

    lim = np.array([MAX_STEP_LENGTH] * 2 + [MAX_STEP_ANGLE])
    y, done, iters = bounded_newton(system, x[:, free], lim, max_iter)
    xs = full(y)
    f1, f2 = frames(phi1, xs)
    return _solution(corner, xs, done, iters, f1, f2, f2 if member == "pinion" else f1)


#: Crossings: a border of the pinion's flank against a border of the gear's (two
#: curves touching where they cross), named "pinion <border> x gear <border>".
CROSSINGS = tuple(
    f"{a} x {b}" for a, ma, _ in EDGES if ma == "pinion" for b, mb, _ in EDGES if mb == "gear"
)


def solve_crossing_contact(
    pinion: ToothBlank,
    gear: ToothBlank,
    asm: Assembly,
    side: str,
    phi1,
    x0,
    crossing: str,
    *,
    max_iter: int = MAX_ITER,
) -> EdgeSolution:
    """Touch of a pinion border with a gear border (one of :data:`CROSSINGS`): the gear
    angle at which the two curves cross, ``r_f1(border_1(s_1)) = r_f2(border_2(s_2))``
    in (s_1, s_2, phi_2) (3 equations). x0 as for :func:`solve_edge_contact`."""
    a, b = crossing.split(" x ")
    b1, b2 = _border(pinion, gear, side, a), _border(pinion, gear, side, b)
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    x0 = np.array(x0, dtype=float).reshape(-1, 5)
    y = np.stack([b1.reduced(x0)[:, 0], b2.reduced(x0)[:, 2], x0[:, 4]], axis=1)
    a2, O2 = asm.gear_axis, asm.gear_origin

    def frames(ph, ya):
        z1, u1, zs1, us1, _, _ = b1.zu(ya[:, 0])
        z2, u2, zs2, us2, _, _ = b2.zu(ya[:, 1])
        f1 = flank_frames(pinion, side, z1, u1, asm.pinion_matrix(ph), asm.pinion_origin)
        f2 = flank_frames(gear, side, z2, u2, asm.gear_matrix(ya[:, 2]), O2)
        t1 = zs1[:, None] * f1["rz"] + us1[:, None] * f1["ru"]
        t2 = zs2[:, None] * f2["rz"] + us2[:, None] * f2["ru"]
        x = np.stack([z1, u1, z2, u2, ya[:, 2]], axis=1)
        return f1, f2, t1, t2, x

    def system(act, ya):
        f1, f2, t1, t2, _ = frames(phi1[act], ya)
        J = np.stack([t1, -t2, -np.cross(a2, f2["r"] - O2)], axis=-1)
        return f1["r"] - f2["r"], J

    lim = np.array([MAX_STEP_LENGTH] * 2 + [MAX_STEP_ANGLE])
    y, done, iters = bounded_newton(system, y, lim, max_iter)
    f1, f2, _, _, xs = frames(phi1, y)
    return _solution(crossing, xs, done, iters, f1, f2, f1)


def _solve(pinion, gear, asm, side, phi1, x0, name, max_iter):
    """A border's (:func:`solve_edge_contact`), a corner's or a crossing's touch."""
    if " x " in name:
        solver = solve_crossing_contact
    elif "/" in name:
        solver = solve_corner_contact
    else:
        solver = solve_edge_contact
    return solver(pinion, gear, asm, side, phi1, x0, name, max_iter=max_iter)


#: Pinion-angle step (rad) of the finite difference that gives an edge contact's
#: tangent along the sweep (a predictor only: Newton corrects it).
TANGENT_STEP = 1e-4


def _limits(pinion, gear, side, x):
    """The first flank limit each contact x (N, 5) violates on the pinion and on the
    gear ("" on the real flank), as :func:`gearbox.tca.local.flank_limits` names them."""
    from ..surface import flank_points
    from .local import flank_limits

    finite = np.all(np.isfinite(x), axis=1)
    xs = np.where(finite[:, None], x, 0.0)
    out = []
    for blank, z, u, who in (
        (pinion, xs[:, 0], xs[:, 1], "pinion"),
        (gear, xs[:, 2], xs[:, 3], "gear"),
    ):
        radius = flank_points(blank, side, z, u, involute_only=True).radius
        lim, _ = flank_limits(blank, side, z, u, radius, who)
        out.append(np.where(finite, lim, "not finite").astype(str))
    return out


def on_flanks(pinion, gear, side, x) -> np.ndarray:
    """Whether contacts x (N, 5) lie on both real flanks (inside the faces, above the
    involute's start, below the tip cones), edges included."""
    lim1, lim2 = _limits(pinion, gear, side, x)
    return (lim1 == "") & (lim2 == "")


def _classify(pinion, gear, side, s: EdgeSolution):
    """(valid, beyond) per solution of a border or corner: ``valid``, a touch on both
    real flanks (the border's own point may sit on its own limit, a corner on two);
    ``beyond``, a touch on the mate's real flank but beyond an end of the border (one of
    its corners lies nearer)."""
    lim1, lim2 = _limits(pinion, gear, side, s.x)
    if " x " in s.edge:  # a crossing: each point on its own border
        a, b = s.edge.split(" x ")
        ok1, ok2 = (lim1 == "") | (lim1 == a), (lim2 == "") | (lim2 == b)
        valid = s.converged & s.opposed & ok1 & ok2
        return valid, np.zeros_like(valid)
    own, mate = (lim1, lim2) if _member(s.edge) == "pinion" else (lim2, lim1)
    touch = s.converged & s.opposed & (mate == "")
    valid = touch & ((own == "") | (own == s.edge) | ("/" in s.edge))
    beyond = touch & ~valid & (own != "not finite")
    return valid, beyond


def _first(side: str, g: np.ndarray, valid: np.ndarray, axis: int = -1):
    """Index of the first contact along ``axis`` among ``valid``: the least gear angle on
    the drive side (R), the largest on the coast side (L); and whether there is one."""
    if side == "R":
        i = np.argmin(np.where(valid, g, np.inf), axis=axis)
    else:
        i = np.argmax(np.where(valid, g, -np.inf), axis=axis)
    return i, valid.any(axis=axis)


#: Every candidate of an edge contact: the borders, then the corners.
CANDIDATES = tuple(e[0] for e in EDGES) + tuple(c[0] for c in CORNERS) + CROSSINGS


def _edge_track(pinion, gear, asm, side, phi1c, x_start, edge, max_iter):
    """A border's, corner's or crossing's touch at phi1c from x_start and its tangent
    d x / d phi_1 (finite difference: the touch at phi1c + TANGENT_STEP solved in the
    same batch), or None where either solve fails."""
    h = TANGENT_STEP
    x0 = np.repeat(np.asarray(x_start, float)[None, :], 2, axis=0)
    s = _solve(pinion, gear, asm, side, [phi1c, phi1c + h], x0, edge, max_iter)
    if not (s.converged.all() and s.opposed[0]):
        return None
    return s.x[0], (s.x[1] - s.x[0]) / h


def edge_start(pinion, gear, asm, side, phi1c, x0, max_iter):
    """Start of the sweep where the surfaces do not touch near the pitch point: the
    border or corner that touches first at phi1c, as (x (5,), tangent (5,)), or None
    where none touches on the flanks there."""
    found = []
    for edge in CANDIDATES:
        got = _edge_track(pinion, gear, asm, side, phi1c, np.asarray(x0, float), edge, max_iter)
        if got is not None:
            s = _solve(pinion, gear, asm, side, [phi1c], got[0][None, :], edge, MAX_ITER)
            if _classify(pinion, gear, side, s)[0][0]:
                found.append(got)
    if not found:
        return None
    g = np.array([x[4] for x, _ in found])
    i, _ = _first(side, g, np.ones(len(found), bool))
    return found[int(i)]


def edge_contacts(pinion, gear, asm, side, phi1, pairs, phi1c, xc, tan, settings):
    """The first-touching border or corner at each pinion angle ``phi1`` (k,): over
    :data:`CANDIDATES` and the tooth pairs ``pairs`` (P,), as the surface sweep takes
    them.

    Each candidate is tracked from the surface contact (or edge start) ``xc`` at
    ``phi1c``, solved there, and carried along the sweep by its own tangent. Returns
    (gear angle (k,) rad, NaN where nothing touches on the flanks; the candidate's name
    (k,) object, "" there; contact point (k, 3) in Sf; its unknowns (k, 5) (z_1, u_1,
    z_2, u_2, phi_2 of the touching pair))."""
    N1, N2 = pinion.teeth, gear.teeth
    phi1 = np.asarray(phi1, float)
    k, P = phi1.size, len(pairs)
    phi_ref = (phi1[:, None] + 2 * np.pi * np.asarray(pairs)[None, :] / N1).ravel()
    g_all, v_all, pts = [], [], []
    for edge in CANDIDATES:
        track = _edge_track(
            pinion, gear, asm, side, phi1c, np.asarray(xc, float), edge, 2 * settings.max_iter
        )
        if track is None:
            continue
        xe, te = track
        X0 = xe + np.outer(phi_ref - phi1c, te)
        s = _solve(pinion, gear, asm, side, phi_ref, X0, edge, settings.max_iter)
        valid, _ = _classify(pinion, gear, side, s)
        g_all.append(s.x[:, 4].reshape(k, P) + 2 * np.pi * np.asarray(pairs)[None, :] / N2)
        v_all.append(valid.reshape(k, P))
        pts.append((edge, s.point.reshape(k, P, 3), s.x.reshape(k, P, 5)))
    angle = np.full(k, np.nan)
    name = np.full(k, "", dtype=object)
    point = np.full((k, 3), np.nan)
    xs = np.full((k, 5), np.nan)
    if not g_all:
        return angle, name, point, xs
    g = np.stack(g_all, axis=1).reshape(k, -1)  # (k, candidates x P)
    v = np.stack(v_all, axis=1).reshape(k, -1)
    i, has = _first(side, g, v, axis=1)
    rows = np.flatnonzero(has)
    angle[rows] = g[rows, i[rows]]
    for r in rows:
        e, j = divmod(int(i[r]), P)
        name[r] = pts[e][0]
        point[r] = pts[e][1][r, j]
        xs[r] = pts[e][2][r, j]
    return angle, name, point, xs

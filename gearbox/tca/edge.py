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
mate's flank passes through (``r_f1 = r_f2`` in the
mate's (z, u) and phi_2); a **crossing** (:data:`CROSSINGS`, a pinion border against a
gear border) is where two curves meet (in both border
parameters and phi_2). Where the tips barely overlap (case 03 on axes 12 mm further
apart) the borders alone had missed first touches at crossings by up to 3.7e-3 rad.
:func:`edge_contacts` takes, per position, the candidate that touches first on both
real flanks; checked against the rigid first touch by brute force in
tests/test_tca_edge.py. All candidates at all angles and tooth pairs go through one
batched Newton iteration (:class:`_Candidates`: four unknowns for every kind, the
three-unknown kinds holding the fourth at 0), so that a step evaluates both flanks once
for all of them; each row iterates on its own, as in a solve of its candidate alone.
"""

from __future__ import annotations

import dataclasses
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
    "edge_unknowns",
    "edge_start",
    "on_flanks",
    "solve_candidate",
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


@dataclass(frozen=True)
class EdgeSolution:
    """Result of :func:`solve_candidate` for N problems (SI).

    ``edge``: the candidate's name, or (N,) names where the rows solve different
    candidates (:func:`edge_contacts` solves them all in one batch); ``x``: (N, 5) as
    the surface contact's unknowns; ``converged``, ``iterations``;
    ``opposed``: the flanks' outward normals point against each other; ``point`` (N, 3)
    in Sf; ``normal`` (N, 3): the unit normal of the flank the border touches, turned
    to point along the pinion's outward normal.
    """

    edge: str | np.ndarray
    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    opposed: np.ndarray
    point: np.ndarray
    normal: np.ndarray


class _Border:
    """One border of one member's flank: its parameter s, the member's (z, u) of it and
    their first and second derivatives in s."""

    def __init__(self, blank: ToothBlank, side: str, kind: str):
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


def _member(name: str) -> str:
    """The member a border or corner lies on: its name's first word."""
    return name.split()[0]


def _corner(pinion, gear, side, corner: str):
    for name, member, end, line in CORNERS:
        if name == corner:
            blank = pinion if member == "pinion" else gear
            z = float(blank.z_toe if end == "toe" else blank.z_heel)
            u = float(_line_spline(blank, side, line)(z))
            return member, z, u
    raise ValueError(f"corner {corner!r} must be one of {', '.join(c[0] for c in CORNERS)}")


#: Crossings: a border of the pinion's flank against a border of the gear's (two
#: curves touching where they cross), named "pinion <border> x gear <border>".
CROSSINGS = tuple(
    f"{a} x {b}" for a, ma, _ in EDGES if ma == "pinion" for b, mb, _ in EDGES if mb == "gear"
)

#: Every candidate of an edge contact: the borders, the corners, the crossings.
CANDIDATES = tuple(e[0] for e in EDGES) + tuple(c[0] for c in CORNERS) + CROSSINGS

#: The kinds of candidate and their four unknowns y, the gear angle phi_2 always last:
#: a pinion border touching the gear's surface (s_1, z_2, u_2, phi_2), a gear border
#: touching the pinion's (z_1, u_1, s_2, phi_2), a pinion corner that the gear's
#: surface passes through (z_2, u_2, 0, phi_2), a gear corner (z_1, u_1, 0, phi_2) and
#: a crossing of two borders (s_1, s_2, 0, phi_2). A border adds the tangency
#: ``n_mate . t = 0`` to the three equations of coincident points; the kinds with three
#: unknowns hold the third at 0 (their fourth equation is ``y_3 = 0``).
PINION_BORDER, GEAR_BORDER, PINION_CORNER, GEAR_CORNER, CROSSING = range(5)


def _kind(name: str) -> tuple[int, str | None, str | None]:
    """(kind, the pinion's border, the gear's border) of a candidate's name."""
    if " x " in name:
        a, b = name.split(" x ")
        _border_kind(a, "pinion")  # each part a border of its member, else ValueError
        _border_kind(b, "gear")
        return CROSSING, a, b
    if "/" in name:  # checked against CORNERS where its point is taken (_corner)
        return (
            (PINION_CORNER, None, None) if _member(name) == "pinion" else (GEAR_CORNER, None, None)
        )
    if _border_kind(name, None) == "pinion":
        return PINION_BORDER, name, None
    return GEAR_BORDER, None, name


def _border_kind(name: str, member: str | None) -> str:
    """The member of the border ``name`` (checked to be ``member`` where given)."""
    for e, m, _ in EDGES:
        if e == name and member in (None, m):
            return m
    raise ValueError(f"edge {name!r} must be one of {', '.join(e[0] for e in EDGES)}")


class _Candidates:
    """N rows, each a candidate (a name of :data:`CANDIDATES`), as one system in the
    four unknowns of :data:`PINION_BORDER` and the others: every candidate at every
    angle goes through one batched Newton iteration, two surface evaluations per step."""

    def __init__(self, pinion, gear, asm, side, names):
        self.pinion, self.gear, self.asm, self.side = pinion, gear, asm, side
        names = np.asarray(names, dtype=object).reshape(-1)
        uniq, inv = np.unique(names.astype(str), return_inverse=True)
        parts = [_kind(str(u)) for u in uniq]
        edge_index = {e[0]: i for i, e in enumerate(EDGES)}
        self.borders = [
            _Border(pinion if m == "pinion" else gear, side, kind) for _, m, kind in EDGES
        ]
        # one more entry (index -1) for rows without a border on that member
        self.face = np.array([b.face for b in self.borders] + [False])
        self.kind = np.array([p[0] for p in parts], int)[inv]
        self.b1 = np.array([edge_index.get(p[1], -1) for p in parts], int)[inv]
        self.b2 = np.array([edge_index.get(p[2], -1) for p in parts], int)[inv]
        points = np.zeros((len(uniq), 2))
        for i, (u, p) in enumerate(zip(uniq, parts, strict=True)):
            if p[0] in (PINION_CORNER, GEAR_CORNER):
                points[i] = _corner(pinion, gear, side, str(u))[1:]
        self.point = points[inv]

    def start(self, x0):
        """The four unknowns from (N, 5) surface-contact ones: a border's own member is
        put on the border (its z on a face end, its u on a line), a corner's on it."""
        x0 = np.asarray(x0, float).reshape(-1, 5)
        k = self.kind
        s1 = np.where(self.face[self.b1], x0[:, 1], x0[:, 0])
        s2 = np.where(self.face[self.b2], x0[:, 3], x0[:, 2])
        y = np.zeros((x0.shape[0], 4))
        y[:, 3] = x0[:, 4]
        for kind, cols in (
            (PINION_BORDER, (s1, x0[:, 2], x0[:, 3])),
            (GEAR_BORDER, (x0[:, 0], x0[:, 1], s2)),
            (PINION_CORNER, (x0[:, 2], x0[:, 3])),
            (GEAR_CORNER, (x0[:, 0], x0[:, 1])),
            (CROSSING, (s1, s2)),
        ):
            m = k == kind
            for j, c in enumerate(cols):
                y[m, j] = c[m]
        return y

    def _zu(self, y, rows, member):
        """(z, u, dz/ds, du/ds, d2z/ds2, d2u/ds2) of ``member`` at ``rows`` (index array)
        from their unknowns y: the free surface's (z, u), a border's at its parameter or a
        corner's point (derivatives in s 0 where there is no border)."""
        k = self.kind[rows]
        out = np.zeros((6, len(rows)))
        if member == "pinion":
            surf = {GEAR_BORDER: (0, 1), GEAR_CORNER: (0, 1)}
            on_border, s, bid, corner = (
                (k == PINION_BORDER) | (k == CROSSING),
                y[:, 0],
                self.b1,
                PINION_CORNER,
            )
        else:
            surf = {PINION_BORDER: (1, 2), PINION_CORNER: (0, 1)}
            on_border = (k == GEAR_BORDER) | (k == CROSSING)
            s, bid, corner = np.where(k == GEAR_BORDER, y[:, 2], y[:, 1]), self.b2, GEAR_CORNER
        for kind, (cz, cu) in surf.items():
            m = k == kind
            out[0, m], out[1, m] = y[m, cz], y[m, cu]
        m = k == corner
        out[0, m], out[1, m] = self.point[rows[m], 0], self.point[rows[m], 1]
        bid = bid[rows]
        for b in np.unique(bid[on_border]):
            m = on_border & (bid == b)
            out[:, m] = np.stack(self.borders[b].zu(s[m]))
        return out

    def system(self, phi1, y, rows):
        """F (n, 4), J (n, 4, 4) at the unknowns y (n, 4) of ``rows``; and x (n, 5), the
        pinion's and the gear's frames there."""
        asm = self.asm
        a2, O2 = asm.gear_axis, asm.gear_origin
        z1, u1, z1s, u1s, z1ss, u1ss = self._zu(y, rows, "pinion")
        z2, u2, z2s, u2s, z2ss, u2ss = self._zu(y, rows, "gear")
        f1 = flank_frames(
            self.pinion, self.side, z1, u1, asm.pinion_matrix(phi1), asm.pinion_origin
        )
        f2 = flank_frames(self.gear, self.side, z2, u2, asm.gear_matrix(y[:, 3]), O2)
        col = lambda v: v[:, None]  # noqa: E731
        dot = lambda a, c: np.einsum("ni,ni->n", a, c)  # noqa: E731
        # the borders' tangents (0 where a member has none)
        t1 = col(z1s) * f1["rz"] + col(u1s) * f1["ru"]
        t2 = col(z2s) * f2["rz"] + col(u2s) * f2["ru"]
        k = self.kind[rows]
        pb, gb, pc, gc, cr = (k == kind for kind in range(5))
        n = y.shape[0]
        F = np.zeros((n, 4))
        J = np.zeros((n, 4, 4))
        F[:, :3] = f1["r"] - f2["r"]
        J[:, :3, 3] = -np.cross(a2, f2["r"] - O2)
        # the pinion's point: its surface's (z_1, u_1) or its border's s_1
        s = gb | gc
        J[s, :3, 0], J[s, :3, 1] = f1["rz"][s], f1["ru"][s]
        s = pb | cr
        J[s, :3, 0] = t1[s]
        # the gear's
        J[pb, :3, 1], J[pb, :3, 2] = -f2["rz"][pb], -f2["ru"][pb]
        J[pc, :3, 0], J[pc, :3, 1] = -f2["rz"][pc], -f2["ru"][pc]
        J[gb, :3, 2] = -t2[gb]
        J[cr, :3, 1] = -t2[cr]

        def bend(f, zs, us, zss, uss, m):
            """The derivative of a border's tangent along s at rows m."""
            zs, us, zss, uss = col(zs[m]), col(us[m]), col(zss[m]), col(uss[m])
            return (
                zs**2 * f["rzz"][m]
                + 2 * zs * us * f["rzu"][m]
                + us**2 * f["ruu"][m]
                + zss * f["rz"][m]
                + uss * f["ru"][m]
            )

        if pb.any():  # y = (s_1, z_2, u_2, phi_2): the pinion's tangent in the gear's plane
            t, nm = t1[pb], f2["n"][pb]
            F[pb, 3] = dot(nm, t)
            J[pb, 3, 0] = dot(nm, bend(f1, z1s, u1s, z1ss, u1ss, pb))
            J[pb, 3, 1] = dot(f2["nz"][pb], t)
            J[pb, 3, 2] = dot(f2["nu"][pb], t)
            J[pb, 3, 3] = dot(np.cross(a2, nm), t)
        if gb.any():  # y = (z_1, u_1, s_2, phi_2); the gear's tangent turns with it
            t, nm = t2[gb], f1["n"][gb]
            F[gb, 3] = dot(nm, t)
            J[gb, 3, 0] = dot(f1["nz"][gb], t)
            J[gb, 3, 1] = dot(f1["nu"][gb], t)
            J[gb, 3, 2] = dot(nm, bend(f2, z2s, u2s, z2ss, u2ss, gb))
            J[gb, 3, 3] = dot(nm, np.cross(a2, t))
        three = pc | gc | cr
        F[three, 3] = y[three, 2]
        J[three, 3, 2] = 1.0
        x = np.stack([z1, u1, z2, u2, y[:, 3]], axis=1)
        return F, J, x, f1, f2


def _solve_rows(pinion, gear, asm, side, phi1, x0, names, max_iter) -> EdgeSolution:
    """The touch of each row's candidate ``names`` (N,) at the pinion angles ``phi1``
    (N,) from ``x0`` (N, 5), all in one batched bounded Newton iteration
    (:func:`gearbox.tca.contact.bounded_newton`); each row iterates on its own."""
    c = _Candidates(pinion, gear, asm, side, names)
    x0 = np.asarray(x0, float).reshape(-1, 5)
    phi1 = np.broadcast_to(np.asarray(phi1, float).reshape(-1), (x0.shape[0],))
    lim = np.array([MAX_STEP_LENGTH] * 3 + [MAX_STEP_ANGLE])

    def system(act, ya):
        F, J, *_ = c.system(phi1[act], ya, np.flatnonzero(act))
        return F, J

    y, done, iters = bounded_newton(system, c.start(x0), lim, max_iter)
    _, _, x, f1, f2 = c.system(phi1, y, np.arange(x0.shape[0]))
    opposed = np.einsum("ni,ni->n", f1["n"], f2["n"]) < 0
    # the contact's normal: that of the flank a border or corner touches (the pinion's
    # for a gear's border or corner and for a crossing), along the pinion's outward one
    mate = (c.kind == PINION_BORDER) | (c.kind == PINION_CORNER)
    touched = np.where(mate[:, None], f2["n"], f1["n"])
    normal = touched * np.sign(np.einsum("ni,ni->n", touched, f1["n"]))[:, None]
    converged = done & np.all(np.isfinite(x), axis=1)
    edge = np.asarray(names, dtype=object).reshape(-1)
    return EdgeSolution(edge, x, converged, iters, opposed, f1["r"], normal)


def solve_candidate(
    pinion: ToothBlank,
    gear: ToothBlank,
    asm: Assembly,
    side: str,
    phi1,
    x0,
    name: str,
    *,
    max_iter: int = MAX_ITER,
) -> EdgeSolution:
    """Touch of the candidate ``name`` (one of :data:`CANDIDATES`: a border, a corner or
    a crossing) for N pinion angles ``phi1`` at once, from ``x0`` (N, 5) as for
    :func:`gearbox.tca.contact.solve_contact`; the candidate's own member is put on it
    (a border's z on a face end, its u on a line; a corner's point). ``edge``: the name.
    Raises ValueError for a name that is no candidate."""
    phi1 = np.atleast_1d(np.asarray(phi1, dtype=float))
    names = np.full(phi1.size, name, dtype=object)
    s = _solve_rows(pinion, gear, asm, side, phi1, x0, names, max_iter)
    return dataclasses.replace(s, edge=name)


def edge_residual(pinion, gear, asm, side, phi1, y, edge: str):
    """F(y) and dF/dy of one candidate's conditions, shapes (N, 4) and (N, 4, 4); y
    (N, 4) its unknowns (:data:`PINION_BORDER` and the others: for a border as in the
    module doc)."""
    y = np.atleast_2d(np.asarray(y, float))
    c = _Candidates(pinion, gear, asm, side, np.full(y.shape[0], edge, dtype=object))
    phi1 = np.broadcast_to(np.atleast_1d(np.asarray(phi1, float)), (y.shape[0],))
    F, J, *_ = c.system(phi1, y, np.arange(y.shape[0]))
    return F, J


def edge_unknowns(pinion, gear, asm, side, x, edge: str) -> np.ndarray:
    """The four unknowns y (N, 4) of the candidate ``edge`` (one of :data:`CANDIDATES`)
    at (N, 5) surface-contact unknowns x, as :func:`edge_residual` takes them."""
    x = np.atleast_2d(np.asarray(x, float))
    names = np.full(x.shape[0], edge, dtype=object)
    return _Candidates(pinion, gear, asm, side, names).start(x)


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
    """(valid, beyond) per solution of a candidate: ``valid``, a touch on both real
    flanks (a border's own point may sit on its own limit, a corner on two, a crossing's
    points each on its border); ``beyond``, a border's or corner's touch on the mate's
    real flank but beyond an end of the border (one of its corners lies nearer)."""
    lim1, lim2 = _limits(pinion, gear, side, s.x)
    names = np.broadcast_to(np.asarray(s.edge, dtype=object), s.converged.shape)
    valid = np.zeros(names.shape, bool)
    beyond = np.zeros(names.shape, bool)
    for name in set(names):
        m = names == name
        if " x " in name:  # a crossing: each point on its own border
            a, b = name.split(" x ")
            ok1 = (lim1[m] == "") | (lim1[m] == a)
            ok2 = (lim2[m] == "") | (lim2[m] == b)
            valid[m] = s.converged[m] & s.opposed[m] & ok1 & ok2
            continue
        own, mate = (lim1[m], lim2[m]) if _member(name) == "pinion" else (lim2[m], lim1[m])
        touch = s.converged[m] & s.opposed[m] & (mate == "")
        valid[m] = touch & ((own == "") | (own == name) | ("/" in name))
        beyond[m] = touch & ~valid[m] & (own != "not finite")
    return valid, beyond


def _first(side: str, g: np.ndarray, valid: np.ndarray, axis: int = -1):
    """Index of the first contact along ``axis`` among ``valid``: the least gear angle on
    the drive side (R), the largest on the coast side (L); and whether there is one."""
    if side == "R":
        i = np.argmin(np.where(valid, g, np.inf), axis=axis)
    else:
        i = np.argmax(np.where(valid, g, -np.inf), axis=axis)
    return i, valid.any(axis=axis)


def _tracks(pinion, gear, asm, side, phi1c, x_start, max_iter):
    """Every candidate's touch at phi1c from x_start and its tangent d x / d phi_1
    (finite difference: the touch at phi1c + TANGENT_STEP), all in one batched solve.
    Returns (the solution at phi1c of each of :data:`CANDIDATES`, an EdgeSolution of
    C rows; tangents (C, 5); ok (C,): both solves converged, the first opposed)."""
    h = TANGENT_STEP
    C = len(CANDIDATES)
    names = np.repeat(np.array(CANDIDATES, dtype=object), 2)
    phi = np.tile([phi1c, phi1c + h], C)
    x0 = np.repeat(np.asarray(x_start, float)[None, :], 2 * C, axis=0)
    s = _solve_rows(pinion, gear, asm, side, phi, x0, names, max_iter)
    ok = s.converged.reshape(C, 2).all(axis=1) & s.opposed[0::2]
    x = s.x.reshape(C, 2, 5)
    at = EdgeSolution(*(getattr(s, f.name)[0::2] for f in dataclasses.fields(s)))
    return at, (x[:, 1] - x[:, 0]) / h, ok


#: Iterations allowed to each candidate's solve at the sweep's start (from the surface
#: contact's start near the pitch point): twice the sweep's default, as the tracking in
#: :func:`edge_contacts` takes. On 80 random designs under random assembly errors
#: (benchmarks/tca_random_errors.py, seeds 11 and 12) every candidate that touched on
#: both flanks there had converged within 17 iterations (within 31 in the tracking);
#: a bound of 200, the surface solve's there, gave the same results, each start's
#: unconverged candidates iterating on to it.
START_MAX_ITER = 2 * MAX_ITER


def edge_start(pinion, gear, asm, side, phi1c, x0, max_iter: int | None = None):
    """Start of the sweep where the surfaces do not touch near the pitch point: the
    border, corner or crossing that touches first at phi1c, as (x (5,), tangent (5,)),
    or None where none touches on the flanks there. max_iter: per candidate, default
    :data:`START_MAX_ITER`."""
    max_iter = START_MAX_ITER if max_iter is None else max_iter
    at, tangent, ok = _tracks(pinion, gear, asm, side, phi1c, x0, max_iter)
    found = ok & _classify(pinion, gear, side, at)[0]
    if not found.any():
        return None
    i, _ = _first(side, at.x[:, 4], found)
    return at.x[int(i)], tangent[int(i)]


def edge_contacts(pinion, gear, asm, side, phi1, pairs, phi1c, xc, settings):
    """The first-touching border, corner or crossing at each pinion angle ``phi1`` (k,): over
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
    at, tangent, ok = _tracks(
        pinion, gear, asm, side, phi1c, np.asarray(xc, float), 2 * settings.max_iter
    )
    angle = np.full(k, np.nan)
    name = np.full(k, "", dtype=object)
    point = np.full((k, 3), np.nan)
    xs = np.full((k, 5), np.nan)
    cands = np.flatnonzero(ok)  # the candidates carried along the sweep
    C = cands.size
    if not C:
        return angle, name, point, xs
    X0 = at.x[cands][:, None, :] + (phi_ref - phi1c)[None, :, None] * tangent[cands][:, None, :]
    names = np.repeat(np.array(CANDIDATES, dtype=object)[cands], k * P)
    phi = np.tile(phi_ref, C)
    s = _solve_rows(pinion, gear, asm, side, phi, X0.reshape(-1, 5), names, settings.max_iter)
    valid, _ = _classify(pinion, gear, side, s)
    # (k, C x P): per position, every candidate at every pair
    gear_angles = s.x[:, 4].reshape(C, k, P) + 2 * np.pi * np.asarray(pairs)[None, None, :] / N2
    g = gear_angles.transpose(1, 0, 2).reshape(k, -1)
    v = valid.reshape(C, k, P).transpose(1, 0, 2).reshape(k, -1)
    i, has = _first(side, g, v, axis=1)
    rows = np.flatnonzero(has)
    angle[rows] = g[rows, i[rows]]
    flat = np.arange(C * k * P).reshape(C, k, P).transpose(1, 0, 2).reshape(k, -1)
    for r in rows:
        j = flat[r, i[r]]
        name[r] = s.edge[j]
        point[r] = s.point[j]
        xs[r] = s.x[j]
    return angle, name, point, xs

"""Loaded TCA over a mesh cycle: per position and torque, the contact solution and
everything the tables, summaries and figures need.

Definitions (stated once, used everywhere):

- ``rotation`` phi: loaded pinion rotation (rad) against the gear, from the
  geometric position; ``phi_0`` the rigid rotation to first contact (unloaded TE);
- normal load ``F_n = sum F_i`` (N); the load-weighted arm ``m = T / F_n`` (m);
- LTE (m): the loaded transmission error as a translation along the line of action,
  ``phi * m`` (for an involute pair ``r_b1 cos(beta_b) phi``), so that
  ``T dphi = F_n dLTE``; the unloaded TE is ``phi_0 * m``;
- secant mesh stiffness ``k = F_n / (LTE - TE_0)`` (N/m): by construction ``k`` times
  the elastic LTE is the transmitted normal load;
- tangent mesh stiffness ``dF_n / dLTE`` by a central difference in torque
  (``+-tangent_step``); the dynamics uses the tangent one, since small vibrations
  about the static load see the local slope of the load-deflection curve
  (:mod:`gearbox.meshtable`);
- mesh point P: load-weighted mean of the contact points; line of action n: the
  normalised load-weighted mean of the normals (force of the pinion on the gear);
- contact pattern: over the cycle, each loaded point covers its Hertz half-width
  (or half the profile travel between positions, whichever is larger) across the
  contact line in its face slice; the area fraction is the covered part of the
  active flank (profile range x face range of the grid);
- mesh loss factor ``H = sum F_i |v_s,i| / (T omega_1)``: the friction power per unit
  coefficient of friction over the transmitted power, with ``v_s`` the flanks'
  sliding velocity at each point (:meth:`ContactGrid.sliding_velocity`); a constant
  coefficient mu loses ``mu H`` of the power in the mesh (ISO/TR 14179-2's tooth
  loss factor H_V is its cycle mean for an idealised load sharing). Friction does not
  act back on the contact loads here.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..errors import Problems
from .compliance import Compliance, FastCompliance
from .grid import ContactGrid
from .slice_model import hertz_half_width, hertz_pressure
from .solver import ContactSolver, pair_sensitivities, solve_contact
from .stress import grid_root_stress, root_stress_matrices

__all__ = ["CycleResult", "LTCAOptions", "ltca_cycle", "root_stress_method"]


@dataclass(frozen=True)
class LTCAOptions:
    """Options of a mesh-cycle loaded TCA.

    positions: pinion positions per mesh cycle (>= 4); tangent_step: relative torque
    step of the tangent stiffness; pattern_cells: (profile, face) cells of the
    contact-pattern raster; edge_tolerance: share of the load on flank-edge points
    above which a position is flagged as edge contact; progress: show a progress bar.
    """

    positions: int = 24
    tangent_step: float = 0.02
    pattern_cells: tuple[int, int] = (40, 40)
    edge_tolerance: float = 0.05
    progress: bool = False

    def __post_init__(self):
        p = Problems()
        p.check(
            isinstance(self.positions, int) and self.positions >= 4,
            "ltca.positions",
            self.positions,
            "must be an integer >= 4 (positions per mesh cycle)",
        )
        p.in_range("tangent_step", self.tangent_step, 0.0, 0.5, lo_open=True)
        p.in_range("edge_tolerance", self.edge_tolerance, 0.0, 1.0)
        p.raise_if_any("invalid loaded TCA options")


@dataclass(frozen=True)
class CycleResult:
    """Loaded TCA of one flank over one mesh cycle and several torques (SI).

    Shapes: T = torques, P = positions, K = tooth pairs tracked, S = face slots,
    U x V = pattern raster (profile x face).

    torque (T,) N m; fraction (P,) position in mesh cycles; stiffness,
    tangent_stiffness (T, P) N/m; lte (T, P) m (loaded, unloaded TE included);
    lte_unloaded (P,) m; normal_load (T, P) N; max_pressure (T, P) Pa;
    root_stress_pinion, root_stress_gear (T, P) Pa, largest over the face;
    root_stress_face_pinion, root_stress_face_gear (T, S) Pa, largest over the cycle
    per face slot; pair_index (K,) and pair_share (T, P, K) load share of each tooth
    pair; pair_root_stress (T, P, K, 2) largest root stress of each tooth pair (Pa,
    pinion and gear); mesh_point, line_of_action (T, P, 3) in the grid's frame;
    pattern_pressure (T, U, V) Pa, largest Hertz pressure met by each cell over the
    cycle (0 = never in contact); pattern_area_fraction (T,);
    edge_load_fraction (T, P); iterations (T, P) active-set iterations;
    converged (T, P) bool; gap_residual (T, P) m; profile_range, face_range (m);
    loss_factor (T, P) mesh loss factor H (dimensionless), sliding_speed (T, P)
    largest sliding speed of a loaded point per unit pinion angular speed (m, i.e.
    m/s per rad/s); friction_arm (T, P, 2) the sliding friction's load-weighted moment
    arms about the pinion's and the gear's axis (m, :meth:`ContactGrid.friction_arms`:
    a mean friction coefficient mu puts -mu F_n arm_1 on the pinion and +mu F_n arm_2
    on the gear): all three ``None`` where the grids carry no axes. pair_weight
    (T, P, K): how much of a tooth pair's normal offset the loaded rotation takes up
    (:func:`~gearbox.ltca.solver.rotation_sensitivity`; sums to 1 over the pairs,
    :mod:`gearbox.ltca.pitch`); pair_load_sensitivity (T, P, K, K): d(normal load of
    pair j) / d(alpha_k) (N/rad) for an offset -m_i alpha_k of pair k's points
    (:func:`~gearbox.ltca.solver.pair_sensitivities`); both ``None`` in results stored
    before they existed. pair_form_weight (T, P, K, 8) and pair_form_load_sensitivity
    (T, P, K, K, 8): the same for unit coefficients of the offset shapes of pair k's
    flanks (slopes and crownings, :meth:`ContactGrid.form_bases`, in the order of
    ``ContactGrid.FORM_BASES``; the rotation changes by -sum w c, docs/ltca.md "Form
    deviations"); flank_range (4, 2):
    the range of the loaded points' flank coordinates (``ContactGrid.flank_coordinates``:
    roll lengths and axial positions of pinion and gear, m) over the cycle and torques,
    the flank the contact covers; all three ``None`` where the grids carry no flank
    coordinates.
    """

    torque: np.ndarray
    fraction: np.ndarray
    stiffness: np.ndarray
    tangent_stiffness: np.ndarray
    lte: np.ndarray
    lte_unloaded: np.ndarray
    normal_load: np.ndarray
    max_pressure: np.ndarray
    root_stress_pinion: np.ndarray
    root_stress_gear: np.ndarray
    root_stress_face_pinion: np.ndarray
    root_stress_face_gear: np.ndarray
    pair_index: np.ndarray
    pair_share: np.ndarray
    pair_root_stress: np.ndarray
    mesh_point: np.ndarray
    line_of_action: np.ndarray
    pattern_pressure: np.ndarray
    pattern_area_fraction: np.ndarray
    edge_load_fraction: np.ndarray
    iterations: np.ndarray
    converged: np.ndarray
    gap_residual: np.ndarray
    profile_range: tuple[float, float]
    face_range: tuple[float, float]
    meta: dict = field(default_factory=dict)
    loss_factor: np.ndarray | None = None
    sliding_speed: np.ndarray | None = None
    friction_arm: np.ndarray | None = None
    pair_weight: np.ndarray | None = None
    pair_load_sensitivity: np.ndarray | None = None
    pair_form_weight: np.ndarray | None = None
    pair_form_load_sensitivity: np.ndarray | None = None
    flank_range: np.ndarray | None = None

    @property
    def edge_contact(self) -> np.ndarray:
        """(T,) True where some position puts more than the tolerated load on a flank edge."""
        tol = self.meta.get("edge_tolerance", 0.05)
        return np.any(self.edge_load_fraction > tol, axis=1)

    @property
    def success(self) -> bool:
        return bool(np.all(self.converged))

    def tooth_load_share(self, t: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Load share of one tooth pair through its whole engagement.

        Returns (x, share): x in mesh cycles from the first position where the pair
        can touch, shape (K P,), and its share of the normal load.
        """
        return self._engagement(self.pair_share[t])

    def tooth_root_stress(self, t: int = 0) -> tuple[np.ndarray, np.ndarray]:
        """Largest root stress of one tooth (pinion, gear) through its engagement, as
        the load moves along the profile (paper Fig. 15(a)): (x, stress (K P, 2) Pa)."""
        return self._engagement(self.pair_root_stress[t])

    def _engagement(self, per_pair):
        # pair k's contact line lies k base pitches further along the path: at
        # position f it is the tooth that entered f + k cycles earlier
        x = np.concatenate([self.fraction + k for k in self.pair_index])
        v = np.concatenate([per_pair[:, kk] for kk in range(self.pair_index.size)])
        o = np.argsort(x)
        return x[o] - x.min(), v[o]

    def to_dict(self) -> dict:
        """Plain JSON-ready dict (arrays as nested lists, SI)."""
        d = {}
        for k, v in self.__dict__.items():
            if isinstance(v, np.ndarray):
                d[k] = v.tolist()
            elif isinstance(v, tuple):
                d[k] = list(v)
            elif isinstance(v, dict):
                d[k] = {kk: (vv.item() if hasattr(vv, "item") else vv) for kk, vv in v.items()}
            else:
                d[k] = v
        return d

    @classmethod
    def from_dict(cls, d) -> CycleResult:
        """Inverse of :meth:`to_dict`."""
        out = {}
        for f in fields(cls):
            v = d.get(f.name) if f.default is None else d[f.name]
            if v is None:
                out[f.name] = None
            elif f.name in ("profile_range", "face_range"):
                out[f.name] = tuple(float(x) for x in v)
            elif f.name == "meta":
                out[f.name] = dict(v)
            elif f.name in ("iterations", "pair_index"):
                out[f.name] = np.asarray(v, dtype=int)
            elif f.name == "converged":
                out[f.name] = np.asarray(v, dtype=bool)
            else:
                out[f.name] = np.asarray(v, dtype=float)
        return cls(**out)


def _pattern(raster, profile_range, face_range, samples, step):
    """Mark the raster's cells (U profile x V face) with the largest Hertz pressure met
    as the teeth sweep over them.

    ``samples``: arrays ``age`` (mesh cycles since the tooth's engagement began:
    position + tooth pair, so that one tooth's samples in a slice are ``step`` apart),
    ``profile``, ``face``, ``half`` (Hertz half-width across the contact line, in the
    profile coordinate), ``width`` (slice width), ``pressure``, ``loaded``, ``edge``
    (a point on a flank border) and ``slot``. Each loaded sample covers its rectangle
    [profile +- half] x [face +- width / 2] (at least its own cell). Between two
    positions a tooth's contact in a slice sweeps the cells between its two profile
    heights, the pressure interpolated linearly, when both samples are loaded and both
    on the flank or both on a border (a contact that moves from a border onto the flank
    jumps). Where a contact begins or ends between two positions it reaches half the
    step towards the other side (the unloaded sample there, or the step before
    extrapolated when the tooth leaves the flank or jumps), plus its half-width. At 24
    positions case 03's drive pattern at 300 N m is within 31 of its 1600 cells of the
    pattern of 192 positions, where the samples' rectangles alone missed 52, with ragged
    rows and holes along the pattern's edges (docs/ltca.md, "Contact pattern").
    """
    U, V = raster.shape
    p0, p1 = profile_range
    f0, f1 = face_range
    du = (p1 - p0) / U
    dv = (f1 - f0) / V
    uc = p0 + du * (np.arange(U) + 0.5)
    vc = f0 + dv * (np.arange(V) + 0.5)
    age, prof, half = samples["age"], samples["profile"], samples["half"]
    pres, loaded = samples["pressure"], samples["loaded"]
    edge, slot = samples["edge"], samples["slot"]
    n = prof.size
    # one tooth's consecutive samples in one slice: a -> b, one position apart, on the
    # same kind of point (flank or border)
    order = np.lexsort((age, slot))
    a, b = order[:-1], order[1:]
    keep = (slot[a] == slot[b]) & np.isclose(age[b] - age[a], step, rtol=1e-6, atol=0.0)
    keep &= edge[a] == edge[b]
    a, b = a[keep], b[keep]
    nxt = np.full(n, -1)
    prv = np.full(n, -1)
    nxt[a] = b
    prv[b] = a
    # segments along the profile (from u0 to u1, pressures q0 to q1) of sample ``who``
    on = np.flatnonzero(loaded)
    u0, u1 = [prof[on] - half[on]], [prof[on] + half[on]]
    q0, q1, who = [pres[on]], [pres[on]], [on]
    both = loaded[a] & loaded[b]
    u0 += [prof[a[both]]]
    u1 += [prof[b[both]]]
    q0 += [pres[a[both]]]
    q1 += [pres[b[both]]]
    who += [a[both]]
    # where the contact begins or ends: half the step beyond, plus the half-width
    for ahead, behind in ((nxt, prv), (prv, nxt)):
        i = on[(ahead[on] < 0) | ~loaded[np.maximum(ahead[on], 0)]]
        j, k = ahead[i], behind[i]
        there = j >= 0  # an unloaded sample on the other side
        step_u = np.where(there, prof[np.maximum(j, 0)] - prof[i], prof[i] - prof[np.maximum(k, 0)])
        ok = there | (k >= 0)
        i, step_u = i[ok], step_u[ok]
        u0 += [prof[i]]
        u1 += [prof[i] + 0.5 * step_u + np.sign(step_u) * half[i]]
        q0 += [pres[i]]
        q1 += [pres[i]]
        who += [i]
    u0, u1, q0, q1, who = (np.concatenate(v) for v in (u0, u1, q0, q1, who))
    for c in range(0, who.size, _PATTERN_CHUNK):  # (segments x cells) blocks of bounded size
        cut = slice(c, c + _PATTERN_CHUNK)
        _mark(
            raster, uc, vc, (p0, du, f0, dv), u0[cut], u1[cut], q0[cut], q1[cut], who[cut], samples
        )


#: Segments per block of :func:`_pattern` (its arrays are segments x raster cells).
_PATTERN_CHUNK = 20000


def _mark(raster, uc, vc, origin, u0, u1, q0, q1, who, samples):
    """Raise the raster's cells to the pressure of each profile segment (u0 -> u1,
    pressure q0 -> q1) of sample ``who`` over the face cells of its slice (at least its
    own cell along both)."""
    U, V = raster.shape
    p0, du, f0, dv = origin
    prof, face, width = samples["profile"], samples["face"], samples["width"]
    rows = (uc[None, :] >= np.minimum(u0, u1)[:, None]) & (
        uc[None, :] <= np.maximum(u0, u1)[:, None]
    )
    own = np.clip(((prof[who] - p0) / du).astype(int), 0, U - 1)
    rows[np.arange(who.size), own] = True
    span = u1 - u0
    with np.errstate(divide="ignore", invalid="ignore"):
        t = np.clip((uc[None, :] - u0[:, None]) / span[:, None], 0.0, 1.0)
    t = np.where(np.abs(span)[:, None] > 0, t, 0.0)
    value = np.where(rows, q0[:, None] + (q1 - q0)[:, None] * t, 0.0)
    lo, hi = face[who] - 0.5 * width[who], face[who] + 0.5 * width[who]
    cols = (vc[None, :] >= lo[:, None]) & (vc[None, :] <= hi[:, None])
    cols[np.arange(who.size), np.clip(((face[who] - f0) / dv).astype(int), 0, V - 1)] = True
    for v in range(V):
        hit = cols[:, v]
        if hit.any():
            raster[:, v] = np.maximum(raster[:, v], value[hit].max(axis=0))


def root_stress_method(compliance) -> str:
    """Where a compliance level's root stresses come from, in words."""
    if callable(getattr(compliance, "grid_root_stress", None)):
        return "FE fillet (largest principal stress, gearbox.fe.stress)"
    return "ISO 6336-3 slices spread along the face by the moment image (gearbox.ltca.stress)"


def _root_stress(compliance, grid: ContactGrid, load: np.ndarray, matrices=None):
    """Root stress of pinion and gear at the grid points under ``load``:
    ``((at1, at2), (top1, top2))``, each shape (n,), ``at`` at the point's face
    position, ``top`` the largest on the point's tooth. A level with its own stress
    model (``grid_root_stress``, the FE level's fillet) gives both; otherwise the
    slices' ISO 6336-3 stresses spread along the face by the moment image, whose
    largest on a tooth is the largest over its points (``matrices``: the grid's
    :func:`~gearbox.ltca.stress.root_stress_matrices`, if made already)."""
    own = getattr(compliance, "grid_root_stress", None)
    if callable(own):
        return own(grid, load)
    at = grid_root_stress(grid, load, matrices=matrices)
    top = []
    for s in at:
        m = np.zeros_like(s)
        for k in np.unique(grid.pair):
            on = grid.pair == k
            m[on] = s[on].max()
        top.append(m)
    return at, (top[0], top[1])


#: The (T, P) float arrays of a :class:`CycleResult`: one value per torque and position.
PER_POSITION = (
    "stiffness",
    "tangent_stiffness",
    "lte",
    "normal_load",
    "max_pressure",
    "root_stress_pinion",
    "root_stress_gear",
    "edge_load_fraction",
    "gap_residual",
)


def touching_grids(grids) -> list[ContactGrid]:
    """The grids of a cycle turned by one rigid gear rotation that brings the cycle's
    first contact to zero gap: the unloaded TE is referenced to its least value over the
    cycle, as the surface path builds its grids
    (:func:`~gearbox.ltca.beveloid.beveloid_grids`). A grid factory may then start from
    any nominal phase: the closed-form parallel grid's
    shaft-angle error and helix slopes leave negative gaps there (the nominal
    assembly in interference), which set the unloaded and loaded TE's mean off that
    path's by the interference (10.9 um on the 29/45 pair at 0.03 deg)."""
    grids = list(grids)
    ref = min(float(np.min(g.separation[g.arm > 0] / g.arm[g.arm > 0])) for g in grids)
    if ref == 0.0:
        return grids
    return [replace(g, separation=g.separation - g.arm * ref) for g in grids]


def ltca_cycle(
    grid_at: Callable[[float], ContactGrid],
    torques,
    *,
    options: LTCAOptions = LTCAOptions(),
    compliance: Compliance | None = None,
    solver: ContactSolver | None = None,
) -> CycleResult:
    """Loaded TCA over one mesh cycle for several torques.

    grid_at: function of the position in mesh cycles (0 <= f < 1) returning the
    :class:`ContactGrid` there; torques: pinion torque levels (N m), each > 0.
    Returns a :class:`CycleResult`.
    """
    torques = np.atleast_1d(np.asarray(torques, dtype=float))
    p = Problems()
    for i, t in enumerate(torques):
        p.in_range(f"torques[{i}]", float(t), 0.0, None, lo_open=True)
    if torques.size == 0:
        p.add("torques", [], "needs at least one torque level")
    p.raise_if_any("invalid loaded TCA input")
    compliance = compliance or FastCompliance()
    solver = solver or ContactSolver()
    P = options.positions
    T = torques.size
    fractions = np.arange(P) / P
    grids = touching_grids(grid_at(float(f)) for f in fractions)
    reserve = getattr(compliance, "reserve", None)
    if callable(reserve):  # a level that sizes its models to the whole cycle
        reserve(grids)
    kmin = min(int(g.pair.min()) for g in grids)
    kmax = max(int(g.pair.max()) for g in grids)
    pair_index = np.arange(kmin, kmax + 1)
    S = grids[0].n_slots
    U, V = options.pattern_cells
    profile_range = grids[0].profile_range
    face_range = grids[0].face_range

    out = {name: np.zeros((T, P)) for name in PER_POSITION}
    iterations = np.zeros((T, P), dtype=int)
    converged = np.ones((T, P), dtype=bool)
    lte0 = np.zeros(P)
    share = np.zeros((T, P, pair_index.size))
    weight = np.zeros((T, P, pair_index.size))
    load_sens = np.zeros((T, P, pair_index.size, pair_index.size))
    form = all(g.flank_coordinates is not None for g in grids)
    nb = len(ContactGrid.FORM_BASES)
    form_weight = np.zeros((T, P, pair_index.size, nb)) if form else None
    form_sens = np.zeros((T, P, pair_index.size, pair_index.size, nb)) if form else None
    flank_lo = np.full(4, np.inf)  # the four flank coordinates
    flank_hi = np.full(4, -np.inf)
    pair_rs = np.zeros((T, P, pair_index.size, 2))
    mesh_point = np.zeros((T, P, 3))
    loa = np.zeros((T, P, 3))
    rs_face1 = np.zeros((T, S))
    rs_face2 = np.zeros((T, S))
    samples = [[] for _ in range(T)]  # per position: see _pattern's names below

    bar = None
    if options.progress:
        from tqdm import tqdm

        bar = tqdm(total=P * T, desc="loaded TCA", unit="solve", leave=False)
    kinematics = all(g.pinion_axis is not None for g in grids)
    loss = np.zeros((T, P)) if kinematics else None
    sliding = np.zeros((T, P)) if kinematics else None
    friction_arm = np.zeros((T, P, 2)) if kinematics else None
    for j, grid in enumerate(grids):
        C0 = compliance.tooth_matrix(grid) if compliance.load_dependent else None
        own_stress = callable(getattr(compliance, "grid_root_stress", None))
        stress_maps = None if own_stress else root_stress_matrices(grid)
        vs = np.linalg.norm(grid.sliding_velocity(), axis=1) if kinematics else None
        arms = grid.friction_arms() if kinematics else None
        phi0 = float(np.min(grid.separation / grid.arm))
        # no form bases: zero columns (the pitch offset alone)
        bases = grid.form_bases() if form else np.zeros((grid.size, 0))
        prev = None
        for t, torque in enumerate(torques):
            init = None if prev is None else prev.load * (torque / torques[t - 1])
            kw = dict(solver=solver, tooth_matrix=C0)
            sol = solve_contact(grid, compliance, torque, initial_load=init, **kw)
            lo = solve_contact(
                grid, compliance, torque * (1 - options.tangent_step), initial_load=sol.load, **kw
            )
            hi = solve_contact(
                grid, compliance, torque * (1 + options.tangent_step), initial_load=sol.load, **kw
            )
            prev = sol
            F = sol.load
            Fn = float(F.sum())
            arm = torque / Fn

            def lte_of(s, tq):
                return s.rotation * tq / float(s.load.sum())

            lte = sol.rotation * arm
            lte0_j = phi0 * arm
            out["lte"][t, j] = lte
            out["normal_load"][t, j] = Fn
            out["stiffness"][t, j] = Fn / (lte - lte0_j)
            dF = float(hi.load.sum() - lo.load.sum())
            dd = lte_of(hi, torque * (1 + options.tangent_step)) - lte_of(
                lo, torque * (1 - options.tangent_step)
            )
            out["tangent_stiffness"][t, j] = dF / dd
            iterations[t, j] = sol.iterations + lo.iterations + hi.iterations
            converged[t, j] = sol.success and lo.success and hi.success
            out["gap_residual"][t, j] = sol.gap_residual
            if t == 0:
                lte0[j] = lte0_j
            q = F / grid.line_length
            E, nu = grid.youngs_modulus, grid.poisson_ratio
            p0 = hertz_pressure(q, grid.curvature_radius, E, nu)
            out["max_pressure"][t, j] = float(p0.max())
            (s1, s2), (m1, m2) = _root_stress(compliance, grid, F, stress_maps)
            out["root_stress_pinion"][t, j] = float(m1.max())
            out["root_stress_gear"][t, j] = float(m2.max())
            np.maximum.at(rs_face1[t], grid.slot, s1)
            np.maximum.at(rs_face2[t], grid.slot, s2)
            w_all, s_all = pair_sensitivities(
                grid, compliance, sol, pair_index, tooth_matrix=C0, bases=bases
            )
            weight[t, j], load_sens[t, j] = w_all[:, 0], s_all[..., 0]
            if form:
                form_weight[t, j], form_sens[t, j] = w_all[:, 1:], s_all[..., 1:]
                # the loaded points, the face positions widened by half their slices
                on = F > 0
                half = np.zeros((int(on.sum()), 4))
                half[:, 1] = 0.5 * grid.width[on]
                half[:, 3] = 0.5 * grid.width2[on]
                c = grid.flank_coordinates[on]
                flank_lo = np.minimum(flank_lo, (c - half).min(axis=0))
                flank_hi = np.maximum(flank_hi, (c + half).max(axis=0))
            for kk, k in enumerate(pair_index):
                on = grid.pair == k
                share[t, j, kk] = float(F[on].sum()) / Fn
                if on.any():
                    pair_rs[t, j, kk] = (float(m1[on].max()), float(m2[on].max()))
            mesh_point[t, j] = (F @ grid.position) / Fn
            nv = F @ grid.normal
            loa[t, j] = nv / np.linalg.norm(nv)
            out["edge_load_fraction"][t, j] = float(F[grid.edge].sum()) / Fn
            if kinematics:
                loss[t, j] = float(F @ vs) / torque
                sliding[t, j] = float(vs[F > 0].max())
                friction_arm[t, j] = (F @ arms) / Fn
            a = hertz_half_width(q, grid.curvature_radius, E, nu) / grid.transverse_projection
            samples[t].append(
                (fractions[j] + grid.pair, grid.profile, grid.face, a, grid.width, p0, F > 0)
                + (grid.edge, grid.slot)
            )
            if bar is not None:
                bar.update(1)
    if bar is not None:
        bar.close()

    # contact pattern: per torque, the teeth's loaded samples swept over the cycle
    pattern = np.zeros((T, U, V))
    area = np.zeros(T)
    names = ("age", "profile", "face", "half", "width", "pressure", "loaded", "edge", "slot")
    for t in range(T):
        cols = zip(*samples[t], strict=True)
        arrays = {n: np.concatenate(c) for n, c in zip(names, cols, strict=True)}
        _pattern(pattern[t], profile_range, face_range, arrays, 1.0 / P)
        area[t] = float(np.mean(pattern[t] > 0))
    return CycleResult(
        torque=torques,
        fraction=fractions,
        stiffness=out["stiffness"],
        tangent_stiffness=out["tangent_stiffness"],
        lte=out["lte"],
        lte_unloaded=lte0,
        normal_load=out["normal_load"],
        max_pressure=out["max_pressure"],
        root_stress_pinion=out["root_stress_pinion"],
        root_stress_gear=out["root_stress_gear"],
        root_stress_face_pinion=rs_face1,
        root_stress_face_gear=rs_face2,
        pair_index=pair_index,
        pair_share=share,
        pair_root_stress=pair_rs,
        mesh_point=mesh_point,
        line_of_action=loa,
        pattern_pressure=pattern,
        pattern_area_fraction=area,
        edge_load_fraction=out["edge_load_fraction"],
        iterations=iterations,
        converged=converged,
        gap_residual=out["gap_residual"],
        profile_range=tuple(profile_range),
        face_range=tuple(face_range),
        meta={
            "edge_tolerance": options.edge_tolerance,
            "compliance": compliance.name,
            "root_stress": root_stress_method(compliance),
        },
        loss_factor=loss,
        sliding_speed=sliding,
        friction_arm=friction_arm,
        pair_weight=weight,
        pair_load_sensitivity=load_sens,
        pair_form_weight=form_weight,
        pair_form_load_sensitivity=form_sens,
        flank_range=np.column_stack([flank_lo, flank_hi]) if form else None,
    )


def cycle_summary(res: CycleResult) -> dict:
    """Per torque: mean and peak-to-peak mesh stiffness and LTE, mean P and n, pattern
    area fraction, edge-contact flag, solver status (JSON-ready, SI)."""
    rows = []
    for t, tq in enumerate(res.torque):
        k = res.stiffness[t]
        e = res.lte[t]
        n = res.line_of_action[t].mean(axis=0)
        rows.append(
            {
                "torque_Nm": float(tq),
                "mean_mesh_stiffness_N_per_m": float(k.mean()),
                "mesh_stiffness_peak_to_peak_N_per_m": float(k.max() - k.min()),
                "mean_tangent_stiffness_N_per_m": float(res.tangent_stiffness[t].mean()),
                "lte_mean_m": float(e.mean()),
                "lte_peak_to_peak_m": float(e.max() - e.min()),
                "unloaded_te_peak_to_peak_m": float(np.ptp(res.lte_unloaded)),
                "mesh_point_m": [float(v) for v in res.mesh_point[t].mean(axis=0)],
                "line_of_action": [float(v) for v in n / np.linalg.norm(n)],
                "contact_pattern_area_fraction": float(res.pattern_area_fraction[t]),
                "max_contact_pressure_Pa": float(res.max_pressure[t].max()),
                "max_root_stress_pinion_Pa": float(res.root_stress_pinion[t].max()),
                "max_root_stress_gear_Pa": float(res.root_stress_gear[t].max()),
                "edge_contact": bool(res.edge_contact[t]),
                "max_edge_load_fraction": float(res.edge_load_fraction[t].max()),
                "solver_converged": bool(np.all(res.converged[t])),
                "solver_iterations_max": int(res.iterations[t].max()),
            }
        )
        if res.loss_factor is not None:
            rows[-1]["mesh_loss_factor"] = float(res.loss_factor[t].mean())
            rows[-1]["max_sliding_speed_per_pinion_speed_m"] = float(res.sliding_speed[t].max())
    return {"torques": rows}


__all__ += ["cycle_summary"]
_ = math

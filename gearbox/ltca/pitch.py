"""Tooth-to-tooth pitch deviations in the loaded TCA: the loaded transmission error over
a hunting period, and its order spectrum.

Each tooth's loaded flank stands off its nominal place by its cumulative pitch
deviation F_p,i (ISO 1328-1: measured along the arc of the reference circle, here the
reference pitch circle of the gear's reference section), positive where the flank
stands proud towards its mating flank (it takes up load early). Teeth are numbered
from the pair that is the loaded TCA's reference pair (``pair_index`` 0) at the first
position of the record, in the order they enter the mesh; a pair k of the loaded TCA
is the pair that was the reference pair k mesh cycles earlier (:class:`CycleResult`),
so in mesh cycle c it holds pinion tooth (c - k) mod z1 and gear tooth (c - k) mod z2.

Pair k's flanks then meet earlier by the pinion angle

    alpha_k = F_p1 / r_1 + F_p2 / r_2 * z2 / z1

(r the reference pitch radii; the gear's angle in pinion radians through the ratio),
which offsets the initial separations of its points by ds_i = -m_i alpha_k (m_i the
arm: normal approach per radian of pinion rotation). Two ways to the loaded rotation
phi under these offsets:

- ``linear``: phi = phi_0 - sum_k w_k alpha_k with the pair weights w_k of the loaded
  TCA (``CycleResult.pair_weight``, :func:`~gearbox.ltca.solver.rotation_sensitivity`):
  the first-order change at the loaded set of the nominal teeth. Exact for a
  deviation shared by every tooth (a rigid turn, the weights sum to 1) and in the
  single-pair zone of a spur pair (weight 1), to first order elsewhere. It does not
  see a pair that a proud tooth lifts off or that touches early: measured against
  ``exact`` in tests/test_ltca_pitch.py and docs/ltca.md ("Pitch deviations").
- ``exact``: the contact problem solved again at every position of the record with the
  offset separations (:func:`exact_rotation`), the load dependence and the changes of
  the loaded set included; one contact solve per sample.

The transmission error is the loaded TCA's ``lte``: the loaded rotation times the
torque arm T / sum F (m along the line of action), so a proud tooth lowers it.

Form deviations (:class:`FormDeviations`): each tooth's profile and helix slope
deviations f_H_alpha, f_H_beta tilt its flank about the point where its pitch is
measured (the reference circle in the face middle), and its crownings C_alpha, C_beta
(less the design's) bend it about the middle of the evaluation range. They offset pair
k's points by ds_i = -B_ij c_kj (:meth:`~gearbox.ltca.grid.ContactGrid.form_bases`: the
flank coordinates and their squares; c the coefficients of pair k's two teeth), which
the loaded TCA's form weights (``CycleResult.pair_form_weight``) carry through the same
two methods: linear, phi = phi_0 - sum_k (w_k alpha_k + sum_j W_kj c_kj), and exact.

Measured traces (:class:`FlankTraces`): each tooth's whole profile and helix traces,
offsets at every grid point (:meth:`FlankTraces.offsets`); the exact method solves with
them, the linear one takes the first-order change of all offsets from the tangent at
the torque (it needs the grids).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import InputError, Problem, Problems
from ..meshtable import FORM_BASES
from .analysis import CycleResult, touching_grids
from .solver import ContactSolver, solve_contact

__all__ = [
    "DeviationLevels",
    "HuntingRecord",
    "LevelRecords",
    "TraceTurns",
    "PitchDeviations",
    "PitchResult",
    "Trace",
    "FlankTraces",
    "FormDeviations",
    "covered_centres",
    "covered_lengths",
    "form_from_section",
    "pair_coefficients",
    "deviations_from_scene",
    "deviations_from_section",
    "exact_rotation",
    "exact_solutions",
    "flank_grids",
    "hunting_lte",
    "level_records",
    "order_kind",
    "pair_angles",
    "same_deviations",
    "trace_turns",
    "traces_from_section",
]

#: Largest cumulative pitch deviation accepted (m): 1 mm, far beyond the deviations
#: of any gear that is measured for its noise.
MAX_DEVIATION = 1.0e-3


def _per_tooth(name: str, values, p: Problems, size: int | None = None) -> np.ndarray:
    """A read-only float array of one value per tooth, each finite and within
    +-MAX_DEVIATION (problems named ``name[i]``)."""
    a = np.array(values, dtype=float).reshape(-1)
    if size is None:
        p.check(a.size >= 8, name, a.size, "needs one deviation per tooth (>= 8 teeth)")
    else:
        p.check(a.size == size, name, f"{a.size} values", f"must give one value per tooth: {size}")
    bad = ~np.isfinite(a) | (np.abs(a) > MAX_DEVIATION)
    if np.any(bad):
        i = int(np.flatnonzero(bad)[0])
        p.add(f"{name}[{i}]", float(a[i]), f"must be finite and within +-{MAX_DEVIATION} m")
    a.setflags(write=False)
    return a


#: The form deviations' shapes on the flanks, (member, kind), in the order of
#: ``FORM_BASES``'s first four (the slopes; the crownings follow in the same order).
_SHAPES = tuple(tuple(b.split("_")) for b in FORM_BASES[:4])


@dataclass(frozen=True)
class FormDeviations:
    """Profile and helix form deviations of each tooth's loaded flank (m), as a gear
    checker reports them, measured in the transverse plane along the base tangent:

    - slopes f_H_alpha, f_H_beta (ISO 1328-1): the departure of the mean trace from the
      design trace over the evaluation length. Positive: plus material growing towards
      the tip (profile) or towards the heel, +z on parallel axes (helix; each member's
      own axis). The flank turns about the reference circle in the face middle, where
      the pitch is measured, so the slopes add no offset there.
    - crownings C_alpha, C_beta less the design's (None: none): the height of the
      trace's arc over its chord across the evaluation length, a parabola with its
      vertex in the middle of the evaluation range. Positive: more crowned than
      designed, the range's ends lower than its middle by C. The parabola has no slope
      over its range (it leaves f_H as it is) and is shifted to add no offset at the
      reference point either: a tooth's offset at roll length or axial position x is
      -C ((2 (x - m) / L)^2 - (2 m / L)^2), m the middle of the range.

    pinion_profile, pinion_helix (z1,), gear_profile, gear_helix (z2,) the slopes and
    the four ``*_crowning`` arrays likewise, tooth i as the module doc numbers them;
    profile_length (L_alpha of pinion, gear: roll length, m) and helix_length (L_beta
    of pinion, gear: axial, m), the evaluation lengths; profile_centre, helix_centre
    (pinion, gear; m from the reference circle and the face middle) the middles of the
    evaluation ranges.
    """

    pinion_profile: np.ndarray
    pinion_helix: np.ndarray
    gear_profile: np.ndarray
    gear_helix: np.ndarray
    profile_length: tuple[float, float]
    helix_length: tuple[float, float]
    pinion_profile_crowning: np.ndarray | None = None
    pinion_helix_crowning: np.ndarray | None = None
    gear_profile_crowning: np.ndarray | None = None
    gear_helix_crowning: np.ndarray | None = None
    profile_centre: tuple[float, float] = (0.0, 0.0)
    helix_centre: tuple[float, float] = (0.0, 0.0)

    def __post_init__(self):
        p = Problems()
        z1 = np.size(self.pinion_profile)
        z2 = np.size(self.gear_profile)
        for member, kind in _SHAPES:
            z = z1 if member == "pinion" else z2
            name = f"{member}_{kind}"
            object.__setattr__(self, name, _per_tooth(name, getattr(self, name), p, z))
            name += "_crowning"
            given = getattr(self, name)
            object.__setattr__(
                self, name, _per_tooth(name, np.zeros(z) if given is None else given, p, z)
            )
        for name in ("profile_length", "helix_length", "profile_centre", "helix_centre"):
            v = tuple(float(x) for x in getattr(self, name))
            p.check(len(v) == 2, name, v, "must give (pinion, gear)")
            for i, x in enumerate(v[:2]):
                if name.endswith("length"):
                    p.in_range(f"{name}[{i}]", x, 0.0, None, lo_open=True)
                else:
                    p.check(math.isfinite(x), f"{name}[{i}]", x, "must be finite")
            object.__setattr__(self, name, v)
        p.raise_if_any("invalid form deviations")

    @property
    def teeth(self) -> tuple[int, int]:
        return int(self.pinion_profile.size), int(self.gear_profile.size)

    @property
    def crowned(self) -> bool:
        """Whether any tooth's crowning differs from the design's."""
        return any(np.any(getattr(self, f"{m}_{k}_crowning")) for m, k in _SHAPES)

    def _range(self, member: str, kind: str) -> tuple[float, float]:
        i = 0 if member == "pinion" else 1
        return getattr(self, f"{kind}_length")[i], getattr(self, f"{kind}_centre")[i]

    def coefficients(self, pinion_teeth, gear_teeth) -> np.ndarray:
        """The coefficients of the offset shapes (``ContactGrid.FORM_BASES``) of the
        given pinion and gear teeth (index arrays of one shape), stacked last: per
        flank coordinate x the slope f / L - 2 m q (m/m), then the crowning's q =
        -4 C / L^2 (1/m), so that the offset q x^2 + (f / L - 2 m q) x is the class
        doc's."""
        lin, quad = [], []
        for member, kind in _SHAPES:
            teeth = pinion_teeth if member == "pinion" else gear_teeth
            length, centre = self._range(member, kind)
            q = -4.0 * getattr(self, f"{member}_{kind}_crowning")[teeth] / length**2
            lin.append(getattr(self, f"{member}_{kind}")[teeth] / length - 2.0 * centre * q)
            quad.append(q)
        return np.stack(lin + quad, axis=-1)

    def to_dict(self) -> dict:
        out = {f"{m}_{k}_slope_m": getattr(self, f"{m}_{k}").tolist() for m, k in _SHAPES}
        if self.crowned:
            out.update(
                {
                    f"{m}_{k}_crowning_m": getattr(self, f"{m}_{k}_crowning").tolist()
                    for m, k in _SHAPES
                }
            )
        out["profile_evaluation_length_m"] = list(self.profile_length)
        out["helix_evaluation_length_m"] = list(self.helix_length)
        out["profile_evaluation_centre_m"] = list(self.profile_centre)
        out["helix_evaluation_centre_m"] = list(self.helix_centre)
        return out


@dataclass(frozen=True)
class Trace:
    """One member's measured profile or helix traces, one per tooth: ``deviation``
    (z, n) m at ``position`` (n,) m, strictly increasing, in the flank coordinate of
    :attr:`ContactGrid.flank_coordinates <gearbox.ltca.grid.ContactGrid>` (roll length
    from the reference circle, or axial position from the face middle). Deviations are
    a checker's: the measured trace less the design trace, in the transverse plane along
    the base tangent, plus material positive; everything the trace holds counts (slope,
    crowning, form, waviness). Between samples linear, beyond them held at the end
    values."""

    position: np.ndarray
    deviation: np.ndarray

    def __post_init__(self):
        p = Problems()
        x = np.array(self.position, dtype=float).reshape(-1)
        f = np.array(self.deviation, dtype=float)
        p.check(x.size >= 2, "position", x.size, "needs at least 2 samples")
        p.check(
            bool(np.all(np.isfinite(x))) and bool(np.all(np.diff(x) > 0)),
            "position",
            "values",
            "must be finite and strictly increasing (m)",
        )
        p.check(
            f.ndim == 2 and f.shape[1] == x.size,
            "deviation",
            f"shape {f.shape}",
            f"must be (teeth, {x.size}): one trace per tooth at the positions",
        )
        if f.ndim == 2 and f.shape[1] == x.size:
            _per_tooth("deviation", f.reshape(-1), p, f.size)
            p.check(f.shape[0] >= 8, "deviation", f"{f.shape[0]} teeth", "needs >= 8 teeth")
        p.raise_if_any("invalid trace")
        for name, a in (("position", x), ("deviation", f)):
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    @property
    def teeth(self) -> int:
        return int(self.deviation.shape[0])

    def at(self, x) -> np.ndarray:
        """Each tooth's offset (m, (z, len(x))) at flank coordinates ``x`` (m), less its
        value at 0 (the reference point, where the pitch is measured)."""
        x = np.asarray(x, dtype=float).reshape(-1)
        pts = np.concatenate([x, [0.0]])
        v = np.array([np.interp(pts, self.position, d) for d in self.deviation])
        return v[:, :-1] - v[:, -1:]


@dataclass(frozen=True)
class FlankTraces:
    """Measured traces of each tooth's loaded flank (:class:`Trace`; None: none) for
    pinion and gear, profile and helix. A point's offset is the sum of its tooth's
    profile trace at its roll length and helix trace at its axial position (the usual
    reading of a profile and a helix trace as the flank's topography), normal to the
    flank through the transverse projection. Each trace is taken less its value at the
    reference point, so the pitch deviations stay where they are measured."""

    pinion_profile: Trace | None = None
    pinion_helix: Trace | None = None
    gear_profile: Trace | None = None
    gear_helix: Trace | None = None

    def __post_init__(self):
        p = Problems()
        for member, kind in _SHAPES:
            t = getattr(self, f"{member}_{kind}")
            p.check(
                t is None or isinstance(t, Trace),
                f"{member}_{kind}",
                type(t).__name__,
                "must be a Trace or None",
            )
        for member in ("pinion", "gear"):
            z = {
                getattr(self, f"{member}_{k}").teeth
                for k in ("profile", "helix")
                if getattr(self, f"{member}_{k}") is not None
            }
            p.check(
                len(z) <= 1,
                f"{member}_helix",
                f"{sorted(z)} teeth",
                "must match the profile traces' teeth",
            )
        p.check(
            any(getattr(self, f"{m}_{k}") is not None for m, k in _SHAPES),
            "traces",
            None,
            "needs at least one trace",
        )
        p.raise_if_any("invalid flank traces")

    def teeth_of(self, member: str) -> int | None:
        for kind in ("profile", "helix"):
            t = getattr(self, f"{member}_{kind}")
            if t is not None:
                return t.teeth
        return None

    def point_offsets(self, grid) -> tuple[np.ndarray | None, np.ndarray | None]:
        """Every tooth's normal offset (m, plus material) at every point of ``grid``,
        pinion (z1, n) and gear (z2, n); None for a member without traces."""
        c = grid.flank_coordinates
        if c is None:
            raise InputError(
                Problem("grid.flank_coordinates", None, "flank traces need the flank coordinates")
            )
        out = []
        for m, (member, t) in enumerate(
            (("pinion", grid.transverse_projection), ("gear", grid.transverse_projection2))
        ):
            total = None
            for j, kind in enumerate(("profile", "helix")):
                tr = getattr(self, f"{member}_{kind}")
                if tr is not None:
                    v = tr.at(c[:, 2 * m + j])
                    total = v if total is None else total + v
            out.append(None if total is None else total * np.asarray(t)[None, :])
        return out[0], out[1]

    def offsets(self, grid, cycles) -> np.ndarray:
        """The grid's normal offsets (R, n) in each of the mesh ``cycles`` (R,): a point
        of pair k takes the offsets of pinion tooth (c - k) mod z1 and gear tooth
        (c - k) mod z2 (the module doc's numbering)."""
        pin, gear = self.point_offsets(grid)
        cyc = np.asarray(cycles, dtype=int)
        k = np.asarray(grid.pair, dtype=int)
        n = k.size
        out = np.zeros((cyc.size, n))
        cols = np.arange(n)[None, :]
        for tab in (pin, gear):
            if tab is not None:
                out += tab[np.mod(cyc[:, None] - k[None, :], tab.shape[0]), cols]
        return out

    def to_dict(self) -> dict:
        out = {}
        for member, kind in _SHAPES:
            t = getattr(self, f"{member}_{kind}")
            if t is not None:
                out[f"{member}_{kind}_trace"] = {
                    "position_m": t.position.tolist(),
                    "deviation_m": t.deviation.tolist(),
                }
        return out


@dataclass(frozen=True)
class PitchDeviations:
    """Cumulative pitch deviations of the loaded flanks (m, arc on the reference pitch
    circle, + proud): ``pinion`` shape (z1,), ``gear`` shape (z2,), tooth i as the
    module doc numbers them; ``pinion_radius``, ``gear_radius`` the reference pitch
    radii r_1, r_2 (m) the arcs are measured on; ``form`` the teeth's profile and
    helix slopes and crownings (:class:`FormDeviations`), ``traces`` their measured
    profile and helix traces (:class:`FlankTraces`), None for none."""

    pinion: np.ndarray
    gear: np.ndarray
    pinion_radius: float
    gear_radius: float
    form: FormDeviations | None = None
    traces: FlankTraces | None = None

    def __post_init__(self):
        p = Problems()
        for name in ("pinion", "gear"):
            object.__setattr__(self, name, _per_tooth(name, getattr(self, name), p))
        p.in_range("pinion_radius", self.pinion_radius, 0.0, None, lo_open=True)
        p.in_range("gear_radius", self.gear_radius, 0.0, None, lo_open=True)
        if self.form is not None:
            p.check(
                self.form.teeth == self.teeth,
                "form",
                f"{self.form.teeth[0]} / {self.form.teeth[1]} teeth",
                f"must match the pitch deviations' {self.teeth[0]} / {self.teeth[1]}",
            )
        if self.traces is not None:
            for member, z in zip(("pinion", "gear"), self.teeth, strict=True):
                zt = self.traces.teeth_of(member)
                p.check(
                    zt is None or zt == z,
                    f"traces.{member}",
                    f"{zt} teeth",
                    f"must match the pitch deviations' {z}",
                )
        p.raise_if_any("invalid pitch deviations")

    @property
    def teeth(self) -> tuple[int, int]:
        return int(self.pinion.size), int(self.gear.size)

    @property
    def hunting_cycles(self) -> int:
        """Mesh cycles until the same pair of teeth meets again: lcm(z1, z2)."""
        z1, z2 = self.teeth
        return z1 * z2 // math.gcd(z1, z2)

    @classmethod
    def from_single(cls, pinion_single, gear_single, pinion_radius, gear_radius, form=None):
        """From single pitch deviations f_pt,i = F_p,i - F_p,i-1 (m; tooth 0's F_p is
        the reference, 0): each list must close (sum 0 within 1e-9 m, the pitches of a
        whole turn add up to the circle)."""
        p = Problems()
        out = []
        for name, f in (("pinion_single", pinion_single), ("gear_single", gear_single)):
            f = np.asarray(f, dtype=float).reshape(-1)
            total = float(np.sum(f))
            p.check(
                abs(total) <= 1e-9,
                name,
                f"sum {total:.3e} m",
                "single pitch deviations must sum to 0 over a turn",
            )
            out.append(_cumulative(f))
        p.raise_if_any("invalid pitch deviations")
        return cls(out[0], out[1], pinion_radius, gear_radius, form)


def _cumulative(single: np.ndarray) -> np.ndarray:
    """Cumulative pitch deviations from single ones that close over the turn: tooth 0
    the reference (0), F_p,i = f_pt,1 + ... + f_pt,i."""
    return np.concatenate([[0.0], np.cumsum(single)[:-1]]) if single.size else single


def pair_angles(dev: PitchDeviations, pair_index, cycles) -> np.ndarray:
    """alpha_k per mesh cycle (module doc): shape (len(cycles), K), pinion radians."""
    z1, z2 = dev.teeth
    c = np.asarray(cycles, dtype=int)[:, None] - np.asarray(pair_index, dtype=int)[None, :]
    a1 = dev.pinion[np.mod(c, z1)] / dev.pinion_radius
    a2 = dev.gear[np.mod(c, z2)] / dev.gear_radius * (z2 / z1)
    return a1 + a2


def pair_coefficients(dev: PitchDeviations, pair_index, cycles) -> np.ndarray:
    """Each pair's offset coefficients per mesh cycle, shape (len(cycles), K, J): alpha_k
    (:func:`pair_angles`), then, with form deviations, the coefficients of its two
    teeth's offset shapes (:meth:`FormDeviations.coefficients`; J = 9, else 1)."""
    alpha = pair_angles(dev, pair_index, cycles)[..., None]
    if dev.form is None:
        return alpha
    z1, z2 = dev.teeth
    c = np.asarray(cycles, dtype=int)[:, None] - np.asarray(pair_index, dtype=int)[None, :]
    return np.concatenate([alpha, dev.form.coefficients(np.mod(c, z1), np.mod(c, z2))], axis=-1)


def _weights(res: CycleResult, torque: float, form: bool):
    """Pair weights (P, K, J) and load sensitivities (P, K, K, J) (None where the result
    has none) at ``torque``, the pitch offset first, then the form shapes' (J = 9)."""
    w = _at_torque(res, torque, res.pair_weight)[..., None]
    S = res.pair_load_sensitivity
    S = None if S is None else _at_torque(res, torque, S)[..., None]
    if form:
        w = np.concatenate([w, _at_torque(res, torque, res.pair_form_weight)], axis=-1)
        if S is not None:
            Sf = _at_torque(res, torque, res.pair_form_load_sensitivity)
            S = np.concatenate([S, Sf], axis=-1)
    return w, S


def _at_torque(res: CycleResult, torque: float, values: np.ndarray) -> np.ndarray:
    """``values`` (T, ...) at ``torque`` between the loaded TCA's levels
    (:func:`_between_levels`)."""
    return _between_levels(res.torque, values, torque)


@dataclass(frozen=True)
class HuntingRecord:
    """Loaded transmission error over a hunting period at one torque (SI).

    angle (n,) pinion angle from the record's start (rad), n = cycles x positions;
    lte (n,) loaded TE with the deviations (m); lte_nominal (n,) without them (the
    loaded TCA's cycle repeated); torque (N m); teeth (z1, z2); cycles (mesh cycles:
    a hunting period); method ('linear' or 'exact'). pair_index (K,); pair_load
    (n, K): each tooth pair's normal load (N; linear: first order through the loaded
    TCA's ``pair_load_sensitivity``, floored at 0; None where the result lacks it);
    pair_load_nominal (P, K) and pair_root_stress_nominal (P, K, 2) (Pa, pinion and
    gear) of the nominal teeth at the torque; pair_root_stress (n, K, 2): each pair's
    largest root stress from each sample's own loads (exact: its solve; linear with the
    grids: its first-order point loads); None where the nominal stresses are scaled.
    """

    angle: np.ndarray
    lte: np.ndarray
    lte_nominal: np.ndarray
    torque: float
    teeth: tuple[int, int]
    cycles: int
    method: str
    pair_index: np.ndarray | None = None
    pair_load: np.ndarray | None = None
    pair_load_nominal: np.ndarray | None = None
    pair_root_stress_nominal: np.ndarray | None = None
    pair_root_stress: np.ndarray | None = None

    @property
    def pinion_revolutions(self) -> float:
        return self.cycles / self.teeth[0]

    def tooth_loads(self) -> tuple[np.ndarray, np.ndarray]:
        """The largest normal load (N) each pinion tooth (z1,) and each gear tooth (z2,)
        carries over the hunting period (teeth numbered as the module doc says)."""
        z1, z2 = self.teeth
        P = self.lte.size // self.cycles
        F = self.pair_load.reshape(self.cycles, P, -1)
        c = np.arange(self.cycles)[:, None] - np.asarray(self.pair_index)[None, :]  # (H, K)
        top = F.max(axis=1)  # (H, K): over the positions of each cycle
        out = []
        for z in (z1, z2):
            t = np.zeros(z)
            np.maximum.at(t, np.mod(c, z).ravel(), top.ravel())
            out.append(t)
        return out[0], out[1]

    @property
    def tooth_load_nominal(self) -> float:
        """The largest normal load (N) a tooth carries through its engagement with
        nominal teeth."""
        return float(np.max(self.pair_load_nominal))

    def root_stress(self) -> tuple[float, float]:
        """The largest root stress (Pa) of the pinion and of the gear over the hunting
        period: from each sample's own loads where the record has them
        (``pair_root_stress``), else each pair's stress at nominal load scaled by its
        load (the load along the contact line keeps its shape)."""
        if self.pair_root_stress is not None:
            s = self.pair_root_stress
            return float(s[..., 0].max()), float(s[..., 1].max())
        P = self.pair_load_nominal.shape[0]
        F = self.pair_load.reshape(self.cycles, P, -1)
        F0 = self.pair_load_nominal[None]
        ratio = np.divide(F, F0, out=np.zeros_like(F), where=F0 > 0)
        s = self.pair_root_stress_nominal[None] * ratio[..., None]  # (H, P, K, 2)
        return float(s[..., 0].max()), float(s[..., 1].max())

    def root_stress_nominal(self) -> tuple[float, float]:
        s = self.pair_root_stress_nominal
        return float(s[..., 0].max()), float(s[..., 1].max())

    def order_spectrum(self, which: str = "lte") -> tuple[np.ndarray, np.ndarray]:
        """(orders, amplitude): single-sided peak amplitudes (m) of ``lte`` (or
        ``lte_nominal``) against pinion orders, rectangular window over the whole
        record, which is one period of the signal (no leakage): order resolution
        1 / pinion_revolutions, so every pinion and gear order is a bin. Order 0
        holds the mean."""
        x = np.asarray(getattr(self, which), dtype=float)
        n = x.size
        X = np.fft.rfft(x) / n
        amp = np.abs(X)
        amp[1:] *= 2.0
        if n % 2 == 0:
            amp[-1] /= 2.0
        return np.arange(amp.size) / self.pinion_revolutions, amp


def _check_result(res: CycleResult, dev: PitchDeviations, teeth, torque: float, method: str):
    p = Problems()
    p.check(method in ("linear", "exact"), "method", method, "must be 'linear' or 'exact'")
    p.check(
        tuple(teeth) == dev.teeth,
        "deviations",
        f"{dev.teeth[0]} / {dev.teeth[1]} values",
        f"must give one value per tooth: {teeth[0]} / {teeth[1]}",
    )
    tq = np.asarray(res.torque, dtype=float)
    p.in_range("torque", torque, float(tq.min()), float(tq.max()))
    p.check(
        res.pair_weight is not None,
        "result.pair_weight",
        None,
        "the loaded TCA result predates the pair weights: run the loaded TCA again",
    )
    if dev.form is not None:
        nb = len(FORM_BASES)
        p.check(
            res.pair_form_weight is not None and res.pair_form_weight.shape[-1] == nb,
            "result.pair_form_weight",
            None if res.pair_form_weight is None else res.pair_form_weight.shape,
            f"form deviations need the loaded TCA's form weights of the {nb} shapes: a "
            "result of grids with flank coordinates (run the loaded TCA again)",
        )
    p.raise_if_any("invalid pitch-deviation analysis")


def hunting_lte(
    res: CycleResult,
    dev: PitchDeviations,
    torque: float,
    *,
    teeth: tuple[int, int],
    method: str = "linear",
    grids=None,
    compliance=None,
    solver: ContactSolver | None = None,
    mapper=None,
) -> HuntingRecord:
    """The loaded TE over a hunting period (lcm(z1, z2) mesh cycles) at ``torque``
    (N m, within the result's torque levels; the linear method interpolates the
    levels linearly, the exact one solves at ``torque``).

    ``method="exact"`` needs the loaded TCA's ``grids`` (one per position, as
    :func:`~gearbox.ltca.analysis.ltca_cycle` made them, :func:`flank_grids`) and
    ``compliance``; ``mapper(fn, jobs) -> list`` may spread the positions over processes
    (a pipeline run's executor), else they run here one after the other. Given them,
    the linear method takes its root stresses from first-order point loads (one solve
    and one tangent per position at ``torque``), so a change of the load's shape along
    the contact lines shows; without them (or on a level with its own stress model) it
    scales each pair's nominal stress by its load.
    """
    _check_result(res, dev, teeth, torque, method)
    z1 = teeth[0]
    H = dev.hunting_cycles
    P = res.fraction.size
    cycles = np.arange(H)
    nominal = _at_torque(res, torque, res.lte)  # (P,)
    angle = (cycles[:, None] + res.fraction[None, :]) * (2.0 * math.pi / z1)
    coef = pair_coefficients(dev, res.pair_index, cycles)  # (H, K, J)
    F0 = _at_torque(res, torque, res.pair_share) * _at_torque(res, torque, res.normal_load)[:, None]
    stress, stress0 = None, _at_torque(res, torque, res.pair_root_stress)
    traces = dev.traces
    gridded = grids is not None and compliance is not None and len(grids) == P
    if not gridded and (method == "exact" or traces is not None):
        p = Problems()
        n = None if grids is None else len(grids)
        why = "the exact method" if method == "exact" else "flank traces"
        p.add("grids", n, f"{why} needs the {P} grids and the compliance")
        p.raise_if_any("invalid pitch-deviation analysis")
    if method == "linear":
        arm = torque / _at_torque(res, torque, res.normal_load)  # (P,)
        loads = None
        if traces is None:  # with traces the grids' tangent gives all (below)
            w, S = _weights(res, torque, dev.form is not None)  # (P, K, J), (P, K, K, J)
            lte = nominal[None, :] - arm[None, :] * np.einsum("hkj,pkj->hp", coef, w)
            if S is not None:
                # first order; a pair it would unload below zero has lifted off
                loads = np.maximum(F0[None] + np.einsum("plkj,hkj->hpl", S, coef), 0.0)
        own = callable(getattr(compliance, "grid_root_stress", None))
        if gridded and (traces is not None or not own):
            # first-order point loads: root stresses from the load's shape (unless the
            # level has its own stress model), and the traces' share of the rotation
            # and of the pair loads
            jobs = [
                (g, compliance, float(torque), coef, res.pair_index, solver, traces, not own)
                for g in grids
            ]
            got = (mapper or _serial)(_linear_column, jobs)
            if not own:
                ps = np.stack([g[0] for g in got], axis=1)  # (H + 1, P, K, 2)
                stress, stress0 = ps[:-1].reshape(H * P, -1, 2), ps[-1]
            if traces is not None:
                # the whole first-order change from the tangent at the torque itself (the
                # weights are interpolated between the torque levels: the two would not
                # add up exactly between them)
                dphi = np.stack([g[1] for g in got], axis=1)  # (H, P)
                lte = nominal[None, :] + arm[None, :] * dphi
                pl = np.stack([g[2] for g in got], axis=1)  # (H + 1, P, K)
                loads, F0 = pl[:-1], pl[-1]  # the nominal's from the same solves
    else:
        rows = np.concatenate([coef, np.zeros((1,) + coef.shape[1:])])  # last: the nominal
        jobs = [(g, compliance, float(torque), rows, res.pair_index, solver, traces) for g in grids]
        got = (mapper or _serial)(_exact_column, jobs)
        cols = np.column_stack([g[0] for g in got])  # (H + 1, P)
        lte, nominal = cols[:-1], cols[-1]
        pl = np.stack([g[1] for g in got], axis=1)  # (H + 1, P, K)
        loads, F0 = pl[:-1], pl[-1]
        ps = np.stack([g[2] for g in got], axis=1)  # (H + 1, P, K, 2)
        stress, stress0 = ps[:-1].reshape(H * P, -1, 2), ps[-1]
    return HuntingRecord(
        angle=angle.reshape(-1),
        lte=lte.reshape(-1),
        lte_nominal=np.tile(nominal, H),
        torque=float(torque),
        teeth=(int(teeth[0]), int(teeth[1])),
        cycles=H,
        method=method,
        pair_index=np.asarray(res.pair_index),
        pair_load=None if loads is None else loads.reshape(H * P, -1),
        pair_load_nominal=F0,
        pair_root_stress_nominal=stress0,
        pair_root_stress=stress,
    )


def _serial(fn, jobs):
    return [fn(j) for j in jobs]


def _linear_column(job):
    """One position's first-order answers for each mesh cycle of the hunting period
    (rows of coefficients ``coef`` (H, K, J), flank ``traces`` or None), and the nominal
    teeth last (module level: runs in worker processes; :func:`_predicted_loads`):
    pair root stresses (Pa, (H + 1, K, 2); None unless ``stress``), the rotation
    dphi = -d^T a of all offsets (rad, (H,); None without traces) and the pair loads
    (N, (H + 1, K), from the point loads floored at 0)."""
    grid, compliance, torque, coef, pair_index, solver, traces, stress = job
    solver = solver or ContactSolver()
    C0 = compliance.tooth_matrix(grid) if compliance.load_dependent else None
    rows = np.concatenate([coef, np.zeros((1,) + coef.shape[1:])])  # last: the nominal
    cycles = np.arange(coef.shape[0])
    extra = None if traces is None else traces.offsets(grid, cycles)
    a = _offsets(grid, rows, pair_index)
    if extra is not None:
        a[: cycles.size] += extra
    F, d = _predicted_loads(grid, compliance, torque, a, solver, C0, rotation=True)
    ks = np.asarray(pair_index)
    member = (np.asarray(grid.pair)[:, None] == ks[None, :]).astype(float)  # (n, K)
    return (
        pair_root_stresses(grid, compliance, F, pair_index) if stress else None,
        None if extra is None else -(a[: cycles.size] @ d),
        F @ member,
    )


@dataclass(frozen=True)
class TraceTurns:
    """Measured traces (:class:`FlankTraces`) as the dynamics take them: for each
    torque level of a loaded TCA, each position of its cycle and each of its tooth
    pairs k, the pinion rotation (rad) by which every pinion tooth's and every gear
    tooth's trace offsets, sitting in pair k, turn the loaded flanks back, to first
    order (``pinion`` (T, P, K, z1), ``gear`` (T, P, K, z2); None for a member without
    traces): sum_i d_i s_i over pair k's points, d the tangent's rotation direction
    at that torque (dphi = -d^T a, :func:`_predicted_loads`) and s_i the tooth's offset
    (:meth:`FlankTraces.point_offsets`). In mesh cycle c at position p the loaded
    rotation changes by -sum_k (pinion[., p, k, (c - k) mod z1] + gear[., p, k,
    (c - k) mod z2]), the linear hunting record's change (:func:`hunting_lte`) at a
    level; between levels linear in torque, as the mesh table's pair weights
    (docs/drivetrain.md §3c). ``traces``: the traces they were made of."""

    torque: np.ndarray
    fraction: np.ndarray
    pair_index: np.ndarray
    pinion: np.ndarray | None
    gear: np.ndarray | None
    traces: FlankTraces

    def at(self, torque: float) -> tuple[np.ndarray | None, np.ndarray | None]:
        """``(pinion (P, K, z1), gear (P, K, z2))`` at ``torque`` (N m), linear between
        the levels as :meth:`MeshTable.values_at <gearbox.meshtable.MeshTable.values_at>`
        interpolates the pair weights; a torque outside the levels is refused."""
        return tuple(
            None if v is None else _between_levels(self.torque, v, torque)
            for v in (self.pinion, self.gear)
        )

    def matches(self, traces: FlankTraces) -> bool:
        """Whether these turns were made of ``traces`` (the same positions and rows)."""
        return _same_numbers(_numbers(traces=self.traces), _numbers(traces=traces))


def _between_levels(levels, values, torque: float) -> np.ndarray:
    """``values`` (T, ...) at ``torque`` (N m), linear between the torque ``levels`` as
    :meth:`MeshTable.values_at <gearbox.meshtable.MeshTable.values_at>` interpolates
    (its weights clipped); a torque outside the levels is refused by name."""
    tq = np.asarray(levels, dtype=float)
    lo, hi = float(tq[0]), float(tq[-1])
    tol = 1e-9 * max(1.0, hi)
    if not lo - tol <= torque <= hi + tol:
        raise InputError(
            Problem("torque_Nm", torque, f"must be within the levels [{lo:g}, {hi:g}] N m")
        )
    if tq.size == 1:
        return values[0]
    j = int(np.clip(np.searchsorted(tq, torque) - 1, 0, tq.size - 2))
    w = float(np.clip((torque - tq[j]) / (tq[j + 1] - tq[j]), 0.0, 1.0))
    return (1.0 - w) * values[j] + w * values[j + 1]


def same_deviations(a: PitchDeviations, b: PitchDeviations) -> bool:
    """Whether two sets of deviations are the same numbers: pitch, form (slopes,
    crownings, their ranges and vertices) and traces."""
    na = _numbers(form=a.form, traces=a.traces) | {"pinion": a.pinion, "gear": a.gear}
    nb = _numbers(form=b.form, traces=b.traces) | {"pinion": b.pinion, "gear": b.gear}
    return _same_numbers(na, nb)


def _numbers(**parts) -> dict[str, np.ndarray]:
    """The arrays of deviation parts with a ``to_dict`` (form, traces; None: none),
    flat, by dotted name."""
    out = {}
    for name, part in parts.items():
        for k, v in ({} if part is None else part.to_dict()).items():
            if isinstance(v, dict):
                out |= {f"{name}.{k}.{f}": np.asarray(x) for f, x in v.items()}
            else:
                out[f"{name}.{k}"] = np.asarray(v)
    return out


def _same_numbers(a: dict, b: dict) -> bool:
    return a.keys() == b.keys() and all(np.array_equal(a[k], b[k]) for k in a)


@dataclass(frozen=True)
class LevelRecords:
    """The exact hunting records' TE changes at every torque level of a loaded TCA, the
    dynamics' approach when ``pitch.method = "exact"`` (docs/drivetrain.md §3c):
    ``change`` (T, H, P) m, each level's exact record (:func:`hunting_lte`) less its
    nominal, mesh cycle by position; between levels linear in torque, as the mesh
    table's pair weights. The levels are the loaded TCA's and the torques of records
    solved already (:func:`level_records`). ``deviations``: what they were made of."""

    torque: np.ndarray
    fraction: np.ndarray
    change: np.ndarray
    deviations: PitchDeviations

    def at(self, torque: float) -> np.ndarray:
        """The TE change (H, P) m at ``torque`` (N m) (:func:`_between_levels`)."""
        return _between_levels(self.torque, self.change, torque)


def level_records(
    res: CycleResult,
    dev: PitchDeviations,
    *,
    teeth: tuple[int, int],
    grids,
    compliance,
    solver: ContactSolver | None = None,
    mapper=None,
    known: tuple[HuntingRecord, ...] = (),
) -> LevelRecords:
    """:class:`LevelRecords`: the exact method's hunting record (:func:`hunting_lte`)
    at each torque level of the loaded TCA ``res``, with its ``grids`` and
    ``compliance``; ``mapper`` may spread the positions over processes. ``known``:
    exact records of these deviations already solved (the pitch stage's, at the
    operating torque): their torques join the levels, solved no second time, so the
    dynamics at that torque take the record itself."""
    H, P = dev.hunting_cycles, res.fraction.size
    have = {float(r.torque): r for r in known if r.method == "exact" and r.cycles == H}
    levels = sorted({float(t) for t in np.asarray(res.torque, dtype=float)} | set(have))
    change = np.empty((len(levels), H, P))
    for t, torque in enumerate(levels):
        rec = have.get(torque)
        if rec is None:
            rec = hunting_lte(
                res,
                dev,
                torque,
                teeth=teeth,
                method="exact",
                grids=grids,
                compliance=compliance,
                solver=solver,
                mapper=mapper,
            )
        change[t] = (rec.lte - rec.lte_nominal).reshape(H, P)
    return LevelRecords(
        np.asarray(levels, dtype=float),
        np.asarray(res.fraction, dtype=float).copy(),
        change,
        dev,
    )


@dataclass(frozen=True)
class DeviationLevels:
    """The tooth deviations at the loaded TCA's torque levels, as the dynamics take them
    beyond the mesh table's weights (the pipeline's ``approach`` stage, docs/drivetrain.md
    §3c): ``levels`` (:class:`LevelRecords`) with ``pitch.method = "exact"``, else the
    measured traces' ``turns`` (:class:`TraceTurns`); the other None."""

    turns: TraceTurns | None = None
    levels: LevelRecords | None = None

    def to_dict(self) -> dict:
        if self.levels is not None:
            ch = self.levels.change
            return {
                "method": "exact",
                "torque_levels_Nm": self.levels.torque.tolist(),
                "positions": int(self.levels.fraction.size),
                "hunting_cycles": int(ch.shape[1]),
                "te_change_peak_to_peak_m": np.ptp(ch.reshape(ch.shape[0], -1), axis=1).tolist(),
            }
        if self.turns is not None:
            return {
                "method": "linear, the measured traces' turns",
                "torque_levels_Nm": self.turns.torque.tolist(),
                "positions": int(self.turns.fraction.size),
                "tooth_pairs": np.asarray(self.turns.pair_index).tolist(),
            }
        return {"method": "none"}


def trace_turns(
    res: CycleResult, grids, compliance, traces: FlankTraces, *, solver=None, mapper=None
) -> TraceTurns:
    """:class:`TraceTurns` of ``traces`` on the loaded TCA ``res`` (its torque levels and
    pair index) with its ``grids`` (one per position, :func:`flank_grids`) and
    ``compliance``: one contact solve and tangent per level and position.
    ``mapper(fn, jobs) -> list`` may spread the positions over processes."""
    p = Problems()
    P = res.fraction.size
    p.check(
        grids is not None and len(grids) == P,
        "grids",
        None if grids is None else len(grids),
        f"needs the {P} grids of the loaded TCA",
    )
    p.check(isinstance(traces, FlankTraces), "traces", type(traces).__name__, "must be FlankTraces")
    p.raise_if_any("invalid trace turns")
    torques = [float(t) for t in np.asarray(res.torque, dtype=float)]
    jobs = [(g, compliance, torques, res.pair_index, solver, traces) for g in grids]
    got = (mapper or _serial)(_turn_column, jobs)
    member = [None if got[0][m] is None else np.stack([g[m] for g in got], axis=1) for m in (0, 1)]
    return TraceTurns(
        torque=np.asarray(res.torque, dtype=float).copy(),
        fraction=np.asarray(res.fraction, dtype=float).copy(),
        pair_index=np.asarray(res.pair_index).copy(),
        pinion=member[0],
        gear=member[1],
        traces=traces,
    )


def _turn_column(job):
    """One position's turns at each torque level: pinion (T, K, z1) and gear (T, K, z2)
    rad, None for a member without traces (module level: runs in worker processes)."""
    grid, compliance, torques, pair_index, solver, traces = job
    solver = solver or ContactSolver()
    C0 = compliance.tooth_matrix(grid) if compliance.load_dependent else None
    offsets = traces.point_offsets(grid)  # (z1, n), (z2, n) or None
    ks = np.asarray(pair_index)
    member = (np.asarray(grid.pair)[:, None] == ks[None, :]).astype(float)  # (n, K)
    none = np.zeros((0, grid.size))
    out = [None if s is None else np.zeros((len(torques), ks.size, s.shape[0])) for s in offsets]
    for t, torque in enumerate(torques):
        _, d = _predicted_loads(grid, compliance, torque, none, solver, C0, rotation=True)
        for m, s in enumerate(offsets):
            if s is not None:
                out[m][t] = (s @ (d[:, None] * member)).T
    return out[0], out[1]


def _exact_column(job):
    """One position's loaded TE (m), pair loads (N) and pair root stresses (Pa) for each
    row of coefficients, the mesh cycles' flank traces added to all rows but the last,
    the nominal (module level: runs in worker processes)."""
    grid, compliance, torque, alpha, pair_index, solver, traces = job
    cycles = None if traces is None else np.arange(len(alpha) - 1)
    rot, arm, loads, stress = exact_solutions(
        grid,
        compliance,
        torque,
        alpha,
        pair_index,
        solver=solver,
        stress=True,
        traces=traces,
        cycles=cycles,
    )
    return rot * arm, loads, stress


def exact_rotation(grid, compliance, torque, alpha, pair_index, *, solver=None):
    """Loaded rotation (rad) and torque arm T / sum F (m) at one grid position for each
    row of pair angles ``alpha`` (:func:`exact_solutions`)."""
    rot, arm, _ = exact_solutions(grid, compliance, torque, alpha, pair_index, solver=solver)[:3]
    return rot, arm


def _offsets(grid, coef, pair_index) -> np.ndarray:
    """Each row's normal offsets of the grid's points, shape (R, n), for coefficients
    (R, K) (pair angles) or (R, K, J) (:func:`pair_coefficients`): m_i alpha_k, plus
    B_ij c_kj with form deviations; the separations are less them."""
    coef = np.asarray(coef, dtype=float)
    coef = coef[None] if coef.ndim == 1 else coef
    coef = coef[..., None] if coef.ndim == 2 else coef  # (R, K, J)
    col = {int(k): kk for kk, k in enumerate(np.asarray(pair_index))}
    idx = np.array([col[int(k)] for k in grid.pair])
    X = grid.arm[:, None]
    if coef.shape[-1] > 1:
        bases = grid.form_bases()
        if bases is None:
            raise InputError(
                Problem(
                    "grid.flank_coordinates", None, "form deviations need the flank coordinates"
                )
            )
        X = np.column_stack([grid.arm, bases])
    return np.einsum("rnj,nj->rn", coef[:, idx, :], X)


def exact_solutions(
    grid,
    compliance,
    torque,
    alpha,
    pair_index,
    *,
    solver=None,
    stress=False,
    traces=None,
    cycles=None,
):
    """Loaded rotation (rad), torque arm T / sum F (m) and each pair's normal load (N,
    shape (R, K)) at one grid position for each row of pair angles ``alpha`` (shape
    (R, K), pinion radians, K = len(pair_index)): the contact problem with the
    separations offset by -m_i alpha_k. ``alpha`` may also be (R, K, 9), the
    coefficients of :func:`pair_coefficients` with form deviations: the offsets are
    then -m_i alpha_k - B_ij c_kj (:meth:`~gearbox.ltca.grid.ContactGrid.form_bases`).
    Rows that repeat are solved once; each solve starts from the first-order loads of
    its offsets at the nominal solution (:func:`_predicted_loads`). ``stress=True``
    adds each pair's largest root stress of pinion and gear under the row's own loads
    (Pa, (R, K, 2); :func:`pair_root_stresses`). ``traces`` (:class:`FlankTraces`)
    with ``cycles`` (the first len(cycles) rows' mesh cycles) add the teeth's measured
    traces to those rows (:meth:`FlankTraces.offsets`)."""
    solver = solver or ContactSolver()
    offsets = _offsets(grid, alpha, pair_index)  # (R, n): ds = -offsets
    if traces is not None:
        cyc = np.asarray(cycles, dtype=int)
        offsets[: cyc.size] += traces.offsets(grid, cyc)
    ks = np.asarray(pair_index)
    member = (np.asarray(grid.pair)[:, None] == ks[None, :]).astype(float)  # (n, K)
    C0 = compliance.tooth_matrix(grid) if compliance.load_dependent else None
    rows, inverse = np.unique(offsets, axis=0, return_inverse=True)
    start = _predicted_loads(grid, compliance, torque, rows, solver, C0)
    rot = np.empty(len(rows))
    arm = np.empty(len(rows))
    loads = np.empty((len(rows), ks.size))
    point_loads = []
    for r, a in enumerate(rows):
        g = replace(grid, separation=grid.separation - a)
        sol = solve_contact(
            g, compliance, torque, solver=solver, tooth_matrix=C0, initial_load=start[r]
        )
        rot[r] = sol.rotation
        arm[r] = torque / float(sol.load.sum())
        loads[r] = sol.load @ member
        point_loads.append(sol.load)
    inverse = np.asarray(inverse).reshape(-1)
    if not stress:
        return rot[inverse], arm[inverse], loads[inverse]
    rs = pair_root_stresses(grid, compliance, np.array(point_loads), ks)
    return rot[inverse], arm[inverse], loads[inverse], rs[inverse]


def _predicted_loads(grid, compliance, torque, offsets, solver, tooth_matrix, *, rotation=False):
    """First-order point loads (N, (R, n), floored at 0) for rows of normal offsets
    (R, n; the separations less them) at the nominal solution, its loaded set held:
    dphi = -d^T a_A, dF_A = K^-1 (m_A dphi + a_A) (:func:`~gearbox.ltca.solver.
    rotation_sensitivity`). A start for the full solve: the default scene's pitch
    deviations at three positions (1305 rows each) took 5.6-5.9 s, against 12.4-13.1 s
    started from the nominal loads (the same rotations to 4e-16 rad).
    ``rotation=True`` also returns d (n,), zero off the loaded set."""
    from .solver import _rotation_direction, _tangent

    sol = solve_contact(grid, compliance, torque, solver=solver, tooth_matrix=tooth_matrix)
    on, K = _tangent(grid, compliance, sol, tooth_matrix, 1.0e-4)
    m = np.asarray(grid.arm, dtype=float)[on]
    d = _rotation_direction(K, m)
    a = np.asarray(offsets, dtype=float)[:, on]  # (R, n_A)
    dphi = -(a @ d)
    dF = np.linalg.solve(K, np.outer(m, dphi) + a.T)  # (n_A, R)
    out = np.zeros((a.shape[0], grid.size))
    out[:, on] = np.maximum(sol.load[on][:, None] + dF, 0.0).T
    if not rotation:
        return out
    full = np.zeros(grid.size)
    full[on] = d
    return out, full


def pair_root_stresses(grid, compliance, loads, pair_index) -> np.ndarray:
    """Each pair's largest root stress of pinion and gear (Pa, shape (R, K, 2)) under
    each row of point loads ``loads`` (R, n), as the loaded TCA computes them
    (its ``pair_root_stress``). The slices' stress is linear in the loads
    (:func:`~gearbox.ltca.stress.root_stress_matrices`); a level with its own stress
    model (the FE fillet) is evaluated row by row."""
    from .analysis import _root_stress
    from .stress import root_stress_matrices

    ks = np.asarray(pair_index)
    loads = np.atleast_2d(np.asarray(loads, dtype=float))
    R = loads.shape[0]
    if callable(getattr(compliance, "grid_root_stress", None)):
        top = np.array([np.stack(_root_stress(compliance, grid, F)[1]) for F in loads])
    else:
        M = np.stack(root_stress_matrices(grid))  # (2, n, n)
        top = np.einsum("mij,rj->rmi", M, np.maximum(loads, 0.0))  # (R, 2, n)
    out = np.zeros((R, ks.size, 2))
    for kk, k in enumerate(ks):
        on = np.asarray(grid.pair) == k
        if on.any():
            out[:, kk] = top[:, :, on].max(axis=2)
    return out


def deviations_from_section(section, teeth: tuple[int, int]) -> tuple[np.ndarray, np.ndarray]:
    """Cumulative deviations (m) of pinion and gear from a scene's ``[pitch]`` section:
    each member's list where given (one value per tooth), else random single pitch
    deviations within +-``random_single_um`` (uniform, less their mean; both members
    drawn from ``seed``, the pinion first), else zeros. Raises InputError naming the
    key of a list of the wrong length."""
    rng = np.random.default_rng(int(section["seed"]))
    a = float(section["random_single_um"]) * 1e-6
    p = Problems()
    out = []
    for member, z in zip(("pinion", "gear"), teeth, strict=True):
        f = rng.uniform(-a, a, int(z))  # drawn for both members alike: the seed's sequence
        out.append(
            _listed_or(section, f"{member}_cumulative_um", member, z, p, _cumulative(f - f.mean()))
        )
    p.raise_if_any("invalid pitch deviations")
    return out[0], out[1]


def _listed_or(section, key: str, member: str, teeth: int, p: Problems, otherwise):
    """The section's list ``key`` (um -> m) where given, checked for one value per
    tooth (a problem named ``pitch.<key>`` otherwise), else ``otherwise``."""
    given = section[key]
    if not given:
        return otherwise
    p.check(
        len(given) == teeth,
        f"pitch.{key}",
        f"{len(given)} values",
        f"must give one value per {member} tooth: {teeth}",
    )
    return np.asarray(given, dtype=float) * 1e-6


def covered_lengths(flank_range) -> tuple[tuple[float, float], tuple[float, float]]:
    """The roll lengths (pinion, gear) and axial lengths (pinion, gear) that the loaded
    contact covers, m, from a loaded TCA's ``flank_range`` (4, 2): the form
    deviations' default evaluation lengths."""
    r = np.asarray(flank_range, dtype=float)
    width = r[:, 1] - r[:, 0]
    return (float(width[0]), float(width[2])), (float(width[1]), float(width[3]))


def covered_centres(flank_range) -> tuple[tuple[float, float], tuple[float, float]]:
    """The middles of those ranges (m from the reference circle and the face middle),
    ordered as :func:`covered_lengths`: the crownings' default vertices."""
    r = np.asarray(flank_range, dtype=float)
    mid = 0.5 * (r[:, 0] + r[:, 1])
    return (float(mid[0]), float(mid[2])), (float(mid[1]), float(mid[3]))


def form_from_section(
    section, teeth: tuple[int, int], lengths=None, centres=None
) -> FormDeviations | None:
    """The form deviations of a scene's ``[pitch]`` section (m), None where it sets
    none: each member's lists where given, else random within +-``random_*_slope_um``
    and +-``random_*_crowning_um`` (uniform, tooth by tooth, from generators seeded
    with [seed, 1] for the slopes and [seed, 2] for the crownings, each drawing
    pinion profile, pinion helix, gear profile, gear helix). The evaluation lengths are
    the section's (mm), else ``lengths`` ((L_alpha pinion, gear), (L_beta pinion,
    gear), m: :func:`covered_lengths` of the loaded TCA); the ranges' middles are
    ``centres`` (:func:`covered_centres`), needed where a crowning is set. Raises
    InputError naming each key that is wrong."""
    rand = {
        (kind, what): float(section[f"random_{kind}_{what}_um"]) * 1e-6
        for kind in ("profile", "helix")
        for what in ("slope", "crowning")
    }
    listed = any(section[f"{m}_{k}_{w}_um"] for m, k in _SHAPES for w in ("slope", "crowning"))
    if not listed and not any(rand.values()):
        return None
    p = Problems()
    got = {}
    for i, what in enumerate(("slope", "crowning")):
        rng = np.random.default_rng([int(section["seed"]), i + 1])
        for member, kind in _SHAPES:
            z = teeth[0] if member == "pinion" else teeth[1]
            a = rand[(kind, what)]
            drawn = rng.uniform(-a, a, int(z))  # drawn alike: the generator's sequence
            key = f"{member}_{kind}_{what}_um"
            got[(member, kind, what)] = _listed_or(section, key, member, z, p, drawn)
    crowned = any(np.any(got[(m, k, "crowning")]) for m, k in _SHAPES)
    length, centre = {}, {}
    for i, kind in enumerate(("profile", "helix")):
        key = f"pitch.{kind}_evaluation_mm"
        given = section[f"{kind}_evaluation_mm"]
        if given:
            p.check(len(given) == 2, key, given, "must give [pinion, gear] (mm)")
            length[kind] = tuple(float(v) * 1e-3 for v in given)
        elif lengths is not None:
            length[kind] = tuple(float(v) for v in lengths[i])
        else:
            p.add(key, given, "needed: no loaded TCA gives the covered lengths here")
        if centres is not None:
            centre[kind] = tuple(float(v) for v in centres[i])
        else:
            centre[kind] = (0.0, 0.0)
            p.check(
                not crowned,
                f"pitch.*_{kind}_crowning_um",
                "set",
                "crownings need the middle of the contact's range on the flank: a loaded "
                "TCA's (run it again)",
            )
    p.raise_if_any("invalid form deviations")
    return FormDeviations(
        *(got[(m, k, "slope")] for m, k in _SHAPES),
        length["profile"],
        length["helix"],
        *(got[(m, k, "crowning")] for m, k in _SHAPES),
        centre["profile"],
        centre["helix"],
    )


def traces_from_section(section, teeth: tuple[int, int]) -> FlankTraces | None:
    """The measured traces of a scene's ``[pitch]`` section (:class:`FlankTraces`, m),
    None where it sets none. Raises InputError naming each key that is wrong: rows
    without positions or the other way round, a row count other than the member's
    teeth, a row length other than its positions', positions that do not increase."""
    p = Problems()
    got = {}
    for member, kind in _SHAPES:
        z = teeth[0] if member == "pinion" else teeth[1]
        pos_key, dev_key = f"{member}_{kind}_trace_mm", f"{member}_{kind}_trace_um"
        x, rows = section[pos_key], section[dev_key]
        if not x and not rows:
            continue
        p.check(bool(rows), f"pitch.{dev_key}", rows, f"needs one row per tooth with {pos_key}")
        p.check(bool(x), f"pitch.{pos_key}", x, f"needs the positions of {dev_key}")
        if not (x and rows):
            continue
        ok = p.check(len(x) >= 2, f"pitch.{pos_key}", x, "needs at least 2 positions")
        ok &= p.check(
            all(b > a for a, b in zip(x, x[1:], strict=False)),
            f"pitch.{pos_key}",
            x,
            "must increase strictly",
        )
        ok &= p.check(
            len(rows) == z,
            f"pitch.{dev_key}",
            f"{len(rows)} rows",
            f"must give one row per {member} tooth: {z}",
        )
        wrong = [i for i, r in enumerate(rows) if len(r) != len(x)]
        if wrong:  # one problem for all of them: the first named, the count given
            i = wrong[0]
            others = f" ({len(wrong)} rows are wrong)" if len(wrong) > 1 else ""
            p.add(
                f"pitch.{dev_key}[{i}]",
                f"{len(rows[i])} values",
                f"must give one value per position of {pos_key}: {len(x)}{others}",
            )
            ok = False
        if ok:
            got[f"{member}_{kind}"] = Trace(
                np.asarray(x, dtype=float) * 1e-3, np.asarray(rows, dtype=float) * 1e-6
            )
    p.raise_if_any("invalid flank traces")
    return FlankTraces(**got) if got else None


def deviations_from_scene(design, scene, flank_range=None) -> PitchDeviations:
    """The scene's ``[pitch]`` deviations (:func:`deviations_from_section`,
    :func:`form_from_section`, :func:`traces_from_section`) on the design's reference pitch radii; ``flank_range``
    the drive flank's loaded TCA's (``CycleResult.flank_range``) for the form
    deviations' default evaluation lengths and the crownings' vertices."""
    teeth = (design.pinion.teeth, design.gear.teeth)
    pin, gear = deviations_from_section(scene["pitch"], teeth)
    covered = (
        (None, None)
        if flank_range is None
        else (
            covered_lengths(flank_range),
            covered_centres(flank_range),
        )
    )
    form = form_from_section(scene["pitch"], teeth, *covered)
    traces = traces_from_section(scene["pitch"], teeth)
    return PitchDeviations(
        pin,
        gear,
        design.pinion.reference_pitch_radius,
        design.gear.reference_pitch_radius,
        form,
        traces,
    )


@dataclass(frozen=True)
class PitchResult:
    """Pitch deviations' loaded TE on the drive flank (the pipeline's ``pitch`` stage):
    the deviations and the hunting record."""

    deviations: PitchDeviations
    record: HuntingRecord
    flank: str = "drive"

    def lines(self, count: int = 12, *, added: bool = False) -> list[dict]:
        """The ``count`` largest lines of the loaded TE's order spectrum other than the
        mean, largest first: pinion order, amplitude (m), and what they are (mesh
        harmonic h, a sideband, a pinion order, a gear order, or a combination:
        :func:`order_kind`). ``added=True`` ranks them by how much the deviations change
        them (|amplitude - the nominal teeth's|; the amplitude given is still the
        line's)."""
        z1, z2 = self.record.teeth
        orders, amp = self.record.order_spectrum()
        rank = amp
        if added:
            rank = np.abs(amp - self.record.order_spectrum("lte_nominal")[1])
        idx = np.argsort(rank[1:])[::-1][:count] + 1
        out = []
        for i in idx:
            o = float(orders[i])
            out.append({"order": o, "amplitude_m": float(amp[i]), "kind": order_kind(o, z1, z2)})
        return out

    def loads_summary(self) -> dict:
        """The teeth's largest normal loads and root stresses over the hunting period
        against the nominal teeth's (SI; empty where the record has no pair loads)."""
        rec = self.record
        if rec.pair_load is None:
            return {}
        pin, gear = rec.tooth_loads()
        rs, rs0 = rec.root_stress(), rec.root_stress_nominal()
        return {
            "pinion_tooth_max_load_N": pin.tolist(),
            "gear_tooth_max_load_N": gear.tolist(),
            "tooth_max_load_nominal_N": rec.tooth_load_nominal,
            "tooth_load_factor": [
                float(pin.max()) / rec.tooth_load_nominal,
                float(gear.max()) / rec.tooth_load_nominal,
            ],
            "root_stress_max_Pa": list(rs),
            "root_stress_max_nominal_Pa": list(rs0),
        }

    def to_dict(self) -> dict:
        rec = self.record
        orders, amp = rec.order_spectrum()
        nominal = rec.order_spectrum("lte_nominal")[1]
        return {
            "flank": self.flank,
            "torque_Nm": rec.torque,
            "method": rec.method,
            "teeth": list(rec.teeth),
            "hunting_cycles": rec.cycles,
            "pinion_cumulative_m": self.deviations.pinion.tolist(),
            "gear_cumulative_m": self.deviations.gear.tolist(),
            "reference_pitch_radii_m": [self.deviations.pinion_radius, self.deviations.gear_radius],
            **({} if self.deviations.form is None else self.deviations.form.to_dict()),
            **({} if self.deviations.traces is None else self.deviations.traces.to_dict()),
            "lte_peak_to_peak_m": float(np.ptp(rec.lte)),
            "lte_nominal_peak_to_peak_m": float(np.ptp(rec.lte_nominal)),
            **self.loads_summary(),
            "lines": self.lines(),
            "spectrum": {
                "order": orders.tolist(),
                "amplitude_m": amp.tolist(),
                "nominal_amplitude_m": nominal.tolist(),
                "scaling": "single-sided peak, rectangular window over one hunting period",
            },
            "record": {"angle_rad": rec.angle.tolist(), "lte_m": rec.lte.tolist()},
        }


def order_kind(order: float, z1: int, z2: int) -> str:
    """What a pinion order is: 'mesh h'; a pinion or gear order near a mesh harmonic as
    its sideband, 'mesh h + pinion d' or 'mesh h - gear d' (d within half a mesh order);
    below half the mesh order 'pinion p' or 'gear g'; else 'combination'."""
    tol = 1e-9
    h = order / z1
    if abs(h - round(h)) < tol:
        return f"mesh {round(h)}"
    for member, per_rev in (("pinion", 1.0), ("gear", z2 / z1)):
        x = order * per_rev  # in that member's orders
        if abs(x - round(x)) >= tol:
            continue
        x = round(x)
        z = z1 if member == "pinion" else z2  # its orders per mesh order
        m = round(x / z)
        if m == 0:
            return f"{member} {x}"
        d = x - m * z
        return f"mesh {m} {'+' if d > 0 else '-'} {member} {abs(d)}"
    return "combination"


def flank_grids(design, scene, positions: int, flank: str = "drive"):
    """The contact grids of ``flank`` (``"drive"`` or ``"coast"``) at ``positions`` per
    mesh cycle and the compliance, as the loaded TCA makes them (for the exact method
    and the linear method's point loads): the closed-form grids and
    ``compliance_for(fidelity)`` of :func:`~gearbox.ltca.table.parallel_ltca` for a
    parallel pair (its coast flank is the drive flank turned half a turn about the
    centre line: the grids of the modifications turned,
    :func:`~gearbox.ltca.table.coast_grids`), else
    :func:`~gearbox.ltca.beveloid.scene_grids` of that side and
    :func:`~gearbox.ltca.beveloid.scene_compliance`; both referenced to the cycle's
    first contact (:func:`~gearbox.ltca.analysis.touching_grids`)."""
    from .beveloid import modifications_from_scene, scene_compliance, scene_grids
    from .compliance import compliance_for
    from .table import is_parallel

    if flank not in ("drive", "coast"):
        raise InputError(Problem("flank", flank, "must be 'drive' or 'coast'"))
    lt = scene["ltca"]
    if is_parallel(design):
        from .parallel import parallel_grid
        from .table import coast_grids, mirrored_grids, parallel_pair_from_design, right_handed

        pair = parallel_pair_from_design(design, scene)
        pair, relief, hand = right_handed(pair, modifications_from_scene(design, scene))
        if flank == "coast":
            relief = tuple(m.reflected() for m in relief)
        grids = [
            parallel_grid(pair, j / positions, lt["grid_face"], relief=relief)
            for j in range(positions)
        ]
        if flank == "coast":
            grids = coast_grids(grids)
        if hand < 0:
            grids = mirrored_grids(grids)
        compliance = compliance_for(lt["fidelity"], face_ends=lt["face_ends"])
    else:
        side = "R" if flank == "drive" else "L"
        grids = scene_grids(design, scene, side, positions)[0]
        compliance = scene_compliance(design, scene)
    grids = touching_grids(grids)  # as ltca_cycle references them
    reserve = getattr(compliance, "reserve", None)
    if callable(reserve):
        reserve(grids)
    return grids, compliance

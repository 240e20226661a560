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
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..errors import Problems
from .analysis import CycleResult
from .solver import ContactSolver, solve_contact

__all__ = [
    "HuntingRecord",
    "PitchDeviations",
    "exact_rotation",
    "hunting_lte",
    "pair_angles",
]

#: Largest cumulative pitch deviation accepted (m): 1 mm, far beyond any gear quality
#: of ISO 1328-1 (class 11 allows about 0.2 mm on the default pair).
MAX_DEVIATION = 1.0e-3


@dataclass(frozen=True)
class PitchDeviations:
    """Cumulative pitch deviations of the loaded flanks (m, arc on the reference pitch
    circle, + proud): ``pinion`` shape (z1,), ``gear`` shape (z2,), tooth i as the
    module doc numbers them; ``pinion_radius``, ``gear_radius`` the reference pitch
    radii r_1, r_2 (m) the arcs are measured on."""

    pinion: np.ndarray
    gear: np.ndarray
    pinion_radius: float
    gear_radius: float

    def __post_init__(self):
        p = Problems()
        for name in ("pinion", "gear"):
            a = np.array(getattr(self, name), dtype=float).reshape(-1)
            p.check(a.size >= 8, name, a.size, "needs one deviation per tooth (>= 8 teeth)")
            bad = ~np.isfinite(a) | (np.abs(a) > MAX_DEVIATION)
            if np.any(bad):
                i = int(np.flatnonzero(bad)[0])
                p.add(f"{name}[{i}]", float(a[i]), f"must be finite and within +-{MAX_DEVIATION} m")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        p.in_range("pinion_radius", self.pinion_radius, 0.0, None, lo_open=True)
        p.in_range("gear_radius", self.gear_radius, 0.0, None, lo_open=True)
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
    def from_single(cls, pinion_single, gear_single, pinion_radius, gear_radius):
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
            out.append(np.concatenate([[0.0], np.cumsum(f)[:-1]]) if f.size else f)
        p.raise_if_any("invalid pitch deviations")
        return cls(out[0], out[1], pinion_radius, gear_radius)


def pair_angles(dev: PitchDeviations, pair_index, cycles) -> np.ndarray:
    """alpha_k per mesh cycle (module doc): shape (len(cycles), K), pinion radians."""
    z1, z2 = dev.teeth
    c = np.asarray(cycles, dtype=int)[:, None] - np.asarray(pair_index, dtype=int)[None, :]
    a1 = dev.pinion[np.mod(c, z1)] / dev.pinion_radius
    a2 = dev.gear[np.mod(c, z2)] / dev.gear_radius * (z2 / z1)
    return a1 + a2


def _at_torque(res: CycleResult, torque: float, values: np.ndarray) -> np.ndarray:
    """``values`` (T, ...) linearly interpolated in the torque levels (no extrapolation)."""
    tq = np.asarray(res.torque, dtype=float)
    if tq.size == 1:
        return values[0]
    i = int(np.clip(np.searchsorted(tq, torque) - 1, 0, tq.size - 2))
    u = (torque - tq[i]) / (tq[i + 1] - tq[i])
    return (1.0 - u) * values[i] + u * values[i + 1]


@dataclass(frozen=True)
class HuntingRecord:
    """Loaded transmission error over a hunting period at one torque (SI).

    angle (n,) pinion angle from the record's start (rad), n = cycles x positions;
    lte (n,) loaded TE with the deviations (m); lte_nominal (n,) without them (the
    loaded TCA's cycle repeated); torque (N m); teeth (z1, z2); cycles (mesh cycles:
    a hunting period); method ('linear' or 'exact').
    """

    angle: np.ndarray
    lte: np.ndarray
    lte_nominal: np.ndarray
    torque: float
    teeth: tuple[int, int]
    cycles: int
    method: str

    @property
    def pinion_revolutions(self) -> float:
        return self.cycles / self.teeth[0]

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

    def to_dict(self) -> dict:
        return {
            "torque_Nm": self.torque,
            "teeth": list(self.teeth),
            "cycles": self.cycles,
            "method": self.method,
            "angle_rad": self.angle.tolist(),
            "lte_m": self.lte.tolist(),
            "lte_nominal_m": self.lte_nominal.tolist(),
            "peak_to_peak_m": float(np.ptp(self.lte)),
            "peak_to_peak_nominal_m": float(np.ptp(self.lte_nominal)),
        }


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
) -> HuntingRecord:
    """The loaded TE over a hunting period (lcm(z1, z2) mesh cycles) at ``torque``
    (N m, within the result's torque levels; the linear method interpolates the
    levels linearly, the exact one solves at ``torque``).

    ``method="exact"`` needs the loaded TCA's ``grids`` (one per position, as
    :func:`~gearbox.ltca.analysis.ltca_cycle` made them) and ``compliance``.
    """
    _check_result(res, dev, teeth, torque, method)
    z1 = teeth[0]
    H = dev.hunting_cycles
    P = res.fraction.size
    cycles = np.arange(H)
    nominal = _at_torque(res, torque, res.lte)  # (P,)
    angle = (cycles[:, None] + res.fraction[None, :]) * (2.0 * math.pi / z1)
    alpha = pair_angles(dev, res.pair_index, cycles)  # (H, K)
    if method == "linear":
        w = _at_torque(res, torque, res.pair_weight)  # (P, K)
        arm = torque / _at_torque(res, torque, res.normal_load)  # (P,)
        lte = nominal[None, :] - arm[None, :] * (alpha @ w.T)
    else:
        if grids is None or compliance is None or len(grids) != P:
            p = Problems()
            n = None if grids is None else len(grids)
            p.add("grids", n, f"the exact method needs the {P} grids and the compliance")
            p.raise_if_any("invalid pitch-deviation analysis")
        lte = np.empty((H, P))
        for j, g in enumerate(grids):
            rot, arm = exact_rotation(g, compliance, torque, alpha, res.pair_index, solver=solver)
            lte[:, j] = rot * arm
        nominal = np.array([_nominal_exact(g, compliance, torque, solver) for g in grids])
    return HuntingRecord(
        angle=angle.reshape(-1),
        lte=lte.reshape(-1),
        lte_nominal=np.tile(nominal, H),
        torque=float(torque),
        teeth=(int(teeth[0]), int(teeth[1])),
        cycles=H,
        method=method,
    )


def _nominal_exact(grid, compliance, torque, solver):
    sol = solve_contact(grid, compliance, torque, solver=solver or ContactSolver())
    return sol.rotation * torque / float(sol.load.sum())


def exact_rotation(grid, compliance, torque, alpha, pair_index, *, solver=None):
    """Loaded rotation (rad) and torque arm T / sum F (m) at one grid position for each
    row of pair angles ``alpha`` (shape (R, K), pinion radians, K = len(pair_index)):
    the contact problem with the separations offset by -m_i alpha_k. Rows that repeat
    are solved once; each solve starts from the previous row's loads."""
    solver = solver or ContactSolver()
    alpha = np.atleast_2d(np.asarray(alpha, dtype=float))
    col = {int(k): kk for kk, k in enumerate(pair_index)}
    idx = np.array([col[int(k)] for k in grid.pair])
    C0 = compliance.tooth_matrix(grid) if compliance.load_dependent else None
    rows, inverse = np.unique(alpha[:, idx], axis=0, return_inverse=True)
    rot = np.empty(len(rows))
    arm = np.empty(len(rows))
    prev = None
    for r, a in enumerate(rows):
        g = replace(grid, separation=grid.separation - grid.arm * a)
        sol = solve_contact(g, compliance, torque, solver=solver, tooth_matrix=C0, initial_load=prev)
        prev = sol.load
        rot[r] = sol.rotation
        arm[r] = torque / float(sol.load.sum())
    inverse = np.asarray(inverse).reshape(-1)
    return rot[inverse], arm[inverse]

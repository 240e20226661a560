"""Campbell diagram: eigenfrequencies against speed, excitation orders, crossings.

Speeds are reference-shaft (pinion = engine) speeds n in rpm and frequencies are in
Hz, as a Campbell diagram is read; an excitation of order o has the frequency
o n / 60. A mode of frequency f(n) is excited in resonance where

    g(n) = f(n) - o n / 60 = 0,

solved here for every (mode, order) pair: sign changes of g on a fine speed grid
bracket each root, then Brent's method (scipy.optimize.brentq) refines it to
``xtol`` rpm. Two crossings closer than one grid step can be missed; the default grid
has 2001 speeds.

Excitation orders of a crossed beveloid marine drive, relative to the pinion:

- mesh order N_1 and its harmonics h N_1 (tooth meshing, mesh stiffness and
  transmission error);
- engine firing order z/2 for a 4-stroke engine with z cylinders (z for a
  2-stroke) and its harmonics; half orders 0.5, 1, 1.5, ... below it from
  cylinder-to-cylinder scatter;
- propeller blade-pass order B N_1 / N_2 (B blades, the propeller on the gear
  shaft turning at N_1 / N_2 of the pinion speed) and its harmonics.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from ..errors import Problems, expect_type

__all__ = [
    "CampbellDiagram",
    "Crossing",
    "ExcitationOrder",
    "OrderCuts",
    "campbell",
    "excitation_orders",
    "excitation_orders_from_scene",
]

ModeSpec = float | Callable[[np.ndarray], np.ndarray] | tuple[Sequence[float], Sequence[float]]


@dataclass(frozen=True)
class ExcitationOrder:
    """One excitation: ``order`` cycles per pinion revolution, from ``source``.

    ``source`` is ``mesh``, ``engine``, ``engine-half``, ``propeller`` or ``eccentricity``.
    """

    label: str
    order: float
    source: str

    def frequency_hz(self, speed_rpm):
        """Excitation frequency (Hz) at pinion speed ``speed_rpm`` (rpm)."""
        return self.order * np.asarray(speed_rpm, dtype=float) / 60.0


@dataclass(frozen=True)
class Crossing:
    """A mode frequency equal to an excitation frequency.

    Attributes: ``mode`` (name), ``excitation`` (label), ``order``, ``source``,
    ``speed_rpm`` (pinion speed, rpm), ``frequency_hz`` (Hz),
    ``in_operating_range`` (the resonance risk flag), ``iterations`` (Brent
    iterations), ``converged``; ``response``: optional, the steady vibration this
    excitation drives at the crossing speed, name -> value, with a ``*_fraction``
    entry for each amplitude relative to its mean load (see
    :meth:`CampbellDiagram.with_responses`).
    """

    mode: str
    excitation: str
    order: float
    source: str
    speed_rpm: float
    frequency_hz: float
    in_operating_range: bool
    iterations: int
    converged: bool
    response: Mapping[str, float] | None = None

    @property
    def severity(self) -> float | None:
        """The largest ``*_fraction`` entry of ``response`` (None without one)."""
        if not self.response:
            return None
        fr = [float(v) for k, v in self.response.items() if k.endswith("_fraction")]
        return max(fr) if fr else None


@dataclass(frozen=True, eq=False)
class OrderCuts:
    """Amplitude of each excitation order against speed (order cuts).

    Attributes
    ----------
    speeds_rpm : ndarray, shape (n_speeds,)
        Pinion speeds (rpm), increasing.
    excitations : tuple of ExcitationOrder, length n_orders
    amplitudes : mapping name -> ndarray, shape (n_orders, n_speeds)
        Peak amplitude of each order at each speed, per channel.
    units : mapping name -> str
    means : mapping name -> ndarray, shape (n_speeds,)
        The mean load each channel vibrates about, where known (for fractions).
    """

    speeds_rpm: np.ndarray
    excitations: tuple[ExcitationOrder, ...]
    amplitudes: Mapping[str, np.ndarray]
    units: Mapping[str, str]
    means: Mapping[str, np.ndarray]

    def fraction(self, name: str) -> np.ndarray:
        """``amplitudes[name]`` over its mean at each speed, shape (n_orders, n_speeds)."""
        return self.amplitudes[name] / np.abs(self.means[name])[None, :]

    def to_dict(self) -> dict:
        """Plain-JSON form."""
        return {
            "speeds_rpm": self.speeds_rpm.tolist(),
            "excitations": [vars(e).copy() for e in self.excitations],
            "amplitudes": {k: v.tolist() for k, v in self.amplitudes.items()},
            "units": dict(self.units),
            "means": {k: v.tolist() for k, v in self.means.items()},
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> OrderCuts:
        """Inverse of :meth:`to_dict`."""
        exc = tuple(ExcitationOrder(**e) for e in data["excitations"])
        speeds = np.asarray(data["speeds_rpm"], dtype=float)
        return cls(
            speeds_rpm=speeds,
            excitations=exc,
            amplitudes={
                k: np.asarray(v, dtype=float).reshape(len(exc), speeds.size)
                for k, v in data["amplitudes"].items()
            },
            units=dict(data["units"]),
            means={k: np.asarray(v, dtype=float) for k, v in data["means"].items()},
        )


@dataclass(frozen=True, eq=False)
class CampbellDiagram:
    """Mode frequencies and excitation orders over a speed range, with crossings.

    Attributes
    ----------
    speeds_rpm : ndarray, shape (n_speeds,)
        Pinion speeds of the sampled curves (rpm).
    mode_names : tuple of str, length n_modes
    mode_frequencies_hz : ndarray, shape (n_modes, n_speeds)
        Mode frequencies (Hz) on ``speeds_rpm``.
    excitations : tuple of ExcitationOrder
    crossings : tuple of Crossing
        Every crossing inside the speed range, sorted by speed.
    operating_range_rpm : tuple (lo, hi) or None
        Crossings in this closed range are flagged ``in_operating_range``.
    response_threshold : float or None
        With responses (:meth:`with_responses`): the severity (response over mean
        load) from which a risk counts as significant.
    order_cuts : OrderCuts or None
        The forced response of each excitation order along the speed range, where
        computed (:meth:`with_responses`).
    """

    speeds_rpm: np.ndarray
    mode_names: tuple[str, ...]
    mode_frequencies_hz: np.ndarray
    excitations: tuple[ExcitationOrder, ...]
    crossings: tuple[Crossing, ...]
    operating_range_rpm: tuple[float, float] | None
    response_threshold: float | None = None
    order_cuts: OrderCuts | None = None

    @property
    def risks(self) -> tuple[Crossing, ...]:
        """Crossings inside the operating range (resonance risks)."""
        return tuple(c for c in self.crossings if c.in_operating_range)

    @property
    def significant(self) -> tuple[Crossing, ...]:
        """Risks whose severity reaches ``response_threshold``, the most severe first;
        every risk (by speed) when the diagram has no responses or no threshold."""
        if self.response_threshold is None or not any(c.response for c in self.risks):
            return self.risks
        hit = [
            c
            for c in self.risks
            if c.severity is not None and c.severity >= self.response_threshold
        ]
        return tuple(sorted(hit, key=lambda c: -c.severity))

    def with_responses(
        self,
        response: Callable[[Crossing], Mapping[str, float] | None],
        threshold: float | None = None,
        order_cuts: OrderCuts | None = None,
    ) -> CampbellDiagram:
        """The diagram with ``response(crossing)`` stored on every crossing (e.g. the
        linear model's steady response to that excitation at the crossing speed),
        ``threshold`` as :attr:`response_threshold` and ``order_cuts``."""
        p = Problems()
        if threshold is not None:
            p.check(
                math.isfinite(threshold) and threshold >= 0,
                "threshold",
                threshold,
                "must be a finite fraction >= 0",
            )
        p.raise_if_any("campbell responses")
        crossings = tuple(
            dataclasses.replace(
                c,
                response=None
                if (r := response(c)) is None
                else {k: float(v) for k, v in r.items()},
            )
            for c in self.crossings
        )
        return dataclasses.replace(
            self, crossings=crossings, response_threshold=threshold, order_cuts=order_cuts
        )

    def to_dict(self) -> dict:
        """Plain-JSON form."""
        return {
            "speeds_rpm": self.speeds_rpm.tolist(),
            "mode_names": list(self.mode_names),
            "mode_frequencies_hz": self.mode_frequencies_hz.tolist(),
            "excitations": [vars(e).copy() for e in self.excitations],
            "crossings": [vars(c).copy() for c in self.crossings],
            "operating_range_rpm": None
            if self.operating_range_rpm is None
            else list(self.operating_range_rpm),
            "response_threshold": self.response_threshold,
            "order_cuts": None if self.order_cuts is None else self.order_cuts.to_dict(),
        }

    @classmethod
    def from_dict(cls, data: Mapping) -> CampbellDiagram:
        """Inverse of :meth:`to_dict`."""
        rng = data["operating_range_rpm"]
        return cls(
            speeds_rpm=np.asarray(data["speeds_rpm"], dtype=float),
            mode_names=tuple(data["mode_names"]),
            mode_frequencies_hz=np.asarray(data["mode_frequencies_hz"], dtype=float).reshape(
                len(data["mode_names"]), -1
            ),
            excitations=tuple(ExcitationOrder(**e) for e in data["excitations"]),
            crossings=tuple(Crossing(**c) for c in data["crossings"]),
            operating_range_rpm=None if rng is None else (float(rng[0]), float(rng[1])),
            response_threshold=data.get("response_threshold"),
            order_cuts=None
            if data.get("order_cuts") is None
            else OrderCuts.from_dict(data["order_cuts"]),
        )


def _fmt(o: float) -> str:
    return f"{o:.4g}"


def excitation_orders(
    *,
    pinion_teeth: int,
    gear_teeth: int | None = None,
    cylinders: int | None = None,
    blades: int | None = None,
    mesh_harmonics: int = 3,
    firing_harmonics: int = 2,
    half_orders: bool = True,
    max_half_order: float | None = None,
    blade_harmonics: int = 1,
    strokes: int = 4,
    pinion_eccentricity: bool = False,
    gear_eccentricity: bool = False,
    pitch_orders: int = 0,
    deviation_orders: tuple[tuple[str, float], ...] = (),
) -> tuple[ExcitationOrder, ...]:
    """Excitation orders relative to the pinion (cycles per pinion revolution).

    Parameters
    ----------
    pinion_teeth, gear_teeth : int
        N_1, N_2. ``gear_teeth`` is needed for the blade-pass order.
    cylinders : int or None
        Engine cylinders z; None: no engine orders.
    blades : int or None
        Propeller blades B on the gear shaft; None: no blade-pass orders.
    mesh_harmonics, firing_harmonics, blade_harmonics : int
        Harmonics of each family (>= 1; 0 drops the family).
    half_orders : bool
        Add 0.5, 1.0, ... below the firing order that are not firing harmonics.
    max_half_order : float or None
        Highest half order added; None: up to the firing order.
    strokes : int
        4 (firing order z/2) or 2 (firing order z).
    pinion_eccentricity, gear_eccentricity : bool
        Add the once per revolution of an eccentric pinion (order 1) or gear (order
        N_1/N_2; needs ``gear_teeth``), docs/drivetrain.md §3b. Their sidebands about
        the mesh orders are not listed.
    pitch_orders : int
        Pitch deviations (docs/drivetrain.md §3c): add pinion orders 1..k and gear
        orders 1..k (k N_1/N_2; needs ``gear_teeth``), family ``pitch``. Their lines
        lie at every multiple of 1 / (the hunting period in pinion revolutions); these
        are the long-wave ones.
    deviation_orders : tuple of (label, order)
        Further lines of the tooth deviations' approach (its largest beyond those
        listed, :func:`gearbox.drivetrain.linear.deviation_lines`: a ghost order, a
        wobble's sidebands), family ``pitch``.

    Returns
    -------
    tuple of ExcitationOrder, sorted by order; duplicates (same order) keep the
    first family in the order mesh, engine, propeller, eccentricity, pitch, engine-half.
    """
    p = Problems()
    p.check(
        isinstance(pinion_teeth, int) and pinion_teeth >= 1,
        "pinion_teeth",
        pinion_teeth,
        "must be an integer >= 1",
    )
    if blades is not None:
        p.check(
            isinstance(blades, int) and blades >= 1, "blades", blades, "must be an integer >= 1"
        )
        p.check(
            isinstance(gear_teeth, int) and gear_teeth >= 1,
            "gear_teeth",
            gear_teeth,
            "must be an integer >= 1 (needed for the blade-pass order)",
        )
    if cylinders is not None:
        p.check(
            isinstance(cylinders, int) and cylinders >= 1,
            "cylinders",
            cylinders,
            "must be an integer >= 1",
        )
    p.check(strokes in (2, 4), "strokes", strokes, "must be 2 or 4")
    if gear_eccentricity or pitch_orders:
        p.check(
            isinstance(gear_teeth, int) and gear_teeth >= 1,
            "gear_teeth",
            gear_teeth,
            "must be an integer >= 1 (needed for the gear's eccentricity and pitch orders)",
        )
    for nm, v in (
        ("mesh_harmonics", mesh_harmonics),
        ("firing_harmonics", firing_harmonics),
        ("blade_harmonics", blade_harmonics),
        ("pitch_orders", pitch_orders),
    ):
        p.check(isinstance(v, int) and v >= 0, nm, v, "must be an integer >= 0")
    for _, order in deviation_orders:
        p.check(math.isfinite(order) and order > 0, "deviation_orders", order, "must be > 0")
    p.raise_if_any("excitation orders")

    out: list[ExcitationOrder] = []
    for h in range(1, mesh_harmonics + 1):
        o = float(h * pinion_teeth)
        out.append(ExcitationOrder("mesh" if h == 1 else f"{h}x mesh", o, "mesh"))
    if cylinders is not None:
        firing = cylinders * (2.0 / strokes)
        for h in range(1, firing_harmonics + 1):
            out.append(ExcitationOrder(f"firing {_fmt(h * firing)}", h * firing, "engine"))
    if blades is not None:
        bp = blades * pinion_teeth / gear_teeth
        for h in range(1, blade_harmonics + 1):
            lbl = "blade pass" if h == 1 else f"{h}x blade pass"
            out.append(ExcitationOrder(lbl, h * bp, "propeller"))
    if pinion_eccentricity:
        out.append(ExcitationOrder("pinion eccentricity", 1.0, "eccentricity"))
    if gear_eccentricity:
        out.append(ExcitationOrder("gear eccentricity", pinion_teeth / gear_teeth, "eccentricity"))
    for h in range(1, pitch_orders + 1):
        out.append(ExcitationOrder(f"pitch, pinion {h}", float(h), "pitch"))
        out.append(ExcitationOrder(f"pitch, gear {h}", h * pinion_teeth / gear_teeth, "pitch"))
    out.extend(ExcitationOrder(label, float(o), "pitch") for label, o in deviation_orders)
    if cylinders is not None and half_orders:
        firing = cylinders * (2.0 / strokes)
        top = firing if max_half_order is None else min(firing, max_half_order + 0.25)
        k = 1
        while 0.5 * k < top - 1e-9:
            out.append(ExcitationOrder(f"order {_fmt(0.5 * k)}", 0.5 * k, "engine-half"))
            k += 1
    seen: set[float] = set()
    unique = []
    for e in out:
        key = round(e.order, 9)
        if key not in seen:
            seen.add(key)
            unique.append(e)
    return tuple(sorted(unique, key=lambda e: e.order))


#: Pinion and gear orders listed for pitch deviations (:func:`excitation_orders`).
PITCH_ORDERS = 3


def excitation_orders_from_scene(scene, **options) -> tuple[ExcitationOrder, ...]:
    """:func:`excitation_orders` of the orders a scene's drivetrain model excites.

    Reads ``pinion.teeth``, ``gear.teeth``, ``drivetrain.engine_cylinders``
    (4-stroke), ``drivetrain.propeller_blades``, and, where the scene has them,
    ``drivetrain.engine_harmonics`` (firing harmonics) and
    ``drivetrain.blade_pass_harmonics``, and the eccentricities' orders where
    ``drivetrain.pinion_eccentricity_um`` / ``gear_eccentricity_um`` > 0, pinion and
    gear orders 1..:data:`PITCH_ORDERS` with ``drivetrain.pitch_deviations``. Half orders 0.5, 1, 1.5 (those the
    drivetrain model drives) are included when ``drivetrain.half_order_ripple`` > 0.
    ``options`` override any of these.
    """
    dt = scene["drivetrain"]
    fields = getattr(dt, "keys", lambda: ())()
    options.setdefault("half_orders", float(dt["half_order_ripple"]) > 0.0)
    options.setdefault("max_half_order", 1.5)
    if "engine_harmonics" in fields:
        options.setdefault("firing_harmonics", int(dt["engine_harmonics"]))
    if "blade_pass_harmonics" in fields:
        options.setdefault("blade_harmonics", int(dt["blade_pass_harmonics"]))
    if "pinion_eccentricity_um" in fields:
        options.setdefault("pinion_eccentricity", float(dt["pinion_eccentricity_um"]) > 0)
        options.setdefault("gear_eccentricity", float(dt["gear_eccentricity_um"]) > 0)
    if "pitch_deviations" in fields:
        options.setdefault("pitch_orders", PITCH_ORDERS if dt["pitch_deviations"] else 0)
    return excitation_orders(
        pinion_teeth=int(scene["pinion"]["teeth"]),
        gear_teeth=int(scene["gear"]["teeth"]),
        cylinders=int(dt["engine_cylinders"]),
        blades=int(dt["propeller_blades"]),
        **options,
    )


def _mode_function(p: Problems, name: str, spec, lo: float, hi: float, interpolation: str):
    """A vectorised f(n_rpm) -> Hz from a constant, a callable or a table."""
    path = f"modes[{name!r}]"
    if callable(spec):
        return spec
    if isinstance(spec, tuple | list) and len(spec) == 2:
        n = np.asarray(spec[0], dtype=float)
        f = np.asarray(spec[1], dtype=float)
        if n.ndim != 1 or f.shape != n.shape or n.size < 2 or np.any(np.diff(n) <= 0):
            p.add(
                path,
                "table",
                "must be (speeds_rpm, frequencies_hz): equal 1-D arrays, speeds increasing",
            )
            return None
        if not (n[0] <= lo * (1 + 1e-12) and n[-1] >= hi * (1 - 1e-12)):
            p.add(
                path,
                f"speeds {n[0]:g}..{n[-1]:g} rpm",
                f"must cover the speed range [{lo:g}, {hi:g}] rpm",
            )
            return None
        if interpolation == "cubic" and n.size >= 4:
            from scipy.interpolate import CubicSpline

            return CubicSpline(n, f)
        return lambda s: np.interp(s, n, f)
    try:
        c = float(spec)
    except (TypeError, ValueError):
        p.add(
            path,
            spec,
            "must be a frequency (Hz), a callable f(speed_rpm) or a "
            "(speeds_rpm, frequencies_hz) table",
        )
        return None
    if not (math.isfinite(c) and c > 0):
        p.add(path, c, "must be a finite frequency > 0 (Hz)")
        return None
    return lambda s: np.full_like(np.asarray(s, dtype=float), c)


def campbell(
    modes: Mapping[str, ModeSpec],
    excitations: Sequence[ExcitationOrder],
    speed_range_rpm: tuple[float, float],
    *,
    operating_range_rpm: tuple[float, float] | None = None,
    n_grid: int = 2001,
    xtol_rpm: float = 1e-9,
    table_interpolation: str = "linear",
) -> CampbellDiagram:
    """Campbell diagram with every crossing speed solved by root finding.

    Parameters
    ----------
    modes : mapping name -> mode
        Each mode's frequency (Hz) against pinion speed (rpm): a constant, a
        vectorised callable ``f(speed_rpm) -> Hz``, or a table
        ``(speeds_rpm, frequencies_hz)`` (``table_interpolation``; must cover the
        speed range), e.g. eigenfrequencies of the linearised drivetrain.
    excitations : sequence of ExcitationOrder
        From :func:`excitation_orders`.
    speed_range_rpm : (lo, hi)
        Pinion speeds of the diagram (rpm), 0 <= lo < hi.
    operating_range_rpm : (lo, hi) or None
        Crossings in this closed range are flagged as resonance risks.
    n_grid : int
        Speeds of the bracketing grid (and of the sampled curves).
    xtol_rpm : float
        Absolute tolerance of the crossing speeds (rpm).
    table_interpolation : str
        ``linear`` or ``cubic`` (not-a-knot cubic spline, for tables of a few
        speeds; needs 4 or more) between the speeds of tabulated modes.
    """
    from scipy.optimize import brentq

    expect_type(modes, Mapping, "campbell: modes", "{name: frequency, callable or table}")
    p = Problems()
    lo = hi = float("nan")
    try:
        lo, hi = (float(v) for v in speed_range_rpm)
    except (TypeError, ValueError):
        p.add("speed_range_rpm", speed_range_rpm, "must be (lo, hi) in rpm")
    else:
        p.check(
            0 <= lo < hi < math.inf,
            "speed_range_rpm",
            speed_range_rpm,
            "must satisfy 0 <= lo < hi (rpm)",
        )
    if operating_range_rpm is not None:
        try:
            olo, ohi = (float(v) for v in operating_range_rpm)
            p.check(
                0 <= olo <= ohi,
                "operating_range_rpm",
                operating_range_rpm,
                "must satisfy 0 <= lo <= hi (rpm)",
            )
        except (TypeError, ValueError):
            p.add("operating_range_rpm", operating_range_rpm, "must be (lo, hi) in rpm or None")
    p.check(isinstance(n_grid, int) and n_grid >= 2, "n_grid", n_grid, "must be an integer >= 2")
    p.check(
        table_interpolation in ("linear", "cubic"),
        "table_interpolation",
        table_interpolation,
        "must be 'linear' or 'cubic'",
    )
    p.check(len(modes) >= 1, "modes", dict(modes), "must name at least one mode")
    for i, e in enumerate(excitations):
        if not isinstance(e, ExcitationOrder) or not (math.isfinite(e.order) and e.order > 0):
            p.add(f"excitations[{i}]", e, "must be an ExcitationOrder with order > 0")
    p.raise_if_any("campbell diagram")
    funcs = {
        name: _mode_function(p, name, spec, lo, hi, table_interpolation)
        for name, spec in modes.items()
    }
    p.raise_if_any("campbell diagram")

    speeds = np.linspace(lo, hi, n_grid)
    names = tuple(funcs)
    freqs = np.empty((len(names), n_grid))
    for j, name in enumerate(names):
        f = np.asarray(funcs[name](speeds), dtype=float)
        if f.shape != speeds.shape or not np.all(np.isfinite(f)):
            p.add(f"modes[{name!r}]", "f(speed_rpm)", "must return finite Hz of the speeds' shape")
            continue
        freqs[j] = f
    p.raise_if_any("campbell diagram")

    orders = np.array([e.order for e in excitations], dtype=float)
    # g = f_mode(n) - o n / 60 on the grid, shape (n_modes, n_orders, n_grid).
    g = freqs[:, None, :] - orders[None, :, None] * speeds[None, None, :] / 60.0
    roots: list[tuple[int, int, float, int, bool]] = [
        (j, k, float(speeds[i]), 0, True) for j, k, i in np.argwhere(g == 0.0)
    ]
    for j, k, i in np.argwhere(g[..., :-1] * g[..., 1:] < 0):

        def gs(s, fun=funcs[names[j]], o=orders[k]):
            return float(np.asarray(fun(np.array([s])), dtype=float)[0]) - o * s / 60.0

        s, r = brentq(gs, speeds[i], speeds[i + 1], xtol=xtol_rpm, full_output=True, disp=False)
        roots.append((int(j), int(k), float(s), int(r.iterations), bool(r.converged)))
    crossings: list[Crossing] = []
    for j, k, s, it, ok in roots:
        e = excitations[k]
        inside = operating_range_rpm is not None and (
            float(operating_range_rpm[0]) <= s <= float(operating_range_rpm[1])
        )
        crossings.append(
            Crossing(
                names[j], e.label, float(e.order), e.source, s, e.order * s / 60.0, inside, it, ok
            )
        )
    crossings.sort(key=lambda c: (c.speed_rpm, c.mode, c.order))
    rng = (
        None
        if operating_range_rpm is None
        else (float(operating_range_rpm[0]), float(operating_range_rpm[1]))
    )
    return CampbellDiagram(speeds, names, freqs, tuple(excitations), tuple(crossings), rng)

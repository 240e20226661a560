"""Flank modifications (micro-geometry) of one gear: the material removed normal to
its flanks, added to every initial separation of the loaded TCA.

Profile modifications act in each transverse section along the roll length
``xi = sqrt(r^2 - r_b^2)`` between the form circle (where the involute starts, radius
``r_F``) and the tip circle ``r_a`` of that section; lead modifications act along the
gear's own axis across its face width ``b``, with ``w`` the axial distance from the face
middle (``-b/2 .. b/2``, positive towards the heel for beveloid gears, towards ``+z``
for parallel pairs). Amounts are removals normal to the flank (m), as ISO 21771:2007
section 9 defines them; every term is zero by default (the paper's flanks):

- tip relief ``C_a`` from ``r_a - L_a`` up to the tip (:class:`TipRelief`), root relief
  ``C_f`` from ``r_F + L_f`` down to the form circle, each linear or parabolic in xi;
- profile crowning ``C_alpha``: a parabola in xi that is 0 in the middle of the
  profile range and ``C_alpha`` at both of its ends;
- lead crowning ``C_beta``: ``C_beta (2 w / b)^2`` (0 in the face middle, ``C_beta`` at
  both face ends);
- end relief ``C_e`` over a length ``L_e`` at each face end, linear or parabolic;
- helix slope ``f_H``: ``f_H w / b``, a removal that grows linearly across the face
  (negative at one end: it tilts the flank, as a lead angle modification does), the
  correction for a known misalignment;
- profile slope ``f_Halpha``: ``f_Halpha (t - 1/2)``, ``t = (xi - xi_F) / (xi_a -
  xi_F)`` the place in the profile range (0 at the form circle, 1 at the tip): a
  removal that grows linearly up the profile (positive: more at the tip, as a smaller
  pressure angle; negative at the root);
- flank twist ``S``: ``S (t - 1/2) w / b``, a profile slope that changes linearly
  across the face, ``-S/2`` at ``w = -b/2`` to ``+S/2`` at ``w = +b/2`` (the twist a
  generated lead crowning leaves on helical teeth, or its correction);
- a topography (:class:`Topography`): any removal given on a grid of roll length from
  the reference circle (``xi - xi_ref``, the coordinate of a gear checker's profile
  traces) and axial position ``w``, interpolated between the grid's points (bicubic or
  bilinear) and held beyond them: a designed bias, a k-chart from a grinding machine,
  or a flank measured on the gear checker less its design.

A gear's removal is the sum of its terms; the separation of a contact point is the
sum of both gears' removals there (:meth:`FlankModification.removal`).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, Problem, Problems

__all__ = [
    "OVERSHOOT_NOTE",
    "PCHIP_REFINE",
    "SHAPES",
    "TOPOGRAPHY_METHODS",
    "FlankModification",
    "TipRelief",
    "Topography",
    "as_modification",
    "describe_pair",
    "removal_map",
    "topography_from_section",
    "topography_notes",
]

#: exponent of the relief laws in the relief coordinate t (0 at the start, 1 at the end)
SHAPES = {"linear": 1, "parabolic": 2}


#: interpolation of a :class:`Topography` -> the fewest grid points it takes on each axis
TOPOGRAPHY_METHODS = {"cubic": 4, "pchip": 2, "linear": 2}

#: a ``"pchip"`` topography is evaluated on its grid refined this many times per cell
#: (along the face first, then up the profile) and read bilinearly between: on a random
#: 4 x 9 grid of 0-5 um within 0.04 um of PCHIP evaluated point by point (measured;
#: the departure halves with each doubling)
PCHIP_REFINE = 16


def _relief_law(amount: float, t, shape: str) -> np.ndarray:
    return amount * np.clip(t, 0.0, None) ** SHAPES[shape]


@dataclass(frozen=True)
class TipRelief:
    """Tip relief (profile modification) of one gear's flanks, SI.

    amount: C_a (m), the material removed normal to the flank at the tip circle
    (0 = the paper's unmodified flanks); length: L_a (m), measured radially down from
    the tip circle r_a(z) at each face position, so the relief starts at
    ``r_s = r_a - L_a`` (the diameter d_Ca = d_a - 2 L_a of ISO 21771 profile
    modifications); shape: ``linear`` or ``parabolic`` in the roll length
    ``xi = sqrt(r^2 - r_b^2)``: ``C(r) = C_a t^e``, ``t = (xi - xi_s) / (xi_a - xi_s)``,
    e = 1 or 2, zero below r_s. Beyond the tip (the flank's continuation, used only to
    tell an interior minimum from an edge one) the same law is continued.
    """

    amount: float = 0.0
    length: float = 0.0
    shape: str = "linear"

    def __post_init__(self):
        p = Problems()
        p.in_range("amount", self.amount, 0.0, None)
        p.in_range("length", self.length, 0.0, None)
        if self.shape not in SHAPES:
            p.add("shape", self.shape, f"must be one of {', '.join(SHAPES)}")
        if self.amount > 0 and not self.length > 0:
            p.add("length", self.length, "must be > 0 when the relief amount is > 0")
        p.raise_if_any("invalid tip relief")

    @property
    def active(self) -> bool:
        return self.amount > 0

    def removal(self, radius, tip_radius, base_radius: float) -> np.ndarray:
        """Material removed normal to the flank (m) at ``radius`` (m) of a transverse
        section whose tip radius is ``tip_radius`` (m); involute base radius r_b (m).
        The relief must start above the base circle (``r_a - L_a > r_b``)."""
        r = np.asarray(radius, dtype=float)
        if not self.active:
            return np.zeros_like(r)
        ra = np.asarray(tip_radius, dtype=float)
        rs = ra - self.length
        if np.any(rs <= base_radius):
            raise InputError(
                Problem(
                    "length",
                    self.length,
                    f"the relief would start at {float(np.min(rs)) * 1e3:.3f} mm radius, "
                    f"not above the base circle ({base_radius * 1e3:.3f} mm)",
                )
            )
        xs = np.sqrt(rs**2 - base_radius**2)
        xa = np.sqrt(ra**2 - base_radius**2)
        xi = np.sqrt(np.maximum(r**2 - base_radius**2, 0.0))
        return _relief_law(self.amount, (xi - xs) / (xa - xs), self.shape)


@dataclass(frozen=True)
class Topography:
    """A flank topography of one gear, SI: the material removed normal to the flank
    (m) on a grid, ``removal[i][j]`` at roll length ``profile[i]`` and axial position
    ``face[j]``.

    profile: roll lengths along the base tangent from the reference circle (m),
    ``sqrt(r^2 - r_b^2) - sqrt(r_ref^2 - r_b^2)``, strictly increasing (the coordinate
    of a gear checker's profile trace, as ``pitch.*_profile_trace_mm``); face: axial
    positions from the face middle (m), + towards the heel (+z on parallel axes),
    strictly increasing; method: ``"cubic"`` (an interpolating bicubic spline, exact
    for polynomials of degree 3 on each axis; at least 4 points on each axis; it rings
    at a step or kink in the grid, :meth:`overshoot`), ``"pchip"`` (shape-preserving
    piecewise cubic Hermite, Fritsch and Carlson, on each axis: no overshoot, smooth,
    exact for linear data; at least 2 points; evaluated on the grid refined
    :data:`PCHIP_REFINE` times per cell and bilinear between) or ``"linear"``
    (bilinear; at least 2). Beyond the grid the removal is held at its border's
    values. Both flanks (drive and coast) of the gear take the same grid.
    """

    profile: tuple[float, ...]
    face: tuple[float, ...]
    removal: tuple[tuple[float, ...], ...]
    method: str = "cubic"

    def __post_init__(self):
        object.__setattr__(self, "profile", tuple(float(v) for v in self.profile))
        object.__setattr__(self, "face", tuple(float(v) for v in self.face))
        object.__setattr__(
            self, "removal", tuple(tuple(float(v) for v in row) for row in self.removal)
        )
        p = Problems()
        least = TOPOGRAPHY_METHODS.get(self.method)
        if least is None:
            p.add("method", self.method, f"must be one of {', '.join(TOPOGRAPHY_METHODS)}")
            least = 2
        for name in ("profile", "face"):
            x = np.asarray(getattr(self, name))
            if p.check(
                x.size >= least,
                name,
                f"{x.size} points",
                f"needs at least {least} points for {self.method} interpolation",
            ):
                if p.check(bool(np.all(np.isfinite(x))), name, list(x), "must be finite"):
                    p.check(bool(np.all(np.diff(x) > 0)), name, list(x), "must increase strictly")
        shape = (len(self.profile), len(self.face))
        rows = [len(r) for r in self.removal]
        if p.check(
            len(rows) == shape[0],
            "removal",
            f"{len(rows)} rows",
            f"must give one row per profile position: {shape[0]}",
        ):
            wrong = [i for i, n in enumerate(rows) if n != shape[1]]
            if wrong:
                p.add(
                    f"removal[{wrong[0]}]",
                    f"{rows[wrong[0]]} values",
                    f"must give one value per face position: {shape[1]}"
                    + (f" ({len(wrong)} rows are wrong)" if len(wrong) > 1 else ""),
                )
            else:
                p.check(bool(np.all(np.isfinite(self.removal))), "removal", "...", "must be finite")
        p.raise_if_any("invalid flank topography")

    @property
    def active(self) -> bool:
        return any(v != 0 for row in self.removal for v in row)

    @functools.cached_property
    def _spline(self):
        from scipy.interpolate import PchipInterpolator, RectBivariateSpline

        x, y, v = np.asarray(self.profile), np.asarray(self.face), np.asarray(self.removal)
        if self.method == "pchip":  # tensor-product PCHIP on a refined grid, axis by axis
            t = np.arange(PCHIP_REFINE) / PCHIP_REFINE

            def refined(g):
                return np.append((g[:-1, None] + t[None, :] * np.diff(g)[:, None]).ravel(), g[-1])

            xf, yf = refined(x), refined(y)
            v = PchipInterpolator(y, v, axis=1)(yf)
            v = PchipInterpolator(x, v, axis=0)(xf)
            return RectBivariateSpline(xf, yf, v, kx=1, ky=1)
        k = 3 if self.method == "cubic" else 1
        return RectBivariateSpline(x, y, v, kx=k, ky=k)

    def __call__(self, roll, face) -> np.ndarray:
        """Removal (m) at roll lengths ``roll`` from the reference circle (m) and axial
        positions ``face`` (m), broadcast; held beyond the grid."""
        x, y = np.broadcast_arrays(np.asarray(roll, float), np.asarray(face, float))
        x = np.clip(x, self.profile[0], self.profile[-1])
        y = np.clip(y, self.face[0], self.face[-1])
        return self._spline.ev(x.ravel(), y.ravel()).reshape(x.shape)

    def overshoot(self, subdivisions: int = 8) -> float:
        """How far (m) the interpolated removal rings beyond its grid: along every grid
        line (each profile position across the face, each face position up the
        profile), sampled ``subdivisions`` times per cell, the largest excursion beyond
        the cell's two end values in cells where the grid's values run one way (the
        differences before, in and after the cell of one sign; where they turn, a
        smooth grid's extremum lies between the points and is not counted). 0 for
        bilinear interpolation; for the bicubic spline, what a step or a kink in the
        grid (an end relief's start, a burr in a measured flank) makes it overshoot."""
        if self.method == "linear":
            return 0.0
        v = np.asarray(self.removal)
        x, y = np.asarray(self.profile), np.asarray(self.face)
        t = np.arange(1, subdivisions) / subdivisions
        worst = 0.0
        for axis, (grid, other) in enumerate(((y, x), (x, y))):
            lines = v if axis == 0 else v.T  # each row: values along ``grid``
            d = np.diff(lines, axis=1)
            pad = np.pad(d, ((0, 0), (1, 1)), mode="edge")
            one_way = (pad[:, :-2] * pad[:, 1:-1] >= 0) & (pad[:, 1:-1] * pad[:, 2:] >= 0)
            pts = grid[:-1, None] + t[None, :] * np.diff(grid)[:, None]  # (cells, k)
            for n, (line, pos) in enumerate(zip(lines, other, strict=True)):
                k = np.flatnonzero(one_way[n])
                if not k.size:
                    continue
                if axis == 0:
                    fine = self._spline(np.full(pts.size, pos), pts.ravel(), grid=False)
                else:
                    fine = self._spline(pts.ravel(), np.full(pts.size, pos), grid=False)
                fine = fine.reshape(pts.shape)
                lo = np.minimum(line[:-1], line[1:])[:, None]
                hi = np.maximum(line[:-1], line[1:])[:, None]
                out = np.maximum(fine - hi, lo - fine)
                worst = max(worst, float(out[k].max()))
        return max(worst, 0.0)

    def reflected(self) -> Topography:
        """The same grid with the face coordinate turned (w -> -w)."""
        return Topography(
            self.profile,
            tuple(-v for v in reversed(self.face)),
            tuple(tuple(reversed(row)) for row in self.removal),
            self.method,
        )

    def describe(self) -> str:
        r = np.asarray(self.removal) * 1e6
        return (
            f"topography {len(self.profile)} x {len(self.face)} ({self.method}, "
            f"{r.min():.3g} to {r.max():.3g} um)"
        )

    def __getstate__(self):  # the spline is made again where it is needed
        return {k: v for k, v in self.__dict__.items() if k != "_spline"}

    def __setstate__(self, state):
        self.__dict__.update(state)


@dataclass(frozen=True)
class FlankModification:
    """All flank modifications of one gear (SI; module doc for the laws).

    tip_relief, tip_relief_length, tip_relief_shape: C_a (m), L_a (m, radial, down
    from the tip circle), linear / parabolic. root_relief, root_relief_length,
    root_relief_shape: C_f (m), L_f (m, radial, up from the form circle).
    profile_crowning: C_alpha (m). lead_crowning: C_beta (m). end_relief,
    end_relief_length, end_relief_shape: C_e (m) at both face ends, L_e (m, along the
    axis). helix_slope: f_H (m), removal ``f_H w / b`` (either sign). profile_slope:
    f_Halpha (m), removal ``f_Halpha (t - 1/2)`` over the profile range (either sign).
    flank_twist: S (m), removal ``S (t - 1/2) w / b`` (either sign). topography: a
    :class:`Topography` or None.
    """

    tip_relief: float = 0.0
    tip_relief_length: float = 0.0
    tip_relief_shape: str = "linear"
    root_relief: float = 0.0
    root_relief_length: float = 0.0
    root_relief_shape: str = "linear"
    profile_crowning: float = 0.0
    lead_crowning: float = 0.0
    end_relief: float = 0.0
    end_relief_length: float = 0.0
    end_relief_shape: str = "linear"
    helix_slope: float = 0.0
    profile_slope: float = 0.0
    flank_twist: float = 0.0
    topography: Topography | None = None

    def __post_init__(self):
        p = Problems()
        for name in ("tip_relief", "root_relief", "end_relief"):
            p.in_range(name, getattr(self, name), 0.0, None)
            p.in_range(f"{name}_length", getattr(self, f"{name}_length"), 0.0, None)
            shape = getattr(self, f"{name}_shape")
            if shape not in SHAPES:
                p.add(f"{name}_shape", shape, f"must be one of {', '.join(SHAPES)}")
            if getattr(self, name) > 0 and not getattr(self, f"{name}_length") > 0:
                p.add(
                    f"{name}_length",
                    getattr(self, f"{name}_length"),
                    f"must be > 0 when {name} is > 0",
                )
        p.in_range("profile_crowning", self.profile_crowning, 0.0, None)
        p.in_range("lead_crowning", self.lead_crowning, 0.0, None)
        for name in ("helix_slope", "profile_slope", "flank_twist"):
            p.check(np.isfinite(getattr(self, name)), name, getattr(self, name), "must be finite")
        p.check(
            self.topography is None or isinstance(self.topography, Topography),
            "topography",
            type(self.topography).__name__,
            "must be a Topography or None",
        )
        p.raise_if_any("invalid flank modification")

    @property
    def tip(self) -> TipRelief:
        return TipRelief(self.tip_relief, self.tip_relief_length, self.tip_relief_shape)

    @property
    def active(self) -> bool:
        return (
            any(
                v != 0
                for v in (
                    self.tip_relief,
                    self.root_relief,
                    self.profile_crowning,
                    self.lead_crowning,
                    self.end_relief,
                    self.helix_slope,
                    self.profile_slope,
                    self.flank_twist,
                )
            )
            or self.topography_active
        )

    def describe(self) -> str:
        """The terms that are set, in um and mm (``"none"`` without any)."""
        parts = []
        for name in ("tip_relief", "root_relief", "end_relief"):
            amount = getattr(self, name)
            if amount > 0:
                length = getattr(self, f"{name}_length") * 1e3
                shape = getattr(self, f"{name}_shape")
                parts.append(
                    f"{name.replace('_', ' ')} {amount * 1e6:g} um over {length:g} mm ({shape})"
                )
        for name in (
            "profile_crowning",
            "lead_crowning",
            "helix_slope",
            "profile_slope",
            "flank_twist",
        ):
            amount = getattr(self, name)
            if amount != 0:
                parts.append(f"{name.replace('_', ' ')} {amount * 1e6:g} um")
        if self.topography_active:
            parts.append(self.topography.describe())
        return ", ".join(parts) or "none"

    @property
    def profile_active(self) -> bool:
        """Whether any term needs the form radius (root relief, profile crowning,
        profile slope, flank twist)."""
        return (
            self.root_relief > 0
            or self.profile_crowning > 0
            or self.profile_slope != 0
            or self.flank_twist != 0
        )

    def reflected(self) -> FlankModification:
        """The modification with the face coordinate turned (w -> -w): what the
        mirror image in the transverse plane, or the half turn about the centre line
        that makes a parallel pair's coast flank of its drive flank, sees. The helix
        slope and the flank twist change sign, a topography turns end for end; the
        other terms are even in w."""
        topo = self.topography
        return dataclasses.replace(
            self,
            helix_slope=-self.helix_slope,
            flank_twist=-self.flank_twist,
            topography=None if topo is None else topo.reflected(),
        )

    @property
    def face_symmetric(self) -> bool:
        """Whether the removal is even in w (:meth:`reflected` gives it back)."""
        return self == self.reflected()

    @property
    def topography_active(self) -> bool:
        """Whether the topography term is set (it needs the reference radius)."""
        return self.topography is not None and self.topography.active

    def removal(
        self,
        radius,
        face,
        *,
        tip_radius,
        base_radius: float,
        face_width: float,
        form_radius=None,
        reference_radius: float | None = None,
    ) -> np.ndarray:
        """Material removed normal to the flank (m) at transverse ``radius`` (m) and
        axial distance ``face`` from the face middle (m); ``tip_radius`` and
        ``form_radius`` (m) of the section there (arrays broadcast with ``radius``);
        ``form_radius`` is needed only for the profile terms (:attr:`profile_active`),
        ``reference_radius`` (m, the reference circle's) only for a topography. Points
        beyond the flank (its continuation) get the laws continued (a topography held
        at its border)."""
        r = np.asarray(radius, dtype=float)
        w = np.asarray(face, dtype=float)
        out = np.zeros(np.broadcast(r, w).shape)
        if not self.active:
            return out
        rb = float(base_radius)
        xi = np.sqrt(np.maximum(r**2 - rb**2, 0.0))  # roll length
        if self.tip_relief > 0:
            out = out + self.tip.removal(r, tip_radius, rb)
        if self.profile_active:
            if form_radius is None:
                raise ValueError("form_radius is needed for the profile terms")
            rF = np.maximum(np.asarray(form_radius, dtype=float), rb)
            ra = np.asarray(tip_radius, dtype=float)
            xF = np.sqrt(rF**2 - rb**2)
            xa = np.sqrt(ra**2 - rb**2)
            if self.root_relief > 0:
                rs = rF + self.root_relief_length
                if np.any(rs >= ra):
                    raise InputError(
                        Problem(
                            "root_relief_length",
                            self.root_relief_length,
                            "the root relief would reach the tip circle "
                            f"({float(np.min(ra - rF)) * 1e3:.3f} mm above the form circle)",
                        )
                    )
                xs = np.sqrt(rs**2 - rb**2)
                out = out + _relief_law(
                    self.root_relief, (xs - xi) / (xs - xF), self.root_relief_shape
                )
            if self.profile_crowning > 0:
                mid, half = 0.5 * (xa + xF), 0.5 * (xa - xF)
                out = out + self.profile_crowning * ((xi - mid) / half) ** 2
            if self.profile_slope != 0 or self.flank_twist != 0:
                t = (xi - xF) / (xa - xF) - 0.5
                slope = self.profile_slope + self.flank_twist * w / float(face_width)
                out = out + slope * t
        b = float(face_width)
        if self.lead_crowning > 0:
            out = out + self.lead_crowning * (2.0 * w / b) ** 2
        if self.end_relief > 0:
            start = 0.5 * b - self.end_relief_length
            t = (np.abs(w) - start) / self.end_relief_length
            out = out + _relief_law(self.end_relief, t, self.end_relief_shape)
        if self.helix_slope != 0:
            out = out + self.helix_slope * w / b
        if self.topography_active:
            if reference_radius is None:
                raise ValueError("reference_radius is needed for a topography")
            xr = math.sqrt(max(float(reference_radius) ** 2 - rb**2, 0.0))
            out = out + self.topography(xi - xr, w)
        return out


def topography_from_section(section, name: str, probs: Problems) -> Topography | None:
    """The topography of gear ``name`` (``pinion`` / ``gear``) of a scene's ``[ltca]``
    section (mm, um -> m), None where it sets none; each problem is added to ``probs``
    under its scene key: positions without values or the other way round, too few
    positions for the interpolation, a row count or row length that does not match."""
    keys = {
        "profile": f"{name}_topography_profile_mm",
        "face": f"{name}_topography_face_mm",
        "removal": f"{name}_topography_um",
    }
    x, y, rows = (section.get(keys[k], []) for k in ("profile", "face", "removal"))
    if not (x or y or rows):
        return None
    method = section.get("topography_interpolation", "cubic")
    for k, v in (("profile", x), ("face", y), ("removal", rows)):
        if not v:
            probs.add(f"ltca.{keys[k]}", v, "must be given with the other topography keys")
    if not (x and y and rows):
        return None
    try:
        return Topography(
            tuple(v * 1e-3 for v in x),
            tuple(v * 1e-3 for v in y),
            tuple(tuple(v * 1e-6 for v in row) for row in rows),
            method,
        )
    except InputError as err:
        for prob in err.problems:
            head, _, index = prob.path.partition("[")
            path = f"ltca.{keys[head]}" + (f"[{index}" if index else "")
            text = prob.expected
            if head in ("profile", "face") and "points" in text:
                text += " (ltca.topography_interpolation = " + repr(method) + ")"
            shown = prob.value
            if head in ("profile", "face") and isinstance(shown, list):
                shown = [round(v * 1e3, 9) for v in shown]
            probs.add(path, shown, text)
        return None


def removal_map(
    mod: FlankModification,
    face,
    *,
    form_radius,
    tip_radius,
    base_radius: float,
    reference_radius: float,
    face_width: float,
    n_profile: int = 25,
) -> dict[str, np.ndarray]:
    """The removal of ``mod`` over one flank, for a map of the modifications: at the
    axial positions ``face`` (m from the face middle, shape (F,)), ``n_profile`` places
    from the form circle to the tip circle of each section (``form_radius``,
    ``tip_radius``: scalars or shape (F,), m). Returns ``face_m`` (F,), ``roll_m`` (F,
    n_profile) the roll length from the reference circle and ``removal_m`` (F,
    n_profile)."""
    w = np.asarray(face, dtype=float)
    rb = float(base_radius)
    rF = np.broadcast_to(np.maximum(np.asarray(form_radius, float), rb), w.shape)[:, None]
    ra = np.broadcast_to(np.asarray(tip_radius, float), w.shape)[:, None]
    t = np.linspace(0.0, 1.0, n_profile)[None, :]
    xF, xa = np.sqrt(rF**2 - rb**2), np.sqrt(ra**2 - rb**2)
    xi = xF + t * (xa - xF)
    r = np.sqrt(rb**2 + xi**2)
    W = np.broadcast_to(w[:, None], r.shape)
    removal = mod.removal(
        r,
        W,
        tip_radius=np.broadcast_to(ra, r.shape),
        base_radius=rb,
        face_width=face_width,
        form_radius=np.broadcast_to(rF, r.shape),
        reference_radius=reference_radius,
    )
    xr = math.sqrt(max(float(reference_radius) ** 2 - rb**2, 0.0))
    return {"face_m": w, "roll_m": xi - xr, "removal_m": removal}


#: a bicubic topography's overshoot (m) that earns a note (about what a gear checker
#: resolves)
OVERSHOOT_NOTE = 0.1e-6


def topography_notes(relief) -> tuple[str, ...]:
    """A note per gear whose bicubic topography overshoots its grid cells by more than
    :data:`OVERSHOOT_NOTE` (:meth:`Topography.overshoot`), for ``LTCAResult.notes``."""
    notes = []
    for name, rel in zip(("pinion", "gear"), relief or (None, None), strict=True):
        topo = as_modification(rel).topography
        if topo is None or not topo.active:
            continue
        over = topo.overshoot()
        if over > OVERSHOOT_NOTE:
            notes.append(
                f"{name}'s topography: the bicubic spline leaves the range of its grid "
                f"cells' values by up to {over * 1e6:.2g} um between the points (a step or "
                "kink in the grid); ltca.topography_interpolation = 'pchip' (smooth) or "
                "'linear' follows the grid without overshoot, or add points where it bends"
            )
    return tuple(notes)


def as_modification(x) -> FlankModification:
    """A :class:`FlankModification` from one, from a :class:`TipRelief`, or from None."""
    if x is None:
        return FlankModification()
    if isinstance(x, FlankModification):
        return x
    if isinstance(x, TipRelief):
        return FlankModification(
            tip_relief=x.amount, tip_relief_length=x.length, tip_relief_shape=x.shape
        )
    raise TypeError(f"expected a FlankModification or TipRelief, got {type(x).__name__}")


def describe_pair(mods) -> str:
    """``"pinion: ...; gear: ..."`` for (pinion, gear) modifications (None: none)."""
    mods = (None, None) if mods is None else mods
    p, g = (as_modification(m) for m in mods)
    return f"pinion: {p.describe()}; gear: {g.describe()}"

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
  correction for a known misalignment.

A gear's removal is the sum of its terms; the separation of a contact point is the
sum of both gears' removals there (:meth:`FlankModification.removal`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import InputError, Problem, Problems

__all__ = ["SHAPES", "FlankModification", "TipRelief", "as_modification", "describe_pair"]

#: exponent of the relief laws in the relief coordinate t (0 at the start, 1 at the end)
SHAPES = {"linear": 1, "parabolic": 2}


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
class FlankModification:
    """All flank modifications of one gear (SI; module doc for the laws).

    tip_relief, tip_relief_length, tip_relief_shape: C_a (m), L_a (m, radial, down
    from the tip circle), linear / parabolic. root_relief, root_relief_length,
    root_relief_shape: C_f (m), L_f (m, radial, up from the form circle).
    profile_crowning: C_alpha (m). lead_crowning: C_beta (m). end_relief,
    end_relief_length, end_relief_shape: C_e (m) at both face ends, L_e (m, along the
    axis). helix_slope: f_H (m), removal ``f_H w / b`` (either sign).
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
        p.check(np.isfinite(self.helix_slope), "helix_slope", self.helix_slope, "must be finite")
        p.raise_if_any("invalid flank modification")

    @property
    def tip(self) -> TipRelief:
        return TipRelief(self.tip_relief, self.tip_relief_length, self.tip_relief_shape)

    @property
    def active(self) -> bool:
        return any(
            v != 0
            for v in (
                self.tip_relief,
                self.root_relief,
                self.profile_crowning,
                self.lead_crowning,
                self.end_relief,
                self.helix_slope,
            )
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
        for name in ("profile_crowning", "lead_crowning", "helix_slope"):
            amount = getattr(self, name)
            if amount != 0:
                parts.append(f"{name.replace('_', ' ')} {amount * 1e6:g} um")
        return ", ".join(parts) or "none"

    @property
    def profile_active(self) -> bool:
        """Whether any term needs the form radius (root relief, profile crowning)."""
        return self.root_relief > 0 or self.profile_crowning > 0

    def removal(
        self,
        radius,
        face,
        *,
        tip_radius,
        base_radius: float,
        face_width: float,
        form_radius=None,
    ) -> np.ndarray:
        """Material removed normal to the flank (m) at transverse ``radius`` (m) and
        axial distance ``face`` from the face middle (m); ``tip_radius`` and
        ``form_radius`` (m) of the section there (arrays broadcast with ``radius``);
        ``form_radius`` is needed only for root relief and profile crowning. Points
        beyond the flank (its continuation) get the laws continued."""
        r = np.asarray(radius, dtype=float)
        w = np.asarray(face, dtype=float)
        out = np.zeros(np.broadcast(r, w).shape)
        if not self.active:
            return out
        rb = float(base_radius)
        if self.tip_relief > 0:
            out = out + self.tip.removal(r, tip_radius, rb)
        if self.profile_active:
            if form_radius is None:
                raise ValueError("form_radius is needed for root relief and profile crowning")
            rF = np.maximum(np.asarray(form_radius, dtype=float), rb)
            ra = np.asarray(tip_radius, dtype=float)
            xi = np.sqrt(np.maximum(r**2 - rb**2, 0.0))
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
        b = float(face_width)
        if self.lead_crowning > 0:
            out = out + self.lead_crowning * (2.0 * w / b) ** 2
        if self.end_relief > 0:
            start = 0.5 * b - self.end_relief_length
            t = (np.abs(w) - start) / self.end_relief_length
            out = out + _relief_law(self.end_relief, t, self.end_relief_shape)
        if self.helix_slope != 0:
            out = out + self.helix_slope * w / b
        return out


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

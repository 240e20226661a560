"""The contact grid: what the loaded TCA needs to know about the flanks at one position.

A :class:`ContactGrid` is the boundary between the geometry (surfaces and unloaded
TCA, or the analytic involute of :mod:`gearbox.ltca.parallel`) and the mechanics
(compliance and contact solver). It lists, for one pinion position, points on the
potential contact lines of every tooth pair that may touch: one point per face
slice (``slot``) and tooth pair, with its initial separation along the common normal
and what the compliance models need of the two teeth there.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np

from ..errors import Problems

__all__ = ["ContactGrid", "ToothSections"]


def _frozen_array(x, n, name, probs, dtype=float):
    a = np.array(x, dtype=dtype)
    if a.ndim == 0:
        a = np.full(n, a.item(), dtype=dtype)
    if a.shape[0] != n:
        probs.add(name, f"shape {a.shape}", f"must have {n} rows (one per grid point)")
    a.setflags(write=False)
    return a


@dataclass(frozen=True)
class ToothSections:
    """Transverse tooth sections of one gear at the grid points (SI).

    All arrays shape (n,): radius of the load point, base radius, root radius, tip
    radius, bore (rim inner) radius, half tooth-thickness angle at the base circle
    psi_b (rad; the involute half-angle at radius r is psi_b - inv(alpha_r)), and
    the number of teeth (the section of a beveloid tooth changes along the face, so
    every point carries its own). For the root stress (ISO 6336-3 method B geometry
    of the normal section): normal module (m), normal pressure angle and reference
    helix angle (rad), local normal profile-shift coefficient, basic-rack dedendum
    h_fP/m_n and root radius rho_fP/m_n.
    """

    radius: np.ndarray
    base_radius: np.ndarray
    root_radius: np.ndarray
    tip_radius: np.ndarray
    bore_radius: np.ndarray
    base_half_angle: np.ndarray
    teeth: np.ndarray
    normal_module: np.ndarray
    normal_pressure_angle: np.ndarray
    helix_angle: np.ndarray
    profile_shift: np.ndarray
    rack_dedendum: np.ndarray
    rack_root_radius: np.ndarray

    @classmethod
    def uniform(cls, n: int, **kw) -> ToothSections:
        """Sections with scalars broadcast to n points."""
        probs = Problems()
        out = {k: _frozen_array(v, n, k, probs) for k, v in kw.items()}
        probs.raise_if_any("invalid tooth sections")
        return cls(**out)

    def take(self, idx) -> ToothSections:
        return ToothSections(**{f.name: getattr(self, f.name)[idx] for f in fields(self)})

    def validate(self, n: int, name: str, probs: Problems) -> None:
        for f in fields(self):
            a = getattr(self, f.name)
            if a.shape != (n,):
                probs.add(f"{name}.{f.name}", f"shape {a.shape}", f"must have shape ({n},)")
        if probs.items:
            return
        bad = ~(self.radius > self.base_radius)
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            probs.add(
                f"{name}.radius[{i}]",
                float(self.radius[i]),
                "load point must lie on the involute, above the base radius "
                f"{self.base_radius[i]:g} m",
            )
        bad = ~(self.radius <= self.tip_radius * (1 + 1e-9))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            probs.add(
                f"{name}.radius[{i}]",
                float(self.radius[i]),
                f"load point leaves the flank: above the tip radius {self.tip_radius[i]:g} m",
            )
        bad = ~((self.bore_radius > 0) & (self.bore_radius < self.root_radius))
        if bad.any():
            i = int(np.flatnonzero(bad)[0])
            probs.add(
                f"{name}.bore_radius[{i}]",
                float(self.bore_radius[i]),
                "must be in (0, root radius)",
            )


@dataclass(frozen=True)
class ContactGrid:
    """Points on the potential contact lines at one pinion position (SI).

    Arrays, shape (n,) unless stated:

    - ``pair`` tooth-pair index (0 = reference pair), ``slot`` face-slice index in
      ``0 .. n_slots-1`` (points of one tooth pair with adjacent slots are adjacent
      slices of the same teeth);
    - ``face`` face coordinate (m, from the face middle, + towards the heel),
      ``width`` slice width along the face (m), ``line_length`` contact-line length
      in the slice (m);
    - ``separation`` initial separation of the flanks along the common normal (m),
      ``arm`` normal approach per radian of pinion rotation (m/rad) = pinion torque
      per newton of normal load (N m/N), ``transverse_projection`` cosine between the
      normal and the transverse plane (cos beta_b for involute helicoids);
    - ``curvature_radius`` relative radius of curvature across the contact line in
      the normal section (m), for the Hertz/Weber flattening;
    - ``profile`` profile coordinate of the point on its pinion tooth (m), with
      ``profile_range`` and ``face_range`` the active flank, for the contact pattern;
    - ``edge`` True where the point lies on the border of the active flank in the
      profile direction (tip or root edge) or the grid cannot see the true minimum
      of the separation;
    - ``position``, ``normal`` shape (n, 3): point and unit normal (force of the pinion
      on the gear) in Sf, for the mesh point P and line of action n;
    - ``tooth1``, ``tooth2``: :class:`ToothSections` of pinion and gear;
    - ``width2``, ``transverse_projection2`` (optional): the same two for the gear,
      where its axis is not parallel to the pinion's (crossed axes): the slice width
      along the gear's axis and the cosine between the normal and the gear's
      transverse plane. ``None`` (parallel axes): the pinion's values.
    """

    pair: np.ndarray
    slot: np.ndarray
    face: np.ndarray
    width: np.ndarray
    line_length: np.ndarray
    separation: np.ndarray
    arm: np.ndarray
    transverse_projection: np.ndarray
    curvature_radius: np.ndarray
    profile: np.ndarray
    profile_range: tuple[float, float]
    face_range: tuple[float, float]
    n_slots: int
    edge: np.ndarray
    position: np.ndarray
    normal: np.ndarray
    tooth1: ToothSections
    tooth2: ToothSections
    youngs_modulus: float
    poisson_ratio: float
    width2: np.ndarray | None = None
    transverse_projection2: np.ndarray | None = None

    def __post_init__(self):
        probs = Problems()
        n = int(np.asarray(self.separation).shape[0]) if np.ndim(self.separation) else 0
        if n == 0:
            probs.add(
                "grid",
                "0 points",
                "the contact grid is empty: no tooth pair reaches the active flank",
            )
            probs.raise_if_any("invalid contact grid")
        for name, dtype in (
            ("pair", int),
            ("slot", int),
            ("face", float),
            ("width", float),
            ("line_length", float),
            ("separation", float),
            ("arm", float),
            ("transverse_projection", float),
            ("curvature_radius", float),
            ("profile", float),
            ("edge", bool),
        ):
            object.__setattr__(
                self, name, _frozen_array(getattr(self, name), n, name, probs, dtype)
            )
        for name in ("position", "normal"):
            a = np.array(getattr(self, name), dtype=float)
            if a.shape != (n, 3):
                probs.add(name, f"shape {a.shape}", f"must have shape ({n}, 3)")
            a.setflags(write=False)
            object.__setattr__(self, name, a)
        for name in ("width2", "transverse_projection2"):
            v = getattr(self, name)
            if v is None:
                v = getattr(self, name[:-1])
            object.__setattr__(self, name, _frozen_array(v, n, name, probs, float))
        probs.raise_if_any("invalid contact grid")
        for name in (
            "width",
            "line_length",
            "arm",
            "curvature_radius",
            "transverse_projection",
            "width2",
            "transverse_projection2",
        ):
            a = getattr(self, name)
            if not np.all(np.isfinite(a) & (a > 0)):
                i = int(np.flatnonzero(~(np.isfinite(a) & (a > 0)))[0])
                probs.add(f"{name}[{i}]", float(a[i]), "must be finite and > 0")
        if not np.all(np.isfinite(self.separation)):
            probs.add("separation", "non-finite", "must be finite")
        if np.any((self.slot < 0) | (self.slot >= self.n_slots)):
            probs.add("slot", "out of range", f"must be in [0, {self.n_slots - 1}]")
        key = self.pair.astype(np.int64) * (self.n_slots + 1) + self.slot
        if np.unique(key).size != n:
            probs.add("slot", "duplicates", "each (pair, slot) must appear once")
        self.tooth1.validate(n, "tooth1", probs)
        self.tooth2.validate(n, "tooth2", probs)
        probs.raise_if_any("invalid contact grid")

    @property
    def size(self) -> int:
        return int(self.separation.shape[0])

    def pairs(self) -> np.ndarray:
        """Tooth-pair indices present, sorted."""
        return np.unique(self.pair)

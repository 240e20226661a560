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
from ..meshtable import FORM_BASES

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
      transverse plane. ``None`` (parallel axes): the pinion's values;
    - ``pinion_axis``, ``gear_axis`` (optional) shape (2, 3): each gear's axis in the
      frame of ``position`` (unit direction, then a point on it), for the flanks'
      sliding (:meth:`sliding_velocity`). ``None``: the grid carries no kinematics.
    - ``flank_coordinates`` (optional) shape (n, 4): where each point lies on the two
      flanks, for deviations of their form (docs/ltca.md "Form deviations"): the
      pinion's roll length from its reference circle (``sqrt(r^2 - r_b^2)`` less its
      value at the reference pitch radius, m, + towards the tip) and its axial
      position from its face middle (m, + towards the heel, or +z on parallel
      axes), then the gear's two in its own frame. ``None``: the grid has none.

    ``pair_sense`` (+1 or -1): the labels ``pair`` count the teeth ahead in each gear's
    sense of rotation (+1, as the grids are built) or behind it (-1: a parallel pair's
    drive grid relabelled as its coast flank's, whose time runs the other way,
    :func:`gearbox.ltca.table.coast_grids`). A compliance that places pairs on teeth
    reads it; one that takes the neighbours' side from the radii does not need it.
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
    pinion_axis: np.ndarray | None = None
    gear_axis: np.ndarray | None = None
    flank_coordinates: np.ndarray | None = None
    pair_sense: int = 1

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
        self._check_axes(probs)
        if self.flank_coordinates is not None:
            a = np.array(self.flank_coordinates, dtype=float)
            if a.shape != (n, 4) or not np.all(np.isfinite(a)):
                probs.add(
                    "flank_coordinates", f"shape {a.shape}", f"must be finite, shape ({n}, 4)"
                )
            a.setflags(write=False)
            object.__setattr__(self, "flank_coordinates", a)
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

    def _check_axes(self, probs: Problems) -> None:
        given = [self.pinion_axis is not None, self.gear_axis is not None]
        if any(given) and not all(given):
            probs.add(
                "pinion_axis" if given[1] else "gear_axis",
                None,
                "both axes are needed for the sliding (or neither)",
            )
            return
        if not any(given):
            return
        for name in ("pinion_axis", "gear_axis"):
            a = np.array(getattr(self, name), dtype=float)
            if a.shape != (2, 3) or not np.all(np.isfinite(a)):
                probs.add(
                    name, f"shape {a.shape}", "must be finite, shape (2, 3): direction, point"
                )
                continue
            norm = float(np.linalg.norm(a[0]))
            if norm == 0.0:
                probs.add(f"{name}[0]", a[0].tolist(), "the axis direction must not be zero")
                continue
            a[0] /= norm
            a.setflags(write=False)
            object.__setattr__(self, name, a)

    def sliding_velocity(self) -> np.ndarray | None:
        """Sliding velocity of the pinion's flank over the gear's at each point per unit
        pinion angular speed, shape (n, 3), m/s per rad/s; ``None`` where the grid has
        no axes.

        Both flanks turn as rigid bodies about their axes, the gear at ``z1 / z2`` of
        the pinion's speed in the sense that keeps them in contact (the flanks' normal
        velocities equal: for conjugate flanks the relative velocity lies in the
        tangent plane). The relative velocity's part in the tangent plane is returned;
        its normal part, the flanks' approach rate, is what the unloaded TE's slope
        leaves (zero for conjugate flanks; :meth:`approach_rate`).
        """
        v = self._relative_velocity()
        if v is None:
            return None
        return v - np.sum(v * self.normal, axis=1, keepdims=True) * self.normal

    def approach_rate(self) -> np.ndarray | None:
        """Normal part of the flanks' relative velocity per unit pinion angular speed
        over the pinion's normal velocity there, shape (n,): zero for conjugate flanks
        at the gear's speed ``z1 / z2``; ``None`` where the grid has no axes."""
        v = self._relative_velocity()
        if v is None:
            return None
        a1, o1 = self.pinion_axis
        v1n = np.sum(np.cross(a1, self.position - o1) * self.normal, axis=1)
        return np.sum(v * self.normal, axis=1) / np.abs(v1n)

    def friction_arms(self) -> np.ndarray | None:
        """Moment arms of the sliding friction at each point, shape (n, 2), m: about
        the pinion's axis and the gear's, each in its sense of rotation, of a unit
        force along the pinion flank's sliding direction over the gear flank (the unit
        :meth:`sliding_velocity`; zero where the flanks roll without sliding).

        Friction mu F_i on the pinion opposes that sliding, so it puts the torque
        -mu F_i arm_1 on the pinion and +mu F_i arm_2 on the gear. Per point
        arm_1 - (z1 / z2) arm_2 = |v_s| per unit pinion speed: the torques' power is
        the friction's loss. ``None`` where the grid has no axes.
        """
        kin = self._kinematics()
        if kin is None:
            return None
        v, (a1, o1), (a2, o2) = kin
        vs = v - np.sum(v * self.normal, axis=1, keepdims=True) * self.normal
        speed = np.linalg.norm(vs, axis=1, keepdims=True)
        u = np.divide(vs, speed, out=np.zeros_like(vs), where=speed > 0)
        arm1 = np.sum(np.cross(self.position - o1, u) * a1, axis=1)
        arm2 = np.sum(np.cross(self.position - o2, u) * a2, axis=1)
        return np.stack([arm1, arm2], axis=1)

    #: The form deviations' offset shapes (:meth:`form_bases`), in their order.
    FORM_BASES = FORM_BASES

    def form_bases(self) -> np.ndarray | None:
        """Normal offsets of the flanks per unit form coefficient, shape (n, 8), in the
        order of :attr:`FORM_BASES`. The first four are the slopes (m per m/m): a
        profile slope f_H_alpha over an evaluation length L_alpha puts f_H_alpha /
        L_alpha times the roll length from the reference circle on the flank, a helix
        slope f_H_beta over L_beta puts f_H_beta / L_beta times the axial position from
        the face middle. The last four are the same coordinates squared (m per 1/m), the
        quadratic part of a crowning (:class:`~gearbox.ltca.pitch.FormDeviations`).
        All are measured in the transverse plane along the base tangent (as a gear
        checker measures them), so normal to the flank times the cosine to the
        transverse plane (cos beta_b on involute helicoids). Plus material closes the
        gap: a point's separation changes by ``-bases @ coefficients``. ``None``
        without ``flank_coordinates``."""
        if self.flank_coordinates is None:
            return None
        c = self.flank_coordinates
        t1, t2 = self.transverse_projection, self.transverse_projection2
        t = np.column_stack([t1, t1, t2, t2])
        return np.column_stack([t * c, t * c * c])

    def _relative_velocity(self):
        kin = self._kinematics()
        return None if kin is None else kin[0]

    def _kinematics(self):
        """The flanks' relative velocity per unit pinion speed (n, 3) and both axes,
        the gear's turned to its sense of rotation; None without axes."""
        if self.pinion_axis is None:
            return None
        (a1, o1), (a2, o2) = self.pinion_axis, self.gear_axis
        v1 = np.cross(a1, self.position - o1)
        v2 = np.cross(a2, self.position - o2)
        ratio = self.tooth1.teeth / self.tooth2.teeth
        # the sense of the gear's rotation: the one whose normal velocity follows the
        # pinion's (one sign for the whole grid, from all its points)
        sense = np.sign(np.sum(np.sum(v1 * self.normal, 1) * np.sum(v2 * self.normal, 1)))
        return v1 - np.reshape(sense * ratio, (-1, 1)) * v2, (a1, o1), (sense * a2, o2)

    #: The fields with one entry per point (arrays of length n, or ToothSections);
    #: the others (ranges, slots, material, axes) belong to the whole grid.
    PER_POINT = (
        "pair",
        "slot",
        "face",
        "width",
        "line_length",
        "separation",
        "arm",
        "transverse_projection",
        "curvature_radius",
        "profile",
        "edge",
        "position",
        "normal",
        "tooth1",
        "tooth2",
        "width2",
        "transverse_projection2",
        "flank_coordinates",
    )

    def fields_at(self, idx) -> dict:
        """Every field's value at the points ``idx`` (per-point fields indexed, the
        rest as they are), for a new grid: ``ContactGrid(**grid.fields_at(idx))``."""
        idx = np.asarray(idx)
        out = {}
        for f in fields(self):
            v = getattr(self, f.name)
            if f.name in self.PER_POINT and v is not None:
                v = v.take(idx) if isinstance(v, ToothSections) else v[idx]
            out[f.name] = v
        return out

    def take(self, idx) -> ContactGrid:
        """The grid of the points ``idx`` only."""
        return ContactGrid(**self.fields_at(idx))

    @property
    def size(self) -> int:
        return int(self.separation.shape[0])

    def pairs(self) -> np.ndarray:
        """Tooth-pair indices present, sorted."""
        return np.unique(self.pair)

"""Assembly of pinion and gear on crossed axes in the fixed frame Sf (paper Fig. 11).

Fixed frame Sf (the same as :mod:`gearbox.geometry.design`):

- origin O_f at the foot of the common perpendicular of the two axes on the pinion
  axis;
- z_f along the pinion axis, towards the pinion's heel;
- x_f along the common perpendicular, from the pinion axis towards the gear axis;
- y_f = z_f x x_f.

The gear axis passes through (E, 0, 0) with direction a_2 = (0, sin delta, cos delta),
pointing to the gear's heel (both heels on the same side, as paper eq. (18) requires).

Pinion frame S1: origin (its reference section, z_1 = 0) at (0, 0, h_1) on the pinion
axis; at pinion angle phi_1 = 0 its y_1 axis (through the middle of tooth 0) points
along +x_f, towards the gear: x_1 = -y_f, y_1 = x_f, z_1 = z_f. The pinion turns by
phi_1 about +z_f.

Gear frame S2: origin at (E, 0, 0) + h_2 a_2; at phi_2 = 0 its y_2 axis points along
-x_f, towards the pinion: y_2 = -x_f, z_2 = a_2, x_2 = y_2 x z_2 = (0, cos delta,
-sin delta). The gear turns by phi_2 about a_2; in mesh phi_2 = -(N_1/N_2) phi_1 + const.

h_1 and h_2 are the axial positions of the design's pitch point P on each axis
(:attr:`gearbox.geometry.GearDesign.pitch_point_axial`), so that each gear's reference
section, where its working pitch radius r_w applies, passes through P. Assembly errors
add to E, delta, h_1 and h_2.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import Problems

__all__ = ["Assembly", "AssemblyErrors", "rotation"]


@dataclass(frozen=True)
class AssemblyErrors:
    """Assembly errors (SI): offset (m), shaft angle (rad), axial shifts (m) of the
    pinion along z_f and of the gear along a_2 (towards each gear's heel)."""

    offset: float = 0.0
    shaft_angle: float = 0.0
    pinion_axial: float = 0.0
    gear_axial: float = 0.0

    def __post_init__(self):
        from ..errors import Problems, is_real

        p = Problems()
        for name, unit in (
            ("offset", "m"),
            ("shaft_angle", "rad"),
            ("pinion_axial", "m"),
            ("gear_axial", "m"),
        ):
            v = getattr(self, name)
            ok = is_real(v) and math.isfinite(v)
            p.check(ok, f"AssemblyErrors.{name}", v, f"must be a finite number ({unit})")
        p.raise_if_any("invalid assembly errors")

    @classmethod
    def from_scene(cls, scene) -> AssemblyErrors:
        a = scene["assembly"]
        return cls(
            offset=a["offset_error_mm"] * 1e-3,
            shaft_angle=math.radians(a["shaft_angle_error_deg"]),
            pinion_axial=a["pinion_axial_error_mm"] * 1e-3,
            gear_axial=a["gear_axial_error_mm"] * 1e-3,
        )


@dataclass(frozen=True)
class Assembly:
    """Positions of both gears in Sf (SI, see the module docstring).

    Attributes:
        offset: offset E of the assembled axes (m).
        shaft_angle: shaft angle delta of the assembled axes (rad).
        pinion_axial: h_1, position of the pinion's reference section on z_f (m).
        gear_axial: h_2, position of the gear's reference section along a_2 from
            (E, 0, 0) (m).
        errors: the :class:`AssemblyErrors` already included in the values above.
    """

    offset: float
    shaft_angle: float
    pinion_axial: float
    gear_axial: float
    errors: AssemblyErrors = AssemblyErrors()

    @classmethod
    def from_design(cls, design, errors: AssemblyErrors | None = None) -> Assembly:
        """The designed assembly (paper eqs (16)-(19)) plus optional errors."""
        e = errors or AssemblyErrors()
        p = Problems()
        p.in_range(
            "assembly.offset_error_mm",
            e.offset * 1e3,
            -0.5 * design.offset * 1e3,
            0.5 * design.offset * 1e3,
        )
        p.in_range(
            "assembly.shaft_angle_error_deg",
            math.degrees(e.shaft_angle),
            -math.degrees(design.shaft_angle),
            90 - math.degrees(design.shaft_angle),
            hi_open=True,
        )
        p.raise_if_any("invalid assembly errors")
        return cls(
            offset=design.offset + e.offset,
            shaft_angle=design.shaft_angle + e.shaft_angle,
            pinion_axial=design.pinion.pitch_point_axial + e.pinion_axial,
            gear_axial=design.gear.pitch_point_axial + e.gear_axial,
            errors=e,
        )

    @property
    def gear_axis(self) -> np.ndarray:
        """a_2, unit direction of the gear axis (towards its heel), shape (3,)."""
        return np.array([0.0, math.sin(self.shaft_angle), math.cos(self.shaft_angle)])

    @property
    def pinion_origin(self) -> np.ndarray:
        return np.array([0.0, 0.0, self.pinion_axial])

    @property
    def gear_origin(self) -> np.ndarray:
        return np.array([self.offset, 0.0, 0.0]) + self.gear_axial * self.gear_axis

    def pinion_matrix(self, phi1) -> np.ndarray:
        """Rotation S1 -> Sf at pinion angle phi_1 (rad), shape phi1.shape + (3, 3)."""
        B1 = np.array([[0.0, 1.0, 0.0], [-1.0, 0.0, 0.0], [0.0, 0.0, 1.0]])  # columns x1, y1, z1
        return rotation(np.array([0.0, 0.0, 1.0]), phi1) @ B1

    def gear_matrix(self, phi2) -> np.ndarray:
        """Rotation S2 -> Sf at gear angle phi_2 (rad), shape phi2.shape + (3, 3)."""
        d = self.shaft_angle
        B2 = np.array(
            [[0.0, -1.0, 0.0], [math.cos(d), 0.0, math.sin(d)], [-math.sin(d), 0.0, math.cos(d)]]
        )
        return rotation(self.gear_axis, phi2) @ B2

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> Assembly:
        d = dict(d)
        d["errors"] = AssemblyErrors(**d.get("errors", {}))
        return cls(**d)


def rotation(axis: np.ndarray, angle) -> np.ndarray:
    """Rodrigues rotation matrices about a unit axis, shape angle.shape + (3, 3)."""
    angle = np.asarray(angle, dtype=float)
    k = np.asarray(axis, dtype=float)
    K = np.array([[0.0, -k[2], k[1]], [k[2], 0.0, -k[0]], [-k[1], k[0], 0.0]])
    s, c = np.sin(angle)[..., None, None], np.cos(angle)[..., None, None]
    return np.eye(3) + s * K + (1 - c) * (K @ K)

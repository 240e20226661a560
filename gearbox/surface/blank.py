"""One gear's cutting data for simulated generation (:class:`ToothBlank`).

Everything a gear's flanks depend on: its own tool (rack) data and blank, nothing of
the mating gear. SI units (m, rad).

Gear frame S_i: z along the gear axis, z = 0 at the reference transverse section
(where x_t applies), +z towards the heel; y through the middle of tooth 0 at z = 0;
x = y cross z. The face width spans ``z_toe <= z <= z_heel`` around the face middle
at ``z = -reference_section``.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

from ..errors import Problems

__all__ = ["ToothBlank", "blanks_from_design", "SIDES"]

#: flank names: "R" (right, drive) and "L" (left, coast), as in the paper
SIDES = ("R", "L")


@dataclass(frozen=True)
class ToothBlank:
    """Tool and blank data of one beveloid gear (SI).

    Attributes:
        teeth: number of teeth N.
        normal_module: tool normal module m_n (m).
        normal_pressure_angle: tool normal pressure angle alpha_n (rad).
        helix_angle: tool helix angle beta (rad), sign gives the hand (> 0 right hand).
        cone_angle: cone angle gamma (rad): tilt of the rack about its direction of
            motion; the rack's reference plane rises towards +z (heel).
        profile_shift_xt: transverse profile-shift coefficient x_t at z = 0; the radial
            rack shift is X(z) = x_t m_t + z tan(gamma), m_t = m_n / cos(beta).
        face_width: face width along the axis (m).
        reference_section: axial position of the reference section from the face
            middle towards the heel (m).
        tool_addendum: tool addendum h_a0 (m), depth of the rack tip below its
            reference plane.
        tool_tip_radius: tool tip (edge) radius rho_a0 (m).
        addendum: gear addendum h_a (m) above the rack reference plane, measured
            normal to it: the tip cone is parallel to the rack reference plane,
            r_a(z) = r_p + X(z) + h_a / cos(gamma).
    """

    teeth: int
    normal_module: float
    normal_pressure_angle: float
    helix_angle: float
    cone_angle: float
    profile_shift_xt: float
    face_width: float
    reference_section: float = 0.0
    tool_addendum: float | None = None
    tool_tip_radius: float | None = None
    addendum: float | None = None

    def __post_init__(self):
        # None: the ISO 53 profile A proportions 1.25 m_n, 0.25 m_n and 1.0 m_n
        for name, coef in (("tool_addendum", 1.25), ("tool_tip_radius", 0.25), ("addendum", 1.0)):
            if getattr(self, name) is None:
                object.__setattr__(self, name, coef * self.normal_module)

    # --- derived data -------------------------------------------------------------
    @property
    def transverse_module(self) -> float:
        """m_t = m_n / cos(beta) (m)."""
        return self.normal_module / math.cos(self.helix_angle)

    @property
    def reference_pitch_radius(self) -> float:
        """r_p = m_n N / (2 cos beta) (m): the rolling radius of the generation."""
        return 0.5 * self.normal_module * self.teeth / math.cos(self.helix_angle)

    @property
    def z_toe(self) -> float:
        """Axial position of the toe face (m)."""
        return -self.reference_section - 0.5 * self.face_width

    @property
    def z_heel(self) -> float:
        """Axial position of the heel face (m)."""
        return -self.reference_section + 0.5 * self.face_width

    def rack_shift(self, z):
        """Radial rack shift X(z) = x_t m_t + z tan(gamma) (m)."""
        return self.profile_shift_xt * self.transverse_module + z * math.tan(self.cone_angle)

    def tip_radius(self, z):
        """Tip-cone radius r_a(z) = r_p + X(z) + h_a / cos(gamma) (m)."""
        return (
            self.reference_pitch_radius
            + self.rack_shift(z)
            + self.addendum / math.cos(self.cone_angle)
        )

    def root_radius(self, z):
        """Root-cone radius r_f(z) = r_p + X(z) - h_a0 / cos(gamma) (m), cut by the rack's
        tip plane (parallel to its reference plane at normal distance h_a0)."""
        return (
            self.reference_pitch_radius
            + self.rack_shift(z)
            - self.tool_addendum / math.cos(self.cone_angle)
        )

    def validate(self, where: str = "gear") -> ToothBlank:
        """Check every input; raise one InputError listing all problems."""
        p = Problems()
        p.check(
            isinstance(self.teeth, int) and self.teeth >= 5,
            f"{where}.teeth",
            self.teeth,
            "must be an integer >= 5",
        )
        p.in_range(f"{where}.normal_module_mm", self.normal_module * 1e3, 0, None, lo_open=True)
        p.in_range(
            f"{where}.normal_pressure_angle_deg",
            math.degrees(self.normal_pressure_angle),
            0,
            45,
            lo_open=True,
            hi_open=True,
        )
        p.in_range(f"{where}.helix_angle_deg", math.degrees(self.helix_angle), -60, 60)
        p.in_range(f"{where}.cone_angle_deg", math.degrees(self.cone_angle), 0, 30)
        p.in_range(f"{where}.face_width_mm", self.face_width * 1e3, 0, None, lo_open=True)
        p.in_range(f"{where}.tool_tip_radius_mm", self.tool_tip_radius * 1e3, 0, None)
        p.in_range(f"{where}.tool_addendum_mm", self.tool_addendum * 1e3, 0, None, lo_open=True)
        p.in_range(f"{where}.addendum_mm", self.addendum * 1e3, 0, None, lo_open=True)
        if not p.items:
            # the two tip roundings of one rack tooth must not overlap
            a, m, rho = self.normal_pressure_angle, self.normal_module, self.tool_tip_radius
            # centre of the rounding inside the rack tooth: s_c <= pi m_n / 2
            rho_max = (math.cos(a) * math.pi * m / 4 - math.sin(a) * self.tool_addendum) / (
                1 - math.sin(a)
            )
            p.check(
                rho <= rho_max,
                f"{where}.tool_tip_radius_mm",
                rho * 1e3,
                f"must be in [0, {1e3 * rho_max:.4g}]: the rack tooth tip would be pointed",
            )
            p.check(
                self.tool_addendum > rho * (1 - math.sin(a)),
                f"{where}.tool_addendum_mm",
                self.tool_addendum * 1e3,
                "must exceed the tip rounding's height rho (1 - sin alpha_n)",
            )
        p.raise_if_any(f"invalid tooth blank ({where})")
        return self

    def to_dict(self) -> dict:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict) -> ToothBlank:
        return cls(**d)


def blanks_from_design(design) -> tuple[ToothBlank, ToothBlank]:
    """Pinion and gear blanks of a :class:`gearbox.geometry.PairDesign`.

    Uses the design's solved gear helix angle and backlash-free x_t2 and the tool
    profile of its spec (coefficients of m_n).
    """
    if not hasattr(design, "spec"):
        from ..errors import expect_type
        from ..geometry import PairDesign

        expect_type(design, PairDesign, "blanks_from_design: design", "design_pair(spec)")
    spec = design.spec
    tool = spec.tool
    m = spec.normal_module
    out = []
    for name, g in (("pinion", design.pinion), ("gear", design.gear)):
        out.append(
            ToothBlank(
                teeth=g.teeth,
                normal_module=m,
                normal_pressure_angle=spec.normal_pressure_angle,
                helix_angle=g.helix_angle,
                cone_angle=g.cone_angle,
                profile_shift_xt=g.profile_shift_xt,
                face_width=g.face_width,
                reference_section=g.reference_section,
                tool_addendum=tool.addendum_coefficient * m,
                tool_tip_radius=tool.tip_radius_coefficient * m,
                addendum=tool.gear_addendum_coefficient * m,
            ).validate(name)
        )
    return out[0], out[1]

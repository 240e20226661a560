"""Frozen inputs of the geometry design, in SI units (m, rad).

:meth:`PairSpec.from_scene` converts a scene's ``[pair]``, ``[pinion]``, ``[gear]``
and ``[tool]`` sections (mm, deg) and validates the whole specification at once.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from ..errors import Problems, expect_scene, expect_type, is_real

__all__ = ["ToolSpec", "GearSpec", "PairSpec"]

_D = math.radians


@dataclass(frozen=True)
class ToolSpec:
    """Reference profile of the rack cutter (hob), as coefficients of m_n.

    Attributes:
        addendum_coefficient: tool addendum h_a0 / m_n (cuts the gear's dedendum).
        tip_radius_coefficient: tool tip radius rho_a0 / m_n.
        gear_addendum_coefficient: gear addendum h_a / m_n above the rack reference line
            (the tip cone follows the profile shift along the face width).
    """

    addendum_coefficient: float = 1.25
    tip_radius_coefficient: float = 0.25
    gear_addendum_coefficient: float = 1.0


@dataclass(frozen=True)
class GearSpec:
    """One beveloid gear's cutting data.

    Attributes:
        teeth: number of teeth N.
        helix_angle: tool (rack) helix angle beta (rad); ``None`` for the gear when it
            is solved by the design (paper eqs (18)-(19)).
        cone_angle: cone angle gamma (rad), >= 0.
        profile_shift_xt: transverse profile-shift coefficient x_t at the reference
            section; ``None`` for the gear when solved from paper eq. (20).
        face_width: face width along the axis (m).
        reference_section: axial position of the reference section, measured from the
            middle of the face width towards the heel (m).
    """

    teeth: int
    helix_angle: float | None
    cone_angle: float
    profile_shift_xt: float | None
    face_width: float = 0.040
    reference_section: float = 0.0


@dataclass(frozen=True)
class PairSpec:
    """A crossed beveloid pair to design (paper Table 1 plus the Fig. 5 inputs).

    Attributes:
        normal_module: tool normal module m_n (m).
        normal_pressure_angle: tool normal pressure angle alpha_n (rad).
        shaft_angle: shaft angle delta (rad), in [0, pi/2).
        offset: offset E (m), the shortest distance between the axes; the centre
            distance when delta = 0.
        pinion, gear: :class:`GearSpec` of each member. The gear's helix angle is
            solved; if given, it is compared with the solution in the design checks.
        tool: rack-cutter profile.
        design_mode: ``"cone_angles"`` (paper Fig. 5 with given cone angles) or
            ``"target_fpd"`` (pinion cone angle solved for a target FPD angle).
        target_fpd_angle: target FPD angle (rad) in ``"target_fpd"`` mode.
        target_flank: ``"right"`` or ``"left"``.
        backlash_free: gear profile shift from paper eq. (20).
        min_total_contact_ratio: the design check ``total_contact_ratio_*``'s least
            eps_gamma (2: two tooth pairs in mesh, the usual aim for quiet helical
            gearing; a spur pair, whose eps_gamma is its eps_alpha, takes less).
    """

    normal_module: float
    normal_pressure_angle: float
    shaft_angle: float
    offset: float
    pinion: GearSpec
    gear: GearSpec
    tool: ToolSpec = ToolSpec()
    design_mode: str = "cone_angles"
    target_fpd_angle: float = 0.0
    target_flank: str = "right"
    backlash_free: bool = True
    min_total_contact_ratio: float = 2.0

    def validate(self) -> PairSpec:
        """Check every input; raise one InputError listing all problems."""
        for name in ("pinion", "gear"):
            expect_type(getattr(self, name), GearSpec, f"PairSpec.{name}", "GearSpec(teeth=...)")
        expect_type(self.tool, ToolSpec, "PairSpec.tool", "ToolSpec()")
        p = Problems()
        p.in_range("pair.normal_module_mm", self.normal_module * 1e3, 0, None, lo_open=True)
        p.in_range(
            "pair.normal_pressure_angle_deg",
            math.degrees(self.normal_pressure_angle),
            0,
            45,
            lo_open=True,
            hi_open=True,
        )
        p.in_range("pair.shaft_angle_deg", math.degrees(self.shaft_angle), 0, 90, hi_open=True)
        p.in_range("pair.offset_mm", self.offset * 1e3, 0, None, lo_open=True)
        p.check(
            self.design_mode in ("cone_angles", "target_fpd"),
            "pair.design_mode",
            self.design_mode,
            "must be 'cone_angles' or 'target_fpd'",
        )
        p.in_range("pair.min_total_contact_ratio", self.min_total_contact_ratio, 1.0, 4.0)
        p.check(
            self.target_flank in ("right", "left"),
            "pair.target_flank",
            self.target_flank,
            "must be 'right' or 'left'",
        )
        for name, g in (("pinion", self.pinion), ("gear", self.gear)):
            p.check(
                isinstance(g.teeth, int) and g.teeth >= 5,
                f"{name}.teeth",
                g.teeth,
                "must be an integer >= 5",
            )
            p.in_range(f"{name}.cone_angle_deg", math.degrees(g.cone_angle), 0, 30)
            p.in_range(f"{name}.face_width_mm", g.face_width * 1e3, 0, None, lo_open=True)
            if is_real(g.face_width) and g.face_width > 0:
                half = 0.5 * g.face_width * 1e3  # the section lies on the face
                p.in_range(f"{name}.reference_section_mm", g.reference_section * 1e3, -half, half)
            if g.helix_angle is not None:
                p.in_range(f"{name}.helix_angle_deg", math.degrees(g.helix_angle), -60, 60)
            if g.profile_shift_xt is not None:
                p.in_range(f"{name}.profile_shift_xt", g.profile_shift_xt, -1.5, 2.5)
        p.check(self.pinion.helix_angle is not None, "pinion.helix_angle_deg", None, "is required")
        p.check(
            self.pinion.profile_shift_xt is not None, "pinion.profile_shift_xt", None, "is required"
        )
        if not self.backlash_free:
            p.check(
                self.gear.profile_shift_xt is not None,
                "gear.profile_shift_xt",
                None,
                "is required when pair.backlash_free = false",
            )
        if self.shaft_angle == 0.0 and (self.pinion.cone_angle > 0 or self.gear.cone_angle > 0):
            p.add(
                "pinion.cone_angle_deg / gear.cone_angle_deg",
                (math.degrees(self.pinion.cone_angle), math.degrees(self.gear.cone_angle)),
                "must both be 0 when pair.shaft_angle_deg = 0 (working pitch cones cannot "
                "touch a common plane otherwise)",
            )
        p.raise_if_any("invalid gear pair specification")
        return self

    @classmethod
    def from_scene(cls, scene) -> PairSpec:
        """Build (and validate) from a :class:`gearbox.scene.Scene`."""
        expect_scene(scene, "PairSpec.from_scene: scene")
        pr, pi, ge, to = scene["pair"], scene["pinion"], scene["gear"], scene["tool"]

        def gear(sec, solved_helix: bool):
            return GearSpec(
                teeth=sec["teeth"],
                helix_angle=None if sec["helix_angle_deg"] is None else _D(sec["helix_angle_deg"]),
                cone_angle=_D(sec["cone_angle_deg"]),
                profile_shift_xt=sec["profile_shift_xt"],
                face_width=sec["face_width_mm"] * 1e-3,
                reference_section=sec["reference_section_mm"] * 1e-3,
            )

        return cls(
            normal_module=pr["normal_module_mm"] * 1e-3,
            normal_pressure_angle=_D(pr["normal_pressure_angle_deg"]),
            shaft_angle=_D(pr["shaft_angle_deg"]),
            offset=pr["offset_mm"] * 1e-3,
            pinion=gear(pi, False),
            gear=gear(ge, True),
            tool=ToolSpec(
                to["addendum_coefficient"],
                to["tip_radius_coefficient"],
                to["gear_addendum_coefficient"],
            ),
            design_mode=pr["design_mode"],
            target_fpd_angle=_D(pr["target_fpd_angle_deg"]),
            target_flank=pr["target_flank"],
            backlash_free=pr["backlash_free"],
            min_total_contact_ratio=pr["min_total_contact_ratio"],
        ).validate()

    def with_pinion(self, **changes) -> PairSpec:
        """A new spec with pinion fields replaced (``with_pinion(cone_angle=0.02)``)."""
        return replace(self, pinion=replace(self.pinion, **changes))

    def with_gear(self, **changes) -> PairSpec:
        """A new spec with gear fields replaced."""
        return replace(self, gear=replace(self.gear, **changes))

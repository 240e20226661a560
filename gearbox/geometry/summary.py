"""Edge-unit summaries of a design (deg, mm): the JSON of ``gearbox design --json``
and the rows of its readable table."""

from __future__ import annotations

import math

from .design import PairDesign

__all__ = ["design_summary", "design_table"]


def _deg(x):
    return math.degrees(x)


def _mm(x):
    return x * 1e3 if math.isfinite(x) else None


def design_summary(d: PairDesign) -> dict:
    """One JSON-ready dict; pairs are [pinion, gear], flank pairs [right, left]."""
    g = d.gears
    checks = {}
    for name, c in d.checks.items():
        margin, unit = (c.margin * 1e3, "mm") if c.unit == "m" else (c.margin, c.unit)
        checks[name] = {"ok": c.ok, "margin": margin, "unit": unit, "detail": c.detail}
    return {
        "scene_mode": d.spec.design_mode,
        "normal_angular_factor": d.normal_angular_factor,
        "fpd_angle_right_deg": _deg(d.fpd_angle_right),
        "fpd_angle_left_deg": _deg(d.fpd_angle_left),
        "helix_angle_deg": [_deg(x.helix_angle) for x in g],
        "cone_angle_deg": [_deg(x.cone_angle) for x in g],
        "profile_shift_xt": [x.profile_shift_xt for x in g],
        "normal_profile_shift_xn": [x.normal_profile_shift for x in g],
        "working_normal_pressure_angle_deg": _deg(d.working_normal_pressure_angle),
        "working_normal_module_mm": d.working_normal_module * 1e3,
        "working_helix_angle_deg": [_deg(x.working_helix_angle) for x in g],
        "working_cone_angle_deg": [_deg(x.working_cone_angle) for x in g],
        "working_pitch_radius_mm": [x.working_pitch_radius * 1e3 for x in g],
        "reference_pitch_radius_mm": [x.reference_pitch_radius * 1e3 for x in g],
        "transverse_pressure_angle_deg": [
            [_deg(a) for a in x.transverse_pressure_angle] for x in g
        ],
        "working_transverse_pressure_angle_deg": [
            [_deg(a) for a in x.working_transverse_pressure_angle] for x in g
        ],
        "base_radius_mm": [[r * 1e3 for r in x.base_radius] for x in g],
        "base_helix_angle_deg": [[_deg(a) for a in x.base_helix_angle] for x in g],
        "fpd_part_deg": [[_deg(a) for a in x.fpd_part] for x in g],
        "mounting_distance_mm": [_mm(x.mounting_distance) for x in g],
        "pitch_point_axial_mm": [x.pitch_point_axial * 1e3 for x in g],
        "pitch_point_mm": [p * 1e3 for p in d.pitch_point],
        "line_of_action_right": list(d.line_of_action[0]),
        "line_of_action_left": list(d.line_of_action[1]),
        "offset_mm": d.offset * 1e3,
        "shaft_angle_deg": _deg(d.shaft_angle),
        "iterations": d.iterations,
        "all_checks_ok": d.ok,
        "checks": checks,
    }


def design_table(d: PairDesign) -> str:
    """A readable text table of the design and its checks."""
    s = design_summary(d)
    rows = [
        ("normal angular factor xi_n", f"{s['normal_angular_factor']:.6f}", ""),
        (
            "FPD angle xi_R / xi_L (deg)",
            f"{s['fpd_angle_right_deg']:.4f}",
            f"{s['fpd_angle_left_deg']:.4f}",
        ),
        (
            "working normal pressure angle (deg)",
            f"{s['working_normal_pressure_angle_deg']:.4f}",
            "",
        ),
        ("working normal module (mm)", f"{s['working_normal_module_mm']:.5f}", ""),
    ]
    per_gear = [
        ("helix angle beta (deg)", "helix_angle_deg", "{:.4f}"),
        ("cone angle gamma (deg)", "cone_angle_deg", "{:.4f}"),
        ("profile shift x_t", "profile_shift_xt", "{:.5f}"),
        ("working helix angle (deg)", "working_helix_angle_deg", "{:.4f}"),
        ("working cone angle (deg)", "working_cone_angle_deg", "{:.4f}"),
        ("reference pitch radius (mm)", "reference_pitch_radius_mm", "{:.4f}"),
        ("working pitch radius (mm)", "working_pitch_radius_mm", "{:.4f}"),
        ("mounting distance (mm)", "mounting_distance_mm", "{:.3f}"),
        ("pitch point from crossing point (mm)", "pitch_point_axial_mm", "{:.3f}"),
    ]
    for label, key, fmt in per_gear:
        vals = [("inf" if v is None else fmt.format(v)) for v in s[key]]
        rows.append((label, *vals))
    for label, key in (
        ("transverse pressure angle R/L (deg)", "transverse_pressure_angle_deg"),
        ("base radius R/L (mm)", "base_radius_mm"),
        ("FPD part R/L (deg)", "fpd_part_deg"),
    ):
        rows.append((label, *[" / ".join(f"{v:.4f}" for v in pair) for pair in s[key]]))
    w = max(len(r[0]) for r in rows) + 2
    lines = [
        f"{'':{w}}{'pinion':>20}{'gear':>20}",
        *(f"{r[0]:{w}}{r[1]:>20}{(r[2] if len(r) > 2 else ''):>20}" for r in rows),
    ]
    lines += ["", "checks:"]
    for name, c in s["checks"].items():
        lines.append(
            f"  {'ok  ' if c['ok'] else 'FAIL'} {name:34} margin {c['margin']:+.4g} {c['unit']:4} {c['detail']}"
        )
    return "\n".join(lines)

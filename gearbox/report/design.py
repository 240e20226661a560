"""Report section of the design stage: pair and gear tables, design checks."""

from __future__ import annotations

import math

from .html import ReportWarning, Section, fmt, table

__all__ = ["render"]


def _deg(x: float) -> float:
    return math.degrees(x)


def _rl(pair, scale=1.0) -> str:
    r, l = pair
    return f"{fmt(r * scale)} / {fmt(l * scale)}"


def render(des, run) -> Section:
    """Design tables (degrees and mm at this edge) and the checks, failures as warnings."""
    pair_rows = [
        ("shaft angle (deg)", _deg(des.shaft_angle)),
        ("offset E (mm)", des.offset * 1e3),
        ("normal module m_n (mm)", des.normal_module * 1e3),
        ("normal pressure angle alpha_n (deg)", _deg(des.normal_pressure_angle)),
        ("working normal pressure angle alpha_nw (deg)", _deg(des.working_normal_pressure_angle)),
        ("normal angular factor xi_n", des.normal_angular_factor),
        ("FPD angle, right flank xi_R (deg), paper eq. (1)", _deg(des.fpd_angle_right)),
        ("FPD angle, left flank xi_L (deg), paper eq. (1)", _deg(des.fpd_angle_left)),
    ]
    g1, g2 = des.pinion, des.gear
    gear_rows = [
        ("teeth N", g1.teeth, g2.teeth),
        ("tool helix angle beta (deg)", _deg(g1.helix_angle), _deg(g2.helix_angle)),
        ("cone angle gamma (deg)", _deg(g1.cone_angle), _deg(g2.cone_angle)),
        ("profile shift x_t", g1.profile_shift_xt, g2.profile_shift_xt),
        ("face width (mm)", g1.face_width * 1e3, g2.face_width * 1e3),
        (
            "reference pitch radius r_p (mm)",
            g1.reference_pitch_radius * 1e3,
            g2.reference_pitch_radius * 1e3,
        ),
        (
            "working pitch radius r_w (mm)",
            g1.working_pitch_radius * 1e3,
            g2.working_pitch_radius * 1e3,
        ),
        (
            "working helix angle beta_w (deg)",
            _deg(g1.working_helix_angle),
            _deg(g2.working_helix_angle),
        ),
        (
            "working cone angle gamma_w (deg)",
            _deg(g1.working_cone_angle),
            _deg(g2.working_cone_angle),
        ),
        (
            "transverse pressure angle R / L (deg)",
            _rl(g1.transverse_pressure_angle, 180 / math.pi),
            _rl(g2.transverse_pressure_angle, 180 / math.pi),
        ),
        ("base radius R / L (mm)", _rl(g1.base_radius, 1e3), _rl(g2.base_radius, 1e3)),
        (
            "base helix angle R / L (deg)",
            _rl(g1.base_helix_angle, 180 / math.pi),
            _rl(g2.base_helix_angle, 180 / math.pi),
        ),
        (
            "mounting distance d (mm), paper eqs (16), (17)",
            g1.mounting_distance * 1e3,
            g2.mounting_distance * 1e3,
        ),
        (
            "FPD part xi_Ri / xi_Li (deg)",
            _rl(g1.fpd_part, 180 / math.pi),
            _rl(g2.fpd_part, 180 / math.pi),
        ),
    ]
    warnings = []
    check_rows = []
    for name, chk in des.checks.items():
        # lengths at the edge in mm, as in `gearbox design`
        margin, unit = (
            (chk.margin * 1e3, "mm")
            if chk.unit == "m"
            else (chk.margin, "" if chk.unit == "1" else chk.unit)
        )
        check_rows.append(
            (
                name,
                ("pass" if chk.ok else "FAIL", "ok" if chk.ok else "bad"),
                f"{fmt(margin)} {unit}".strip(),
                chk.detail,
            )
        )
        if not chk.ok:
            warnings.append(ReportWarning("design", f"check {name} fails: {chk.detail}"))
    body = (
        "<h3>Pair</h3>"
        + table(["quantity", "value"], pair_rows)
        + "<h3>Gears</h3>"
        + table(["quantity", "pinion", "gear"], gear_rows)
        + '<p class="muted">Flanks: R = right = drive, L = left = coast; the pinion\'s R flank '
        "meshes with the gear's R flank.</p>"
        + "<h3>Design checks</h3>"
        + table(["check", "result", "margin", "detail"], check_rows)
    )
    return Section("Design", body, tuple(warnings), anchor="design")

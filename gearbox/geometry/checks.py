"""Design checks along the whole face width of both gears.

A beveloid gear's profile shift varies along its axis: the rack pitch plane is tilted
by the cone angle, so the radial rack shift in the transverse section at axial
position z (from the reference section) is ``X(z) = x_t m_t + z tan(gamma)``. Toe
(small z) and heel differ, so every check is evaluated on ``N_SECTIONS`` transverse
sections from toe to heel and reports the worst section and its margin.

Each flank of a beveloid gear is an involute helicoid with its own base radius
``r_bj = r_p cos(alpha_Pj)`` (j = R, L), the same in every section; the section only
changes the radial position of the rack. The checks use the transverse section of
the tilted rack: the rack depth measured perpendicular to its pitch plane becomes
``h / cos(gamma)`` radially.

- undercut (per gear and flank): the end of the straight part of the tool flank,
  ``h_lim = (h_a0 - rho_a0 (1 - sin alpha_n)) m_n / cos gamma`` below the rack pitch line,
  must stay above the interference point of the generating rack, ``r_p sin^2(alpha_Pj)``
  below the pitch circle (the classic no-undercut condition, e.g. ISO 21771 /
  Niemann-Winter vol. I, sec. 21.4, written per flank). margin (m) =
  ``r_p sin^2(alpha_Pj) - (h_lim - X(z))``.
- topping (per gear): normal tooth thickness at the tip cone,
  ``s_an = r_a psi_a cos(beta)`` with
  ``psi_a = pi/N + X (tan a_PR + tan a_PL) / r_p + sum_j (inv a_Pj - inv a_aj)``, must be
  at least ``TOPPING_MIN_SAN * m_n`` (a usual minimum; 0.2-0.4 m_n in practice).
  margin (m) = ``s_an - TOPPING_MIN_SAN m_n``.
- transverse contact ratio (per flank): ``eps_a = sum_i (sqrt(r_ai^2 - r_bij^2) -
  sqrt(r_wi(z)^2 - r_bij^2)) / p_btij`` with ``p_bt = 2 pi r_b / N``, evaluated for
  corresponding sections (toe with toe, heel with heel: both heels point along +z_f)
  and ``r_w(z) = r_w + z tan(gamma_w)``; the crossed-helical approximation of each
  gear's addendum path in its own transverse plane. margin = ``min eps_a - 1``.
- total contact ratio (per flank): ``eps_gamma = min eps_a + eps_b`` with the pinion's
  overlap ratio ``eps_b = b |tan beta_b| / p_bt``; margin = ``eps_gamma -
  min_total_contact_ratio`` (:class:`~gearbox.geometry.spec.PairSpec`, scene key
  ``pair.min_total_contact_ratio``, default :data:`TOTAL_CONTACT_MIN` = 2: a total
  contact ratio of at least 2 keeps two tooth pairs in mesh, the usual aim for quiet
  helical gearing; a spur pair's eps_gamma is its eps_alpha and needs a lower aim).
  Both gears' overlap ratios are in the detail.
- active root (per gear and flank): the mating gear's tip contact must end above the
  root form circle (ISO 21771 d_Nf >= d_Ff; below it the tip runs onto the fillet,
  meshing interference). In each section the mate's addendum path ``g_a`` (its own
  transverse plane, as for the contact ratio) is carried over in base pitches,
  ``l = g_a,mate p_bt / p_bt,mate``; the contact then ends at roll length
  ``sqrt(r_w(z)^2 - r_b^2) - l`` from the base circle, and the form circle lies at
  ``(r_p sin^2 a_Pj - (h_lim - X(z))) / sin a_Pj`` (0 when undercut). margin (m, along
  the path of contact) = the difference. For parallel gears it is ISO 21771's d_Nf.
  On the surfaces the unloaded TCA measures where the path really ends (a path that
  ends at a root form circle is reported); the check is the conservative side: on a
  12-tooth pinion of case 03's pair it fails for x_t1 <= 0.84, the TCA's path reaches
  the pinion's form circle for x_t1 <= 0.76 (the check then reads about -1 mm: its
  worst face section against the path's own end).
- gear helix angle: when the scene gives beta_2, it must match the solved value
  within 0.01 deg (the printed precision of the paper's Table 2).
- gear profile shift: when the scene gives x_t2 with ``pair.backlash_free = true``
  (which solves it), it must match the solved value within ``PROFILE_SHIFT_TOL``.
"""

from __future__ import annotations

import math

import numpy as np

from .design import Check, GearDesign, PairDesign
from .involute import inv

__all__ = [
    "design_checks",
    "overlap_ratio",
    "sections",
    "N_SECTIONS",
    "TOPPING_MIN_SAN",
    "TOTAL_CONTACT_MIN",
]

N_SECTIONS = 21
TOPPING_MIN_SAN = 0.25
HELIX_TOL_DEG = 0.01
#: Tolerance of a given gear profile shift x_t2 against the backlash-free one (a
#: printed value to 4 decimals; at m_n 6 mm, 1e-3 shifts the profile by 6 um, 4.4 um
#: of tooth thickness at 20 deg).
PROFILE_SHIFT_TOL = 1e-3
TOTAL_CONTACT_MIN = 2.0


def sections(g: GearDesign, n: int = N_SECTIONS) -> np.ndarray:
    """Axial positions z (m) from toe to heel, relative to the reference section."""
    half = 0.5 * g.face_width
    return np.linspace(-half, half, n) - g.reference_section


def _radial_shift(g: GearDesign, z):
    return g.profile_shift_xt * g.transverse_module + z * math.tan(g.cone_angle)


def _tip_radius(g: GearDesign, z, m_n, tool):
    return (
        g.reference_pitch_radius
        + _radial_shift(g, z)
        + tool.gear_addendum_coefficient * m_n / math.cos(g.cone_angle)
    )


def _beside(value: float, limit: float) -> str:
    """``value`` to 3 decimals, more where 3 would print it equal to ``limit`` though it
    is not (1.99953 against 2: "1.9995", not "2.000" beside a failed check)."""
    for decimals in range(3, 10):
        text = f"{value:.{decimals}f}"
        if value == limit or float(text) != limit:
            return text
    return text


def _where(g, z, i) -> str:
    return f"z = {z[i] * 1e3:+.1f} mm from the reference section ({'toe' if i == 0 else 'heel' if i == len(z) - 1 else 'mid'})"


def overlap_ratio(g: GearDesign) -> float:
    """Overlap ratio eps_beta = b |tan beta_b| / p_bt of one gear (smaller-helix flank)."""
    p_bt = 2 * math.pi * min(g.base_radius) / g.teeth
    return g.face_width * abs(math.tan(min(g.base_helix_angle, key=abs))) / p_bt


def _interference_margin(g: GearDesign, j: int, z, h_lim: float) -> np.ndarray:
    """How far (m, radially) the interference point of flank j, ``r_p sin^2 a_Pj`` below
    the pitch circle, lies below the end of the tool's straight flank, ``h_lim - X(z)``
    below it, in sections z: the undercut check's margin (< 0: undercut)."""
    a_p = g.transverse_pressure_angle[j]
    return g.reference_pitch_radius * math.sin(a_p) ** 2 - (h_lim - _radial_shift(g, z))


def form_roll(g: GearDesign, j: int, z, h_lim: float) -> np.ndarray:
    """Roll length (m) of flank j's root form circle in sections z: where the involute
    that the tool's straight flank generates meets the fillet, the interference margin
    over ``sin a_Pj`` (ISO 21771 d_Ff, per flank); 0 when undercut (the involute then
    starts no lower than the base circle)."""
    margin = _interference_margin(g, j, z, h_lim)
    return np.maximum(margin, 0.0) / math.sin(g.transverse_pressure_angle[j])


def _active_root(name, flank, g: GearDesign, z, j, h_lim, roll_w, reach) -> Check:
    """The mating tip's contact on gear ``g``'s flank j ends above its root form circle:
    the roll length there, ``roll_w - reach`` (``reach``: the mate's addendum path in
    base pitches, times this gear's base pitch), at least the form circle's."""
    r_b = g.base_radius[j]
    roll_f = form_roll(g, j, z, h_lim)
    roll_n = roll_w - reach
    margin = roll_n - roll_f
    i = int(np.argmin(margin))
    d_ff = 2 * math.hypot(r_b, roll_f[i])
    if roll_n[i] >= 0:
        ends = f"the active root diameter d_Nf {2 * math.hypot(r_b, roll_n[i]) * 1e3:.3f} mm"
    else:
        ends = f"{-roll_n[i] * 1e3:.3f} mm of path below the base circle"
    mate = "gear" if name == "pinion" else "pinion"
    return Check(
        bool(margin[i] >= 0),
        float(margin[i]),
        "m",
        f"{name} {flank} flank: the {mate}'s tip contact ends above the root form circle "
        f"(d_Ff {d_ff * 1e3:.3f} mm), at {ends} (margin along the path of contact; "
        f"below d_Ff the tip meets the fillet: meshing interference); worst at {_where(g, z, i)}",
    )


def design_checks(d: PairDesign) -> dict[str, Check]:
    """All checks of a design, name -> :class:`Check` (see module docstring)."""
    spec = d.spec
    m_n, a_n, tool = spec.normal_module, spec.normal_pressure_angle, spec.tool
    out: dict[str, Check] = {}
    h_lims = []  # per gear: the tool's straight flank ends this far below the pitch line (m)
    for name, g in (("pinion", d.pinion), ("gear", d.gear)):
        z = sections(g)
        X = _radial_shift(g, z)
        h_lim = (
            (tool.addendum_coefficient - tool.tip_radius_coefficient * (1 - math.sin(a_n)))
            * m_n
            / math.cos(g.cone_angle)
        )
        h_lims.append(h_lim)
        for j, flank in enumerate(("right", "left")):
            margin = _interference_margin(g, j, z, h_lim)
            i = int(np.argmin(margin))
            out[f"{name}_undercut_{flank}"] = Check(
                bool(margin[i] >= 0),
                float(margin[i]),
                "m",
                f"{name} {flank} flank: no undercut while the tool's straight flank ends above the interference "
                f"point; worst at {_where(g, z, i)}",
            )
        r_a = _tip_radius(g, z, m_n, tool)
        psi = (
            math.pi / g.teeth
            + X
            * (math.tan(g.transverse_pressure_angle[0]) + math.tan(g.transverse_pressure_angle[1]))
            / g.reference_pitch_radius
        )
        for j in range(2):
            a_a = np.arccos(np.clip(g.base_radius[j] / r_a, -1, 1))
            psi = psi + inv(g.transverse_pressure_angle[j]) - inv(a_a)
        s_an = r_a * psi * math.cos(g.helix_angle)
        margin = s_an - TOPPING_MIN_SAN * m_n
        i = int(np.argmin(margin))
        out[f"{name}_topping"] = Check(
            bool(margin[i] >= 0),
            float(margin[i]),
            "m",
            f"{name}: normal tip tooth thickness {s_an[i] * 1e3:.3f} mm >= {TOPPING_MIN_SAN:g} m_n; worst at {_where(g, z, i)}",
        )
    # transverse contact ratio, corresponding sections of both gears
    zs = [sections(g) for g in d.gears]
    eps_b = [overlap_ratio(g) for g in d.gears]
    for j, flank in enumerate(("right", "left")):
        eps = 0.0
        # per gear: roll length at the working pitch point and addendum path (m), base
        # pitch (m); the mating tip's reach on each gear follows (the active root)
        roll_w, path, p_bt = [], [], []
        for g, z in zip(d.gears, zs, strict=True):
            r_b = g.base_radius[j]
            r_a = _tip_radius(g, z, m_n, tool)
            r_w = g.working_pitch_radius + z * math.tan(g.working_cone_angle)
            l_w = np.sqrt(np.maximum(r_w**2 - r_b**2, 0))
            g_a = np.sqrt(np.maximum(r_a**2 - r_b**2, 0)) - l_w
            eps = eps + g_a / (2 * math.pi * r_b / g.teeth)
            roll_w.append(l_w)
            path.append(g_a)
            p_bt.append(2 * math.pi * r_b / g.teeth)
        for i, (name, g) in enumerate((("pinion", d.pinion), ("gear", d.gear))):
            out[f"{name}_active_root_{flank}"] = _active_root(
                name, flank, g, zs[i], j, h_lims[i], roll_w[i], path[1 - i] / p_bt[1 - i] * p_bt[i]
            )
        i = int(np.argmin(eps))
        out[f"transverse_contact_ratio_{flank}"] = Check(
            bool(eps[i] >= 1.0),
            float(eps[i] - 1.0),
            "1",
            f"{flank} flanks: transverse contact ratio min {_beside(eps[i], 1.0)} (toe {eps[0]:.3f}, heel {eps[-1]:.3f}) >= 1",
        )
        eps_g = float(eps[i]) + eps_b[0]
        least = spec.min_total_contact_ratio
        out[f"total_contact_ratio_{flank}"] = Check(
            bool(eps_g >= least),
            eps_g - least,
            "1",
            f"{flank} flanks: eps_gamma = eps_alpha + eps_beta(pinion) = {_beside(eps_g, least)} >= {least:g} "
            f"(pair.min_total_contact_ratio; overlap ratios: pinion {eps_b[0]:.3f}, gear {eps_b[1]:.3f})",
        )
    if spec.gear.helix_angle is not None:
        diff = abs(math.degrees(spec.gear.helix_angle - d.gear.helix_angle))
        out["gear_helix_angle_given"] = Check(
            bool(diff <= HELIX_TOL_DEG),
            HELIX_TOL_DEG - diff,
            "deg",
            f"given gear helix angle {math.degrees(spec.gear.helix_angle):.4f} deg vs solved "
            f"{math.degrees(d.gear.helix_angle):.4f} deg (tolerance {HELIX_TOL_DEG} deg)",
        )
    if spec.backlash_free and spec.gear.profile_shift_xt is not None:
        # solved for zero backlash: a given value is a cross-check, as the helix angle
        diff = abs(spec.gear.profile_shift_xt - d.gear.profile_shift_xt)
        out["gear_profile_shift_given"] = Check(
            bool(diff <= PROFILE_SHIFT_TOL),
            PROFILE_SHIFT_TOL - diff,
            "1",
            f"given gear profile shift x_t2 {spec.gear.profile_shift_xt:.5f} vs solved "
            f"{d.gear.profile_shift_xt:.5f} for zero backlash (tolerance {PROFILE_SHIFT_TOL}; "
            "pair.backlash_free = false takes the given one)",
        )
    return out

"""Design of a crossed beveloid pair with the line-contact condition (paper section 2).

The procedure of paper Fig. 5: from Table 1 (m_n, alpha_n, N_1, N_2, delta, E) plus the
pinion helix angle, both cone angles and x_t1, solve the normal angular factor xi_n
and the gear helix angle beta_2 (paper eqs (18), (19)); then the working rack data
(eqs (11)-(15)), the FPD angles (eqs (1), (8), (9)), the mounting distances (eqs (16),
(17), corrected, see below) and the backlash-free gear profile shift (eq. (20)).

Solution method. For a given xi_n every working quantity of the pinion follows in
closed form (:func:`gearbox.geometry.rack.working_rack`), and eq. (18) gives the sum
beta_w1 + beta_w2 directly, hence beta_w2 and r_w2 without knowing beta_2. What
remains is one scalar equation in xi_n, eq. (19), solved by a safeguarded Newton
iteration on log E (E is nearly proportional to 1/xi_n), vectorised so that parameter
studies solve thousands of designs at once.

Limits. Eqs (18)-(19) contain ``sin(beta_w1 + beta_w2) / sin(delta)``, which is 0/0 for
parallel axes. With ``D = sin^2 delta - sin^2 g_w1 - sin^2 g_w2 - 2 sin g_w1 sin g_w2 cos
delta`` one has ``sin(beta_w1 + beta_w2) = sqrt(D) / (cos g_w1 cos g_w2)`` (from the 3-D
construction below), so eq. (19) reads ``E = (r_w1 / cos g_w1 + r_w2 / cos g_w2)
sqrt(D) / sin(delta)``. D is evaluated in the factored form ``(sin d - s1 - s2)(sin d +
s1 + s2) + 4 s1 s2 sin^2(d/2)`` and ``sqrt(D)/sin(delta)`` is exactly 1 when both cone
angles vanish, so crossed helical pairs (cone angles 0) and parallel helical pairs
(delta = 0: ISO 21771) come out exactly, without NaN or loss of digits.

3-D construction (used for the mounting distances and the pitch point, and as the
independent check of eqs (18)-(19) in the tests). Fixed frame Sf: origin at the foot
of the common perpendicular on the pinion axis; z_f along the pinion axis towards its
heel; x_f along the common perpendicular towards the gear axis; the gear axis passes
through (E, 0, 0) with direction (0, sin delta, cos delta), pointing to the gear's heel.
The working pitch plane (pitch plane of the common rack) has the unit normal
``m = (sqrt(D)/sin d, (s2 + s1 cos d)/sin d, -s1)``; it touches the pinion's working pitch
cone (half angle g_w1) and, from the other side, the gear's (g_w2) at the pitch point P.

Paper eqs (16), (17) as printed contain one misprint each. The construction gives,
with d_i the distance along axis i from the foot of the common perpendicular to the
apex of working pitch cone i (positive towards the toe)::

    d_1 = -r_w2 / (s1 c2) + E (sin^2 d - s1^2 - s1 s2 cos d) / (s1 sin d sqrt(D))
    d_2 =  r_w2 / (s2 c2) - E (s1 cos d + s2) / (sin d sqrt(D))

where the paper prints ``sin^2 g_w1 cos d`` for ``s1 s2 cos d`` in eq. (16) and
``sin^2 g_w2`` for ``s2`` in eq. (17). The printed forms put the cone apex tens of
millimetres away from the apex of the cone that touches the common pitch plane at P
(145 mm for d_1 and 73 mm for d_2 in case 01); the corrected forms agree with the construction to rounding
(``tests/test_geometry_construction.py``).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import InputError, Problem
from .involute import inv
from .rack import base_helix_angles, fpd_parts, transverse_pressure_angles, working_rack
from .spec import PairSpec

__all__ = ["GearDesign", "PairDesign", "design_pair", "solve_pair_arrays", "Check"]

MAX_ITER = 40
RTOL = 4e-16


@dataclass(frozen=True)
class Check:
    """One design check: ``ok`` when ``margin >= 0``; ``margin`` in ``unit``."""

    ok: bool
    margin: float
    unit: str
    detail: str


@dataclass(frozen=True)
class GearDesign:
    """One gear of a designed pair (SI: m, rad). Pairs are (right, left) flank values."""

    teeth: int
    helix_angle: float
    cone_angle: float
    profile_shift_xt: float
    face_width: float
    reference_section: float
    transverse_module: float
    reference_pitch_radius: float
    working_pitch_radius: float
    working_helix_angle: float
    working_cone_angle: float
    transverse_pressure_angle: tuple[float, float]
    working_transverse_pressure_angle: tuple[float, float]
    base_radius: tuple[float, float]
    base_helix_angle: tuple[float, float]
    normal_profile_shift: float
    mounting_distance: float
    pitch_point_axial: float
    fpd_part: tuple[float, float]

    @property
    def transverse_angular_factor(self) -> float:
        """xi_t = r_p / r_w (paper eq. (15))."""
        return self.reference_pitch_radius / self.working_pitch_radius


@dataclass(frozen=True)
class PairDesign:
    """Result of :func:`design_pair` (SI: m, rad).

    Attributes:
        spec: the input specification (pinion cone angle replaced by the solved one in
            ``target_fpd`` mode).
        normal_angular_factor: xi_n (paper eq. (15)).
        working_normal_pressure_angle: alpha_nw of the common rack (eq. (14)).
        working_normal_module: m_nw = m_n / xi_n (m).
        fpd_angle_right, fpd_angle_left: xi_R, xi_L (eqs (1), (8), (9)).
        pinion, gear: :class:`GearDesign`.
        pitch_point: P in Sf (m), shape (3,).
        pitch_plane_normal: unit normal of the common rack's pitch plane in Sf.
        gear_axis: unit direction of the gear axis in Sf (the pinion axis is z_f).
        line_of_action: unit normals of the common rack's right and left flanks at P
            in Sf, shape (2, 3): the lines of action of the drive (R) and coast (L)
            sides at the pitch point. Oriented as the paper's Table 3 (which gives
            ``(n_x, n_y, -n_z)`` of the right one: its Sf is ours mirrored in z).
        iterations: Newton iterations of the xi_n solve; ``residual``: |E(xi_n)/E - 1|.
        checks: name -> :class:`Check` (filled by :mod:`gearbox.geometry.checks`).
    """

    spec: PairSpec
    normal_angular_factor: float
    working_normal_pressure_angle: float
    working_normal_module: float
    fpd_angle_right: float
    fpd_angle_left: float
    pinion: GearDesign
    gear: GearDesign
    pitch_point: tuple[float, float, float]
    pitch_plane_normal: tuple[float, float, float]
    gear_axis: tuple[float, float, float]
    line_of_action: tuple[tuple[float, float, float], tuple[float, float, float]]
    iterations: int
    residual: float
    checks: dict[str, Check] = field(default_factory=dict)

    # convenient pass-throughs of the pair data
    @property
    def shaft_angle(self) -> float:
        return self.spec.shaft_angle

    @property
    def offset(self) -> float:
        return self.spec.offset

    @property
    def normal_module(self) -> float:
        return self.spec.normal_module

    @property
    def normal_pressure_angle(self) -> float:
        return self.spec.normal_pressure_angle

    @property
    def gears(self) -> tuple[GearDesign, GearDesign]:
        return (self.pinion, self.gear)

    @property
    def ok(self) -> bool:
        """All design checks pass."""
        return all(c.ok for c in self.checks.values())

    def to_dict(self) -> dict:
        """Plain nested dict (SI), JSON-serialisable."""
        return asdict(self)


def _root_D(delta, s1, s2):
    """D of the module docstring, in factored form (less cancellation near limits)."""
    sd = np.sin(delta)
    return (sd - s1 - s2) * (sd + s1 + s2) + 4.0 * s1 * s2 * np.sin(0.5 * delta) ** 2


def _offset_of(xi, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2):
    """Offset E(xi_n) from eqs (18)-(19) and the intermediate quantities (vectorised)."""
    alpha_nw, gw1, bw1, _ = working_rack(xi, alpha_n, beta1, gamma1)
    with np.errstate(invalid="ignore", divide="ignore"):
        sin_gw2 = np.where(
            np.asarray(gamma2) == 0.0, 0.0, np.sin(alpha_n) * np.sin(gamma2) / np.sin(alpha_nw)
        )
        gw2 = np.arcsin(sin_gw2)
        s1, s2 = np.sin(gw1), sin_gw2
        c1, c2 = np.cos(gw1), np.cos(gw2)
        D = _root_D(delta, s1, s2)
        # a tiny negative D from rounding at exact limits is zero; a real one is no solution
        D = np.where((D < 0) & (D > -1e-15), 0.0, D)
        rD = np.sqrt(D)
        cones_zero = (s1 == 0.0) & (s2 == 0.0)
        q = np.where(
            cones_zero, 1.0, rD / np.sin(delta)
        )  # sqrt(D)/sin(delta); exact 1 at the limits
        s = np.arctan2(rD, s1 * s2 + np.cos(delta))  # beta_w1 + beta_w2, eq. (18)
        bw2 = s - bw1
        rw1 = m_n * n1 / (2.0 * xi * np.cos(bw1))
        rw2 = m_n * n2 / (2.0 * xi * np.cos(bw2))
        E = (rw1 / c1 + rw2 / c2) * q  # eq. (19)
    return E, dict(
        alpha_nw=alpha_nw,
        gw1=gw1,
        gw2=gw2,
        bw1=bw1,
        bw2=bw2,
        rw1=rw1,
        rw2=rw2,
        q=q,
        D=D,
        s1=s1,
        s2=s2,
        c1=c1,
        c2=c2,
    )


def solve_pair_arrays(
    m_n, alpha_n, delta, offset, n1, n2, beta1, gamma1, gamma2, *, max_iter=MAX_ITER
):
    """Solve eqs (18)-(19) for xi_n and beta_2 over broadcast arrays of inputs.

    All angles in rad, lengths in m. Returns a dict of arrays (``xi_n``, ``beta2``,
    ``fpd_right``, ``fpd_left``, the working data of both gears) plus ``ok`` (bool
    array: converged, inside the domain) and ``iterations``. Entries without a
    solution are NaN with ``ok = False``; no warning is emitted.
    """
    args = np.broadcast_arrays(
        *(
            np.asarray(a, dtype=float)
            for a in (m_n, alpha_n, delta, offset, n1, n2, beta1, gamma1, gamma2)
        )
    )
    m_n, alpha_n, delta, offset, n1, n2, beta1, gamma1, gamma2 = args
    xi = np.ones_like(m_n)
    # fixed-point start: E is nearly proportional to 1/xi
    E, _ = _offset_of(xi, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2)
    xi = np.clip(xi * E / offset, 0.2, 0.999 / np.cos(alpha_n))
    it = 0
    converged = np.zeros(xi.shape, dtype=bool)
    for it in range(1, max_iter + 1):  # noqa: B007 - the count is reported
        E, _ = _offset_of(xi, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2)
        with np.errstate(invalid="ignore", divide="ignore"):  # E <= 0: no solution, NaN
            g = np.log(E / offset)
        h = 1e-6 * xi
        Ep, _ = _offset_of(xi + h, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2)
        Em, _ = _offset_of(xi - h, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2)
        with np.errstate(invalid="ignore", divide="ignore"):
            dg = (np.log(Ep) - np.log(Em)) / (2 * h)
        dg = np.where(np.isfinite(dg) & (dg < 0), dg, -1.0 / xi)  # E ~ 1/xi fallback
        step = np.clip(-g / dg, -0.2 * xi, 0.2 * xi)
        step = np.where(np.isfinite(step), step, 0.0)
        xi_new = np.minimum(xi + step, 0.9999999 / np.cos(alpha_n))
        converged = np.isfinite(g) & (np.abs(g) <= 8 * RTOL)
        xi = np.where(converged, xi, xi_new)
        if np.all(converged | ~np.isfinite(g)):
            break
    E, w = _offset_of(xi, m_n, alpha_n, delta, n1, n2, beta1, gamma1, gamma2)
    resid = np.abs(E / offset - 1.0)
    ok = np.isfinite(resid) & (resid <= 1e-13)
    # gear tool helix angle from its working helix angle (inverse of working_rack)
    with np.errstate(invalid="ignore"):
        sin_b2 = (
            np.sin(w["bw2"])
            * np.cos(w["alpha_nw"])
            * np.cos(w["gw2"])
            / (np.cos(alpha_n) * np.cos(gamma2))
        )
        beta2 = np.arcsin(sin_b2)
    fr1, fl1 = fpd_parts(w["alpha_nw"], w["bw1"], w["gw1"])
    fr2, fl2 = fpd_parts(w["alpha_nw"], w["bw2"], w["gw2"])
    ok &= np.isfinite(beta2) & np.isfinite(fr1 + fr2 + fl1 + fl2)
    nan = np.where(ok, 1.0, np.nan)
    out = dict(
        xi_n=xi * nan,
        beta2=beta2 * nan,
        fpd_right=(fr1 + fr2) * nan,
        fpd_left=(fl1 + fl2) * nan,
        fpd_parts=((fr1 * nan, fl1 * nan), (fr2 * nan, fl2 * nan)),
        residual=resid,
        ok=ok,
        iterations=it,
    )
    out.update({k: v * nan for k, v in w.items()})
    return out


def solve_spec(spec: PairSpec, *, offset=None, pinion_cone_angle=None):
    """:func:`solve_pair_arrays` on a spec's data; ``offset`` (m) and
    ``pinion_cone_angle`` (rad) may be replaced by arrays for studies."""
    return solve_pair_arrays(
        spec.normal_module,
        spec.normal_pressure_angle,
        spec.shaft_angle,
        spec.offset if offset is None else offset,
        spec.pinion.teeth,
        spec.gear.teeth,
        spec.pinion.helix_angle,
        spec.pinion.cone_angle if pinion_cone_angle is None else pinion_cone_angle,
        spec.gear.cone_angle,
    )


def _solvable_offsets(spec: PairSpec, lo: float, hi: float, n: int = 3000):
    """Intervals ``[(a, b), ...]`` (m) of the offsets in ``[lo, hi]`` for which eqs
    (18)-(19) solve with a real gear helix angle (:func:`solve_spec` on a geometric grid
    of ``n`` offsets; the ends are grid points, neighbours a factor (hi / lo)^(1 / (n -
    1)) apart)."""
    offsets = np.geomspace(lo, hi, n)
    ok = np.asarray(solve_spec(spec, offset=offsets)["ok"], bool)
    edges = np.flatnonzero(np.diff(np.concatenate([[0], ok.astype(int), [0]])))
    return [(offsets[a], offsets[b - 1]) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _no_solution_error(spec: PairSpec) -> InputError:
    """Explain a failed xi_n solve: which offsets would have a solution."""
    pi, ge = spec.pinion, spec.gear
    xis = np.linspace(0.3, 0.9999 / math.cos(spec.normal_pressure_angle), 4000)
    E, _ = _offset_of(
        xis,
        spec.normal_module,
        spec.normal_pressure_angle,
        spec.shaft_angle,
        pi.teeth,
        ge.teeth,
        pi.helix_angle,
        pi.cone_angle,
        ge.cone_angle,
    )
    E = E[np.isfinite(E) & (E > 0)]
    runs = _solvable_offsets(spec, E.min() / 2, E.max() * 2) if E.size else []
    if runs:
        spans = " or ".join(f"{a * 1e3:.1f} <= offset_mm <= {b * 1e3:.1f}" for a, b in runs[:3])
        rng = f"for these teeth, angles and module a solution exists for about {spans}"
        return InputError(
            Problem(
                "pair.offset_mm", spec.offset * 1e3, f"paper eqs (18)-(19) have no solution; {rng}"
            ),
            "no design exists",
        )
    g_sum = math.degrees(pi.cone_angle + ge.cone_angle)
    return InputError(
        Problem(
            "pinion.cone_angle_deg + gear.cone_angle_deg",
            round(g_sum, 6),
            f"paper eqs (18)-(19) have no solution: the working pitch cones cannot touch a common plane; "
            f"the sum must stay below about the shaft angle ({math.degrees(spec.shaft_angle):g} deg)",
        ),
        "no design exists",
    )


XT_RANGE = (-1.5, 2.5)
#: Largest helix angle magnitude (deg) of either gear: the scene's range of
#: pinion.helix_angle_deg and the tooth blanks' (gearbox.surface.ToothBlank)
HELIX_LIMIT_DEG = 60.0


def _profile_shift_error(spec: PairSpec, xt2: float) -> InputError:
    """The offset needs an impossible gear profile shift: say which offsets work."""
    from dataclasses import replace

    def xt2_at(E):
        sol = solve_spec(spec, offset=E)
        return backlash_free_xt2(replace(spec, offset=E), float(sol["beta2"]), float(sol["xi_n"]))

    # scan offsets around the sum of the reference pitch radii (zero working shift)
    a0 = (
        0.5
        * spec.normal_module
        * (spec.pinion.teeth / math.cos(spec.pinion.helix_angle) + spec.gear.teeth)
    )
    good = []
    for E in np.linspace(0.8 * a0, 1.25 * a0, 181):
        try:
            x = xt2_at(E)
        except (ValueError, ZeroDivisionError):
            continue
        if XT_RANGE[0] <= x <= XT_RANGE[1]:
            good.append(E)
    rng = (
        f"about {min(good) * 1e3:.1f} <= offset_mm <= {max(good) * 1e3:.1f} keeps it in range"
        if good
        else "no offset near the reference centre distance keeps it in range"
    )
    return InputError(
        Problem(
            "pair.offset_mm",
            spec.offset * 1e3,
            f"gives a backlash-free gear profile shift x_t2 = {xt2:.3f}, outside [{XT_RANGE[0]}, {XT_RANGE[1]}]; {rng}",
        ),
        "no usable design",
    )


def _gear_design(g, helix, xt, xi, alpha_n, m_n, mounting, h_axial, fpd):
    alpha_nw, gw, bw, ratio = working_rack(xi, alpha_n, helix, g.cone_angle)
    rp = m_n * g.teeth / (2.0 * math.cos(helix))
    aR, aL = transverse_pressure_angles(alpha_n, helix, g.cone_angle)
    awR, awL = transverse_pressure_angles(alpha_nw, bw, gw)
    bbR, bbL = base_helix_angles(alpha_n, helix, g.cone_angle)
    return GearDesign(
        teeth=g.teeth,
        helix_angle=float(helix),
        cone_angle=g.cone_angle,
        profile_shift_xt=float(xt),
        face_width=g.face_width,
        reference_section=g.reference_section,
        transverse_module=m_n / math.cos(helix),
        reference_pitch_radius=rp,
        working_pitch_radius=float(rp * ratio),
        working_helix_angle=float(bw),
        working_cone_angle=float(gw),
        transverse_pressure_angle=(float(aR), float(aL)),
        working_transverse_pressure_angle=(float(awR), float(awL)),
        base_radius=(float(rp * math.cos(aR)), float(rp * math.cos(aL))),
        base_helix_angle=(float(bbR), float(bbL)),
        normal_profile_shift=float(xt * math.cos(g.cone_angle) / math.cos(helix)),
        mounting_distance=float(mounting),
        pitch_point_axial=float(h_axial),
        fpd_part=(float(fpd[0]), float(fpd[1])),
    )


def backlash_free_xt2(spec: PairSpec, beta2: float, xi_n: float) -> float:
    """Gear profile shift x_t2 from the backlash-free condition, paper eq. (20)."""
    a_n = spec.normal_pressure_angle
    rhs = 0.0
    for g, helix in ((spec.pinion, spec.pinion.helix_angle), (spec.gear, beta2)):
        alpha_nw, gw, bw, _ = working_rack(xi_n, a_n, helix, g.cone_angle)
        aR, aL = transverse_pressure_angles(a_n, helix, g.cone_angle)
        awR, awL = transverse_pressure_angles(alpha_nw, bw, gw)
        rhs += 0.5 * g.teeth * (inv(awL) + inv(awR) - inv(aL) - inv(aR))
    p = spec.pinion
    xn1 = p.profile_shift_xt * math.cos(p.cone_angle) / math.cos(p.helix_angle)
    xn2 = rhs / (2.0 * math.tan(a_n)) - xn1
    return xn2 * math.cos(beta2) / math.cos(spec.gear.cone_angle)


def _cone_construction(E, delta, w):
    """Pitch point, pitch-plane normal, axial positions h_i and apex distances d_i."""
    s1, s2, c1, c2, q = w["s1"], w["s2"], w["c1"], w["c2"], w["q"]
    rw1, rw2 = w["rw1"], w["rw2"]
    sd, cd = math.sin(delta), math.cos(delta)
    if s1 == 0.0 and s2 == 0.0:
        m_y, h1, h2 = 0.0, 0.0, 0.0
    else:
        m_y = (s2 + s1 * cd) / sd
        h2 = m_y * (rw1 / c1 + rw2 / c2) / sd - rw2 * s2 / c2
        h1 = h2 * cd + rw2 * (s1 + s2 * cd) / c2
    d1 = rw1 * c1 / s1 - h1 if s1 > 0 else math.inf
    d2 = rw2 * c2 / s2 - h2 if s2 > 0 else math.inf
    P = (float(rw1 * q / c1), float(rw1 * m_y / c1), float(h1))
    normal = (float(q), float(m_y), float(-s1))
    return P, normal, float(h1), float(h2), float(d1), float(d2)


def _lines_of_action(P, alpha_nw, beta_w1, gamma_w1):
    """Unit normals of the working rack's R and L flanks at P in Sf (module docstring of rack.py)."""
    a1 = np.array([0.0, 0.0, 1.0])
    e1 = np.array([P[0], P[1], 0.0]) / math.hypot(P[0], P[1])
    t1 = np.cross(a1, e1)
    sa, ca = math.sin(alpha_nw), math.cos(alpha_nw)
    sb, cb = math.sin(beta_w1), math.cos(beta_w1)
    sg, cg = math.sin(gamma_w1), math.cos(gamma_w1)
    out = []
    for sign in (1.0, -1.0):  # R, L
        n = (
            sign * ca * cb * t1
            + (sa * cg - sign * ca * sb * sg) * e1
            + (sa * sg + sign * ca * sb * cg) * a1
        )
        out.append(tuple(float(x) for x in -n))
    return tuple(out)


def design_pair(spec: PairSpec, *, with_checks: bool = True) -> PairDesign:
    """Design a crossed beveloid pair (paper Fig. 5); see the module docstring.

    Raises :class:`InputError` when the specification is invalid or eqs (18)-(19) have
    no solution (the message names the offending input and the valid range).
    """
    from ..errors import expect_type

    expect_type(spec, PairSpec, "design_pair: spec", "PairSpec.from_scene(scene)")
    spec.validate()
    if spec.design_mode == "target_fpd":
        from .target import solve_cone_angle_for_fpd

        spec = spec.with_pinion(cone_angle=solve_cone_angle_for_fpd(spec))
    pi, ge = spec.pinion, spec.gear
    sol = solve_spec(spec)
    if not bool(sol["ok"]):
        raise _no_solution_error(spec)
    w = {k: float(v) for k, v in sol.items() if k not in ("fpd_parts", "ok", "iterations")}
    xi, beta2 = w["xi_n"], w["beta2"]
    if abs(math.degrees(beta2)) > HELIX_LIMIT_DEG:
        raise InputError(
            Problem(
                "pair.offset_mm",
                spec.offset * 1e3,
                f"gives a gear helix angle beta_2 = {math.degrees(beta2):.2f} deg (eqs "
                f"(18)-(19)), outside [-{HELIX_LIMIT_DEG:g}, {HELIX_LIMIT_DEG:g}] deg, the "
                "range of a helix angle here (pair.shaft_angle_deg, the teeth and the "
                "cone angles set it with the offset)",
            ),
            "no usable design",
        )
    xt2 = backlash_free_xt2(spec, beta2, xi) if spec.backlash_free else ge.profile_shift_xt
    if spec.backlash_free and not XT_RANGE[0] <= xt2 <= XT_RANGE[1]:
        raise _profile_shift_error(spec, xt2)
    P, normal, h1, h2, d1, d2 = _cone_construction(spec.offset, spec.shaft_angle, w)
    (fr1, fl1), (fr2, fl2) = (tuple(float(x) for x in part) for part in sol["fpd_parts"])
    a_n, m_n = spec.normal_pressure_angle, spec.normal_module
    pinion = _gear_design(pi, pi.helix_angle, pi.profile_shift_xt, xi, a_n, m_n, d1, h1, (fr1, fl1))
    gear = _gear_design(ge, beta2, xt2, xi, a_n, m_n, d2, h2, (fr2, fl2))
    sd, cd = math.sin(spec.shaft_angle), math.cos(spec.shaft_angle)
    design = PairDesign(
        spec=spec,
        normal_angular_factor=xi,
        working_normal_pressure_angle=w["alpha_nw"],
        working_normal_module=m_n / xi,
        fpd_angle_right=w["fpd_right"],
        fpd_angle_left=w["fpd_left"],
        pinion=pinion,
        gear=gear,
        pitch_point=P,
        pitch_plane_normal=normal,
        gear_axis=(0.0, sd, cd),
        line_of_action=_lines_of_action(P, w["alpha_nw"], w["bw1"], w["gw1"]),
        iterations=int(sol["iterations"]),
        residual=w["residual"],
    )
    if with_checks:
        from .checks import design_checks

        design = PairDesign(**{**design.__dict__, "checks": design_checks(design)})
    return design

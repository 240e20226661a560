"""Analytical compliance of one thin tooth slice and of the contact between two.

Tooth (per unit face width, load along the transverse line of action), the
potential-energy beam model of a variable-section cantilever on an elastic
foundation:

- bending, shear and axial compression of the tooth from the root circle to the
  load point: Yang, D.C.H., Lin, J.Y., "Hertzian damping, tooth friction and bending
  elasticity in gear impact dynamics", J. Mech. Transm. Autom. Des. 109 (1987)
  189-196 (bending); Tian, X., "Dynamic simulation for system response of gearbox
  including localized gear faults", MSc thesis, University of Alberta (2004),
  section 3.2 (shear and axial compression). The integrals are evaluated on the real
  section (involute above the base circle, radial flank between root and base circle
  as in Tian) by Gauss-Legendre quadrature, so a beveloid slice with its local profile
  shift uses the same code;
- fillet-foundation flexibility: Sainsot, P., Velex, P., Duverger, O., "Contribution
  of gear body to tooth deflections - a new bidimensional analytical formula",
  J. Mech. Des. 126 (2004) 748-752, eq. (8) with the coefficients of its Table 1.

The fillet-foundation term holds the torsion of the gear body between the bore and
the root circle: its dependence on the bore (through ``r_f / r_int``) is that of an
annulus twisted by the tooth force's moment, :func:`body_torsion` (bore ratio 2 -> 6
on case 03's grid, both gears, normal and transverse sections: the growth of
Sainsot's term over the torsion's is 0.967 to 1.070, ``tests/test_ltca_lte_ripple.py``).
That torsion is a rigid rotation of the rim shared by every tooth in mesh, so the
fast level takes it out of the slices and adds it once per gear
(:class:`~gearbox.ltca.compliance.FastCompliance`).

Contact flattening (local, per unit length of contact line): Weber's line-load
formula for each body, ``w_i = 2 q (1 - nu^2) / (pi E) [ln(2 h_i / a) - nu / (2 (1 - nu))]``
with the Hertz half-width ``a = sqrt(8 q R (1 - nu^2) / (pi E))`` (equal materials),
h_i the depth of the reference point below the contact: Weber, C., Banaschek,
K., "Formänderung und Profilrücknahme bei gerad- und schrägverzahnten Rädern",
Schriftenreihe Antriebstechnik 11, Vieweg (1953). It is load dependent (weakly,
through ln a); :func:`weber_approach` returns the approach for a given line load.
The formula is the plane-strain half-plane's: the approach of the surface under a
Hertzian line load relative to the point at depth h on the load's line of action.
Weber and Banaschek take h down to the tooth's centre line, where the beam model
takes over; :class:`~gearbox.ltca.compliance.FastCompliance` offers that
(``contact="centre_line"``, the default) and the FE level's matching depth
(``contact="matching_depth"``), below which the FE level reads the tooth from its
mesh and the fast level from the slices (docs/ltca.md, "The contact term").
"""

from __future__ import annotations

import numpy as np

from ..geometry.involute import inv

__all__ = [
    "SliceCompliance",
    "body_torsion",
    "foundation_compliance",
    "hertz_half_width",
    "normal_section",
    "slice_compliance",
    "weber_approach",
]

# Sainsot et al. (2004) Table 1: X* = A/theta_f^2 + B h_f^2 + C h_f/theta_f + D/theta_f + E h_f + F
_SAINSOT = {
    "L": (-5.574e-5, -1.9986e-3, -2.3015e-4, 4.7702e-3, 0.0271, 6.8045),
    "M": (60.111e-5, 28.100e-3, -83.431e-4, -9.9256e-3, 0.1624, 0.9086),
    "P": (-50.952e-5, 185.50e-3, 0.0538e-4, 53.300e-3, 0.2895, 0.9236),
    "Q": (-6.2042e-5, 9.0889e-3, -4.0964e-4, 7.8297e-3, -0.1472, 0.6904),
}

_GL_X, _GL_W = np.polynomial.legendre.leggauss(16)


def _sainsot(name, hf, tf):
    a, b, c, d, e, f = _SAINSOT[name]
    return a / tf**2 + b * hf**2 + c * hf / tf + d / tf + e * hf + f


def _half_angle(rho, rb, psi_b):
    """Half tooth-thickness angle at radius rho: involute above the base circle,
    radial flank below it (Tian 2004)."""
    ca = np.clip(rb / np.maximum(rho, rb), -1.0, 1.0)
    alpha = np.arccos(ca)
    return np.where(rho > rb, psi_b - inv(alpha), psi_b)


def _dhalf_angle(rho, rb):
    """d psi / d rho: -tan^2(alpha) d alpha/d rho = -sqrt(rho^2 - rb^2) / rho^2 above rb."""
    above = rho > rb
    return np.where(above, -np.sqrt(np.maximum(rho**2 - rb**2, 0.0)) / rho**2, 0.0)


def _centre_x(rho, rb, psi_b):
    """Distance along the tooth's centre line of the flank point at radius rho."""
    return rho * np.cos(_half_angle(rho, rb, psi_b))


def _fillet_x(phi, r, sc, yc, rho):
    """Distance along the tooth's centre line of the fillet point cut at phi."""
    radius, psi = _fillet_points(phi, r, sc, yc, rho)
    return radius * np.cos(psi)


def _bisect(f, target, lo, hi, steps=50):
    """The parameter in [lo, hi] where the increasing f reaches target (clipped to the
    ends), elementwise by bisection."""
    lo, hi = np.array(lo, float), np.array(hi, float)
    below = f(lo) >= target
    above = f(hi) <= target
    a, b = lo.copy(), hi.copy()
    for _ in range(steps):
        m = 0.5 * (a + b)
        up = f(m) < target
        a, b = np.where(up, m, a), np.where(up, b, m)
    return np.where(below, lo, np.where(above, hi, 0.5 * (a + b)))


class SliceCompliance(tuple):
    """(bending, shear, axial, foundation) compliances per unit face width (m^2/N
    ... i.e. deflection along the load per line load, m per N/m), each shape (n,)."""

    __slots__ = ()

    @property
    def total(self) -> np.ndarray:
        return self[0] + self[1] + self[2] + self[3]


def fillet_root(sections, normal: bool = True):
    """Where the generated fillet meets the root circle, and the fillet's extent.

    The fillet of a tooth generated by a rack is the envelope of the rack's tip round
    (radius rho_fP m_n); its lowest point, on the root circle, is cut when the round's
    centre passes over the pitch point, so it lies at the polar angle ``s_c / r`` from
    the tooth's centre line, s_c the distance of the round's centre from that line
    along the generating pitch line (radius r): ``s_c = pi m / 4 + x m_n tan(alpha) +
    y_c tan(alpha) + rho / cos(alpha)``, ``y_c = (h_fP - x) m_n - rho`` the centre's
    depth below the pitch line. normal: the sections are virtual spur sections of the
    normal section (module m_n, pressure angle alpha_n, :func:`normal_section`), else
    transverse sections (m_t, alpha_t; the round taken as a circle of radius rho_fP m_n
    there too, exact for spur teeth). Returns ``(theta_f, r, s_c, y_c, rho, alpha)``,
    each shape (n,): the root half-angle including the fillets and the rack data.

    A profile shift above ``h_fP - rho_fP`` puts the round's centre above the pitch
    line (y_c < 0); at exactly that shift (y_c = 0) the round cuts its whole arc at one
    rolling angle, and y_c is taken 1e-9 m_n off the line (its sign kept), where the
    rolling angles of :func:`_fillet_points` still spread over that arc. (Such a
    section, x = 1.0 for the ISO 53 rack, is a node of the FE tooth tables' lattice: it
    had failed their factorisation, and a shift above it had lost its fillet.)
    """
    beta = 0.0 if normal else np.abs(sections.helix_angle)
    an = sections.normal_pressure_angle
    alpha = np.arctan(np.tan(an) / np.cos(beta))
    mn = sections.normal_module
    m = mn / np.cos(beta)
    r = sections.base_radius / np.cos(alpha)
    x = sections.profile_shift
    rho = sections.rack_root_radius * mn
    yc = (sections.rack_dedendum - x) * mn - rho
    yc = np.where(np.abs(yc) < 1e-9 * mn, np.where(yc < 0, -1e-9, 1e-9) * mn, yc)
    sc = 0.25 * np.pi * m + x * mn * np.tan(alpha) + yc * np.tan(alpha) + rho / np.cos(alpha)
    return sc / r, r, sc, yc, rho, alpha


def fillet_top(sections, normal: bool = True):
    """Where the tooth's outline passes from the fillet to the involute: ``(phi, rho)``,
    the rolling angle of the fillet point and its radius, each shape (n,).

    Without undercut the fillet ends where the rack's straight flank starts, ``phi_1 =
    (s_c + y_c / tan(alpha)) / r``, on the involute (or, should that point lie below the
    base circle, the outline takes the involute from the base circle). A tooth is
    undercut when that start lies deeper below the pitch line than the interference
    point, ``y_c + rho sin(alpha) > r sin^2(alpha)`` (ISO 21771's condition, the rack's
    form line below the line of action's end): the envelope of the straight flank then
    folds on the base circle, and the fillet cuts the regular involute above it, where
    the fillet's half-angle passes the involute's (found by bisection between the
    fillet's point on the base circle and phi_1); the outline is the fillet below that
    point and the involute above it (the same cut the generated surface makes,
    :func:`gearbox.surface.form_point`)."""
    _, rg, sc, yc, rr, alpha = fillet_root(sections, normal)
    rb = np.broadcast_to(np.asarray(sections.base_radius, float), np.shape(rg))
    psi_b = np.broadcast_to(np.asarray(sections.base_half_angle, float), np.shape(rg))
    phi0 = sc / rg
    phi1 = (sc + yc / np.tan(alpha)) / rg
    r_top, _ = _fillet_points(phi1, rg, sc, yc, rr)
    cut = yc + rr * np.sin(alpha) > rg * np.sin(alpha) ** 2
    if not np.any(cut):
        return phi1, np.maximum(r_top, rb)
    a = (rg, sc, yc, rr)
    phi_b = _bisect(lambda p: _fillet_points(p, *a)[0], rb, phi0, phi1)

    def gap(p):  # the fillet's half-angle less the involute's at the same radius
        rho, psi = _fillet_points(p, *a)
        return psi - _half_angle(rho, rb, psi_b)

    phi_c = _bisect(gap, 0.0, phi_b, phi1, steps=60)
    r_c, _ = _fillet_points(phi_c, *a)
    return np.where(cut, phi_c, phi1), np.where(cut, r_c, np.maximum(r_top, rb))


def _fillet_points(phi, r, sc, yc, rho):
    """Radius and half-angle (from the tooth's centre line) of the fillet point cut at
    rolling angle phi (arrays broadcast): the rack's tip-round centre C = (s_c - r phi,
    r - y_c) in the fixed frame, the point of the round whose normal passes through the
    pitch point P = (0, r) on the side towards the gear's axis, ``C - rho sgn(y_c) (P -
    C) / |P - C|`` (the far side from P when the centre lies below the pitch line, the
    near side when it lies above), turned back by phi into the gear's frame."""
    cx, cy = sc - r * phi, r - yc
    dx, dy = -cx, r - cy
    n = np.hypot(dx, dy) * np.where(yc < 0, -1.0, 1.0)
    fx, fy = cx - rho * dx / n, cy - rho * dy / n
    gx = np.cos(phi) * fx + np.sin(phi) * fy
    gy = -np.sin(phi) * fx + np.cos(phi) * fy
    return np.hypot(gx, gy), np.arctan2(gx, gy)


def slice_compliance(
    sections,
    youngs_modulus: float,
    poisson_ratio: float,
    *,
    root: str = "radial",
    normal: bool = True,
    beam_at: str = "load_point",
) -> SliceCompliance:
    """Tooth compliance of thin transverse slices for a load at ``sections.radius``.

    sections: :class:`~gearbox.ltca.grid.ToothSections` (arrays of shape (n,)).
    root: the tooth below the involute, ``"radial"`` (a radial flank from the base
    circle down to the root circle, Tian 2004, and Sainsot's root thickness
    ``2 r_f psi_b``) or ``"fillet"`` (the generated fillet, :func:`fillet_root`: the
    beam's section follows the trochoid of the rack's tip round from the root circle
    to where it meets the involute, and Sainsot's root thickness ``S_f = 2 r_f
    theta_f`` is the tooth's thickness at the root circle between the fillets' ends);
    normal: for ``"fillet"``, whether the sections are the normal section's virtual
    spur teeth (see :func:`fillet_root`).
    beam_at: where the beam's deflection along the load is taken, ``"load_point"``
    (the load's own displacement, the energy of the beam: Yang & Lin, Tian) or
    ``"centre_line"`` (the point where the load's line of action crosses the tooth's
    centre line, Maxwell-Mohr's unit-load integral ``int (M M_c / EI + 1.2 V V_c /
    GA + N N_c / EA) dx`` with the unit load at that point). Weber & Banaschek (1953)
    take the tooth's deflection there and the flattening from the contact down to
    it, and Sainsot's lever ``u_f`` is measured to it; the load point's deflection
    holds in addition the beam's shear strain along the load's line between the
    centre line and the flank, ``gamma h_L sin(alpha)``, which is largest where the
    beam is short (near the root: docs/ltca.md).
    Returns the bending, shear, axial and fillet-foundation parts (m per N/m of
    transverse line load, along the transverse line of action), each shape (n,).
    Vectorised: 32 quadrature nodes per point (48 with the fillet).
    """
    if root not in ("radial", "fillet"):
        raise ValueError(f"root must be 'radial' or 'fillet', not {root!r}")
    if beam_at not in ("load_point", "centre_line"):
        raise ValueError(f"beam_at must be 'load_point' or 'centre_line', not {beam_at!r}")
    E = youngs_modulus
    G = E / (2.0 * (1.0 + poisson_ratio))
    rL = sections.radius
    rb = sections.base_radius
    rf = sections.root_radius
    psi_b = sections.base_half_angle
    psi_L = _half_angle(rL, rb, psi_b)
    alpha_L = np.arccos(np.clip(rb / rL, -1.0, 1.0))
    a1 = alpha_L - psi_L  # load angle against the normal of the centre line
    xL = rL * np.cos(psi_L)
    hL = rL * np.sin(psi_L)
    cos1, sin1 = np.cos(a1), np.sin(a1)

    # the point the deflection is read at: the load point or, along the load's line
    # of action, the centre line (the unit load there has no lever h sin(alpha))
    if beam_at == "centre_line":
        xR, hR = xL - hL * np.tan(a1), np.zeros_like(hL)
    else:
        xR, hR = xL, hL

    def sums(w, x, h):
        inertia = 2.0 * h**3 / 3.0  # (2h)^3 / 12 per unit width
        area = 2.0 * h
        mb = (xL[:, None] - x) * cos1[:, None] - hL[:, None] * sin1[:, None]
        mr = (xR[:, None] - x) * cos1[:, None] - hR[:, None] * sin1[:, None]
        cb = np.sum(w * mb * mr / (E * inertia), axis=1)
        cs = np.sum(w * 1.2 * cos1[:, None] ** 2 / (G * area), axis=1)
        ca = np.sum(w * sin1[:, None] ** 2 / (E * area), axis=1)
        return cb, cs, ca

    def integrate(lo, hi):
        # Gauss-Legendre in rho on [lo, hi] (rows: points, cols: nodes)
        half = 0.5 * (hi - lo)
        rho = 0.5 * (hi + lo)[:, None] + half[:, None] * _GL_X[None, :]
        psi = _half_angle(rho, rb[:, None], psi_b[:, None])
        dpsi = _dhalf_angle(rho, rb[:, None])
        x = rho * np.cos(psi)
        dx = np.cos(psi) - rho * np.sin(psi) * dpsi  # dx/drho
        w = (_GL_W[None, :] * half[:, None]) * dx
        return sums(w, x, rho * np.sin(psi))

    if root == "fillet":
        _, rg, sc, yc, rr, alpha = fillet_root(sections, normal)
        # the fillet from the root circle (phi_0 = s_c / r) up to where the round's
        # normal is the flank's (phi_1 = (s_c + y_c / tan(alpha)) / r), in the rolling
        # angle; above it the involute
        phi0 = sc / rg
        phi1, top = fillet_top(sections, normal)
        rR = rL
        if beam_at == "centre_line":
            # the fillet up to the reading point where it lies below the fillet's top
            phi1 = _bisect(lambda p: _fillet_x(p, rg, sc, yc, rr), xR, phi0, phi1)
            rR = _bisect(lambda r: _centre_x(r, rb, psi_b), xR, np.minimum(top, rL), rL)
        half = 0.5 * (phi1 - phi0)
        phi = 0.5 * (phi0 + phi1)[:, None] + half[:, None] * _GL_X[None, :]
        a = (rg[:, None], sc[:, None], yc[:, None], rr[:, None])
        rho, psi = _fillet_points(phi, *a)
        eps = 1e-7 * np.abs(half)[:, None]
        rp_, pp_ = _fillet_points(phi + eps, *a)
        rm_, pm_ = _fillet_points(phi - eps, *a)
        dx = (rp_ * np.cos(pp_) - rm_ * np.cos(pm_)) / (2.0 * eps)  # dx/dphi
        w = _GL_W[None, :] * half[:, None] * dx
        cb1, cs1, ca1 = sums(w, rho * np.cos(psi), rho * np.sin(psi))
        cb2, cs2, ca2 = integrate(np.minimum(top, rR), rR)
    else:
        rR = rL
        if beam_at == "centre_line":
            rR = _bisect(lambda r: _centre_x(r, rb, psi_b), xR, np.minimum(rf, rb), rL)
        # segment 1: root circle to base circle (radial flank), only where rf < rb
        lo1 = np.minimum(rf, rb)
        hi1 = np.maximum(np.minimum(rb, rR), lo1)
        cb1, cs1, ca1 = integrate(lo1, hi1)
        # segment 2: involute from max(rf, rb) to the load point
        lo2 = np.maximum(rf, rb)
        cb2, cs2, ca2 = integrate(lo2, np.maximum(rR, lo2))
    cf = foundation_compliance(sections, E, root=root, normal=normal)
    return SliceCompliance((cb1 + cb2, cs1 + cs2, ca1 + ca2, cf))


def foundation_compliance(
    sections, youngs_modulus: float, *, root: str = "radial", normal: bool = True
) -> np.ndarray:
    """Sainsot's fillet foundation (Sainsot et al. 2004, eq. (8)), the fourth part of
    :func:`slice_compliance` and on its own for the plane-strain tooth (m per N/m of
    transverse line load), shape (n,): root thickness ``S_f = 2 r_f psi_f`` (``root``
    as in :func:`slice_compliance`), lever ``u_f`` from the root circle to where the
    load's line crosses the centre line, a1 the load's angle to the centre line's
    normal."""
    rL, rb, rf = sections.radius, sections.base_radius, sections.root_radius
    psi_b = sections.base_half_angle
    psi_L = _half_angle(rL, rb, psi_b)
    a1 = np.arccos(np.clip(rb / rL, -1.0, 1.0)) - psi_L
    if root == "fillet":
        psi_f, rg, _, yc, rr, _ = fillet_root(sections, normal)
        rf = rg - yc - rr  # the rack's root circle, where the fillet ends
    else:
        psi_f = _half_angle(rf, rb, psi_b)
    uf = rL * np.cos(psi_L) - rL * np.sin(psi_L) * np.tan(a1) - rf * np.cos(psi_f)
    sf = 2.0 * rf * psi_f
    L, M, P, Q = (_sainsot(k, rf / sections.bore_radius, psi_f) for k in "LMPQ")
    return (
        np.cos(a1) ** 2
        / youngs_modulus
        * (L * (uf / sf) ** 2 + M * (uf / sf) + P * (1.0 + Q * np.tan(a1) ** 2))
    )


def body_torsion(sections, shear_modulus: float) -> np.ndarray:
    """Torsion of the gear body (an annulus from the bore to the root circle, clamped
    at the bore) per unit face width, along the transverse line of action (m per N/m),
    shape (n,).

    A line load q on the line of action at the base radius r_b twists the annulus by
    the moment ``q r_b``: its shear stress ``tau = q r_b / (2 pi r^2)`` rotates the
    root circle by ``q r_b (1/r_i^2 - 1/r_f^2) / (4 pi G)`` (plane torsion of a
    disc, the same in plane stress and plane strain), so the load point moves
    ``r_b^2 (1/r_i^2 - 1/r_f^2) / (4 pi G)`` per unit line load along the line of action.
    """
    rb = sections.base_radius
    return (
        rb**2
        * (1.0 / sections.bore_radius**2 - 1.0 / sections.root_radius**2)
        / (4.0 * np.pi * shear_modulus)
    )


def normal_section(sections):
    """The virtual spur sections in the normal section of helical (or beveloid) slices.

    ISO 6336-1 (and Weber's and Schmidt's theory behind its c'_th) take a helical tooth
    as the spur tooth of its normal section, the virtual gear with
    ``z_n = z / (cos^2 beta_b cos beta)``, module m_n, pressure angle alpha_n and the
    normal profile-shift coefficient, loaded per unit length of the tooth. Heights above
    the reference circle are kept (load point, root and tip circles); the bore keeps its
    ratio to the root radius. Returns ``(sections, factor)``: the virtual sections
    (:class:`~gearbox.ltca.grid.ToothSections`) and ``cos beta``, the factor that
    turns the virtual slice's compliance per unit tooth length into the compliance
    along the flank normal per unit face width (a face width w holds w / cos beta of
    tooth length). For beta = 0 the sections are returned unchanged and the factor is 1.
    """
    from dataclasses import replace

    beta = np.abs(sections.helix_angle)
    an = sections.normal_pressure_angle
    mn = sections.normal_module
    beta_b = np.arcsin(np.sin(beta) * np.cos(an))
    zv = sections.teeth / (np.cos(beta_b) ** 2 * np.cos(beta))
    rp = sections.teeth * mn / (2.0 * np.cos(beta))
    rv = 0.5 * zv * mn
    rbv = rv * np.cos(an)
    psi_b = (0.5 * np.pi + 2.0 * sections.profile_shift * np.tan(an)) / zv + inv(an)
    d = rv - rp
    r_load = np.maximum(sections.radius + d, rbv * (1.0 + 1e-9))
    rf = sections.root_radius + d
    virtual = replace(
        sections,
        radius=r_load,
        base_radius=rbv,
        root_radius=rf,
        tip_radius=np.maximum(sections.tip_radius + d, r_load),
        bore_radius=rf * sections.bore_radius / sections.root_radius,
        base_half_angle=psi_b,
        teeth=zv,
    )
    return virtual, np.cos(beta)


def hertz_half_width(line_load, curvature_radius, youngs_modulus, poisson_ratio):
    """Hertz half-width a (m) of a line contact of equal materials (Johnson, Contact
    Mechanics, 1985, eq. (4.43)): a^2 = 4 q R / (pi E*), E* = E / (2 (1 - nu^2))."""
    e_star = youngs_modulus / (2.0 * (1.0 - poisson_ratio**2))
    return np.sqrt(4.0 * np.maximum(line_load, 0.0) * curvature_radius / (np.pi * e_star))


def hertz_pressure(line_load, curvature_radius, youngs_modulus, poisson_ratio):
    """Maximum Hertz pressure p0 = 2 q / (pi a) (Pa) of a line contact
    (Johnson 1985, eq. (4.45))."""
    a = hertz_half_width(line_load, curvature_radius, youngs_modulus, poisson_ratio)
    return np.where(
        a > 0, 2.0 * np.maximum(line_load, 0.0) / (np.pi * np.where(a > 0, a, 1.0)), 0.0
    )


def weber_approach(line_load, curvature_radius, h1, h2, youngs_modulus, poisson_ratio):
    """Approach of two teeth by contact flattening (m), Weber & Banaschek (1953).

    line_load: q (N/m of contact line), curvature_radius: R (m), h1, h2: depth of
    each tooth's reference point below the contact (m; Weber: the distance from the
    tooth's centre line). Arrays broadcast. The logarithm
    is floored at 1 (a >= 2h/e) so that a vanishing load gives a vanishing approach.
    """
    nu = poisson_ratio
    q = np.maximum(line_load, 0.0)
    a = hertz_half_width(q, curvature_radius, youngs_modulus, nu)
    a = np.maximum(a, 1e-12)
    k = 2.0 * q * (1.0 - nu**2) / (np.pi * youngs_modulus)
    t1 = np.maximum(np.log(2.0 * h1 / a), 1.0) - nu / (2.0 * (1.0 - nu))
    t2 = np.maximum(np.log(2.0 * h2 / a), 1.0) - nu / (2.0 * (1.0 - nu))
    return k * (t1 + t2)

"""Mesh tables from an analytical stiffness model (before, or beside, the loaded TCA).

Model (parallel-axis involute helical equivalent of the pair, at the reference section):

- Mean mesh stiffness from ISO 6336-1:2019, tooth stiffness method B (evaluated by
  :mod:`gearbox.ltca.iso6336`, which is checked against a published worked report): the theoretical
  single stiffness ``c'_th = 1/q'`` with ``q'`` the regression in the virtual tooth
  numbers ``z_n = z / (cos^2 beta_b cos beta)`` and the profile shifts (coefficients
  C1..C9 = 0.04723, 0.15551, 0.25791, -0.00635, -0.11654, -0.00193, -0.24188, 0.00529,
  0.00182; q' in mm um/N), then ``c' = c'_th C_M C_R C_B cos(beta)`` with C_M = 0.8
  (solid disc gears), C_R = 1 (solid blanks),
  ``C_B = [1 + 0.5 (1.2 - h_fP/m_n)] [1 - 0.02 (20 deg - alpha_n)]``, the load
  correction ``(F_t/b / 100 N/mm)^0.25`` below 100 N/mm, and the mesh stiffness
  ``c_gamma_alpha = c' (0.75 eps_alpha + 0.25)`` (N/(mm um)).
- ``c_gamma_alpha b`` is the stiffness in the transverse plane along the base tangent
  (ISO's convention); along the line of action n (normal to the flank) it is
  ``k_mean = c_gamma_alpha b / cos^2(beta_b)``, so that both give the same resonance
  (ISO 6336-1:2019, resonance speed with the reduced mass ``J / r_b^2``).
- Variation over the mesh cycle: stiffness per unit length of contact line constant,
  so ``k(theta) = k_mean L(theta) / mean(L)`` with ``L`` the total length of the
  contact lines in the field of action (rectangle eps_alpha p_bt by b in the base
  plane, lines inclined at beta_b); the usual "contact line length" model of helical
  gear mesh stiffness (e.g. Velex & Maatar, J. Sound Vib. 191 (1996), section 2).
- Loaded transmission error ``LTE = F_n / k(theta)`` (linear mesh: secant = tangent
  stiffness), ``F_n = T / (r_b1 cos beta_b)``.

Geometry: ISO 21771 involute helical relations (transverse pressure angle, working
pressure angle from the profile shift sum, tip radii ``r + m_n (h_a + x_n)``, transverse
contact ratio eps_alpha, overlap ratio eps_beta = b sin|beta| / (pi m_n)).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .errors import Problems
from .meshtable import FRICTION_ARMS, MeshTable

__all__ = [
    "HelicalPair",
    "analytical_table",
    "contact_line_length",
    "friction_arms",
    "iso_mesh_stiffness",
    "pair_from_scene",
]


def _inv(a: float) -> float:
    return math.tan(a) - a


def _inv_inverse(v: float) -> float:
    """Inverse involute by a capped Newton iteration (raises if it does not converge)."""
    a = (3.0 * v) ** (1 / 3) if v > 0 else 0.0
    for _ in range(50):
        f = _inv(a) - v
        da = f / (math.tan(a) ** 2 + 1e-300)
        a -= da
        if abs(da) < 1e-15:
            return a
    raise ArithmeticError(f"inverse involute of {v!r} did not converge")


@dataclass(frozen=True)
class HelicalPair:
    """Parallel-axis involute helical pair (SI).

    teeth: (N_1, N_2); normal_module (m); normal_pressure_angle (rad);
    helix_angle (rad, pinion; the gear has the opposite hand); face_width (m);
    profile_shift: normal profile-shift coefficients (x_n1, x_n2);
    addendum: h_a / m_n; dedendum_tool: h_fP / m_n of the basic rack.
    """

    teeth: tuple[int, int]
    normal_module: float
    normal_pressure_angle: float
    helix_angle: float
    face_width: float
    profile_shift: tuple[float, float] = (0.0, 0.0)
    addendum: float = 1.0
    dedendum_tool: float = 1.25

    def __post_init__(self):
        p = Problems()
        for i, z in enumerate(self.teeth):
            p.check(z >= 5, f"teeth[{i}]", z, "must be >= 5")
        p.in_range("normal_module", self.normal_module, 0, None, lo_open=True)
        p.in_range(
            "normal_pressure_angle", self.normal_pressure_angle, 0, math.pi / 4, lo_open=True
        )
        p.in_range("helix_angle", self.helix_angle, -math.pi / 3, math.pi / 3)
        p.in_range("face_width", self.face_width, 0, None, lo_open=True)
        p.raise_if_any("invalid helical pair")

    # ISO 21771 relations ----------------------------------------------------
    @property
    def beta(self) -> float:
        return abs(self.helix_angle)

    @property
    def transverse_module(self) -> float:
        return self.normal_module / math.cos(self.beta)

    @property
    def transverse_pressure_angle(self) -> float:
        return math.atan(math.tan(self.normal_pressure_angle) / math.cos(self.beta))

    @property
    def base_helix_angle(self) -> float:
        return math.asin(math.sin(self.beta) * math.cos(self.normal_pressure_angle))

    def pitch_radius(self, i: int) -> float:
        return self.transverse_module * self.teeth[i] / 2

    def base_radius(self, i: int) -> float:
        return self.pitch_radius(i) * math.cos(self.transverse_pressure_angle)

    @property
    def working_pressure_angle(self) -> float:
        z1, z2 = self.teeth
        x1, x2 = self.profile_shift
        v = _inv(self.transverse_pressure_angle) + 2 * math.tan(self.normal_pressure_angle) * (
            x1 + x2
        ) / (z1 + z2)
        return _inv_inverse(v)

    @property
    def centre_distance(self) -> float:
        a = self.pitch_radius(0) + self.pitch_radius(1)
        return a * math.cos(self.transverse_pressure_angle) / math.cos(self.working_pressure_angle)

    def tip_radius(self, i: int) -> float:
        return self.pitch_radius(i) + self.normal_module * (self.addendum + self.profile_shift[i])

    @property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt (m)."""
        return math.pi * self.transverse_module * math.cos(self.transverse_pressure_angle)

    @property
    def path_of_contact(self) -> float:
        """Length of the transverse path of contact g_alpha (m)."""
        g = -self.centre_distance * math.sin(self.working_pressure_angle)
        for i in (0, 1):
            g += math.sqrt(self.tip_radius(i) ** 2 - self.base_radius(i) ** 2)
        return g

    @property
    def contact_ratio(self) -> float:
        """Transverse contact ratio eps_alpha."""
        return self.path_of_contact / self.base_pitch

    @property
    def overlap_ratio(self) -> float:
        """Overlap ratio eps_beta = b sin|beta| / (pi m_n)."""
        return self.face_width * math.sin(self.beta) / (math.pi * self.normal_module)

    def virtual_teeth(self, i: int) -> float:
        bb = self.base_helix_angle
        return self.teeth[i] / (math.cos(bb) ** 2 * math.cos(self.beta))


def iso_mesh_stiffness(pair: HelicalPair, torque: float) -> tuple[float, float]:
    """(c', c_gamma_alpha) of ISO 6336-1 method B (N/(mm um)) at pinion ``torque`` (N m).

    Evaluated by :func:`gearbox.ltca.iso6336.iso_mesh_stiffness` (checked against a
    published worked report there), with the load per face width ``T / r_1 / b``.
    """
    from .ltca.iso6336 import iso_mesh_stiffness as _iso

    s = _iso(
        teeth=pair.teeth,
        helix_angle=pair.beta,
        normal_pressure_angle=pair.normal_pressure_angle,
        profile_shift=pair.profile_shift,
        transverse_contact_ratio=pair.contact_ratio,
        load_per_width=torque / pair.pitch_radius(0) / pair.face_width,
        dedendum_coefficient=(pair.dedendum_tool, pair.dedendum_tool),
    )
    return s.c_prime * 1e-9, s.c_gamma_alpha * 1e-9  # N/m^2 -> N/(mm um)


def contact_line_length(pair: HelicalPair, theta: np.ndarray) -> np.ndarray:
    """Total length of the contact lines (m) at pinion angles ``theta`` (rad), shape as theta.

    Field of action unrolled on the base plane: transverse coordinate s in [0, g_alpha],
    axial z in [0, b]; line j lies on s = s_j + z tan(beta_b), s_j = r_b1 theta + j p_bt
    (modulo the base pitch), length inside the rectangle over cos(beta_b).
    """
    th = np.asarray(theta, dtype=float)
    g = pair.path_of_contact
    pb = pair.base_pitch
    b = pair.face_width
    tb = math.tan(pair.base_helix_angle)
    cb = math.cos(pair.base_helix_angle)
    s0 = np.mod(pair.base_radius(0) * th, pb)
    total = np.zeros_like(s0)
    jmax = int(math.ceil((g + b * tb) / pb)) + 2
    for j in range(-jmax, jmax + 1):
        sj = s0 + j * pb
        if tb > 1e-12:
            z_lo = np.clip((0.0 - sj) / tb, 0.0, b)
            z_hi = np.clip((g - sj) / tb, 0.0, b)
            total += np.maximum(z_hi - z_lo, 0.0) / cb
        else:
            total += np.where((sj >= 0) & (sj < g), b, 0.0)
    return total


def friction_arms(pair: HelicalPair, theta: np.ndarray, flank: str = "drive") -> np.ndarray:
    """Moment arms (m) of the sliding friction about the pinion's and the gear's axis,
    the load spread evenly along the contact lines, at pinion angles ``theta`` (rad);
    shape theta + (2,). Conventions of :meth:`gearbox.ltca.grid.ContactGrid.friction_arms`.

    In a parallel involute pair the flanks slide along the profile, in the transverse
    plane: friction at roll distance x from the pinion's base-circle tangent point T_1
    acts at the arm x about the pinion's axis and T_1T_2 - x about the gear's, and
    reverses at the pitch point x_c = r_b1 tan(alpha_wt): arm_1 = sgn(x - x_c) x,
    arm_2 = sgn(x - x_c) (T_1T_2 - x) (e.g. Vaishya & Singh, J. Sound Vib. 243 (2001)).
    On the coast flank the contact runs along its path the other way: its roll distance
    is the drive flank's mirrored about the path's middle.
    """
    th = np.asarray(theta, dtype=float)
    g = pair.path_of_contact
    pb = pair.base_pitch
    b = pair.face_width
    tb = math.tan(pair.base_helix_angle)
    aw = pair.working_pressure_angle
    rb1 = pair.base_radius(0)
    line = pair.centre_distance * math.sin(aw)  # T_1 T_2
    xc = rb1 * math.tan(aw)
    xa = math.sqrt(pair.tip_radius(1) ** 2 - pair.base_radius(1) ** 2)
    xa = line - xa  # start of the path (the gear's tip) from T_1

    def prim1(x):  # integral of sgn(x - xc) x
        return np.abs(x - xc) * (x + xc) / 2

    def prim2(x):  # integral of sgn(x - xc) (line - x)
        return line * np.abs(x - xc) - prim1(x)

    s0 = np.mod(rb1 * th, pb)
    num = np.zeros(th.shape + (2,))
    den = np.zeros(th.shape)
    jmax = int(math.ceil((g + b * tb) / pb)) + 2
    for j in range(-jmax, jmax + 1):
        sj = s0 + j * pb
        if tb > 1e-12:
            lo = np.clip(sj, 0.0, g)
            hi = np.clip(sj + b * tb, 0.0, g)
            if flank != "drive":
                lo, hi = g - hi, g - lo
            x0, x1 = xa + lo, xa + hi
            num[..., 0] += prim1(x1) - prim1(x0)
            num[..., 1] += prim2(x1) - prim2(x0)
            den += hi - lo
        else:
            on = (sj >= 0) & (sj < g)
            x = xa + (sj if flank == "drive" else g - sj)
            sg = np.sign(x - xc)
            num[..., 0] += np.where(on, sg * x, 0.0)
            num[..., 1] += np.where(on, sg * (line - x), 0.0)
            den += on
    return num / den[..., None]


def analytical_table(
    pair: HelicalPair,
    torques,
    *,
    positions: int = 48,
    flanks: tuple[str, ...] = ("drive", "coast"),
    scene: str = "",
) -> MeshTable:
    """A :class:`MeshTable` from ISO 6336-1 method B and the contact line length.

    torques: pinion torque levels (N m), increasing. positions: per mesh cycle (>= 4).
    Frame (the table's Sf): pinion axis +z through the origin; gear axis -z through
    (r_w1 (1 + N_2/N_1), 0, 0), so that the rotation radii keep the tooth ratio
    (lambda_2 / lambda_1 = N_2 / N_1); mesh point at the pinion's working pitch radius
    r_w1 on +x; drive line of action (-sin a_wt cos b_b, cos a_wt cos b_b, sin b_b). Drive and coast flanks
    have the same stiffness; on the coast flank the tangential force and the axial thrust of the helical
    teeth reverse while the radial component stays: (-sin a_wt cos b_b, -cos a_wt cos b_b, -sin b_b).
    """
    from . import __version__

    tq = np.asarray(torques, dtype=float)
    p = Problems()
    p.check(positions >= 4, "positions", positions, "must be >= 4")
    p.check(tq.size >= 1 and bool(np.all(tq > 0)), "torques", tq.tolist(), "must be > 0 N m")
    p.raise_if_any("invalid analytical mesh table request")
    z1, z2 = pair.teeth
    period = 2 * math.pi / z1
    angle = np.arange(positions) * (period / positions)
    length = contact_line_length(pair, angle)
    # Mean over a fine grid (the table grid may be coarse).
    fine = contact_line_length(pair, np.arange(4096) * (period / 4096))
    shape_factor = length / fine.mean()
    bb = pair.base_helix_angle
    aw = pair.working_pressure_angle
    r1 = pair.centre_distance * z1 / (z1 + z2)
    lam1 = r1 * math.cos(aw) * math.cos(bb)
    # the force of the pinion on the gear (the pinion flank's outward normal, as the
    # TCA's and the loaded TCA's on the same scene): the separating radial part towards
    # the gear (+x), tangential, the thrust of a positive helix angle towards -z
    nd = np.array([math.sin(aw) * math.cos(bb), math.cos(aw) * math.cos(bb), -math.sin(bb)])
    nc = np.array([nd[0], -nd[1], -nd[2]])  # coast: tangential force and axial thrust reverse
    P = np.array([r1, 0.0, 0.0])
    nf, nt = len(flanks), tq.size
    k = np.empty((nf, nt, positions))
    for j, t in enumerate(tq):
        _, cga = iso_mesh_stiffness(pair, float(t))
        kmean = cga * pair.face_width * 1e3 * 1e6 / math.cos(bb) ** 2  # N/(mm um) * mm -> N/m
        k[:, j, :] = kmean * shape_factor
    fn = (tq / lam1)[None, :, None]
    lte = fn / k
    mp = np.broadcast_to(P, (nf, nt, positions, 3)).copy()
    loa = np.empty((nf, nt, positions, 3))
    for i, f in enumerate(flanks):
        loa[i] = nd if f == "drive" else nc
    centre = r1 * (1 + z2 / z1)
    return MeshTable(
        pinion_teeth=z1,
        gear_teeth=z2,
        angle=angle,
        torque=tq,
        flanks=tuple(flanks),
        stiffness=k,
        tangent_stiffness=k.copy(),
        lte=lte,
        mesh_point=mp,
        line_of_action=loa,
        pinion_axis=np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]),
        gear_axis=np.array([[0.0, 0.0, -1.0], [centre, 0.0, 0.0]]),
        extra={
            "contact_line_length_m": np.broadcast_to(length, (nf, nt, positions)).copy(),
            **{
                name: np.stack(
                    [
                        np.broadcast_to(friction_arms(pair, angle, f)[:, i], (nt, positions))
                        for f in flanks
                    ]
                )
                for i, name in enumerate(FRICTION_ARMS)
            },
        },
        attrs={
            "scene": scene,
            "method": "analytical: ISO 6336-1:2019 method B mean stiffness, contact-line-length variation",
            "fidelity": "analytical",
            "gearbox_version": __version__,
            "frame": "parallel-axis equivalent: pinion axis +z at origin, mesh point on +x",
            "contact_ratio": pair.contact_ratio,
            "overlap_ratio": pair.overlap_ratio,
        },
    )


def pair_from_scene(scene) -> HelicalPair:
    """The parallel-axis equivalent of a scene's pair (reference sections, pinion helix).

    Normal profile shifts from the transverse ones by paper eq. (20),
    x_n = x_t cos(gamma) / cos(beta); the gear's x_t is the scene value, or the
    designed one when :mod:`gearbox.geometry` is available, else 0.
    """
    pr, pn, gr = scene["pair"], scene["pinion"], scene["gear"]
    beta = math.radians(pn["helix_angle_deg"])
    x1 = pn["profile_shift_xt"] * math.cos(math.radians(pn["cone_angle_deg"])) / math.cos(beta)
    xt2 = gr["profile_shift_xt"]
    beta2 = math.radians(gr["helix_angle_deg"]) if gr["helix_angle_deg"] is not None else beta
    if xt2 is None:
        try:
            from .geometry import PairSpec, design_pair

            des = design_pair(PairSpec.from_scene(scene))
            xt2 = des.gear.profile_shift_xt
            beta2 = des.gear.helix_angle
        except Exception:  # geometry stage unavailable or failing: plain numbers
            xt2 = 0.0
    x2 = xt2 * math.cos(math.radians(gr["cone_angle_deg"])) / math.cos(beta2)
    return HelicalPair(
        teeth=(pn["teeth"], gr["teeth"]),
        normal_module=pr["normal_module_mm"] * 1e-3,
        normal_pressure_angle=math.radians(pr["normal_pressure_angle_deg"]),
        helix_angle=beta,
        face_width=min(pn["face_width_mm"], gr["face_width_mm"]) * 1e-3,
        profile_shift=(x1, x2),
        addendum=scene["tool"]["gear_addendum_coefficient"],
        dedendum_tool=scene["tool"]["addendum_coefficient"],
    )

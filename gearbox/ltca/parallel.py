"""Parallel-axis involute pairs (spur and helical): the analytic reference geometry.

For parallel axes the contact lines lie in the plane of action and are straight,
inclined by the base helix angle beta_b (ISO 21771:2007, section 5), so the initial
separation of perfect involute flanks along every contact line is zero and the whole
loaded TCA input is known in closed form. This module builds that input
(:class:`~gearbox.ltca.grid.ContactGrid`) for any pinion position; the loaded TCA
then runs exactly as for the beveloid pair.

Plane-of-action coordinates: roll distance ``xi`` along the transverse line of
action, measured from the pinion's tangent point T1 (so the pinion's transverse
radius of curvature at the contact is ``xi``), and ``y`` along the face width from the
face middle. Contact line of tooth pair k: ``xi = xi_0 + k p_bt + y tan(beta_b)``.

Flank modifications (``parallel_grid(..., relief=...)``, one
:class:`gearbox.ltca.modification.FlankModification` per gear): the material removed at
the pinion radius ``sqrt(r_b1^2 + xi^2)`` and at the gear radius
``sqrt(r_b2^2 + (T1T2 - xi)^2)``, at the point's face position y (both gears), is the
separation there.
"""

from __future__ import annotations

import functools
import math
from dataclasses import asdict, dataclass

import numpy as np

from ..errors import InputError, Problem, Problems
from ..geometry.involute import inv
from .grid import ContactGrid, ToothSections

__all__ = ["ParallelPair", "parallel_grid"]


#: Fewest teeth of either gear
MIN_TEETH = 8


@dataclass(frozen=True)
class ParallelPair:
    """A parallel-axis external involute gear pair, SI.

    normal_module: m_n (m); normal_pressure_angle: alpha_n (rad); helix_angle: beta
    (rad, pinion; the gear has the opposite hand); teeth: (z1, z2); profile_shift:
    (x1, x2) normal coefficients; face_width: b (m); center_distance: a (m), ``None``
    for the backlash-free distance of the profile shifts; addendum_coefficient
    h_aP/m_n; dedendum_coefficient h_fP/m_n; root_radius_coefficient rho_fP/m_n
    of the basic rack (ISO 53 profile A: 1.25 and 0.38); bore_ratio: bore radius over root
    radius (the rim for the fillet-foundation term); youngs_modulus (Pa);
    poisson_ratio; misalignment: error of the (zero) shaft angle (rad): the gear axis
    turned about the centre line to the direction (0, sin g, cos g), as a shaft-angle
    error of :class:`gearbox.tca.assembly.AssemblyErrors` (|g| <= 0.035 rad); it enters
    the separations to first order in g (the rigid displacement of the gear flank along
    the contact normal), which suits the small errors of real assemblies.
    """

    normal_module: float
    normal_pressure_angle: float
    helix_angle: float
    teeth: tuple[int, int]
    profile_shift: tuple[float, float] = (0.0, 0.0)
    face_width: float = 0.04
    center_distance: float | None = None
    addendum_coefficient: float = 1.0
    dedendum_coefficient: float = 1.25
    root_radius_coefficient: float = 0.38
    bore_ratio: float = 0.5
    youngs_modulus: float = 206.0e9
    poisson_ratio: float = 0.3
    misalignment: float = 0.0

    def __post_init__(self):
        p = Problems()
        p.check(
            isinstance(self.normal_module, int | float) and 0.0 < self.normal_module <= 0.1,
            "normal_module",
            self.normal_module,
            "must be in (0, 0.1] m (SI: a 4 mm module is 0.004)",
        )
        p.in_range("normal_pressure_angle", self.normal_pressure_angle, 0.0, 0.7, lo_open=True)
        lim = math.radians(60.0)  # rad: the scene's +-60 deg
        p.in_range("helix_angle", self.helix_angle, -lim, lim)
        p.in_range("teeth[0]", self.teeth[0], MIN_TEETH, None)
        p.in_range("teeth[1]", self.teeth[1], MIN_TEETH, None)
        p.check(
            isinstance(self.face_width, int | float) and 0.0 < self.face_width <= 2.0,
            "face_width",
            self.face_width,
            "must be in (0, 2] m (SI: a 40 mm face is 0.04)",
        )
        p.in_range("bore_ratio", self.bore_ratio, 0.0, 0.95, lo_open=True)
        p.in_range("youngs_modulus", self.youngs_modulus, 0.0, None, lo_open=True)
        p.in_range("poisson_ratio", self.poisson_ratio, 0.0, 0.5, hi_open=True)
        p.in_range("misalignment", self.misalignment, -0.035, 0.035)
        p.raise_if_any("invalid parallel gear pair")
        object.__setattr__(self, "teeth", tuple(int(z) for z in self.teeth))
        object.__setattr__(self, "profile_shift", tuple(float(x) for x in self.profile_shift))

    # ---------------------------------------------------------------- derived
    @property
    def transverse_module(self) -> float:
        return self.normal_module / math.cos(self.helix_angle)

    @property
    def transverse_pressure_angle(self) -> float:
        """alpha_t (rad), tan alpha_t = tan alpha_n / cos beta."""
        return math.atan(math.tan(self.normal_pressure_angle) / math.cos(self.helix_angle))

    @property
    def base_helix_angle(self) -> float:
        """beta_b (rad), sin beta_b = sin beta cos alpha_n (magnitude)."""
        return math.asin(abs(math.sin(self.helix_angle)) * math.cos(self.normal_pressure_angle))

    def pitch_radius(self, i: int) -> float:
        return 0.5 * self.transverse_module * self.teeth[i]

    def base_radius(self, i: int) -> float:
        return self.pitch_radius(i) * math.cos(self.transverse_pressure_angle)

    def tip_radius(self, i: int) -> float:
        return self.pitch_radius(i) + self.normal_module * (
            self.addendum_coefficient + self.profile_shift[i]
        )

    def root_radius(self, i: int) -> float:
        return self.pitch_radius(i) - self.normal_module * (
            self.dedendum_coefficient - self.profile_shift[i]
        )

    @functools.lru_cache(maxsize=64)  # noqa: B019 - a frozen pair, a handful per process
    def form_radius(self, i: int) -> float:
        """Root form radius r_Ff (m): where the involute generated by the basic rack
        meets its fillet (ISO 21771:2007, d_Ff). On an undercut gear (the rack's
        straight flank starts below the interference point: ISO's roll length below
        0) where the fillet cuts the regular involute, from the generated flank
        (:func:`gearbox.surface.form_point`, the tool and blank of this gear)."""
        an, at = self.normal_pressure_angle, self.transverse_pressure_angle
        m = self.normal_module
        rise = m * (
            self.dedendum_coefficient
            - self.profile_shift[i]
            - self.root_radius_coefficient * (1.0 - math.sin(an))
        )
        roll = self.pitch_radius(i) * math.sin(at) - rise / math.sin(at)
        rb = self.base_radius(i)
        if roll > 0:
            return math.sqrt(rb**2 + roll**2)
        from ..surface import ToothBlank, flank_points, form_point

        blank = ToothBlank(
            teeth=self.teeth[i],
            normal_module=m,
            normal_pressure_angle=an,
            helix_angle=self.helix_angle,
            cone_angle=0.0,
            profile_shift_xt=self.profile_shift[i] * math.cos(self.helix_angle),
            face_width=self.face_width,
            tool_addendum=self.dedendum_coefficient * m,
            tool_tip_radius=self.root_radius_coefficient * m,
            addendum=self.addendum_coefficient * m,
        )
        z = np.zeros(1)
        return float(flank_points(blank, "R", z, form_point(blank, "R", z)[1]).radius[0])

    def base_half_angle(self, i: int) -> float:
        """Half tooth-thickness angle at the base circle psi_b (rad), ISO 21771:
        s_t / (2 r) + inv(alpha_t) with s_t = m_t (pi/2 + 2 x tan alpha_t)."""
        at = self.transverse_pressure_angle
        x = self.profile_shift[i]
        return (math.pi / 2 + 2 * x * math.tan(self.normal_pressure_angle)) / self.teeth[i] + inv(
            at
        )

    @property
    def working_pressure_angle(self) -> float:
        """alpha_wt (rad) at the centre distance."""
        if self.center_distance is None:
            z1, z2 = self.teeth
            at = self.transverse_pressure_angle
            y = inv(at) + 2 * math.tan(self.normal_pressure_angle) * sum(self.profile_shift) / (
                z1 + z2
            )
            return _inv_inverse(y)
        return math.acos((self.base_radius(0) + self.base_radius(1)) / self.center_distance)

    @property
    def working_center_distance(self) -> float:
        return (self.base_radius(0) + self.base_radius(1)) / math.cos(self.working_pressure_angle)

    @property
    def line_of_action_length(self) -> float:
        """T1 T2 (m), the transverse line of action between the tangent points."""
        return self.working_center_distance * math.sin(self.working_pressure_angle)

    @property
    def roll_limits(self) -> tuple[float, float]:
        """(xi_A, xi_E): pinion roll distances (m) of the start and end of the active
        path: the gear's tip and the pinion's tip, or a root form circle where a tip
        reaches below it (meshing interference, ISO 21771 d_Nf < d_Ff: the involute
        ends there, on an undercut gear where the fillet cuts it)."""
        rb1, rb2 = self.base_radius(0), self.base_radius(1)
        L = self.line_of_action_length
        xa = L - math.sqrt(self.tip_radius(1) ** 2 - rb2**2)
        xe = math.sqrt(self.tip_radius(0) ** 2 - rb1**2)
        xa = max(xa, math.sqrt(max(self.form_radius(0) ** 2 - rb1**2, 0.0)))
        xe = min(xe, L - math.sqrt(max(self.form_radius(1) ** 2 - rb2**2, 0.0)))
        return max(xa, 0.0), min(xe, L)

    @property
    def base_pitch(self) -> float:
        """Transverse base pitch p_bt (m)."""
        return 2 * math.pi * self.base_radius(0) / self.teeth[0]

    @property
    def transverse_contact_ratio(self) -> float:
        xa, xe = self.roll_limits
        return (xe - xa) / self.base_pitch

    @property
    def overlap_ratio(self) -> float:
        return self.face_width * abs(math.sin(self.helix_angle)) / (math.pi * self.normal_module)

    def to_dict(self) -> dict:
        d = asdict(self)
        d["teeth"] = list(self.teeth)
        d["profile_shift"] = list(self.profile_shift)
        return d

    @classmethod
    def from_dict(cls, d) -> ParallelPair:
        d = dict(d)
        d["teeth"] = tuple(d["teeth"])
        d["profile_shift"] = tuple(d["profile_shift"])
        return cls(**d)


def _inv_inverse(y: float) -> float:
    """Angle a in (0, pi/2) with tan(a) - a = y > 0: bracketed root (scipy brentq)."""
    from scipy.optimize import brentq

    if not y > 0:
        raise InputError(Problem("working pressure angle", y, "inv(alpha_wt) must be > 0"))
    return float(brentq(lambda a: inv(a) - y, 1e-6, 1.5, xtol=1e-15, rtol=1e-15, maxiter=200))


def parallel_grid(
    pair: ParallelPair, fraction: float, n_face: int = 40, relief=None
) -> ContactGrid:
    """Contact grid of a parallel involute pair at one pinion position.

    fraction: pinion position in mesh cycles (0 = the reference pair's contact line
    starts at the start of the active path at the face middle), any real.
    n_face: slices across the face width (cell centres).

    Every tooth pair whose contact line crosses the active flank gets one point per
    slice inside the active path; separations are zero (perfect involutes) unless
    ``relief`` = (pinion, gear) :class:`~gearbox.ltca.modification.FlankModification`
    (or :class:`~gearbox.ltca.modification.TipRelief`) is given: then each point's
    separation is the material both gears' modifications remove there.
    """
    p = Problems()
    p.in_range("n_face", n_face, 3, None)
    p.raise_if_any("invalid contact grid request")
    b = pair.face_width
    dy = b / n_face
    y = -0.5 * b + dy * (np.arange(n_face) + 0.5)
    tb = math.tan(pair.base_helix_angle)
    pb = pair.base_pitch
    xa, xe = pair.roll_limits
    lam = pair.line_of_action_length
    xi0 = xa + (fraction % 1.0) * pb
    kmax = int(math.ceil((xe - xa + b * tb) / pb)) + 1
    rows = []
    for k in range(-kmax, kmax + 1):
        xi = xi0 + k * pb + y * tb
        inside = (xi >= xa) & (xi <= xe)
        if not inside.any():
            continue
        rows.append((k, xi[inside], y[inside], np.flatnonzero(inside)))
    pair_idx = np.concatenate([np.full(r[1].size, r[0]) for r in rows])
    xi = np.concatenate([r[1] for r in rows])
    face = np.concatenate([r[2] for r in rows])
    slot = np.concatenate([r[3] for r in rows])
    n = xi.size
    cb = math.cos(pair.base_helix_angle)
    rb1, rb2 = pair.base_radius(0), pair.base_radius(1)
    r1 = np.sqrt(rb1**2 + xi**2)
    r2 = np.sqrt(rb2**2 + (lam - xi) ** 2)
    rho = xi * (lam - xi) / lam / cb  # relative radius of curvature, normal section
    # the contact lines are exact and end on the tip edges: the true contact never
    # lies beyond this grid (corner contact outside the path of contact, from
    # deflections, is not modelled by the fast level)
    edge = np.zeros(n, dtype=bool)
    teeth1, teeth2 = (
        ToothSections.uniform(
            n,
            radius=r,
            base_radius=pair.base_radius(i),
            root_radius=pair.root_radius(i),
            tip_radius=pair.tip_radius(i),
            bore_radius=pair.bore_ratio * pair.root_radius(i),
            base_half_angle=pair.base_half_angle(i),
            teeth=pair.teeth[i],
            normal_module=pair.normal_module,
            normal_pressure_angle=pair.normal_pressure_angle,
            helix_angle=abs(pair.helix_angle),
            profile_shift=pair.profile_shift[i],
            rack_dedendum=pair.dedendum_coefficient,
            rack_root_radius=pair.root_radius_coefficient,
        )
        for i, r in ((0, r1), (1, r2))
    )
    # mesh point and normal in a pair frame: x along the centre line, z along the axis
    aw = pair.working_pressure_angle
    t1 = np.array([rb1 * math.cos(aw), rb1 * math.sin(aw), 0.0])  # T1 seen from O1
    u = np.array([-math.sin(aw), math.cos(aw), 0.0])  # along T1 -> T2 ... transverse LOA
    u = -u if np.dot(u, np.array([1.0, 0.0, 0.0])) < 0 else u
    pos = t1[None, :] + xi[:, None] * u[None, :] + face[:, None] * np.array([0.0, 0.0, 1.0])
    nrm = np.tile(cb * u + math.sin(pair.base_helix_angle) * np.array([0.0, 0.0, 1.0]), (n, 1))
    sep = _relief_separation(pair, relief, r1, r2, face)
    if pair.misalignment != 0.0:
        # the gear axis turned to (0, sin g, cos g) of this frame about the centre line
        # (g of _grid_misalignment) moves a gear flank point p by g (0, p_z, -p_y)
        # (first order); the gap grows by that
        # displacement's component along the flank normal. The contact lines here run as
        # xi = xi_0 + y tan(beta_b), normal to (cos beta_b u - sin beta_b z); ``nrm``
        # carries +sin(beta_b) (the table's line of action, before table._in_sf turns
        # it into Sf), hence the sign of its axial part below. Checked against the generated flanks of the surface path with
        # the same shaft-angle error, both hands (tests/test_ltca_modifications.py).
        g = _grid_misalignment(pair)
        sep = sep + g * (nrm[:, 1] * pos[:, 2] + nrm[:, 2] * pos[:, 1])
    # roll lengths from each gear's reference circle; both faces share y
    roll1 = xi - math.sqrt(pair.pitch_radius(0) ** 2 - rb1**2)
    roll2 = (lam - xi) - math.sqrt(pair.pitch_radius(1) ** 2 - rb2**2)
    return ContactGrid(
        pair=pair_idx.astype(int),
        slot=slot.astype(int),
        face=face,
        width=np.full(n, dy),
        line_length=np.full(n, dy / cb),
        separation=sep,
        arm=np.full(n, rb1 * cb),
        transverse_projection=np.full(n, cb),
        curvature_radius=rho,
        profile=xi - xa,
        profile_range=(0.0, xe - xa),
        face_range=(-0.5 * b, 0.5 * b),
        n_slots=n_face,
        edge=edge,
        position=pos,
        normal=nrm,
        tooth1=teeth1,
        tooth2=teeth2,
        youngs_modulus=pair.youngs_modulus,
        poisson_ratio=pair.poisson_ratio,
        # pinion on the z axis through O1 (the origin), gear through O2 on the centre
        # line (x), its direction turned by the misalignment
        pinion_axis=np.array([[0.0, 0.0, 1.0], [0.0, 0.0, 0.0]]),
        gear_axis=np.array(
            [
                [0.0, math.sin(_grid_misalignment(pair)), math.cos(_grid_misalignment(pair))],
                [pair.working_center_distance, 0.0, 0.0],
            ]
        ),
        flank_coordinates=np.column_stack([roll1, face, roll2, face]),
    )


def _grid_misalignment(pair: ParallelPair) -> float:
    """The shaft-angle error as the grid's frame sees it: the grid's transverse plane is
    the surface path's Sf (:class:`gearbox.tca.assembly.Assembly`) with y -> -y (its
    drive contact at y < 0), so the gear axis (0, sin g, cos g) of Sf is (0, -sin g,
    cos g) here. Checked against the generated flanks in the assembly with the same
    error: the load's end of the face and the unloaded TE's sawtooth, both hands
    (tests/test_ltca_modifications.py)."""
    return -pair.misalignment


def _relief_separation(pair: ParallelPair, relief, r1, r2, face) -> np.ndarray:
    """Separation (m) from the flank modifications (pinion, gear) at pinion and gear
    radii r1, r2 (m) and face position ``face`` (m from the face middle, both gears)."""
    from .modification import as_modification

    sep = np.zeros(np.shape(r1))
    if relief is None:
        return sep
    for i, (rel, r) in enumerate(zip(relief, (r1, r2), strict=True)):
        mod = as_modification(rel)
        if mod.active:
            sep = sep + mod.removal(
                r,
                face,
                tip_radius=pair.tip_radius(i),
                base_radius=pair.base_radius(i),
                face_width=pair.face_width,
                form_radius=pair.form_radius(i) if mod.profile_active else None,
                reference_radius=pair.pitch_radius(i),
            )
    return sep

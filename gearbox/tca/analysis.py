"""Unloaded tooth contact analysis over a sweep of pinion angles (drive and coast).

For each flank side the reference tooth pair (pinion tooth 0, gear tooth 0) is solved
at the pinion angles ``phi_1 + 2 pi j / N_1`` for ``j = -J..J``: pinion tooth j at
phi_1 is tooth 0 at that angle, so one batched solve covers every tooth pair that can
be in contact. The starting values come from the tangent of the contact path at the
pitch point (implicit function theorem), then :func:`gearbox.tca.contact.solve_contact`
iterates. A contact is *active* when it lies on both real flanks: inside the face
widths, above both form circles (start of the involute) and below both tip cones.

Per pinion angle the gear angle is set by the active pair that stops it first: on the
drive side (R, pinion turning +phi_1 about z_f pushes the gear towards -phi_2) the
smallest phi_2, on the coast side (L) the largest. Unloaded transmission error is the
gear angle minus the ideal ``phi_2c - (N_1/N_2)(phi_1 - phi_1c)``.

Measured FPD angle: the angle between the two flanks' zero-curvature principal
directions (their rulings, the contact lines with the common rack, paper Fig. 2) at
each contact point, from the generated surfaces.

Contact ellipse: the surfaces' curvature tensors in the common tangent plane are
added (both convex-positive), and the separation ``delta`` gives the semi-axes
``sqrt(2 delta / lambda_i)`` (Litvin & Fuentes, sec. 9.3, "instantaneous contact
ellipse", marking-compound thickness 6.35 um by default).
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import InputError, Problem, Problems
from ..surface import ToothBlank, flank_points
from .assembly import Assembly
from .contact import solve_contact, tangent_predictor

__all__ = ["TCASettings", "FlankContact", "TCAResult", "run_tca", "tca_of_blanks", "SIDE_NAMES"]

#: flank side -> name: the pinion's right flank R drives (pinion turning +phi_1 about
#: z_f, i.e. towards its heel by the right-hand rule), the left flank L is the coast side
SIDE_NAMES = {"R": "drive", "L": "coast"}

#: FPD angle (rad) below which a side is reported as line contact
LINE_CONTACT_FPD = 1e-6

#: limit codes of a contact point outside the real flanks
LIMITS = (
    "pinion toe",
    "pinion heel",
    "pinion root",
    "pinion tip",
    "gear toe",
    "gear heel",
    "gear root",
    "gear tip",
)


@dataclass(frozen=True)
class TCASettings:
    """Settings of the unloaded TCA sweep.

    Attributes:
        positions: pinion positions of the sweep.
        mesh_cycles: sweep length in mesh cycles (2 pi / N_1 each), centred on the
            pitch-point passage of tooth 0.
        marking_compound: separation that defines the contact ellipse (m).
        pairs: J, tooth pairs examined on each side of the reference pair.
        max_iter: iteration bound of the contact solve.
    """

    positions: int = 61
    mesh_cycles: float = 1.5
    marking_compound: float = 6.35e-6
    pairs: int = 4
    max_iter: int = 30

    @classmethod
    def from_scene(cls, scene) -> TCASettings:
        t = scene["tca"]
        return cls(
            positions=t["positions"],
            mesh_cycles=t["mesh_cycles"],
            marking_compound=t["marking_compound_mm"] * 1e-3,
        ).validate()

    def validate(self) -> TCASettings:
        p = Problems()
        p.check(
            isinstance(self.positions, int) and self.positions >= 2,
            "tca.positions",
            self.positions,
            "must be an integer >= 2",
        )
        p.in_range("tca.mesh_cycles", self.mesh_cycles, 0, 20, lo_open=True)
        p.in_range("tca.marking_compound_mm", self.marking_compound * 1e3, 0, 1, lo_open=True)
        p.check(
            isinstance(self.pairs, int) and 1 <= self.pairs <= 20,
            "tca.pairs",
            self.pairs,
            "must be an integer in [1, 20]",
        )
        p.check(
            isinstance(self.max_iter, int) and 1 <= self.max_iter <= 200,
            "tca.max_iter",
            self.max_iter,
            "must be an integer in [1, 200]",
        )
        p.raise_if_any("invalid TCA settings")
        return self


@dataclass(frozen=True)
class FlankContact:
    """TCA of one flank side over the sweep; n positions, P = 2J + 1 tooth pairs.

    Attributes:
        side: ``"R"`` or ``"L"``; ``name``: ``"drive"`` or ``"coast"``.
        pinion_angle: (n,) phi_1 (rad).
        gear_angle: (n,) phi_2 set by the active pairs (rad), NaN where none is active.
        transmission_error: (n,) unloaded TE, gear angle minus ideal (rad).
        pairs_in_contact: (n,) number of active pairs.
        pair: (P,) tooth-pair offsets j.
        active, converged: (n, P) bool; ``iterations``: (n, P).
        limit: (n, P) str, the first flank limit a contact violates ("" if active);
            "not converged" where the solve failed on or near the flanks, "<limit> (not
            converged)" where it failed far outside them.
        point: (n, P, 3) contact point in Sf (m); ``normal``: (n, P, 3) common normal
            (pinion's outward normal) in Sf.
        pinion_zu, gear_zu: (n, P, 2) flank parameters (z, u) (m).
        pinion_flank, gear_flank: (n, P, 2) position on the flank: (face, profile)
            fractions, face -1 toe .. +1 heel, profile 0 form circle .. 1 tip.
        fpd_angle: (n, P) measured FPD angle (rad), in [0, pi/2].
        fpd_angle_signed: (n, P) angle from the pinion's to the gear's ruling about the
            common normal, both rulings pointing to their heels (rad).
        ellipse_axes: (n, P, 2) semi-axes (major, minor) (m); inf where the relative
            curvature vanishes (line contact).
        ellipse_direction: (n, P, 3) major-axis direction in Sf.
        ellipse_angle: (n, P) angle of the major axis from the pinion's face-width
            direction (its axis projected on the tangent plane, towards the heel),
            positive towards the pinion's tip, in (-pi/2, pi/2] (rad).
        gear_angle_pairs: (n, P) gear angle of each pair's contact (rad).
    """

    side: str
    name: str
    pinion_angle: np.ndarray
    gear_angle: np.ndarray
    transmission_error: np.ndarray
    pairs_in_contact: np.ndarray
    pair: np.ndarray
    active: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    limit: np.ndarray
    point: np.ndarray
    normal: np.ndarray
    pinion_zu: np.ndarray
    gear_zu: np.ndarray
    pinion_flank: np.ndarray
    gear_flank: np.ndarray
    fpd_angle: np.ndarray
    fpd_angle_signed: np.ndarray
    ellipse_axes: np.ndarray
    ellipse_direction: np.ndarray
    ellipse_angle: np.ndarray
    gear_angle_pairs: np.ndarray
    path_limits: tuple[str, str] = ("", "")
    contact_ratio: float = float("nan")

    @property
    def active_points(self) -> np.ndarray:
        """Active contact points in Sf, shape (k, 3)."""
        return self.point[self.active]

    def straightness(self) -> float:
        """Largest distance (m) of an active contact point from their best line."""
        pts = self.active_points
        if len(pts) < 3:
            return float("nan")
        c = pts.mean(axis=0)
        _, _, vt = np.linalg.svd(pts - c)
        return float(np.max(np.linalg.norm(np.cross(pts - c, vt[0]), axis=1)))

    def te_peak_to_peak(self) -> float:
        """Peak-to-peak unloaded TE over positions with contact (rad)."""
        te = self.transmission_error[np.isfinite(self.transmission_error)]
        return float(np.ptp(te)) if te.size else float("nan")

    def path_position(self, which: str) -> dict:
        """Where the active path lies on a flank: centroid and extent (fractions, mm)."""
        fl = self.pinion_flank if which == "pinion" else self.gear_flank
        zu = self.pinion_zu if which == "pinion" else self.gear_zu
        a = self.active
        if not a.any():
            return {"face_centroid": None, "profile_centroid": None}
        f, p = fl[..., 0][a], fl[..., 1][a]
        return {
            "face_centroid": float(np.mean(f)),
            "face_range": [float(f.min()), float(f.max())],
            "profile_centroid": float(np.mean(p)),
            "profile_range": [float(p.min()), float(p.max())],
            "z_centroid_mm": float(np.mean(zu[..., 0][a]) * 1e3),
            "region": _region(float(np.mean(f))),
        }


def _region(face: float) -> str:
    """toe / middle / heel from the face fraction (middle third is 'middle')."""
    return "toe" if face < -1 / 3 else ("heel" if face > 1 / 3 else "middle")


@dataclass(frozen=True)
class TCAResult:
    """Unloaded TCA of a pair: both flank sides, the assembly and the blanks."""

    pinion: ToothBlank
    gear: ToothBlank
    assembly: Assembly
    settings: TCASettings
    drive: FlankContact
    coast: FlankContact
    backlash_angle: np.ndarray  # (n,) free play of the gear (rad), < 0 = interference
    designed_fpd: tuple[float, float] | None = None  # (xi_R, xi_L) of the design (rad)
    status: str = "ok"
    messages: tuple[str, ...] = field(default_factory=tuple)

    @property
    def sides(self) -> dict[str, FlankContact]:
        return {"R": self.drive, "L": self.coast}

    def summary(self) -> dict:
        """JSON-ready summary (degrees, arcsec, um, mm at the edge)."""
        arcsec = 180 / math.pi * 3600
        out: dict = {"status": self.status, "messages": list(self.messages)}
        for key, fc in (("right", self.drive), ("left", self.coast)):
            f = fc.fpd_angle[fc.active]
            out[f"measured_fpd_angle_{key}_deg"] = float(np.degrees(np.mean(f))) if f.size else None
            out[f"measured_fpd_angle_{key}_spread_deg"] = (
                float(np.degrees(np.ptp(f))) if f.size else None
            )
        if self.designed_fpd is not None:
            out["designed_fpd_angle_right_deg"] = math.degrees(self.designed_fpd[0])
            out["designed_fpd_angle_left_deg"] = math.degrees(self.designed_fpd[1])
        out["unloaded_te_peak_to_peak_arcsec"] = {
            fc.name: _fin(fc.te_peak_to_peak() * arcsec) for fc in (self.drive, self.coast)
        }
        out["contact_path_straightness_um"] = {
            fc.name: _fin(fc.straightness() * 1e6) for fc in (self.drive, self.coast)
        }
        out["path_position"] = {
            fc.name: {"pinion": fc.path_position("pinion"), "gear": fc.path_position("gear")}
            for fc in (self.drive, self.coast)
        }
        out["path_limits"] = {fc.name: list(fc.path_limits) for fc in (self.drive, self.coast)}
        out["contact_ratio"] = {fc.name: _fin(fc.contact_ratio) for fc in (self.drive, self.coast)}
        out["positions_without_contact"] = {
            fc.name: int(np.sum(fc.pairs_in_contact == 0)) for fc in (self.drive, self.coast)
        }
        out["max_iterations"] = {
            fc.name: int(fc.iterations.max()) for fc in (self.drive, self.coast)
        }
        out["not_converged"] = {
            fc.name: int(np.sum(~fc.converged)) for fc in (self.drive, self.coast)
        }
        out["not_converged_near_flanks"] = {
            fc.name: int(np.sum(fc.limit == "not converged")) for fc in (self.drive, self.coast)
        }
        bl = self.backlash_angle[np.isfinite(self.backlash_angle)]
        r2 = self.gear.reference_pitch_radius
        out["backlash_um"] = {
            "min": _fin(float(bl.min()) * r2 * 1e6) if bl.size else None,
            "max": _fin(float(bl.max()) * r2 * 1e6) if bl.size else None,
            "note": "circumferential free play of the gear on its reference pitch circle; < 0 is interference",
        }
        ax = {}
        for fc in (self.drive, self.coast):
            e = fc.ellipse_axes[fc.active]
            ax[fc.name] = {
                "major_mm": _fin(float(np.median(e[:, 0])) * 1e3) if e.size else None,
                "minor_mm": _fin(float(np.median(e[:, 1])) * 1e3) if e.size else None,
            }
        out["contact_ellipse_semi_axes_median"] = ax
        out["contact_ellipse_angle_deg_median"] = {
            fc.name: _fin(float(np.degrees(np.median(fc.ellipse_angle[fc.active]))))
            if fc.active.any()
            else None
            for fc in (self.drive, self.coast)
        }
        out["contact_ellipse_angle_note"] = (
            "major axis from the pinion's face-width direction (towards its heel), "
            "positive towards its tip"
        )
        out["marking_compound_um"] = self.settings.marking_compound * 1e6
        mp = {}
        for fc in (self.drive, self.coast):
            pts = fc.active_points
            nrm = fc.normal[fc.active]
            mp[fc.name] = {
                "mean_contact_point_m": [float(v) for v in pts.mean(axis=0)] if len(pts) else None,
                "line_of_action": [float(v) for v in nrm.mean(axis=0)] if len(pts) else None,
            }
        out["mesh_point_sf"] = mp
        return out

    def to_dict(self) -> dict:
        """Everything as plain lists (SI), JSON-serialisable except inf/NaN."""

        def fc_dict(fc):
            d = {}
            for k, v in fc.__dict__.items():
                d[k] = v.tolist() if isinstance(v, np.ndarray) else v
            return d

        return {
            "pinion": self.pinion.to_dict(),
            "gear": self.gear.to_dict(),
            "assembly": self.assembly.to_dict(),
            "settings": asdict(self.settings),
            "drive": fc_dict(self.drive),
            "coast": fc_dict(self.coast),
            "backlash_angle": self.backlash_angle.tolist(),
            "designed_fpd": self.designed_fpd,
            "status": self.status,
            "messages": list(self.messages),
        }

    @classmethod
    def from_dict(cls, d: dict) -> TCAResult:
        """Inverse of :meth:`to_dict`."""

        def fc_of(x):
            x = dict(x)
            for k, v in x.items():
                if isinstance(v, list) and k != "path_limits":
                    x[k] = np.asarray(v, dtype=str if k == "limit" else None)
            x["path_limits"] = tuple(x["path_limits"])
            return FlankContact(**x)

        fpd = d.get("designed_fpd")
        return cls(
            pinion=ToothBlank.from_dict(d["pinion"]),
            gear=ToothBlank.from_dict(d["gear"]),
            assembly=Assembly.from_dict(d["assembly"]),
            settings=TCASettings(**d["settings"]),
            drive=fc_of(d["drive"]),
            coast=fc_of(d["coast"]),
            backlash_angle=np.asarray(d["backlash_angle"], dtype=float),
            designed_fpd=None if fpd is None else tuple(fpd),
            status=d["status"],
            messages=tuple(d["messages"]),
        )


def _fin(x):
    return float(x) if x is not None and np.isfinite(x) else None


def _pitch_profile_parameter(b: ToothBlank) -> float:
    """u of the rack point on its reference plane (v = 0) (m)."""
    sa, ca = math.sin(b.normal_pressure_angle), math.cos(b.normal_pressure_angle)
    vt = -b.tool_addendum + b.tool_tip_radius * (1 - sa)
    return -vt / ca


def _angle_about(v, axis, ref):
    """Angle of v about a unit axis, measured from ref (both projected)."""
    v = v - (v @ axis) * axis
    e1 = ref - (ref @ axis) * axis
    e1 = e1 / np.linalg.norm(e1)
    e2 = np.cross(axis, e1)
    return math.atan2(v @ e2, v @ e1)


def _centre_start(pinion, gear, asm, side, target):
    """Pinion angle and starting values that put both flanks' pitch points at target."""
    u1, u2 = _pitch_profile_parameter(pinion), _pitch_profile_parameter(gear)
    q1 = flank_points(pinion, side, 0.0, u1).position
    p10 = asm.pinion_matrix(0.0) @ q1
    phi1 = math.atan2(target[1], target[0]) - math.atan2(p10[1], p10[0])
    p1 = asm.pinion_matrix(phi1) @ q1 + asm.pinion_origin
    q2 = flank_points(gear, side, 0.0, u2).position
    g0 = asm.gear_matrix(0.0) @ q2
    a2 = asm.gear_axis
    phi2 = _angle_about(p1 - asm.gear_origin, a2, np.array([-1.0, 0, 0])) - _angle_about(
        g0, a2, np.array([-1.0, 0, 0])
    )
    return phi1, np.array([0.0, u1, 0.0, u2, phi2])


def _flank_limits(blank: ToothBlank, side: str, z, u, radius, who: str):
    """First violated limit per point ("" if on the flank) and (face, profile) fractions."""
    z = np.asarray(z)
    form = flank_points(blank, side, z, np.zeros_like(z)).radius
    tip = blank.tip_radius(z)
    lim = np.full(z.shape, "", dtype=object)
    tol = 1e-12
    lim = np.where(u < -tol, f"{who} root", lim)
    lim = np.where(radius > tip + tol, f"{who} tip", lim)
    lim = np.where(z > blank.z_heel + tol, f"{who} heel", lim)
    lim = np.where(z < blank.z_toe - tol, f"{who} toe", lim)
    zmid = -blank.reference_section
    face = (z - zmid) / (0.5 * blank.face_width)
    prof = (radius - form) / (tip - form)
    return lim, np.stack([face, prof], axis=-1)


def _margin(pinion, gear, side, x):
    """Signed distance (m) of contacts x (N, 5) from the nearest flank limit (>= 0 on
    both real flanks): face ends, form circle (u = 0, in rack-profile length) and tip cone."""
    from ..surface import flank_jets

    out = np.full(x.shape[0], np.inf)
    for blank, z, u in ((pinion, x[:, 0], x[:, 1]), (gear, x[:, 2], x[:, 3])):
        r, _, _ = flank_jets(blank, side, z, u, involute_only=True)
        radius = np.hypot(r[0].val, r[1].val)
        for m in (z - blank.z_toe, blank.z_heel - z, u, blank.tip_radius(z) - radius):
            out = np.minimum(out, m)
    return out


def _refine_ends(
    pinion, gear, asm, side, phi_in, x_in, phi_out, x_out, settings, tan, steps: int = 12
):
    """Where the reference pair's contact leaves the flanks, by regula falsi in phi_1.

    ``phi_in``/``x_in``: active solutions next to each end, ``phi_out``/``x_out`` the
    inactive neighbours (arrays of 2). The limit margin (:func:`_margin`) is smooth in
    phi_1 along the path; the Illinois variant of regula falsi keeps the bracket and
    converges superlinearly. Returns the two end angles (rad).
    """
    a, b = np.array(phi_in, float), np.array(phi_out, float)
    xa = np.array(x_in, float)
    fa, fb = _margin(pinion, gear, side, xa), _margin(pinion, gear, side, np.array(x_out, float))
    side_kept = np.zeros(2, dtype=int)
    for _ in range(steps):
        c = b - fb * (b - a) / (fb - fa)
        c = np.where(np.isfinite(c), c, 0.5 * (a + b))
        sol = solve_contact(
            pinion, gear, asm, side, c, xa + np.outer(c - a, tan), max_iter=settings.max_iter
        )
        fc = np.where(sol.converged & sol.opposed, _margin(pinion, gear, side, sol.x), -np.inf)
        fc = np.where(np.isfinite(fc), fc, -abs(fb))
        inside = fc >= 0
        # Illinois: halve the function value at the end that stays
        fb = np.where(inside & (side_kept == 1), 0.5 * fb, fb)
        fa = np.where(~inside & (side_kept == -1), 0.5 * fa, fa)
        side_kept = np.where(inside, 1, -1)
        a, fa = np.where(inside, c, a), np.where(inside, fc, fa)
        xa = np.where(inside[:, None], sol.x, xa)
        b, fb = np.where(inside, b, c), np.where(inside, fb, fc)
        if np.all(np.abs(b - a) < 1e-12):
            break
    return np.where(np.abs(fa) < np.abs(fb), a, b)


def _far_outside(blank: ToothBlank, z, u, radius):
    """True where (z, u) lies more than one module outside the flank's limits."""
    m = blank.normal_module
    return (
        (z < blank.z_toe - m)
        | (z > blank.z_heel + m)
        | (u < -m)
        | (radius > blank.tip_radius(z) + m)
        | ~np.isfinite(radius)
    )


def _ellipse(k1, d1, k2, d2, n, delta):
    """Contact ellipse from both surfaces' principal curvatures (convex-positive).

    k_i (N, 2), d_i (N, 2, 3) in Sf, n (N, 3). Returns semi-axes (N, 2) (major,
    minor) and the major-axis direction (N, 3).
    """
    e1 = d1[:, 0, :]
    e1 = e1 - np.einsum("ni,ni->n", e1, n)[:, None] * n
    e1 /= np.linalg.norm(e1, axis=1, keepdims=True)
    e2 = np.cross(n, e1)
    C = np.zeros((len(n), 2, 2))
    for k, d in ((k1, d1), (k2, d2)):
        for i in range(2):
            a = np.stack(
                [np.einsum("ni,ni->n", d[:, i], e1), np.einsum("ni,ni->n", d[:, i], e2)], axis=1
            )
            C += k[:, i, None, None] * a[:, :, None] * a[:, None, :]
    lam, vec = np.linalg.eigh(C)
    with np.errstate(divide="ignore", invalid="ignore"):
        axes = np.sqrt(2 * delta / lam)
    # relative curvature below 1e-9 of the largest: line contact, no finite ellipse
    axes = np.where(lam > 1e-9 * np.abs(lam[:, 1:]), axes, np.inf)
    major = vec[:, 0, 0, None] * e1 + vec[:, 1, 0, None] * e2
    return np.stack([axes[:, 0], axes[:, 1]], axis=1), major


def _side(pinion, gear, asm, side, phi1_grid, settings, target):
    N1, N2 = pinion.teeth, gear.teeth
    J = settings.pairs
    pairs = np.arange(-J, J + 1)
    phi1c, x0 = _centre_start(pinion, gear, asm, side, target)
    c = solve_contact(pinion, gear, asm, side, [phi1c], x0[None, :], max_iter=settings.max_iter)
    if not (c.converged[0] and c.opposed[0]):
        raise InputError(
            Problem(
                f"tca[{SIDE_NAMES[side]}]",
                "pitch-point contact",
                f"the contact conditions have no solution near the pitch point within {settings.max_iter} "
                f"iterations (residual {c.residual_position[0]:.3g} m): check the assembly errors",
            ),
            "tooth contact analysis failed",
        )
    xc = c.x[0]
    tan = tangent_predictor(pinion, gear, asm, side, [phi1c], c.x)[0]
    phi_ref = (phi1_grid[:, None] + 2 * np.pi * pairs[None, :] / N1).ravel()
    X0 = xc + np.outer(phi_ref - phi1c, tan)
    s = solve_contact(pinion, gear, asm, side, phi_ref, X0, max_iter=settings.max_iter)
    n, P = len(phi1_grid), len(pairs)
    x = s.x
    M1 = asm.pinion_matrix(phi_ref)
    M2 = asm.gear_matrix(x[:, 4])
    fp1 = flank_points(pinion, side, x[:, 0], x[:, 1], involute_only=True)
    fp2 = flank_points(gear, side, x[:, 2], x[:, 3], involute_only=True)
    lim1, fl1 = _flank_limits(pinion, side, x[:, 0], x[:, 1], fp1.radius, "pinion")
    lim2, fl2 = _flank_limits(gear, side, x[:, 2], x[:, 3], fp2.radius, "gear")
    ok = s.converged & s.opposed
    limit = np.where(lim1 != "", lim1, lim2)
    # a problem that did not converge is reported as such; when its last iterate is far
    # outside the flanks (more than one module beyond a limit: involute continuation
    # near the base cylinder, where the surface is singular) it is also named by that limit
    far = _far_outside(pinion, x[:, 0], x[:, 1], fp1.radius) | _far_outside(
        gear, x[:, 2], x[:, 3], fp2.radius
    )
    named = np.char.add(limit.astype(str), " (not converged)")
    limit = np.where(ok, limit, np.where(far & (limit != ""), named, "not converged"))
    active = ok & (limit == "")
    # rulings (zero-curvature directions) and curvature tensors in Sf
    d1 = np.einsum("nij,nkj->nki", M1, fp1.directions)
    d2 = np.einsum("nij,nkj->nki", M2, fp2.directions)
    r1 = d1[:, 0, :] * np.sign(d1[:, 0, 2])[:, None]
    a2 = asm.gear_axis
    r2 = d2[:, 0, :] * np.sign(d2[:, 0, :] @ a2)[:, None]
    nrm = s.normal
    fpd_signed = np.arctan2(
        np.einsum("ni,ni->n", nrm, np.cross(r1, r2)), np.einsum("ni,ni->n", r1, r2)
    )
    fpd = np.arccos(np.clip(np.abs(np.einsum("ni,ni->n", r1, r2)), 0.0, 1.0))
    axes, major = _ellipse(fp1.curvatures, d1, fp2.curvatures, d2, nrm, settings.marking_compound)
    e_face = np.array([0.0, 0.0, 1.0]) - nrm[:, 2:3] * nrm
    e_face /= np.linalg.norm(e_face, axis=1, keepdims=True)
    e_prof = np.cross(nrm, e_face)
    # towards the pinion's tip: the radial direction away from the pinion axis
    radial = s.point - asm.pinion_origin
    radial[:, 2] = 0.0
    e_prof *= np.sign(np.einsum("ni,ni->n", e_prof, radial))[:, None]
    ang = np.arctan2(np.einsum("ni,ni->n", major, e_prof), np.einsum("ni,ni->n", major, e_face))
    ang = np.where(ang > np.pi / 2, ang - np.pi, np.where(ang <= -np.pi / 2, ang + np.pi, ang))
    # gear angle of each pair at the sweep's pinion angles
    g_pairs = x[:, 4].reshape(n, P) + 2 * np.pi * pairs[None, :] / N2
    act = active.reshape(n, P)
    gp = np.where(act, g_pairs, np.nan)
    with np.errstate(all="ignore"):
        if side == "R":
            gear_angle = np.where(act.any(1), np.nanmin(np.where(act, gp, np.inf), axis=1), np.nan)
        else:
            gear_angle = np.where(act.any(1), np.nanmax(np.where(act, gp, -np.inf), axis=1), np.nan)
    te = gear_angle - (xc[4] - (N1 / N2) * (phi1_grid - phi1c))
    # path limits and contact ratio of the reference pair (sorted by its pinion angle);
    # the ends of its active interval are refined by bisection in phi_1
    order = np.argsort(phi_ref)
    a_sorted = active[order]
    lim_sorted = limit[order]
    if a_sorted.any():
        first, last = np.flatnonzero(a_sorted)[[0, -1]]
        start = lim_sorted[first - 1] if first > 0 else "beyond the examined pairs"
        end = lim_sorted[last + 1] if last + 1 < len(order) else "beyond the examined pairs"
        ph = phi_ref[order]
        if 0 < first and last + 1 < len(order):
            ends = _refine_ends(
                pinion,
                gear,
                asm,
                side,
                ph[[first, last]],
                x[order][[first, last]],
                ph[[first - 1, last + 1]],
                x[order][[first - 1, last + 1]],
                settings,
                tan,
            )
            ratio = (ends[1] - ends[0]) / (2 * np.pi / N1)
        else:
            ratio = float("nan")
    else:
        start = end = "no contact"
        ratio = 0.0
    r = lambda a: a.reshape((n, P) + a.shape[1:])  # noqa: E731
    return FlankContact(
        side=side,
        name=SIDE_NAMES[side],
        pinion_angle=phi1_grid,
        gear_angle=gear_angle,
        transmission_error=te,
        pairs_in_contact=act.sum(axis=1),
        pair=pairs,
        active=act,
        converged=r(s.converged),
        iterations=r(s.iterations),
        limit=r(np.asarray(limit, dtype=str)),
        point=r(s.point),
        normal=r(nrm),
        pinion_zu=r(x[:, :2]),
        gear_zu=r(x[:, 2:4]),
        pinion_flank=r(fl1),
        gear_flank=r(fl2),
        fpd_angle=r(fpd),
        fpd_angle_signed=r(fpd_signed),
        ellipse_axes=r(axes),
        ellipse_direction=r(major),
        ellipse_angle=r(ang),
        gear_angle_pairs=g_pairs,
        path_limits=(str(start), str(end)),
        contact_ratio=float(ratio),
    ), phi1c


def tca_of_blanks(
    pinion: ToothBlank,
    gear: ToothBlank,
    assembly: Assembly,
    settings: TCASettings | None = None,
    *,
    pitch_point=None,
    designed_fpd=None,
    pinion_angles=None,
) -> TCAResult:
    """Unloaded TCA of both flank sides over a sweep of pinion angles.

    Args:
        pinion, gear: :class:`gearbox.surface.ToothBlank` of both members.
        assembly: :class:`Assembly` in Sf.
        settings: :class:`TCASettings` (defaults: 61 positions over 1.5 mesh cycles).
        pitch_point: a point of Sf near which the contact passes (m), shape (3,);
            default: the point at the pinion's reference pitch radius on x_f.
        designed_fpd: (xi_R, xi_L) of the design (rad), stored for comparison.
        pinion_angles: explicit pinion angles phi_1 of the sweep (rad), shape (n,),
            instead of the range centred on the pitch-point passage.

    Raises:
        InputError: when no contact is found near the pitch point, or when no tooth
            pair is in contact anywhere on the flanks.
    """
    settings = (settings or TCASettings()).validate()
    target = np.asarray(
        pitch_point
        if pitch_point is not None
        else (pinion.reference_pitch_radius, 0.0, assembly.pinion_axial),
        dtype=float,
    )
    N1 = pinion.teeth
    # the sweep is centred on the drive side's pitch-point passage
    phi1c, _ = _centre_start(pinion, gear, assembly, "R", target)
    half = 0.5 * settings.mesh_cycles * 2 * np.pi / N1
    if pinion_angles is None:
        grid = phi1c + np.linspace(-half, half, settings.positions)
    else:
        grid = np.atleast_1d(np.asarray(pinion_angles, dtype=float))
    drive, _ = _side(pinion, gear, assembly, "R", grid, settings, target)
    coast, _ = _side(pinion, gear, assembly, "L", grid, settings, target)
    pitch2 = 2 * np.pi / gear.teeth
    play = drive.gear_angle - coast.gear_angle
    play = np.mod(play + 0.5 * pitch2, pitch2) - 0.5 * pitch2
    msgs = []
    status = "ok"
    for fc in (drive, coast):
        if not fc.active.any():
            raise InputError(
                Problem(
                    f"tca[{fc.name}]",
                    "no contact",
                    "no tooth pair is in contact on the real flanks anywhere: the assembly separates the "
                    "gears (offset or axial errors too large) or the flanks do not overlap",
                ),
                "tooth contact analysis failed",
            )
        gaps = int(np.sum(fc.pairs_in_contact == 0))
        if gaps:
            status = "edge contact"
            msgs.append(
                f"{fc.name}: {gaps} of {len(grid)} positions have no flank-flank contact "
                f"(contact ratio {fc.contact_ratio:.3f} < 1): edge contact there"
            )
        f_act = fc.fpd_angle[fc.active]
        if f_act.size and np.max(f_act) < LINE_CONTACT_FPD:
            msgs.append(
                f"{fc.name}: line contact (measured FPD angle {np.degrees(np.max(f_act)):.2g} deg): each "
                "contact point is one point of the instantaneous contact line, so the path position "
                "on the face is not defined by the flanks"
            )
        near = fc.limit == "not converged"
        if near.any():
            msgs.append(
                f"{fc.name}: {int(near.sum())} contact solves on or near the flanks did not converge "
                f"in {settings.max_iter} iterations (flagged 'not converged', excluded)"
            )
    r2 = gear.reference_pitch_radius
    if np.nanmin(play) * r2 < -1e-9:
        status = "interference"
        msgs.append(
            f"drive and coast flanks overlap by up to {-np.nanmin(play) * r2 * 1e6:.3f} um (circumferential, "
            f"gear pitch circle): the gears interfere in this assembly"
        )
    elif np.nanmax(play) * r2 > 1e-9:
        msgs.append(
            f"backlash up to {np.nanmax(play) * r2 * 1e6:.3f} um (circumferential, gear pitch circle)"
        )
    return TCAResult(
        pinion, gear, assembly, settings, drive, coast, play, designed_fpd, status, tuple(msgs)
    )


def run_tca(
    design, scene=None, *, settings: TCASettings | None = None, errors=None, pinion_angles=None
) -> TCAResult:
    """Unloaded TCA of a designed pair (:class:`gearbox.geometry.PairDesign`).

    The blanks come from the design and its tool profile
    (:func:`gearbox.surface.blanks_from_design`), the assembly from its pitch point
    (:meth:`Assembly.from_design`). With a ``scene``, its ``[tca]`` section gives the
    settings and its ``[assembly]`` section the assembly errors, unless ``settings``
    or ``errors`` (:class:`AssemblyErrors`) are given.
    """
    from ..surface import blanks_from_design
    from .assembly import AssemblyErrors

    if scene is not None:
        settings = settings or TCASettings.from_scene(scene)
        errors = errors or AssemblyErrors.from_scene(scene)
    pinion, gear = blanks_from_design(design)
    asm = Assembly.from_design(design, errors)
    return tca_of_blanks(
        pinion,
        gear,
        asm,
        settings,
        pitch_point=design.pitch_point,
        designed_fpd=(design.fpd_angle_right, design.fpd_angle_left),
        pinion_angles=pinion_angles,
    )

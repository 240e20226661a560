"""Settings and result objects of the unloaded TCA (frozen, persistable)."""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass, field

import numpy as np

from ..errors import Problems
from ..surface import ToothBlank
from .assembly import Assembly

__all__ = ["TCASettings", "FlankContact", "TCAResult", "SIDE_NAMES", "LINE_CONTACT_FPD"]

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
        pairs: J, tooth pairs examined on each side of the reference pair at every
            position (the sweep's own half width in pitches is added).
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
        edge: (n,) str, what of a real flank touches the mate first and sets the gear
            angle at a position where no pair's surfaces touch on the real flanks
            (:data:`gearbox.tca.edge.CANDIDATES`): a border (a face end, the tip or the
            form line of either member, e.g. "gear heel"), a corner of two ("gear
            toe/tip") or a pinion border crossing a gear border ("pinion tip x gear
            heel"); "" elsewhere (surface contact, or none).
        edge_point: (n, 3) that edge contact's point in Sf (m), NaN elsewhere.
        edge_pair: (n,) int, its tooth pair's offset j (as ``pair``), 0 elsewhere.
        edge_pinion_flank, edge_gear_flank: (n, 2) its place on each flank as
            ``pinion_flank``, NaN elsewhere.
        edge_corner: (n,) bool, positions where that touch is at a corner (a face
            end's tip or root end, :data:`gearbox.tca.edge.CORNERS`, e.g.
            "gear toe/tip").
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
    edge: np.ndarray | None = None
    edge_point: np.ndarray | None = None
    edge_pair: np.ndarray | None = None
    edge_pinion_flank: np.ndarray | None = None
    edge_gear_flank: np.ndarray | None = None
    edge_corner: np.ndarray | None = None

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
        out["edge_contact_positions"] = {
            fc.name: _edge_tally(fc) for fc in (self.drive, self.coast)
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
                    x[k] = np.asarray(v, dtype=str if k in ("limit", "edge") else None)
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


def _edge_tally(fc) -> dict:
    """{border, corner or crossing: positions} of a side's edge contacts
    (``FlankContact.edge``)."""
    if fc.edge is None:
        return {}
    names, counts = np.unique(fc.edge[fc.edge != ""], return_counts=True)
    return {str(a): int(c) for a, c in zip(names, counts, strict=True)}


def _fin(x):
    return float(x) if x is not None and np.isfinite(x) else None

"""The drivetrain model: engine - input shaft - pinion - mesh - gear - output shaft - propeller.

Equations in docs/drivetrain.md (sections refer to it). :class:`DrivetrainModel` holds
every parameter in SI; :meth:`DrivetrainModel.params` flattens them into a dict of
arrays that :func:`rhs` consumes with ``xp = numpy`` (scipy reference) or
``xp = jax.numpy`` (diffrax backend): one implementation of the right-hand side.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError, Problem, Problems
from ..meshtable import FRICTION_ARMS, MeshTable, fourier_eval, fourier_fit

__all__ = [
    "CHANNEL_UNITS",
    "DrivetrainModel",
    "PitchApproach",
    "approach",
    "approach_terms",
    "eccentricity_approach",
    "eccentricity_terms",
    "energy",
    "friction_torques",
    "loaded_force",
    "outputs",
    "pitch_terms",
    "power",
    "rhs",
]

#: Mesh laws of :meth:`DrivetrainModel.build` (docs/drivetrain.md §3, §3d).
MESH_LAWS = ("tangent", "loaded")

_DOF_NAMES = ("engine", "pinion", "gear", "propeller", "pinion_bearing", "gear_bearing")


@dataclass(frozen=True)
class MeshFlank:
    """One flank's mesh law at the operating torque (docs/drivetrain.md §2-3).

    k_coef, e_coef: Fourier coefficients [a0, a_1..a_h, b_1..b_h] of the tangent
    stiffness (N/m) and of the no-load-equivalent error e (m) in the pinion angle.
    lte_coef: the same for the table's LTE (m), for the DTE channel.
    lambda1, lambda2: rotation radii (m). direction: mean line of action (Sf).
    damping: c_f (N s/m). backlash: b_f (m).
    friction_coef: the same for the sliding friction's moment arms about the pinion's
    and the gear's axis (m), shape (2, 1 + 2 h) (docs §3a); None where the table has
    none.
    transverse: the line of action's components along each member's transverse axes,
    shape (2, 2): rows pinion, gear; columns u_i . n_f, v_i . n_f, with u_i the unit
    vector from the axis towards the drive flank's mean mesh point (perpendicular to
    a_i) and v_i = a_i x u_i: an eccentricity's approach of the flanks (docs §3b).
    None for a model built before it existed (then no eccentricity is allowed).
    load_coef, load_forces: the loaded mesh law (docs §3d), None for the tangent law:
    Fourier coefficients, shape (2 J + 1, 1 + 2 h), of the flank's deflection at no load,
    its deflections (the LTE) at the table's J torque levels (m) and its tangent
    stiffnesses there (N/m); and the mesh forces of the levels (N, shape (J,)).
    """

    k_coef: np.ndarray
    e_coef: np.ndarray
    lte_coef: np.ndarray
    lambda1: float
    lambda2: float
    direction: np.ndarray
    damping: float
    backlash: float
    friction_coef: np.ndarray | None = None
    transverse: np.ndarray | None = None
    load_coef: np.ndarray | None = None
    load_forces: np.ndarray | None = None

    @property
    def mean_stiffness(self) -> float:
        return float(self.k_coef[0])

    @property
    def mean_friction_arms(self) -> tuple[float, float]:
        """Cycle means of the friction arms about the pinion's and the gear's axis (m)."""
        if self.friction_coef is None:
            return 0.0, 0.0
        return float(self.friction_coef[0, 0]), float(self.friction_coef[1, 0])


@dataclass(frozen=True)
class PitchApproach:
    """The pitch deviations' approach of the drive flank over a hunting period
    (docs/drivetrain.md §3c): samples a_j (m) at the pinion angles angle0 + j step,
    j = 0..n-1, periodic with n step, through which a periodic cubic spline passes.
    a = -(the loaded TE's change), arm(theta) sum_k w_k(theta) alpha_k of
    docs/ltca.md "Pitch deviations", at the model's torque. ``carries``: what the
    samples hold, for reports ("pitch deviations", "slopes and crownings", "measured
    traces", and "exact re-solves" from :meth:`from_levels`).
    """

    values: np.ndarray
    angle0: float
    step: float
    carries: tuple[str, ...] = ()

    def __post_init__(self):
        v = np.array(self.values, dtype=float).reshape(-1)
        p = Problems()
        p.check(
            v.size >= 4 and np.all(np.isfinite(v)),
            "pitch.values",
            v.size,
            "must be >= 4 finite samples (m)",
        )
        p.check(
            math.isfinite(self.step) and self.step > 0, "pitch.step", self.step, "must be > 0 rad"
        )
        p.raise_if_any("invalid pitch approach")
        v.setflags(write=False)
        object.__setattr__(self, "values", v)

    @property
    def period(self) -> float:
        """Pinion angle of a hunting period (rad)."""
        return self.values.size * self.step

    def coefficients(self) -> np.ndarray:
        """Spline coefficients per sample interval, shape (n, 4): a = c0 + c1 d + c2 d^2
        + c3 d^3 with d in [0, 1) the position within the interval (in samples); fitted
        once (read-only)."""
        if "_coef" not in self.__dict__:
            from scipy.interpolate import CubicSpline

            v = self.values
            cs = CubicSpline(np.arange(v.size + 1), np.append(v, v[0]), bc_type="periodic")
            c = np.ascontiguousarray(cs.c[::-1].T)
            c.setflags(write=False)
            object.__setattr__(self, "_coef", c)
        return self.__dict__["_coef"]

    def __call__(self, theta1):
        """a (m) and da / dtheta_1 (m/rad) at pinion angles theta1 (any shape)."""
        return _pitch_eval(
            np.asarray(theta1, dtype=float), self.coefficients(), self.angle0, self.step, np
        )

    @classmethod
    def from_table(
        cls, table: MeshTable, pinion, gear, torque: float, form=None, turns=None
    ) -> PitchApproach:
        """From a mesh table with pair weights and torque arm (a loaded TCA's) and the
        cumulative pitch deviations of the drive flanks (m, one per tooth, docs/ltca.md
        "Pitch deviations"), at ``torque``: samples over lcm(N_1, N_2) mesh cycles.
        ``form``: the teeth's profile and helix slopes and crownings
        (:class:`~gearbox.ltca.pitch.FormDeviations`, docs/ltca.md "Form deviations"),
        which need the table's form weights. ``turns``: measured traces as
        :class:`~gearbox.ltca.pitch.TraceTurns` of the loaded TCA the table holds (same
        torque levels, positions and tooth pairs; docs/ltca.md "Measured traces")."""
        from ..meshtable import TORQUE_ARM, form_weight_fields, pair_weight_fields

        p = Problems()
        fields_ = pair_weight_fields(table)
        p.check(
            bool(fields_) and TORQUE_ARM in table.extra and "drive" in table.flanks,
            "mesh table",
            table.attrs.get("method", ""),
            "pitch deviations need a loaded-TCA mesh table with the drive flank's pair "
            "weights and torque arm (the analytical tables have none)",
        )
        weights = form_weight_fields(table) if form is not None else {}
        if form is not None:
            p.check(
                bool(weights) and set(weights) == set(fields_),
                "mesh table",
                table.attrs.get("method", ""),
                "form deviations need a loaded-TCA mesh table with the drive flank's form "
                "weights (run the loaded TCA again)",
            )
        radii = [table.attrs.get(f"{m}_reference_pitch_radius_m") for m in ("pinion", "gear")]
        p.check(
            all(r is not None and float(r) > 0 for r in radii),
            "mesh table attrs",
            radii,
            "need pinion_reference_pitch_radius_m and gear_reference_pitch_radius_m",
        )
        z1, z2 = table.pinion_teeth, table.gear_teeth
        pin = np.asarray(pinion, dtype=float).reshape(-1)
        gea = np.asarray(gear, dtype=float).reshape(-1)
        p.check(pin.size == z1, "pinion deviations", pin.size, f"must be {z1} values")
        p.check(gea.size == z2, "gear deviations", gea.size, f"must be {z2} values")
        if form is not None:
            p.check(
                tuple(form.teeth) == (z1, z2),
                "form deviations",
                form.teeth,
                f"must be {z1} / {z2} values",
            )
        ks = np.array(sorted(fields_))
        if turns is not None:
            _check_turns(p, turns, table, ks, (z1, z2))
        p.raise_if_any("invalid pitch deviations")
        H = z1 * z2 // math.gcd(z1, z2)
        w = np.stack([table.values_at(fields_[k], "drive", torque) for k in ks], axis=1)  # (P,K)
        arm = table.values_at(TORQUE_ARM, "drive", torque)  # (P,)
        c = np.arange(H)[:, None] - ks[None, :]
        alpha = pin[c % z1] / float(radii[0]) + gea[c % z2] / float(radii[1]) * (z2 / z1)
        turn = alpha @ w.T  # (H, P): sum_k w_k alpha_k
        if form is not None:
            W = np.stack(
                [[table.values_at(n, "drive", torque) for n in weights[k]] for k in ks], axis=1
            )  # (J, K, P)
            turn = turn + np.einsum("hkj,jkp->hp", form.coefficients(c % z1, c % z2), W)
        if turns is not None:
            ct = np.arange(H)[:, None] - np.asarray(turns.pair_index)[None, :]
            for t, z in zip(turns.at(torque), (z1, z2), strict=True):
                if t is not None:  # t (P, K, z): pair k holds tooth (c - k) mod z
                    turn = turn + sum(t[:, kk, ct[:, kk] % z].T for kk in range(ct.shape[1]))
        values = (arm[None, :] * turn).reshape(-1)
        step = float(table.angle[1] - table.angle[0])
        carries = _carries(pin, gea, form is not None, turns is not None)
        return cls(values, float(table.angle[0]), step, carries)

    @classmethod
    def from_levels(cls, table: MeshTable, levels, torque: float) -> PitchApproach:
        """From the exact hunting records at the torque levels of the loaded TCA the
        table holds, and any further torques (:class:`~gearbox.ltca.pitch.LevelRecords`):
        minus their TE change, linear in torque between them, sampled at the table's
        positions over the hunting period."""
        p = Problems()
        p.check(
            levels.fraction.size == table.angle.size,
            "level records",
            f"{levels.fraction.size} positions",
            f"must be made at the table's {table.angle.size} positions",
        )
        made = np.asarray(levels.torque, dtype=float)
        p.check(
            all(np.any(np.isclose(made, t, rtol=1e-12, atol=0.0)) for t in table.torque),
            "level records",
            made.tolist(),
            f"must hold the table's torque levels {np.asarray(table.torque).tolist()} N m",
        )
        z1, z2 = table.pinion_teeth, table.gear_teeth
        p.check(
            tuple(levels.deviations.teeth) == (z1, z2),
            "level records",
            levels.deviations.teeth,
            f"must be made for {z1} / {z2} teeth",
        )
        p.raise_if_any("invalid pitch deviations")
        values = -levels.at(torque).reshape(-1)
        dev = levels.deviations
        carries = _carries(dev.pinion, dev.gear, dev.form is not None, dev.traces is not None)
        step = float(table.angle[1] - table.angle[0])
        return cls(values, float(table.angle[0]), step, (*carries, "exact re-solves"))


def _carries(pinion, gear, form: bool, traces: bool) -> tuple[str, ...]:
    """What an approach holds, by name (:attr:`PitchApproach.carries`)."""
    named = (
        ("pitch deviations", bool(np.any(pinion) or np.any(gear))),
        ("slopes and crownings", form),
        ("measured traces", traces),
    )
    return tuple(name for name, on in named if on)


def _check_turns(p: Problems, turns, table: MeshTable, ks, teeth) -> None:
    """Trace turns against the table: its torque levels, positions and tooth pairs,
    and each member's teeth."""
    p.check(
        set(np.asarray(turns.pair_index).tolist()) <= set(ks.tolist()),
        "trace turns",
        np.asarray(turns.pair_index).tolist(),
        f"must be made for tooth pairs among the table's {ks.tolist()}",
    )
    p.check(
        turns.fraction.size == table.angle.size,
        "trace turns",
        f"{turns.fraction.size} positions",
        f"must be made at the table's {table.angle.size} positions",
    )
    p.check(
        turns.torque.shape == table.torque.shape
        and np.allclose(turns.torque, table.torque, rtol=1e-12, atol=0.0),
        "trace turns",
        np.asarray(turns.torque).tolist(),
        f"must be made at the table's torque levels {np.asarray(table.torque).tolist()} N m",
    )
    for t, z, name in zip((turns.pinion, turns.gear), teeth, ("pinion", "gear"), strict=True):
        if t is not None:
            p.check(
                t.shape[-1] == z,
                f"trace turns ({name})",
                f"{t.shape[-1]} teeth",
                f"must be {z} values",
            )


def _pitch_eval(theta1, coef, angle0, step, xp):
    """The spline of :class:`PitchApproach` (coefficients ``coef`` (n, 4)) and its
    derivative per radian at ``theta1``: the interval found by division (uniform
    samples), so numpy and jax alike."""
    n = coef.shape[0]
    u = (theta1 - angle0) / step
    i0 = xp.floor(u)
    d = u - i0
    i = xp.mod(i0, n).astype(int) if xp is np else xp.mod(i0, n).astype(xp.int32)
    c = coef[i]
    a = c[..., 0] + d * (c[..., 1] + d * (c[..., 2] + d * c[..., 3]))
    da = (c[..., 1] + d * (2.0 * c[..., 2] + 3.0 * d * c[..., 3])) / step
    return a, da


def _pitch_of(
    scene, table: MeshTable, torque: float, turns=None, levels=None
) -> PitchApproach | None:
    """The scene's ``[pitch]`` deviations as the drive flank's approach when
    ``drivetrain.pitch_deviations`` is on (docs §3c), else None. Measured traces
    need their ``turns`` (:func:`~gearbox.ltca.pitch.trace_turns`, made of the same
    traces); ``pitch.method = "exact"`` needs the exact records at the torque levels,
    ``levels`` (:func:`~gearbox.ltca.pitch.level_records`, made of the same
    deviations)."""
    if not scene["drivetrain"]["pitch_deviations"]:
        return None
    from ..ltca.pitch import (
        PitchDeviations,
        deviations_from_section,
        form_from_section,
        same_deviations,
        traces_from_section,
    )
    from ..meshtable import CONTACT_CENTRES, CONTACT_LENGTHS

    teeth = (table.pinion_teeth, table.gear_teeth)
    pin, gear = deviations_from_section(scene["pitch"], teeth)
    traces = traces_from_section(scene["pitch"], teeth)
    covered = []
    for names in (CONTACT_LENGTHS, CONTACT_CENTRES):
        v = [table.attrs.get(k) for k in names]
        covered.append(None if None in v else ((v[0], v[1]), (v[2], v[3])))
    form = form_from_section(scene["pitch"], teeth, *covered)
    if scene["pitch"]["method"] == "exact":
        why = "none given"
        if levels is not None:
            dev = PitchDeviations(pin, gear, 1.0, 1.0, form, traces)  # radii not compared
            same = same_deviations(levels.deviations, dev)
            why = None if same else "those given were made of other deviations"
        if why is not None:
            raise InputError(
                Problem(
                    "pitch.method",
                    "exact",
                    "the dynamics take the exact method's approach from its records at the "
                    "loaded TCA's torque levels (gearbox.ltca.pitch.level_records, made by "
                    f"`gearbox run`'s approach stage): {why}",
                )
            )
        return PitchApproach.from_levels(table, levels, torque)
    if traces is None:
        turns = None  # none to carry
    elif turns is None or not turns.matches(traces):
        raise InputError(
            Problem(
                "drivetrain.pitch_deviations",
                True,
                "the scene's measured traces (pitch.*_trace_um) enter the dynamics through "
                "their turns on the loaded TCA (gearbox.ltca.pitch.trace_turns, made by "
                "`gearbox run`'s approach stage): "
                + ("none given" if turns is None else "those given were made of other traces"),
            )
        )
    return PitchApproach.from_table(table, pin, gear, torque, form, turns)


@dataclass(frozen=True)
class DrivetrainModel:
    """All parameters of the drivetrain in SI (docs/drivetrain.md §8).

    Inertias (kg m^2), stiffnesses (N m/rad, N/m), damping ratios (-), speed (rad/s),
    torques (N m), masses (kg), backlash (m). ``drive``/``coast``: :class:`MeshFlank`
    at the operating torque (``coast`` is None when the table has no coast flank).
    """

    pinion_teeth: int
    gear_teeth: int
    speed: float  # Omega, engine = pinion (rad/s)
    torque: float  # T_op (N m)
    engine_inertia: float
    pinion_inertia: float
    gear_inertia: float
    propeller_inertia: float  # incl. added water inertia
    input_stiffness: float
    output_stiffness: float
    input_damping_ratio: float
    output_damping_ratio: float
    drive: MeshFlank
    coast: MeshFlank | None
    bearing_dofs: bool = False
    pinion_bearing_stiffness: float = 1e9
    gear_bearing_stiffness: float = 1e9
    pinion_mass: float = 8.0
    gear_mass: float = 15.0
    bearing_damping_ratio: float = 0.02
    engine_cylinders: int = 8
    firing_ripple: float = 0.1
    engine_harmonics: int = 1
    half_order_ripple: float = 0.0
    governor: bool = False
    governor_kp: float = 0.0
    governor_ki: float = 0.0
    propeller_blades: int = 3
    blade_pass_ripple: float = 0.05
    blade_pass_harmonics: int = 1
    phase: float = 0.0
    mesh_friction_coefficient: float = 0.0
    pinion_eccentricity: float = 0.0  # e_1 (m), docs §3b
    pinion_eccentricity_angle: float = 0.0  # psi_1 (rad)
    gear_eccentricity: float = 0.0  # e_2 (m)
    gear_eccentricity_angle: float = 0.0  # psi_2 (rad)
    pitch: PitchApproach | None = None  # docs §3c
    meta: Mapping[str, Any] = field(default_factory=dict)

    def __post_init__(self):
        p = Problems()
        for name in (
            "engine_inertia",
            "pinion_inertia",
            "gear_inertia",
            "propeller_inertia",
            "input_stiffness",
            "output_stiffness",
            "speed",
            "torque",
        ):
            v = getattr(self, name)
            p.check(math.isfinite(v) and v > 0, name, v, "must be finite and > 0")
        for name in ("input_damping_ratio", "output_damping_ratio", "bearing_damping_ratio"):
            p.in_range(name, getattr(self, name), 0, 1)
        p.in_range("mesh_friction_coefficient", self.mesh_friction_coefficient, 0, 0.3)
        for name in ("pinion_eccentricity", "gear_eccentricity"):
            v = getattr(self, name)
            p.in_range(name, v, 0, 1e-3)
            if v > 0:
                p.check(
                    self.drive.transverse is not None,
                    name,
                    v,
                    "needs the flanks' transverse projections (a model built from a mesh "
                    "table, DrivetrainModel.build); set it to 0",
                )
        for name in ("pinion_eccentricity_angle", "gear_eccentricity_angle"):
            v = getattr(self, name)
            p.check(math.isfinite(v), name, v, "must be finite (rad)")
        if self.mesh_friction_coefficient > 0:
            for fl_name in ("drive", "coast"):
                fl = getattr(self, fl_name)
                p.check(
                    fl is None or fl.friction_coef is not None,
                    "mesh_friction_coefficient",
                    self.mesh_friction_coefficient,
                    f"needs the friction arms of the {fl_name} flank, which the mesh table "
                    "lacks (friction_arm_pinion_m / friction_arm_gear_m); set it to 0",
                )
        if self.bearing_dofs:
            for name in (
                "pinion_bearing_stiffness",
                "gear_bearing_stiffness",
                "pinion_mass",
                "gear_mass",
            ):
                v = getattr(self, name)
                p.check(math.isfinite(v) and v > 0, name, v, "must be finite and > 0")
        for fl_name in ("drive", "coast"):
            fl = getattr(self, fl_name)
            if fl is None:
                continue
            k0 = fl.k_coef[0]
            p.check(k0 > 0, f"{fl_name}.mean_stiffness", float(k0), "must be > 0 N/m")
            p.check(
                (fl.load_coef is None) == (self.drive.load_coef is None)
                and (fl.load_coef is None) == (fl.load_forces is None),
                f"{fl_name}.load_coef",
                "given" if fl.load_coef is not None else None,
                "both flanks take one mesh law: the loaded law's rows and forces on both, "
                "or on neither",
            )
            p.check(fl.backlash >= 0, f"{fl_name}.backlash", fl.backlash, "must be >= 0 m")
        p.check(
            self.drive.lambda1 > 0 and self.drive.lambda2 > 0,
            "drive rotation radii",
            (self.drive.lambda1, self.drive.lambda2),
            "must be > 0 m (check the table's axes and line of action)",
        )
        mu = self.mesh_friction_coefficient
        if mu > 0 and self.drive.friction_coef is not None:
            f1, f2 = self.drive.mean_friction_arms
            arms = (self.drive.lambda1 + mu * f1, self.drive.lambda2 + mu * f2)
            p.check(
                min(arms) > 0,
                "mesh_friction_coefficient",
                mu,
                f"leaves the drive flank's torque arms lambda + mu phi at {arms[0]:.4g} / "
                f"{arms[1]:.4g} m: they must stay > 0 (the friction would reverse the drive)",
            )
        p.raise_if_any("invalid drivetrain model")

    # ---------------------------------------------------------------- build
    @classmethod
    def from_scene(
        cls,
        scene,
        table: MeshTable | None = None,
        *,
        speed_rpm: float | None = None,
        trace_turns=None,
        level_records=None,
        mesh_law: str | None = None,
    ) -> DrivetrainModel:
        """Model of a scene's ``[drivetrain]`` with a mesh table (analytical if None).

        speed_rpm overrides ``drivetrain.engine_speed_rpm``; mesh_law overrides
        ``drivetrain.mesh_law``, whose ``"auto"`` builds the tangent law (a run then
        repeats with the loaded law where it needs it,
        :func:`gearbox.drivetrain.simulate.run_with_auto_law`). ``trace_turns``: the
        scene's measured traces on the table's loaded TCA
        (:func:`gearbox.ltca.pitch.trace_turns`), needed when
        ``drivetrain.pitch_deviations`` is on and ``[pitch]`` sets traces;
        ``level_records``: the exact records at the table's torque levels
        (:func:`gearbox.ltca.pitch.level_records`), needed instead with
        ``pitch.method = "exact"``.
        """
        from ..errors import expect_scene, expect_type

        expect_scene(scene, "DrivetrainModel.from_scene: scene")
        if table is not None:
            expect_type(
                table,
                MeshTable,
                "DrivetrainModel.from_scene: table",
                "MeshTable.from_netcdf(path), or the tables stage's result",
            )
            p = Problems()
            for member in ("pinion", "gear"):
                try:  # a pipeline stage's scene holds only what it reads: its tables
                    want = scene[member]["teeth"]  # come from the same scene's design
                except KeyError:
                    continue
                have = getattr(table, f"{member}_teeth")
                p.check(
                    have == want,
                    f"{member}.teeth",
                    want,
                    f"the mesh table is of a pair with {have} {member} teeth: a table of "
                    "another design (make it from this scene: gearbox ltca, or gearbox run)",
                )
            p.raise_if_any("mesh table and scene disagree")
        d = scene["drivetrain"]
        if table is None:
            from ..mesh_analytical import analytical_table, pair_from_scene

            table = analytical_table(
                pair_from_scene(scene), scene["load"]["torques_Nm"], scene=scene.name
            )
        rpm = float(speed_rpm if speed_rpm is not None else d["engine_speed_rpm"])
        omega = rpm * math.pi / 30.0
        if d["engine_power_kW"] is not None:
            torque = d["engine_power_kW"] * 1e3 / omega
            key, value = "drivetrain.engine_power_kW", d["engine_power_kW"]
            how = f"gives {torque:.6g} N m on the pinion at {rpm:g} rpm"
        else:
            torque = scene["load"]["operating_torque_Nm"]
            key, value, how = "load.operating_torque_Nm", torque, "is the pinion torque"
        lo, hi = float(np.min(table.torque)), float(np.max(table.torque))
        if not lo * (1 - 1e-9) <= torque <= hi * (1 + 1e-9):
            raise InputError(
                Problem(
                    key,
                    value,
                    f"{how}, outside the mesh table's torque levels [{lo:g}, {hi:g}] N m "
                    "(load.torques_Nm; tables are not extrapolated)",
                ),
                "operating point outside the mesh table",
            )
        return cls.build(
            table,
            speed=omega,
            torque=torque,
            engine_inertia=d["engine_inertia_kgm2"],
            pinion_inertia=d["pinion_inertia_kgm2"],
            gear_inertia=d["gear_inertia_kgm2"],
            propeller_inertia=d["propeller_inertia_kgm2"]
            * (1 + d["propeller_added_inertia_fraction"]),
            input_stiffness=d["input_shaft_stiffness_Nm_per_rad"],
            output_stiffness=d["output_shaft_stiffness_Nm_per_rad"],
            input_damping_ratio=d["input_shaft_damping_ratio"],
            output_damping_ratio=d["output_shaft_damping_ratio"],
            mesh_damping_ratio=d["mesh_damping_ratio"],
            backlash=d["backlash_mm"] * 1e-3,
            mesh_harmonics=d["mesh_harmonics"],
            mesh_law=mesh_law or ("tangent" if d["mesh_law"] == "auto" else d["mesh_law"]),
            bearing_dofs=d["bearing_dofs"],
            pinion_bearing_stiffness=d["pinion_bearing_stiffness_N_per_m"],
            gear_bearing_stiffness=d["gear_bearing_stiffness_N_per_m"],
            pinion_mass=d["pinion_mass_kg"],
            gear_mass=d["gear_mass_kg"],
            bearing_damping_ratio=d["bearing_damping_ratio"],
            engine_cylinders=d["engine_cylinders"],
            firing_ripple=d["firing_torque_ripple"],
            engine_harmonics=d["engine_harmonics"],
            half_order_ripple=d["half_order_ripple"],
            governor=d["governor"],
            governor_kp=d["governor_kp_Nms_per_rad"],
            governor_ki=d["governor_ki_Nm_per_rad"],
            propeller_blades=d["propeller_blades"],
            blade_pass_ripple=d["blade_pass_ripple"],
            blade_pass_harmonics=d["blade_pass_harmonics"],
            mesh_friction_coefficient=d["mesh_friction_coefficient"],
            pinion_eccentricity=d["pinion_eccentricity_um"] * 1e-6,
            pinion_eccentricity_angle=math.radians(d["pinion_eccentricity_angle_deg"]),
            gear_eccentricity=d["gear_eccentricity_um"] * 1e-6,
            gear_eccentricity_angle=math.radians(d["gear_eccentricity_angle_deg"]),
            pitch=_pitch_of(scene, table, torque, trace_turns, level_records),
            meta={"scene": scene.name, "table_method": table.attrs.get("method", "")},
        )

    @classmethod
    def build(
        cls,
        table: MeshTable,
        *,
        speed: float,
        torque: float,
        mesh_damping_ratio: float = 0.05,
        backlash: float = 1e-4,
        mesh_harmonics: int = 0,
        mesh_law: str = "tangent",
        **kw,
    ) -> DrivetrainModel:
        """Model from SI parameters and a table; the mesh flanks are evaluated at ``torque``.

        speed: Omega (rad/s); torque: T_op (N m), must lie in the table's torque range.
        mesh_law: ``"tangent"``, the tangent stiffness and LTE at ``torque`` (docs §3;
        between the table's levels the loaded law's tangent, :func:`tangent_at`), or
        ``"loaded"``, the force against the deflection through all of the table's torque
        levels (docs §3d), whose tangent at ``torque`` is the same. Other keywords: the
        dataclass fields.
        """
        p = Problems()
        p.in_range("mesh_damping_ratio", mesh_damping_ratio, 0, 1)
        p.in_range("backlash", backlash, 0, None)
        p.check(math.isfinite(torque) and torque > 0, "torque", torque, "must be > 0 N m")
        p.check(mesh_law in MESH_LAWS, "mesh_law", mesh_law, f"must be one of {MESH_LAWS}")
        if mesh_law == "loaded":
            p.check(
                table.torque.size >= 2,
                "mesh_law",
                mesh_law,
                f"needs a mesh table with >= 2 torque levels (it has {table.torque.size})",
            )
        p.raise_if_any("invalid drivetrain model")
        j1 = kw["pinion_inertia"]
        j2 = kw["gear_inertia"]

        def flank(name: str, b: float) -> MeshFlank:
            lam1, lam2 = table.rotation_radii(name, torque)
            lam1d = table.rotation_radii("drive", torque)[0] if "drive" in table.flanks else lam1
            fn = torque / abs(lam1d)
            a0 = float(table.angle[0])

            def coef(values):  # [a0, a, b] in the absolute pinion angle
                return np.concatenate(_fit(values, mesh_harmonics, table.pinion_teeth, a0))

            load = None
            if mesh_law == "loaded":
                rows, forces = loaded_law_samples(table, name, abs(lam1d))
                lte, kt = loaded_law_point(rows, forces, fn)
                load = (np.stack([coef(r) for r in rows]), forces)
            else:
                (kt, lte), _ = tangent_at(table, name, abs(lam1d), torque)
            e = lte - fn / kt
            kc, ec, lc = coef(kt), coef(e), coef(lte)
            inv_m = lam1**2 / j1 + lam2**2 / j2
            c = 2 * mesh_damping_ratio * math.sqrt(kc[0] / inv_m) if kc[0] > 0 else 0.0
            fc = None
            if all(k in table.extra for k in FRICTION_ARMS):
                fc = np.stack([coef(table.values_at(k, name, torque)) for k in FRICTION_ARMS])
            direction = table.mean_direction(name, torque)
            return MeshFlank(
                kc, ec, lc, lam1, lam2, direction, c, b, fc, basis @ direction, *(load or ())
            )

        basis = transverse_axes(table, torque)

        drive = flank("drive", 0.0)
        coast = flank("coast", backlash) if "coast" in table.flanks else None
        return cls(
            pinion_teeth=table.pinion_teeth,
            gear_teeth=table.gear_teeth,
            speed=speed,
            torque=torque,
            drive=drive,
            coast=coast,
            **kw,
        )

    def with_speed(self, speed: float) -> DrivetrainModel:
        """Same model at another speed Omega (rad/s); torque and mesh law unchanged."""
        return dataclasses.replace(self, speed=float(speed))

    # ---------------------------------------------------------------- layout
    @property
    def mesh_law(self) -> str:
        """``"loaded"`` when the flanks carry the loaded mesh law (docs §3d), else
        ``"tangent"``."""
        return "tangent" if self.drive.load_coef is None else "loaded"

    @property
    def n_dof(self) -> int:
        return 6 if self.bearing_dofs else 4

    @property
    def dof_names(self) -> tuple[str, ...]:
        return _DOF_NAMES[: self.n_dof]

    @property
    def gear_speed(self) -> float:
        """Omega_2 = Omega N_1 / N_2 (rad/s)."""
        return self.speed * self.pinion_teeth / self.gear_teeth

    @property
    def mesh_frequency(self) -> float:
        """N_1 Omega / (2 pi) (Hz)."""
        return self.pinion_teeth * self.speed / (2 * math.pi)

    @property
    def torque_ratio(self) -> float:
        """Mean gear torque over mean pinion torque in steady drive-flank contact:
        (lambda_2 + mu phi_2) / (lambda_1 + mu phi_1) with the friction arms' cycle means
        (docs §3a; lambda_2 / lambda_1 without friction)."""
        mu = self.mesh_friction_coefficient
        f1, f2 = self.drive.mean_friction_arms
        return (self.drive.lambda2 + mu * f2) / (self.drive.lambda1 + mu * f1)

    @property
    def mean_mesh_force(self) -> float:
        """Static drive-flank mesh force at T_op (N): T_op / (lambda_1 + mu phi_1)."""
        mu = self.mesh_friction_coefficient
        return self.torque / (self.drive.lambda1 + mu * self.drive.mean_friction_arms[0])

    @property
    def propeller_coefficient(self) -> float:
        """kappa (N m s^2/rad^2): nominal torque balance (docs §6)."""
        return self.torque * self.torque_ratio / self.gear_speed**2

    def mass_vector(self) -> np.ndarray:
        m = [self.engine_inertia, self.pinion_inertia, self.gear_inertia, self.propeller_inertia]
        if self.bearing_dofs:
            m += [self.pinion_mass, self.gear_mass]
        return np.array(m)

    def structural_matrices(self) -> tuple[np.ndarray, np.ndarray]:
        """K_s, C_s (shafts and bearings), shape (n, n) (docs §4)."""
        n = self.n_dof
        K = np.zeros((n, n))
        C = np.zeros((n, n))
        je, j1, j2, jp = self.mass_vector()[:4]

        def spring(i, j, k, c):
            K[i, i] += k
            K[j, j] += k
            K[i, j] -= k
            K[j, i] -= k
            C[i, i] += c
            C[j, j] += c
            C[i, j] -= c
            C[j, i] -= c

        cin = 2 * self.input_damping_ratio * math.sqrt(self.input_stiffness * je * j1 / (je + j1))
        cout = (
            2 * self.output_damping_ratio * math.sqrt(self.output_stiffness * j2 * jp / (j2 + jp))
        )
        spring(0, 1, self.input_stiffness, cin)
        spring(2, 3, self.output_stiffness, cout)
        if self.bearing_dofs:
            for i, k, m in (
                (4, self.pinion_bearing_stiffness, self.pinion_mass),
                (5, self.gear_bearing_stiffness, self.gear_mass),
            ):
                K[i, i] += k
                C[i, i] += 2 * self.bearing_damping_ratio * math.sqrt(k * m)
        return K, C

    def mesh_vectors(self) -> np.ndarray:
        """G, shape (2, n): rows drive, coast (zeros when there is no coast flank) (docs §2)."""
        G = np.zeros((2, self.n_dof))
        nd = self.drive.direction
        for r, fl in enumerate((self.drive, self.coast)):
            if fl is None:
                continue
            G[r, 1] = fl.lambda1
            G[r, 2] = -fl.lambda2
            if self.bearing_dofs:
                proj = float(nd @ fl.direction)
                G[r, 4] = proj
                G[r, 5] = -proj
        return G

    def common_period_mesh_cycles(self, max_cycles: int = 100_000) -> int:
        """Mesh cycles in the common period of every excitation (0 if above ``max_cycles``).

        Mesh (N_1 per pinion revolution), engine orders (per revolution), propeller
        orders (per gear revolution = N_1/N_2 per pinion revolution) with non-zero
        amplitude and the eccentricities' once per revolution of their member are written as rational orders of the pinion revolution; the common
        period is the least common multiple of their periods. The response settles to
        a periodic one with this period (when it is stable), so one common period is
        the natural record for spectra and the periodicity check.
        """
        from fractions import Fraction

        eo, ea, po, pa = self.excitation_orders()
        orders = [Fraction(self.pinion_teeth)]
        orders += [Fraction(o).limit_denominator(1000) for o, a in zip(eo, ea, strict=True) if a]
        ratio = Fraction(self.pinion_teeth, self.gear_teeth)
        orders += [
            Fraction(o).limit_denominator(1000) * ratio for o, a in zip(po, pa, strict=True) if a
        ]
        if self.pinion_eccentricity > 0:
            orders.append(Fraction(1))  # once per pinion revolution (docs §3b)
        if self.gear_eccentricity > 0:
            orders.append(ratio)  # once per gear revolution
        if self.pitch is not None:  # once per hunting period (docs §3c)
            z1, z2 = self.pinion_teeth, self.gear_teeth
            orders.append(Fraction(z1, z1 * z2 // math.gcd(z1, z2)))
        # period of order o (in revolutions) is 1/o = q/p; LCM of fractions q_i/p_i
        num = 1
        den = 0
        for o in orders:
            per = 1 / o
            num = math.lcm(num, per.numerator)
            den = math.gcd(den, per.denominator)
        revs = Fraction(num, den)
        cycles = revs * self.pinion_teeth
        if cycles.denominator != 1 or cycles > max_cycles:
            return 0
        return int(cycles)

    def excitation_orders(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Engine (orders of Omega, amplitudes/T_op) and propeller (orders of Omega_2, amplitudes)."""
        eo, ea = [], []
        of = self.engine_cylinders / 2.0
        for h in range(1, self.engine_harmonics + 1):
            eo.append(h * of)
            ea.append(self.firing_ripple / h)
        for k in range(1, 4):
            eo.append(0.5 * k)
            ea.append(self.half_order_ripple / k)
        po, pa = [], []
        for h in range(1, self.blade_pass_harmonics + 1):
            po.append(h * self.propeller_blades)
            pa.append(self.blade_pass_ripple / h)
        return np.array(eo), np.array(ea), np.array(po), np.array(pa)

    def friction_vectors(self) -> np.ndarray:
        """Phi, shape (2, n): the cycle means of the friction's generalised-force
        direction per unit contact force, rows drive, coast (docs §3a): mu phi_1 on the
        pinion, -mu phi_2 on the gear; zeros without friction."""
        Phi = np.zeros((2, self.n_dof))
        mu = self.mesh_friction_coefficient
        for r, fl in enumerate((self.drive, self.coast)):
            if fl is not None:
                f1, f2 = fl.mean_friction_arms
                Phi[r, 1], Phi[r, 2] = mu * f1, -mu * f2
        return Phi

    @property
    def has_eccentricity(self) -> bool:
        return self.pinion_eccentricity > 0 or self.gear_eccentricity > 0

    def eccentricity_coefficients(self) -> np.ndarray:
        """Coefficients of the eccentricities' approach of the flanks (m), shape (2, 4):
        rows drive, coast; eps_f = A_1 cos theta_1 + B_1 sin theta_1 + A_2 cos theta_2 +
        B_2 sin theta_2 with columns [A_1, B_1, A_2, B_2] (docs §3b): the pinion's
        eccentricity e_1 (u_1 cos(theta_1 + psi_1) + v_1 sin(theta_1 + psi_1)) moves
        its flanks along n_f towards the gear, the gear's moves its own away."""
        out = np.zeros((2, 4))
        for r, fl in enumerate((self.drive, self.coast)):
            if fl is None or fl.transverse is None:
                continue
            for m, (e, psi, sign) in enumerate(
                (
                    (self.pinion_eccentricity, self.pinion_eccentricity_angle, 1.0),
                    (self.gear_eccentricity, self.gear_eccentricity_angle, -1.0),
                )
            ):
                pu, pv = fl.transverse[m]
                c, s = math.cos(psi), math.sin(psi)
                out[r, 2 * m] = sign * e * (pu * c + pv * s)
                out[r, 2 * m + 1] = sign * e * (pv * c - pu * s)
        return out

    def static_state(self) -> np.ndarray:
        """State y0 = [x, v] of the static equilibrium of the mean torques (docs §7), q_p = 0."""
        n = self.n_dof
        K, _ = self.structural_matrices()
        G = self.mesh_vectors()
        W = G[0] + self.friction_vectors()[0]  # the mesh force's generalised direction
        kd = self.drive.mean_stiffness
        ed = float(self.drive.e_coef[0])
        Kt = K + kd * np.outer(W, G[0])
        f = np.zeros(n)
        f[0] = self.torque
        f[3] = -self.propeller_coefficient * self.gear_speed**2
        f += kd * ed * W
        keep = [i for i in range(n) if i != 3]
        x = np.zeros(n)
        x[keep] = np.linalg.solve(Kt[np.ix_(keep, keep)], f[keep])
        return np.concatenate([x, np.zeros(n)])

    def state_scale(self) -> np.ndarray:
        """Per-state scale (rad, m, rad/s, m/s) so that one absolute tolerance fits all.

        Angles: static mesh deflection over the rotation radius; translations: the static
        deflection; speeds: those times the mesh circular frequency.
        """
        n = self.n_dof
        defl = self.torque / self.drive.lambda1 / self.drive.mean_stiffness
        x = np.empty(n)
        x[0] = x[1] = defl / self.drive.lambda1
        x[2] = x[3] = defl / self.drive.lambda2
        if self.bearing_dofs:
            x[4:] = defl
        w = 2 * math.pi * self.mesh_frequency
        return np.concatenate([x, x * w])

    def params(self) -> dict[str, np.ndarray]:
        """Flat parameter dict (numpy arrays) consumed by :func:`rhs`."""
        K, C = self.structural_matrices()
        G = self.mesh_vectors()
        h = max(len(self.drive.k_coef), len(self.coast.k_coef) if self.coast else 0)

        def pad(c):
            hh = (len(c) - 1) // 2
            out = np.zeros(h)
            hc = (h - 1) // 2
            out[0] = c[0]
            out[1 : 1 + hh] = c[1 : 1 + hh]
            out[1 + hc : 1 + hc + hh] = c[1 + hh :]
            return out

        zero = np.zeros(h)
        fl = [self.drive, self.coast]
        mu = self.mesh_friction_coefficient
        if mu > 0:
            fc = np.stack(
                [
                    np.stack([pad(r) for r in f.friction_coef]) * mu
                    if f is not None and f.friction_coef is not None
                    else np.zeros((2, h))
                    for f in fl
                ]
            )
        else:
            fc = np.zeros((2, 2, 0))  # no friction: nothing to evaluate (docs §3a)
        eo, ea, po, pa = self.excitation_orders()
        x0 = self.static_state()
        # eccentricities: none -> nothing to evaluate (docs §3b)
        rc = self.eccentricity_coefficients() if self.has_eccentricity else np.zeros((2, 0))
        if self.mesh_law == "loaded":  # docs §3d
            lc = np.stack([np.stack([pad(r) for r in f.load_coef]) for f in fl if f])
            lf = np.stack([f.load_forces for f in fl if f])
            if self.coast is None:  # no coast flank: a law that closes a metre away
                J = lf.shape[-1]
                never = np.zeros_like(lc[0])
                never[:, 0] = np.concatenate([np.arange(1.0, J + 2.0), np.ones(J)])
                lc = np.stack([lc[0], never])
                lf = np.stack([lf[0], np.arange(1.0, J + 1.0)])
        else:
            lc, lf = np.zeros((2, 0, h)), np.zeros((2, 0))
        return {
            "Minv": 1.0 / self.mass_vector(),
            "K": K,
            "C": C,
            "G": G,
            "kc": np.stack([pad(f.k_coef) if f else zero for f in fl]),
            "ec": np.stack([pad(f.e_coef) if f else zero for f in fl]),
            "fc": fc,
            "lc": lc,
            "lF": lf,
            "cm": np.array([f.damping if f else 0.0 for f in fl]),
            "bl": np.array([f.backlash if f else 0.0 for f in fl]),
            "N1": np.array(float(self.pinion_teeth)),
            "Omega": np.array(self.speed),
            "Omega2": np.array(self.gear_speed),
            "phase": np.array(self.phase),
            "phase2": np.array(self.phase * self.pinion_teeth / self.gear_teeth),
            "rc": rc,
            # pitch deviations: none -> nothing to evaluate (docs §3c)
            "pt": self.pitch.coefficients() if self.pitch is not None else np.zeros((0, 4)),
            "pt0": np.array(self.pitch.angle0 if self.pitch is not None else 0.0),
            "pts": np.array(self.pitch.step if self.pitch is not None else 1.0),
            "T": np.array(self.torque),
            "eo": eo,
            "ea": ea,
            "kappa": np.array(self.propeller_coefficient),
            "po": po,
            "pa": pa,
            "Kp": np.array(self.governor_kp if self.governor else 0.0),
            "Ki": np.array(self.governor_ki if self.governor else 0.0),
            "qe0": np.array(x0[0]),
            "scale": self.state_scale(),
            "M": self.mass_vector(),
            "Wn": np.array([self.speed, self.speed, self.gear_speed, self.gear_speed, 0.0, 0.0])[
                : self.n_dof
            ],
        }

    def speed_params(self, speeds) -> dict[str, np.ndarray]:
        """:meth:`params` of ``with_speed(w)`` for every w in ``speeds`` (rad/s, shape (B,)),
        stacked along a leading axis of length B, without building B models.

        Only Omega, Omega_2, kappa (docs §6), the speed part of the state scale and the
        nominal speeds change with the speed; the static state does not (kappa Omega_2^2
        = T_op lambda_2 / lambda_1).
        """
        base = self.params()
        w = np.asarray(speeds, dtype=float).ravel()
        out = {k: np.repeat(np.asarray(v)[None], w.size, axis=0) for k, v in base.items()}
        w2 = w * self.pinion_teeth / self.gear_teeth
        n = self.n_dof
        out["Omega"] = w
        out["Omega2"] = w2
        out["kappa"] = self.torque * self.torque_ratio / w2**2
        out["scale"][:, n:] = out["scale"][:, :n] * (self.pinion_teeth * w)[:, None]
        out["Wn"] = np.stack([w, w, w2, w2, 0 * w, 0 * w], axis=1)[:, :n]
        return out

    def to_dict(self) -> dict[str, Any]:
        d = dataclasses.asdict(self)

        def conv(o):
            if isinstance(o, np.ndarray):
                return o.tolist()
            if isinstance(o, dict):
                return {k: conv(v) for k, v in o.items()}
            return o

        d["meta"] = dict(self.meta)
        return conv(d)

    @classmethod
    def from_dict(cls, d: Mapping[str, Any]) -> DrivetrainModel:
        d = dict(d)
        for k in ("drive", "coast"):
            if d.get(k) is not None:
                f = dict(d[k])
                for a in ("k_coef", "e_coef", "lte_coef", "direction"):
                    f[a] = np.asarray(f[a], dtype=float)
                for a in ("friction_coef", "transverse", "load_coef", "load_forces"):
                    if f.get(a) is not None:
                        f[a] = np.asarray(f[a], dtype=float)
                d[k] = MeshFlank(**f)
        return cls(**d)


def transverse_axes(table: MeshTable, torque: float) -> np.ndarray:
    """Each member's transverse axes (u_i, v_i), shape (2 members, 2, 3), in Sf: u_i the
    unit vector from the axis towards the drive flank's mean mesh point at ``torque``,
    perpendicular to the axis a_i; v_i = a_i x u_i, so that a vector fixed to the member
    at angle psi from u_i lies along cos(theta + psi) u_i + sin(theta + psi) v_i when
    the member has turned by theta in its driving sense (docs/drivetrain.md §3b)."""
    P = table.values_at("mesh_point", "drive", torque).mean(axis=0)
    out = np.empty((2, 2, 3))
    for i, ax in enumerate((table.pinion_axis, table.gear_axis)):
        a = ax[0] / np.linalg.norm(ax[0])
        r = P - ax[1]
        u = r - (r @ a) * a
        norm = np.linalg.norm(u)
        if not norm > 0:
            raise ValueError("the mean mesh point lies on a member's axis")
        u = u / norm
        out[i] = u, np.cross(a, u)
    return out


def _fit(
    v: np.ndarray, harmonics: int, teeth: int, angle0: float
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Fourier coefficients in the absolute pinion angle of samples taken from ``angle0``.

    The fit is in theta' = theta - angle0; rotating each harmonic by k N angle0 expresses
    it in theta, so the right-hand side needs no table offset.
    """
    a0, a, b = fourier_fit(v, harmonics)
    ph = np.arange(1, a.size + 1) * teeth * angle0
    c, s = np.cos(ph), np.sin(ph)
    return np.array([a0]), a * c - b * s, a * s + b * c


def _split(c, xp):
    h = (c.shape[-1] - 1) // 2
    return c[..., 0], c[..., 1 : 1 + h], c[..., 1 + h :]


def _series_rows(theta1, coef, n1, xp, derivative: bool = False):
    """Fourier series in theta_1 of every row of ``coef`` (shape R + (1 + 2 h,), [a0, a, b]
    with harmonics k N_1): values, shape S + R for theta1 of shape S, and with
    ``derivative`` also d/d theta_1. One set of cos / sin(k N_1 theta_1) serves every
    row: the sums over harmonics are one matrix product, (..., h) @ (h, rows)."""
    rows = coef.shape[:-1]
    a0, a, b = _split(coef, xp)
    h = a.shape[-1]
    m = math.prod(rows)
    kk = xp.arange(1, h + 1) * n1
    arg = xp.asarray(theta1)[..., None] * kk  # (..., h)
    c = xp.cos(arg)
    s = xp.sin(arg)
    A = a.reshape(m, h)
    B = b.reshape(m, h)
    f = (a0.reshape(m) + c @ A.T + s @ B.T).reshape(arg.shape[:-1] + rows)
    if not derivative:
        return f
    df = (c @ (kk * B).T - s @ (kk * A).T).reshape(arg.shape[:-1] + rows)
    return f, df


def mesh_laws(theta1, p, xp=np):
    """k_f, dk_f, e_f, de_f at pinion angle theta1 (rad, any shape S); each shape S + (2,)
    [drive, coast]."""
    coef = xp.stack([p["kc"], p["ec"]])  # (2 fields, 2 flanks, 1 + 2 h)
    f, df = _series_rows(theta1, coef, p["N1"], xp, derivative=True)
    return f[..., 0, :], df[..., 0, :], f[..., 1, :], df[..., 1, :]


def law_levels(table: MeshTable, flank: str, lam1: float):
    """The loaded mesh law's level samples of ``flank``: the LTE x_j (m, shape (J, P)),
    the tangent stiffnesses k_j (N/m), limited where a cubic between two levels would
    not grow (Fritsch and Carlson: slopes within 3 times the interval's secant), and the
    levels' mesh forces T_j / lam1 (N, shape (J,)); ``ok`` when the law can take them
    (the LTE grows with the torque and the stiffnesses are > 0 at every position)."""
    i = table.flank_index(flank)
    forces = np.asarray(table.torque, dtype=float) / lam1
    X = np.asarray(table.lte[i], dtype=float)
    K = np.array(table.tangent_stiffness[i], dtype=float)
    ok = bool(np.all(np.diff(X, axis=0) > 0) and np.all(K > 0))
    if ok:
        for j in range(forces.size - 1):
            m = (forces[j + 1] - forces[j]) / (X[j + 1] - X[j])
            r = np.hypot(K[j] / m, K[j + 1] / m)
            tau = np.where(r > 3.0, 3.0 / r, 1.0)
            K[j] *= tau
            K[j + 1] *= tau
    return X, K, forces, ok


def loaded_law_samples(table: MeshTable, flank: str, lam1: float):
    """The loaded mesh law's samples of ``flank`` at the table's positions (docs §3d):
    rows, shape (2 J + 1, P), the deflection at no load, the LTE at the J torque levels
    (m) and the tangent stiffnesses there (N/m), limited as :func:`law_levels` says;
    and the levels' mesh forces T_j / lam1 (N, shape (J,)), with lam1 the model's drive
    rotation radius of the pinion (m)."""
    X, K, forces, _ = law_levels(table, flank, lam1)
    S = np.asarray(table.stiffness[table.flank_index(flank)], dtype=float)
    p = Problems()
    p.check(
        bool(np.all(np.diff(X, axis=0) > 0)),
        f"mesh table ({flank} flank)",
        table.attrs.get("method", ""),
        "the loaded mesh law needs the LTE to grow with the torque at every position",
    )
    p.check(
        bool(np.all(K > 0) and np.all(S[0] > 0)),
        f"mesh table ({flank} flank)",
        table.attrs.get("method", ""),
        "the loaded mesh law needs stiffnesses > 0 N/m",
    )
    p.raise_if_any("invalid mesh table for drivetrain.mesh_law = 'loaded'")
    xu = X[0] - forces[0] / S[0]
    return np.concatenate([xu[None], X, K]), forces


def tangent_at(table: MeshTable, flank: str, lam1: float, torque: float):
    """The tangent mesh law's stiffness (N/m) and LTE (m) of ``flank`` at ``torque`` (N
    m), each shape (P,) (docs §3): between the table's torque levels the loaded mesh
    law's tangent at the mesh force torque / lam1 (cubic in the deflection through the
    levels, :func:`loaded_force`), at a level the level's samples (tangents limited as
    :func:`law_levels` says); the table interpolated linearly in torque where the law
    cannot take it (one level, an LTE that does not grow with the torque). The second
    value says which: ``"law"`` or ``"linear"``."""
    if table.torque.size >= 2:
        X, K, forces, ok = law_levels(table, flank, lam1)
        if ok:
            # between the levels only the cubics count: x_u is any deflection below x_0
            rows = np.concatenate([(X[0] - forces[0] / K[0])[None], X, K])
            lte, kt = loaded_law_point(rows, forces, torque / lam1)
            return (kt, lte), "law"
    kt = table.values_at("tangent_stiffness", flank, torque)
    return (kt, table.values_at("lte", flank, torque)), "linear"


def law_mean_stiffness(table: MeshTable, flank: str, lam1: float, forces) -> np.ndarray:
    """Cycle means (N/m) of the loaded mesh law's tangent stiffness of ``flank`` at the
    mesh forces ``forces`` (N, any shape; the result's shape), lam1 the drive rotation
    radius of :func:`loaded_law_samples`, which raises InputError where the law cannot
    take the table. One solve (:func:`loaded_law_point`) for all forces and positions."""
    rows, levels = loaded_law_samples(table, flank, lam1)
    forces = np.asarray(forces, dtype=float)
    flat, P = forces.ravel(), rows.shape[1]
    _, k = loaded_law_point(np.tile(rows, flat.size), levels, np.repeat(flat, P))
    return k.reshape(flat.size, P).mean(axis=1).reshape(forces.shape)


def law_stiffness_ratio(table: MeshTable, model, forces) -> np.ndarray:
    """:func:`law_mean_stiffness` of the drive flank at the mesh forces ``forces`` (N,
    any shape; clipped at 0) over the model's mean drive tangent stiffness, less 1: how
    far a run's force range takes the loaded TCA's stiffness from the constant one of
    the tangent law (docs §3d). NaN where the law cannot take the table."""
    from ..errors import InputError

    forces = np.maximum(np.asarray(forces, dtype=float), 0.0)
    try:
        k = law_mean_stiffness(table, "drive", abs(model.drive.lambda1), forces)
    except InputError:
        return np.full(forces.shape, np.nan)
    return k / model.drive.mean_stiffness - 1.0


def loaded_force(d, rows, forces, xp=np, derivative: bool = False):
    """The loaded mesh law's elastic force (N) at deflections d (m, shape S) of one
    flank (docs §3d). rows, shape S + (2 J + 1,): the no-load deflection x_u, the
    levels' deflections x_j and tangent stiffnesses k_j; forces (J,): the levels'
    forces F_j. Zero up to x_u, a parabola from (x_u, 0) to (x_0, F_0) with slope k_0
    there (clipped at 0), cubic Hermite between the levels, straight with slope
    k_{J-1} beyond the last. With ``derivative`` also dF/dd. Each piece is evaluated
    once, between the ends that the deflection selects."""
    J = forces.shape[-1]
    xu = rows[..., 0]
    X = [rows[..., 1 + j] for j in range(J)]
    K = [rows[..., 1 + J + j] for j in range(J)]
    F = [forces[..., j] for j in range(J)]
    # the cubic's ends: levels j and j + 1, j the last level at or below d (0 below)
    xa, xb, ka, kb, fa, fb = X[0], X[1], K[0], K[1], F[0], F[1]
    for j in range(1, J - 1):
        c = d >= X[j]
        xa, xb = xp.where(c, X[j], xa), xp.where(c, X[j + 1], xb)
        ka, kb = xp.where(c, K[j], ka), xp.where(c, K[j + 1], kb)
        fa, fb = xp.where(c, F[j], fa), xp.where(c, F[j + 1], fb)
    h = xb - xa
    t = (d - xa) / h
    t2 = t * t
    t3 = t2 * t
    val = (2 * t3 - 3 * t2 + 1) * fa + (t3 - 2 * t2 + t) * h * ka + (3 * t2 - 2 * t3) * fb
    val = val + (t3 - t2) * h * kb
    der = (6 * t2 - 6 * t) * (fa - fb) / h + (3 * t2 - 4 * t + 1) * ka + (3 * t2 - 2 * t) * kb
    # below the lowest level: the parabola, zero up to x_u
    w = X[0] - xu
    a = (K[0] * w - F[0]) / (w * w)
    u = d - X[0]
    q = F[0] + u * (K[0] + a * u)
    on = (d > xu) & (q > 0)
    low = d < X[0]
    val = xp.where(low, xp.where(on, q, 0.0), val)
    der = xp.where(low, xp.where(on, K[0] + 2.0 * a * u, 0.0), der)
    # beyond the highest: straight
    top = d >= X[J - 1]
    val = xp.where(top, F[J - 1] + K[J - 1] * (d - X[J - 1]), val)
    der = xp.where(top, K[J - 1], der)
    return (val, der) if derivative else val


def loaded_law_point(rows, forces, force):
    """Deflection (m) and tangent stiffness (N/m) of the loaded mesh law at the mesh
    force ``force`` (N; a number, or one per sample), at every sample of ``rows`` (shape
    (2 J + 1, P)): Newton's method on the non-decreasing law, kept inside a bracket that
    every evaluation narrows (a step that would leave it bisects it), until the force is
    met to the rounding of the law's evaluation (4 eps of the force plus the top level's).
    The start is the levels' deflections interpolated linearly in force. At a force <= 0
    the flank is open: the deflection is the no-load one, x_u, the stiffness 0."""
    r = np.moveaxis(np.asarray(rows, dtype=float), 0, -1)  # (P, 2J + 1)
    J = forces.size
    P = r.shape[0]
    force = np.broadcast_to(np.asarray(force, dtype=float), (P,))
    lo = r[:, 0].copy()
    top = r[:, J] + np.maximum(force - forces[-1], 0.0) / r[:, 2 * J] + 1e-9
    hi = np.maximum(top, lo + 1e-9)
    # start: between the levels whose forces hold the force (below the lowest: from x_u)
    fx = np.concatenate([[0.0], forces])
    xx = np.concatenate([lo[:, None], r[:, 1 : 1 + J]], axis=1)  # (P, J + 1)
    j = np.clip(np.searchsorted(fx, force) - 1, 0, J - 1)
    rows_p = np.arange(P)
    w = np.clip((force - fx[j]) / (fx[j + 1] - fx[j]), 0.0, 1.0)
    x = np.clip(xx[rows_p, j] + w * (xx[rows_p, j + 1] - xx[rows_p, j]), lo, hi)
    live = force > 0
    x = np.where(live, x, lo)
    tol = 4.0 * np.finfo(float).eps * (np.abs(force) + forces[-1])  # the law's rounding
    for _ in range(100):
        f, k = loaded_force(x, r, forces, derivative=True)
        g = f - force
        below = g < 0
        lo = np.where(below, x, lo)
        hi = np.where(below, hi, x)
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.where(k > 0, g / k, np.inf)
        nxt = x - step
        inside = (nxt > lo) & (nxt < hi)
        nxt = np.where(inside, nxt, 0.5 * (lo + hi))
        # done: on the force to its rounding, or no float left between the bracket's ends
        live &= (np.abs(g) > tol) & (nxt != x) & (0.5 * (lo + hi) > lo) & (0.5 * (lo + hi) < hi)
        if not live.any():
            break
        x = np.where(live, nxt, x)
    on = force > 0
    x = np.where(on, x, r[:, 0])
    _, k = loaded_force(x, r, forces, np, True)
    return x, np.where(on, k, 0.0)


def load_laws(theta1, p, xp=np):
    """The loaded mesh law's rows (:func:`loaded_force`) of both flanks at pinion angle
    theta1 (any shape S), shape S + (2, 2 J + 1); None for the tangent law."""
    lc = p["lc"]
    if lc.shape[1] == 0:
        return None
    return _series_rows(theta1, lc, p["N1"], xp)


def contact_forces(s, sdot, k, e, rows, damping, forces, xp=np):
    """Contact forces (N) from the gaps s and their rates sdot (any shape): k s + c sdot
    (the tangent law, docs §3) or, with the loaded law's ``rows`` (:func:`load_laws`),
    its elastic force at the deflection s + e plus c sdot (docs §3d); zero where the
    flank is open, never negative. damping: c (N s/m); forces: the law's level forces
    (:func:`loaded_force`). Per flank or both at once (a trailing flank axis)."""
    if rows is None:
        return xp.where(s > 0, xp.maximum(k * s + damping * sdot, 0.0), 0.0)
    el = loaded_force(s + e, rows, forces, xp)
    return xp.where(el > 0, xp.maximum(el + damping * sdot, 0.0), 0.0)


def friction_arms(theta1, p, xp=np):
    """mu times the friction arms about the pinion's and the gear's axis (m) at pinion
    angle theta1 (any shape S), shape S + (2 flanks, 2 arms); None without friction
    (``p['fc']`` with no coefficients), docs §3a."""
    fc = p["fc"]
    if fc.shape[-1] == 0:
        return None
    return _series_rows(theta1, fc, p["N1"], xp)


def friction_torques(theta1, f, p, xp=np):
    """Friction torques (N m) on the pinion and on the gear from the contact forces f
    (N, shape S + (2,)) at theta1 (shape S): -sum_f mu phi_1f F_f and +sum_f mu phi_2f
    F_f, each shape S; zeros without friction (docs §3a)."""
    arms = friction_arms(theta1, p, xp)
    if arms is None:
        z = xp.zeros(xp.shape(f)[:-1])
        return z, z
    return -xp.sum(arms[..., 0] * f, axis=-1), xp.sum(arms[..., 1] * f, axis=-1)


def eccentricity_terms(t, q1, q2, v1, v2, p, xp=np):
    """The eccentricities' approach eps_f (m) and its rate d eps_f / dt (m/s) of both
    flanks from the pinion's and the gear's coordinates q_1, q_2 and speeds v_1, v_2
    (scalars, or arrays of one shape): two lists [drive, coast] (docs §3b); None
    without eccentricity (``p['rc']`` with no coefficients). The pinion turns by
    theta_1 = Omega t + q_1 + theta_10, the gear by theta_2 = Omega_2 t + q_2 + theta_10
    N_1 / N_2."""
    rc = p["rc"]
    if rc.shape[-1] == 0:
        return None
    th1 = p["Omega"] * t + q1 + p["phase"]
    th2 = p["Omega2"] * t + q2 + p["phase2"]
    w1, w2 = p["Omega"] + v1, p["Omega2"] + v2
    c1, s1, c2, s2 = xp.cos(th1), xp.sin(th1), xp.cos(th2), xp.sin(th2)
    eps = [rc[f, 0] * c1 + rc[f, 1] * s1 + rc[f, 2] * c2 + rc[f, 3] * s2 for f in range(2)]
    rate = [
        (rc[f, 1] * c1 - rc[f, 0] * s1) * w1 + (rc[f, 3] * c2 - rc[f, 2] * s2) * w2
        for f in range(2)
    ]
    return eps, rate


def pitch_terms(t, q1, v1, p, xp=np):
    """The pitch deviations' approach a (m) of the drive flank and its rate da/dt (m/s)
    from the pinion's coordinate q_1 and speed v_1 (docs §3c); None without them
    (``p['pt']`` with no rows)."""
    pt = p["pt"]
    if pt.shape[0] == 0:
        return None
    th1 = p["Omega"] * t + q1 + p["phase"]
    a, da = _pitch_eval(th1, pt, p["pt0"], p["pts"], xp)
    return a, da * (p["Omega"] + v1)


def approach_terms(t, q1, q2, v1, v2, p, xp=np):
    """The flanks' kinematic approach and its rate, two lists [drive, coast]: the
    eccentricities' (:func:`eccentricity_terms`) plus the pitch deviations' on the
    drive flank (:func:`pitch_terms`); None with neither."""
    ecc = eccentricity_terms(t, q1, q2, v1, v2, p, xp)
    pit = pitch_terms(t, q1, v1, p, xp)
    if pit is None:
        return ecc
    if ecc is None:
        return [pit[0], 0.0 * pit[0]], [pit[1], 0.0 * pit[1]]
    (e0, e1), (r0, r1) = ecc
    return [e0 + pit[0], e1], [r0 + pit[1], r1]


def approach(t, x, v, p, xp=np):
    """:func:`approach_terms` of states x, v of shape S + (n,): each shape S + (2,);
    None with neither eccentricity nor pitch deviations."""
    out = approach_terms(t, x[..., 1], x[..., 2], v[..., 1], v[..., 2], p, xp)
    if out is None:
        return None
    return xp.stack(out[0], axis=-1), xp.stack(out[1], axis=-1)


def eccentricity_approach(t, x, v, p, xp=np):
    """:func:`eccentricity_terms` of states x, v of shape S + (n,): eps_f and its rate,
    each shape S + (2,); None without eccentricity."""
    out = eccentricity_terms(t, x[..., 1], x[..., 2], v[..., 1], v[..., 2], p, xp)
    if out is None:
        return None
    return xp.stack(out[0], axis=-1), xp.stack(out[1], axis=-1)


def mesh_forces(t, x, v, p, xp=np):
    """Contact forces F_f (N, shape (2,)), gaps s_f and the pinion angle (docs §3)."""
    theta1 = p["Omega"] * t + x[1] + p["phase"]
    k, _, e, de = mesh_laws(theta1, p, xp)
    delta = p["G"] @ x
    ddelta = p["G"] @ v
    s = delta - e - p["bl"]
    sdot = ddelta - de * (p["Omega"] + v[1])
    ecc = approach(t, x, v, p, xp)
    if ecc is not None:
        s = s + ecc[0]
        sdot = sdot + ecc[1]
    f = contact_forces(s, sdot, k, e, load_laws(theta1, p, xp), p["cm"], p["lF"], xp)
    return f, s, theta1


def external_torques(t, x, v, p, xp=np):
    """Engine torque (with governor) and propeller load torque (N m), docs §5-6."""
    te = p["T"] * (1.0 + xp.sum(p["ea"] * xp.sin(p["eo"] * p["Omega"] * t)))
    te = te - p["Kp"] * v[0] - p["Ki"] * (x[0] - p["qe0"])
    wp = p["Omega2"] + v[3]
    tp = p["kappa"] * wp * wp * (1.0 + xp.sum(p["pa"] * xp.sin(p["po"] * p["Omega2"] * t)))
    return te, tp


def rhs(t, z, p, xp=np):
    """d z / dt of the scaled state z = y / scale, y = [x, v] (docs §7). Shape (2 n,)."""
    y = z * p["scale"]
    n = y.shape[0] // 2
    x = y[:n]
    v = y[n:]
    f, _, theta1 = mesh_forces(t, x, v, p, xp)
    te, tp = external_torques(t, x, v, p, xp)
    q = -(p["K"] @ x) - (p["C"] @ v) - p["G"].T @ f
    t1, t2 = friction_torques(theta1, f, p, xp)
    unit = xp.zeros(n)
    if xp is np:
        unit[0] = te
        unit[1] = t1
        unit[2] = t2
        unit[3] = -tp
    else:
        unit = unit.at[0].set(te).at[1].set(t1).at[2].set(t2).at[3].set(-tp)
    a = (q + unit) * p["Minv"]
    return xp.concatenate([v, a]) / p["scale"]


def _tangent_only(p, what: str) -> None:
    if p["lc"].shape[1]:
        raise InputError(
            Problem(
                "mesh_law",
                "loaded",
                f"{what}() holds the tangent law's strain energy (1/2) k s^2 only: build the "
                "model with mesh_law = 'tangent' for the energy balance",
            )
        )


def energy(t, y, p, xp=np):
    """Mechanical energy (J) of the unscaled state y: kinetic (absolute speeds), shaft and
    bearing strain, mesh strain (1/2) k_f s_f^2 of the flanks in contact.

    With zero damping, dE/dt = :func:`power` (energy-balance check).
    """
    _tangent_only(p, "energy")
    n = y.shape[0] // 2
    x, v = y[:n], y[n:]
    w = p["Wn"] + v
    theta1 = p["Omega"] * t + x[1] + p["phase"]
    k, _, e, _ = mesh_laws(theta1, p, xp)
    s = p["G"] @ x - e - p["bl"]
    ecc = approach(t, x, v, p, xp)
    if ecc is not None:
        s = s + ecc[0]
    sp = xp.maximum(s, 0.0)
    return 0.5 * xp.sum(p["M"] * w * w) + 0.5 * x @ (p["K"] @ x) + 0.5 * xp.sum(k * sp * sp)


def power(t, y, p, xp=np):
    """dE/dt (W) of an undamped run: engine and propeller power plus the parametric mesh
    terms (1/2) k_f' s_f^2 theta1' - F_f e_f' theta1' + F_f eps_f' (the time-varying
    mesh and the eccentricities store and release energy); exact when the rotation radii keep the tooth ratio
    (lambda_1 Omega = lambda_2 Omega_2).
    """
    _tangent_only(p, "power")
    n = y.shape[0] // 2
    x, v = y[:n], y[n:]
    theta1 = p["Omega"] * t + x[1] + p["phase"]
    dth = p["Omega"] + v[1]
    k, dk, e, de = mesh_laws(theta1, p, xp)
    f, s, _ = mesh_forces(t, x, v, p, xp)
    sp = xp.maximum(s, 0.0)
    te, tp = external_torques(t, x, v, p, xp)
    ext = te * (p["Wn"][0] + v[0]) - tp * (p["Wn"][3] + v[3])
    t1, t2 = friction_torques(theta1, f, p, xp)
    ext = ext + t1 * dth + t2 * (p["Wn"][2] + v[2])
    ecc = approach(t, x, v, p, xp)
    if ecc is not None:
        ext = ext + xp.sum(f * ecc[1])
    return ext + xp.sum(0.5 * dk * sp * sp * dth - f * de * dth)


CHANNEL_UNITS = {
    "engine_angle_rad": "rad",
    "pinion_angle_rad": "rad",
    "gear_angle_rad": "rad",
    "propeller_angle_rad": "rad",
    "engine_speed_rad_per_s": "rad/s",
    "pinion_speed_rad_per_s": "rad/s",
    "gear_speed_rad_per_s": "rad/s",
    "propeller_speed_rad_per_s": "rad/s",
    "mesh_deflection_m": "m",
    "mesh_force_N": "N",
    "dynamic_transmission_error_m": "m",
    "input_shaft_torque_Nm": "N m",
    "output_shaft_torque_Nm": "N m",
    "engine_torque_Nm": "N m",
    "propeller_torque_Nm": "N m",
    "pinion_bearing_force_N": "N",
    "gear_bearing_force_N": "N",
    "pinion_friction_torque_Nm": "N m",
    "gear_friction_torque_Nm": "N m",
    "mesh_friction_power_W": "W",
    "eccentricity_approach_m": "m",
    "pitch_approach_m": "m",
}


def outputs(model: DrivetrainModel, t: np.ndarray, y: np.ndarray, p=None) -> dict[str, np.ndarray]:
    """Named channels (SI) from unscaled states y, shape (n_t, 2 n); see CHANNEL_UNITS.

    Angles are absolute (nominal rotation + deviation); speeds absolute.
    """
    p = p if p is not None else model.params()
    n = model.n_dof
    x = y[:, :n]
    v = y[:, n:]
    # Vectorised over samples: the same formulas as mesh_forces / external_torques.
    theta1 = p["Omega"] * t + x[:, 1] + p["phase"]
    k, _, e, de = mesh_laws(theta1, p)  # (n_t, 2)
    s = x @ p["G"].T - e - p["bl"]
    sdot = v @ p["G"].T - de * (p["Omega"] + v[:, 1])[:, None]
    ecc = eccentricity_approach(t, x, v, p)
    pit = pitch_terms(t, x[:, 1], v[:, 1], p)
    if ecc is not None:  # the same sum as approach(), each part kept for its channel
        s = s + ecc[0]
        sdot = sdot + ecc[1]
    if pit is not None:  # the drive flank only
        s[:, 0] = s[:, 0] + pit[0]
        sdot[:, 0] = sdot[:, 0] + pit[1]
    forces = contact_forces(s, sdot, k, e, load_laws(theta1, p), p["cm"], p["lF"])
    tt = t[:, None]
    te = p["T"] * (1.0 + np.sum(p["ea"] * np.sin(p["eo"] * p["Omega"] * tt), axis=-1))
    te = te - p["Kp"] * v[:, 0] - p["Ki"] * (x[:, 0] - p["qe0"])
    wp = p["Omega2"] + v[:, 3]
    tp = (
        p["kappa"] * wp * wp * (1.0 + np.sum(p["pa"] * np.sin(p["po"] * p["Omega2"] * tt), axis=-1))
    )
    theta1 = p["Omega"] * t + x[:, 1] + p["phase"]
    la = model.drive.lte_coef
    hh = (la.size - 1) // 2
    lte, _ = fourier_eval(la[0], la[1 : 1 + hh], la[1 + hh :], model.pinion_teeth, theta1[:, None])
    K, C = model.structural_matrices()
    w1, w2 = model.speed, model.gear_speed
    out = {
        "engine_angle_rad": w1 * t + x[:, 0],
        "pinion_angle_rad": theta1,
        "gear_angle_rad": w2 * t + x[:, 2],
        "propeller_angle_rad": w2 * t + x[:, 3],
        "engine_speed_rad_per_s": w1 + v[:, 0],
        "pinion_speed_rad_per_s": w1 + v[:, 1],
        "gear_speed_rad_per_s": w2 + v[:, 2],
        "propeller_speed_rad_per_s": w2 + v[:, 3],
        "mesh_deflection_m": x @ p["G"][0],
        "mesh_force_N": forces[:, 0] - forces[:, 1],
        "input_shaft_torque_Nm": K[0, 0] * (x[:, 0] - x[:, 1]) + C[0, 0] * (v[:, 0] - v[:, 1]),
        "output_shaft_torque_Nm": K[3, 3] * (x[:, 2] - x[:, 3]) + C[3, 3] * (v[:, 2] - v[:, 3]),
        "engine_torque_Nm": te,
        "propeller_torque_Nm": tp,
    }
    out["dynamic_transmission_error_m"] = out["mesh_deflection_m"] - lte
    if model.bearing_dofs:
        out["pinion_bearing_force_N"] = K[4, 4] * x[:, 4] + C[4, 4] * v[:, 4]
        out["gear_bearing_force_N"] = K[5, 5] * x[:, 5] + C[5, 5] * v[:, 5]
    if ecc is not None:
        out["eccentricity_approach_m"] = ecc[0][:, 0]
    if pit is not None:
        out["pitch_approach_m"] = pit[0]
    if p["fc"].shape[-1]:
        t1, t2 = friction_torques(theta1, forces, p)
        out["pinion_friction_torque_Nm"] = t1
        out["gear_friction_torque_Nm"] = t2
        # the friction's loss: minus the power of its torques on the two bodies
        out["mesh_friction_power_W"] = -(
            t1 * out["pinion_speed_rad_per_s"] + t2 * out["gear_speed_rad_per_s"]
        )
    return out

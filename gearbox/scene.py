"""Scene files: one TOML file describes a whole job, from gear pair to report.

A scene is validated against :data:`SCHEMA` as a whole: every problem (unknown key,
wrong type, value out of range) is collected with its TOML key path and raised once
as :class:`gearbox.errors.InputError`. Degrees, mm, rpm, kW and so on appear only here,
with the unit in the key name; each stage converts its section to SI in its own
``*Spec.from_scene``.

The schema is versioned (``schema = 1``); the documentation of every key is generated
from :data:`SCHEMA` (``gearbox scene-doc`` / ``docs/scene.md``).
"""

from __future__ import annotations

import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import MappingProxyType
from typing import Any

from ._pickling import PicklesReadOnly
from .errors import InputError, Problems, is_real

__all__ = ["SCHEMA", "SCHEMA_VERSION", "Field", "Scene", "load_scene", "scene_from_dict"]

SCHEMA_VERSION = 1

_REQUIRED = object()


@dataclass(frozen=True)
class Field:
    """One scene key: its kind, default, valid range and meaning.

    ``kind`` is one of ``float``, ``int``, ``bool``, ``str``, ``floats`` (list of
    float), ``strs`` (list of str), ``rows`` (list of lists of float: a table, or the
    name of a CSV file that holds one, read when the scene is). ``lo``/``hi`` bound numbers (and every element of
    a list); ``lo_open``/``hi_open`` make the bound strict. ``choices`` restricts
    strings. ``default`` of ``None`` means optional with no value; the module-level
    ``_REQUIRED`` makes the key mandatory.
    """

    kind: str
    default: Any = None
    doc: str = ""
    lo: float | None = None
    hi: float | None = None
    lo_open: bool = False
    hi_open: bool = False
    choices: tuple[str, ...] | None = None
    min_len: int = 0
    max_len: int | None = None  # lists: at most this many entries
    increasing: bool = False  # lists of numbers: strictly increasing

    @property
    def required(self) -> bool:
        return self.default is _REQUIRED


def _f(default=None, doc="", lo=None, hi=None, lo_open=False, hi_open=False):
    return Field("float", default, doc, lo, hi, lo_open, hi_open)


def _i(default=None, doc="", lo=None, hi=None):
    return Field("int", default, doc, lo, hi)


def _s(default=None, doc="", choices=None):
    return Field("str", default, doc, choices=choices)


def _fl(
    default=None, doc="", lo=None, hi=None, lo_open=False, min_len=1, max_len=None, increasing=False
):
    return Field(
        "floats",
        default,
        doc,
        lo,
        hi,
        lo_open,
        min_len=min_len,
        max_len=max_len,
        increasing=increasing,
    )


def _rows(default=None, doc="", lo=None, hi=None):
    return Field("rows", default, doc, lo, hi)


R = _REQUIRED

#: The whole scene schema: section -> key -> Field. Sub-sections use dotted names.
SCHEMA: dict[str, dict[str, Field]] = {
    "": {
        "schema": _i(R, "Scene schema version; must be 1.", 1, 1),
        "name": _s("", "Short name of the scene, used in reports and file names."),
        "description": _s("", "Free text."),
    },
    "pair": {
        "normal_module_mm": _f(R, "Normal module m_n of the tool (mm).", 0, None, lo_open=True),
        "normal_pressure_angle_deg": _f(
            R, "Normal pressure angle alpha_n of the tool (deg).", 0, 45, True, True
        ),
        "shaft_angle_deg": _f(
            R, "Shaft angle delta between the gear axes (deg).", 0, 90, False, True
        ),
        "offset_mm": _f(
            R,
            "Offset E: shortest distance between the axes (mm). For shaft angle 0 it is "
            "the centre distance.",
            0,
            None,
            True,
        ),
        "design_mode": _s(
            "cone_angles",
            "'cone_angles': both cone angles given, solve xi_n and beta_2 (paper Fig. 5). "
            "'target_fpd': pinion cone angle solved so that the FPD angle of "
            "target_flank equals target_fpd_angle_deg (line contact, paper eq. (10)).",
            ("cone_angles", "target_fpd"),
        ),
        "target_fpd_angle_deg": _f(
            0.0, "Target FPD angle for design_mode 'target_fpd' (deg).", -45, 45
        ),
        "target_flank": _s("right", "Flank whose FPD angle is targeted.", ("right", "left")),
        "backlash_free": Field(
            "bool", True, "Gear profile shift from the backlash-free condition, paper eq. (20)."
        ),
        "min_total_contact_ratio": _f(
            2.0,
            "Least total contact ratio eps_gamma of the design check total_contact_ratio_* "
            "(2: two tooth pairs in mesh, the usual aim for quiet helical gearing; a spur "
            "pair's eps_gamma is its transverse contact ratio, 1.2 to 1.9).",
            1,
            4,
        ),
    },
    "pinion": {
        "teeth": _i(R, "Number of teeth N_1.", 5, 1000),
        "helix_angle_deg": _f(
            R, "Tool (rack) helix angle beta_1 (deg); sign gives the hand.", -60, 60
        ),
        "cone_angle_deg": _f(
            R, "Cone angle gamma_1 (deg); ignored in design_mode 'target_fpd'.", 0, 30
        ),
        "profile_shift_xt": _f(
            R, "Transverse profile-shift coefficient x_t1 at the reference section.", -1.5, 2.5
        ),
        "face_width_mm": _f(40.0, "Face width along the axis (mm).", 0, None, True),
        "reference_section_mm": _f(
            0.0,
            "Axial position of the reference transverse section (where x_t applies), "
            "measured from the middle of the face width towards the heel (mm); on the face: "
            "within +-face_width_mm / 2.",
        ),
    },
    "gear": {
        "teeth": _i(R, "Number of teeth N_2.", 5, 1000),
        "cone_angle_deg": _f(R, "Cone angle gamma_2 (deg).", 0, 30),
        "helix_angle_deg": _f(
            None,
            "Gear helix angle beta_2 (deg). Solved by the design (paper eqs (18)-(19)); if given, it is checked against the solution.",
            -60,
            60,
        ),
        "profile_shift_xt": _f(
            None,
            "Gear profile shift x_t2. Solved from the backlash-free condition (paper eq. (20)) "
            "unless pair.backlash_free = false.",
            -1.5,
            2.5,
        ),
        "face_width_mm": _f(40.0, "Face width along the axis (mm).", 0, None, True),
        "reference_section_mm": _f(0.0, "As for the pinion (mm)."),
    },
    "tool": {
        "addendum_coefficient": _f(
            1.25, "Tool addendum h_a0/m_n (cuts the gear dedendum).", 0.5, 2.0
        ),
        "tip_radius_coefficient": _f(0.25, "Tool tip radius rho_a0/m_n.", 0.0, 0.6),
        "gear_addendum_coefficient": _f(
            1.0, "Gear addendum h_a/m_n from the reference line of the rack.", 0.5, 1.5
        ),
    },
    "material": {
        "youngs_modulus_GPa": _f(206.0, "Young's modulus, both gears (GPa).", 0, None, True),
        "poisson_ratio": _f(0.3, "Poisson's ratio, both gears.", 0.0, 0.5, False, True),
        "density_kg_per_m3": _f(7850.0, "Density (kg/m^3).", 0, None, True),
    },
    "load": {
        "torques_Nm": _fl(
            [150.0, 300.0, 450.0],
            "Pinion torque levels of the mesh tables (N m), increasing.",
            0,
            None,
            True,
            increasing=True,
        ),
        "operating_torque_Nm": _f(
            300.0, "Pinion torque at the operating point (N m).", 0, None, True
        ),
    },
    "assembly": {
        "offset_error_mm": _f(0.0, "Error of the offset E (mm).", -5, 5),
        "shaft_angle_error_deg": _f(0.0, "Error of the shaft angle (deg).", -2, 2),
        "pinion_axial_error_mm": _f(
            0.0,
            "Axial displacement of the pinion (mm); 0 for the loaded TCA of a parallel-axis "
            "pair (its path does not model the face overlap a shift changes).",
            -10,
            10,
        ),
        "gear_axial_error_mm": _f(
            0.0, "Axial displacement of the gear (mm); as the pinion's.", -10, 10
        ),
    },
    "tca": {
        "positions": _i(61, "Pinion positions of the unloaded TCA sweep.", 4, 100000),
        "mesh_cycles": _f(1.5, "Pinion angle range in mesh cycles (2 pi / N_1 each).", 0, 20, True),
        "marking_compound_mm": _f(
            0.00635, "Separation that defines the instantaneous contact ellipse (mm).", 0, 1, True
        ),
    },
    "ltca": {
        "fidelity": _s(
            "fast",
            "Compliance level: 'fast' (semi-analytical) or 'fe' (finite elements).",
            ("fast", "fe"),
        ),
        "face_ends": Field(
            "bool",
            False,
            "Fast level only: soften each slice towards a helical tooth's acute face end as "
            "the FE level's tooth is (FastCompliance(helix_ends=HELIX_ENDS), docs/ltca.md "
            "'The face ends in the compliance'). For helix angles near 30 deg or helical "
            "faces narrower than about 5 m_n; the paper's cases are as near the FE level "
            "without it. The FE level has the face ends in its mesh.",
        ),
        "edge_borders": Field(
            "bool",
            True,
            "Crossed (surface-path) pairs: put each edge point, a contact that would go on "
            "beyond a flank border, on the border itself (the pinion's form or tip line, "
            "or where the mate's tip or form line or face end crosses the pinion's "
            "profile), its separation projected there, instead of on the last profile "
            "sample inside it. The loaded TE then needs no finer profile grid: case 03 "
            "drive at 300 N m reads 1.60 um peak-to-peak with the default grid (1.58 at "
            "320 profile points); false (the last samples) reads 2.09 um there, 1.61 at "
            "320 (docs/ltca.md 'Edge points on the flank borders'). False builds the "
            "grids of the stored FE reference runs, made before this became the default.",
        ),
        "positions": _i(24, "Pinion positions per mesh cycle in the mesh tables.", 4, 10000),
        "grid_profile": _i(20, "Contact grid points along the profile.", 3, 2000),
        "grid_face": _i(40, "Contact grid points along the face width.", 3, 4000),
        "flanks": Field(
            "strs", ["drive", "coast"], "Flanks to analyse.", choices=("drive", "coast"), min_len=1
        ),
        "topography_interpolation": _s(
            "cubic",
            "Interpolation of the flank topographies (*_topography_um) between their grid "
            "points: 'cubic' (bicubic spline, at least 4 positions on each axis; rings at "
            "a step or kink in the grid), 'pchip' (shape-preserving piecewise cubic on "
            "each axis: smooth, no overshoot; at least 2) or 'linear' (bilinear, at "
            "least 2).",
            ("cubic", "pchip", "linear"),
        ),
        "pinion_tip_relief_um": _f(
            0.0,
            "Tip relief C_a of the pinion (um): material removed normal to both flanks at "
            "the tip circle; 0 = the paper's unmodified flanks. Rule of thumb (ISO/Niemann): "
            "about the mesh deflection at the design load.",
            0,
            100,
        ),
        "pinion_tip_relief_length_mm": _f(
            0.0,
            "Length of the pinion's tip relief (mm), measured radially down from the tip "
            "circle at each face position (start diameter d_Ca = d_a - 2 L); must be > 0 "
            "when the relief is, and the relief must start above the base circle.",
            0,
            50,
        ),
        "pinion_tip_relief_shape": _s(
            "linear",
            "Shape of the pinion's tip relief over the roll length sqrt(r^2 - r_b^2) from "
            "its start to the tip: 'linear' or 'parabolic'.",
            ("linear", "parabolic"),
        ),
        "gear_tip_relief_um": _f(
            0.0,
            "Tip relief C_a of the gear (um): material removed normal to both flanks at "
            "the tip circle; 0 = the paper's unmodified flanks. Rule of thumb (ISO/Niemann): "
            "about the mesh deflection at the design load.",
            0,
            100,
        ),
        "gear_tip_relief_length_mm": _f(
            0.0,
            "Length of the gear's tip relief (mm), measured radially down from the tip "
            "circle at each face position (start diameter d_Ca = d_a - 2 L); must be > 0 "
            "when the relief is, and the relief must start above the base circle.",
            0,
            50,
        ),
        "gear_tip_relief_shape": _s(
            "linear",
            "Shape of the gear's tip relief over the roll length sqrt(r^2 - r_b^2) from "
            "its start to the tip: 'linear' or 'parabolic'.",
            ("linear", "parabolic"),
        ),
    },
    "pitch": {
        "pinion_cumulative_um": _fl(
            [],
            "Cumulative pitch deviations F_p of the pinion's drive flanks (um, along the "
            "reference pitch circle of the reference section), one per tooth: tooth 0 is "
            "the pinion tooth of the loaded TCA's reference pair at the record's start, the "
            "rest in the order they enter the mesh; + where the flank stands proud towards "
            "its mate. Empty: random (random_single_um) or none.",
            -1000,
            1000,
            min_len=0,
        ),
        "gear_cumulative_um": _fl(
            [],
            "As pinion_cumulative_um, for the gear's drive flanks (one per gear tooth).",
            -1000,
            1000,
            min_len=0,
        ),
        "random_single_um": _f(
            0.0,
            "For a member without a list: random single pitch deviations f_pt drawn "
            "uniform within +- this (um), less their mean so that they close over the "
            "turn. 0: none.",
            0,
            100,
        ),
        **{
            f"{member}_{kind}_slope_um": _fl(
                [],
                f"{kind.capitalize()} slope deviations f_H_{'alpha' if kind == 'profile' else 'beta'} "
                f"of the {member}'s drive flanks (um), one per tooth as {member}_cumulative_um "
                "numbers them, as a gear checker reports them (transverse plane, along the "
                "base tangent) over the evaluation length "
                f"{kind}_evaluation_mm; + where material grows towards the "
                + ("tip." if kind == "profile" else "heel (+z on parallel axes).")
                + f" Empty: random (random_{kind}_slope_um) or none.",
                -1000,
                1000,
                min_len=0,
            )
            for member in ("pinion", "gear")
            for kind in ("profile", "helix")
        },
        "random_profile_slope_um": _f(
            0.0,
            "For a member without a profile slope list: profile slope deviations drawn "
            "uniform within +- this (um), tooth by tooth. 0: none.",
            0,
            100,
        ),
        "random_helix_slope_um": _f(
            0.0,
            "For a member without a helix slope list: helix slope deviations drawn uniform "
            "within +- this (um), tooth by tooth. 0: none.",
            0,
            100,
        ),
        **{
            f"{member}_{kind}_crowning_um": _fl(
                [],
                f"{kind.capitalize()} crowning C_{'alpha' if kind == 'profile' else 'beta'} "
                f"of the {member}'s drive flanks less the design's (um), one per tooth as "
                f"{member}_cumulative_um numbers them, as a gear checker reports them "
                "(transverse plane, along the base tangent): the height of the trace's arc "
                f"over its chord across {kind}_evaluation_mm, its vertex in the middle of the "
                "range the loaded contact covers; + where the tooth is more crowned than "
                f"designed. Empty: random (random_{kind}_crowning_um) or none.",
                -1000,
                1000,
                min_len=0,
            )
            for member in ("pinion", "gear")
            for kind in ("profile", "helix")
        },
        **{
            f"random_{kind}_crowning_um": _f(
                0.0,
                f"For a member without a {kind} crowning list: {kind} crowning deviations "
                "drawn uniform within +- this (um), tooth by tooth. 0: none.",
                0,
                100,
            )
            for kind in ("profile", "helix")
        },
        **{
            f"{member}_{kind}_trace_mm": _fl(
                [],
                f"Positions of the {member}'s measured {kind} traces (mm, strictly "
                "increasing): "
                + (
                    "roll length along the base tangent from the reference circle "
                    "(a checker's roll length less sqrt(r^2 - r_b^2) at the reference radius)"
                    if kind == "profile"
                    else "axial position from the face middle, + towards the heel (+z on "
                    "parallel axes)"
                )
                + f". Empty: no {kind} traces.",
                -1000,
                1000,
                min_len=0,
            )
            for member in ("pinion", "gear")
            for kind in ("profile", "helix")
        },
        **{
            f"{member}_{kind}_trace_um": _rows(
                [],
                f"The {member}'s measured {kind} traces (um): one row per tooth, numbered "
                f"as {member}_cumulative_um, one value per position of {member}_{kind}_trace_mm; "
                "the measured trace less the design trace in the transverse plane along the "
                "base tangent, + plus material. Everything in it counts (slope, crowning, "
                "form, waviness), taken less its value at the reference point; linear "
                "between positions, held beyond them. Or the name of a CSV file (relative "
                "to the scene file): one line per tooth, values separated by commas, # "
                "starts a comment.",
                -1000,
                1000,
            )
            for member in ("pinion", "gear")
            for kind in ("profile", "helix")
        },
        "profile_evaluation_mm": _fl(
            [],
            "Evaluation lengths L_alpha of the profile slopes and crownings (mm of roll length), "
            "[pinion, gear]. Empty: the roll length the loaded contact covers on each "
            "member's drive flank in the loaded TCA.",
            0,
            1000,
            True,
            min_len=0,
        ),
        "helix_evaluation_mm": _fl(
            [],
            "Evaluation lengths L_beta of the helix slopes and crownings (mm along each member's axis), "
            "[pinion, gear]. Empty: the axial length the loaded contact covers on each "
            "member's drive flank in the loaded TCA.",
            0,
            1000,
            True,
            min_len=0,
        ),
        "seed": _i(
            1,
            "Seed of the random deviations: the single pitch deviations (pinion drawn "
            "first); the slopes from a generator seeded with [seed, 1], the crownings from one "
            "seeded with [seed, 2].",
            0,
        ),
        "flank": _s(
            "drive",
            "The flank the hunting record loads: 'drive' or 'coast' (astern behind a "
            "reversing gear, or braking; the record runs in the drive's sense of rotation, "
            "which leaves its spectrum's amplitudes as they are). The lists above are that "
            "flank's deviations (a tooth's two flanks differ by its thickness deviation), "
            "tooth 0 the tooth of that flank's reference pair. Needs the flank in "
            "ltca.flanks; the dynamics carry the drive flank's only.",
            ("drive", "coast"),
        ),
        "method": _s(
            "linear",
            "'linear': the loaded TE's first-order change through the loaded TCA's pair "
            "weights (milliseconds); 'exact': the contact problem solved again at every "
            "position of the hunting period (one solve each: 30 s on the default scene, 2 cores). "
            "With drivetrain.pitch_deviations the dynamics take the same method: 'linear' "
            "through the mesh table's weights (and the traces' turns), 'exact' from exact "
            "records at every torque level of the loaded TCA as well (five records in all; "
            "docs/drivetrain.md section 3c).",
            ("linear", "exact"),
        ),
        "torque_Nm": _f(
            None,
            "Pinion torque of the analysis (N m), within load.torques_Nm; default "
            "load.operating_torque_Nm.",
            0,
            None,
            True,
        ),
    },
    "drivetrain": {
        "engine_inertia_kgm2": _f(2.0, "Engine inertia incl. flywheel (kg m^2).", 0, None, True),
        "engine_cylinders": _i(
            8, "Cylinders of the 4-stroke engine (firing order = cylinders/2).", 1, 24
        ),
        "engine_power_kW": _f(
            None,
            "Engine power at the operating speed (kW); mean torque = power/speed. "
            "If absent, the mean torque is load.operating_torque_Nm.",
            0,
            None,
            True,
        ),
        "engine_speed_rpm": _f(2000.0, "Operating engine (= pinion) speed (rpm).", 0, None, True),
        "firing_torque_ripple": _f(
            0.1, "Firing-order torque amplitude over mean engine torque.", 0, 10
        ),
        "engine_harmonics": _i(1, "Harmonics of the firing order (amplitude ripple/h).", 1, 50),
        "half_order_ripple": _f(
            0.0,
            "Torque amplitude at orders 0.5, 1, 1.5 (divided by 1, 2, 3) over mean (cylinder imbalance).",
            0,
            10,
        ),
        "governor": Field(
            "bool", False, "Hold the set speed with a PI speed governor on top of the mean torque."
        ),
        "governor_kp_Nms_per_rad": _f(50.0, "Governor proportional gain (N m s/rad).", 0, None),
        "governor_ki_Nm_per_rad": _f(500.0, "Governor integral gain (N m/rad).", 0, None),
        "input_shaft_stiffness_Nm_per_rad": _f(
            2.0e5, "Torsional stiffness engine - pinion (N m/rad).", 0, None, True
        ),
        "input_shaft_damping_ratio": _f(0.02, "Modal damping ratio of the input shaft.", 0, 1),
        "pinion_inertia_kgm2": _f(
            0.05, "Pinion inertia incl. shaft share (kg m^2).", 0, None, True
        ),
        "gear_inertia_kgm2": _f(0.12, "Gear inertia incl. shaft share (kg m^2).", 0, None, True),
        "output_shaft_stiffness_Nm_per_rad": _f(
            4.0e5, "Torsional stiffness gear - propeller (N m/rad).", 0, None, True
        ),
        "output_shaft_damping_ratio": _f(0.02, "Modal damping ratio of the output shaft.", 0, 1),
        "bearing_dofs": Field(
            "bool", False, "Add pinion and gear bearing translations along the line of action."
        ),
        "pinion_bearing_stiffness_N_per_m": _f(
            1.0e9, "Pinion bearing stiffness along the line of action (N/m).", 0, None, True
        ),
        "gear_bearing_stiffness_N_per_m": _f(
            1.0e9, "Gear bearing stiffness along the line of action (N/m).", 0, None, True
        ),
        "pinion_mass_kg": _f(8.0, "Pinion mass for the bearing translation (kg).", 0, None, True),
        "gear_mass_kg": _f(15.0, "Gear mass for the bearing translation (kg).", 0, None, True),
        "bearing_damping_ratio": _f(0.02, "Damping ratio of each bearing translation.", 0, 1),
        "mesh_damping_ratio": _f(0.05, "Mesh damping ratio (of the mesh mode).", 0, 1),
        "mesh_harmonics": _i(
            0, "Mesh-order harmonics kept in the Fourier series of the tables (0 = all).", 0, 10000
        ),
        "mesh_law": _s(
            "tangent",
            "Mesh force against deflection. 'tangent': the tangent stiffness and LTE at the "
            "model's mean torque (between the tables' torque levels the loaded law's "
            "tangent), linear about it (docs/drivetrain.md section 3); 'loaded': through "
            "every torque level of the tables, so that a dynamic load far from the mean "
            "meets the stiffness of its own load (section 3d); 'auto': each run with the "
            "tangent law, repeated with the loaded law where its mesh force's range takes "
            "the loaded TCA's tangent stiffness more than 10 % from the law's constant one "
            "(the FMU takes the loaded law). Every solver and the FMU carry both; with "
            "simulation.solver = 'exudyn' the loaded law runs on exudyn's Python user "
            "functions (its symbolic ones carry the tangent law only).",
            ("tangent", "loaded", "auto"),
        ),
        "backlash_mm": _f(0.1, "Circumferential backlash along the line of action (mm).", 0, 10),
        "mesh_friction_coefficient": _f(
            0.0,
            "Mean coefficient of sliding friction in the mesh (Coulomb, along the flanks' "
            "nominal sliding; 0 = none). Needs a mesh table with friction arms.",
            0,
            0.3,
        ),
        "pinion_eccentricity_um": _f(
            0.0,
            "Eccentricity of the pinion's teeth about its axis of rotation (um; a pure "
            "eccentricity's radial runout F_r of ISO 1328-2 is twice it). 0 = none.",
            0,
            1000,
        ),
        "pinion_eccentricity_angle_deg": _f(
            0.0,
            "Direction of the pinion's eccentricity at pinion angle 0, from the axis "
            "towards the mean mesh point, in the pinion's driving sense (deg).",
            -360,
            360,
        ),
        "gear_eccentricity_um": _f(
            0.0,
            "Eccentricity of the gear's teeth about its axis of rotation (um). 0 = none.",
            0,
            1000,
        ),
        "gear_eccentricity_angle_deg": _f(
            0.0,
            "Direction of the gear's eccentricity at gear angle 0, from the axis towards "
            "the mean mesh point, in the gear's driving sense (deg).",
            -360,
            360,
        ),
        "pitch_deviations": Field(
            "bool",
            False,
            "Apply the [pitch] section's deviations in the dynamics: their approach of the "
            "drive flank over a hunting period at the model's torque (docs/drivetrain.md "
            "section 3c). Needs loaded-TCA mesh tables (their pair and form weights); "
            "measured traces (pitch.*_trace_um) also need their turns on the loaded TCA, "
            "which the approach stage of `gearbox run` makes. All three solvers and the FMU "
            "carry it.",
        ),
        "propeller_inertia_kgm2": _f(5.0, "Propeller inertia in air (kg m^2).", 0, None, True),
        "propeller_added_inertia_fraction": _f(
            0.25, "Added water inertia over propeller inertia.", 0, 10
        ),
        "propeller_blades": _i(3, "Number of propeller blades.", 1, 12),
        "blade_pass_ripple": _f(
            0.05, "Blade-pass torque amplitude over mean propeller torque.", 0, 10
        ),
        "blade_pass_harmonics": _i(
            1, "Harmonics of the blade-pass order (amplitude ripple/h).", 1, 50
        ),
    },
    "simulation": {
        "solver": _s(
            "diffrax",
            "Dynamics solver: 'diffrax', 'exudyn' or 'scipy'.",
            ("diffrax", "exudyn", "scipy"),
        ),
        "rtol": _f(
            1e-6,
            "Relative tolerance of the adaptive 'scipy' and 'exudyn' solvers. 'diffrax' takes"
            " fixed steps from the model's frequencies and does not read it (a run that loses"
            " contact is repeated with adaptive steps at rtol 1e-9; gearbox simulate --rtol"
            " asks for adaptive steps).",
            0,
            1,
            True,
            True,
        ),
        "settle_time_s": _f(
            None,
            "Simulated time before recording (s); default 20 mesh cycles.",
            0,
            None,
        ),
        "settled_mesh_cycles": _i(
            200, "Mesh cycles of settled response used for spectra.", 1, 10**7
        ),
        "samples_per_mesh_cycle": _i(32, "Output samples per mesh cycle.", 4, 10000),
        "speed_sweep_rpm": _fl(
            [500.0, 3000.0],
            "Engine speed range of sweeps [min, max] (rpm).",
            0,
            None,
            True,
            min_len=2,
            max_len=2,
            increasing=True,
        ),
        "sweep_speeds": _i(40, "Speeds in a sweep.", 2, 100000),
        "operating_range_rpm": _fl(
            [],
            "Engine speeds of service [min, max] (rpm): the Campbell diagram spans the "
            "sweep's range and flags its crossings in this one as resonance risks (warned "
            "of by resonance_threshold); [] takes the sweep's range, every crossing then "
            "in it. A sweep wider than the service range shows the crossings beside it.",
            0,
            None,
            min_len=0,
            max_len=2,
            increasing=True,
        ),
        "resonance_threshold": _f(
            0.05,
            "Campbell crossings in the operating range whose steady response reaches this "
            "fraction of the mean load in the mesh or in either shaft are warned of, the "
            "most severe first (the crossing's excitation alone at the crossing speed: "
            "engine and propeller orders on the linear model, mesh orders by harmonic "
            "balance with the time-varying mesh stiffness); the Campbell section lists "
            "every crossing with its response. A choice, not a standard's limit.",
            0.0,
            None,
        ),
    },
    "outputs": {
        "requested": Field(
            "strs",
            ["design"],
            "Results to produce; the stages they need are computed, the rest skipped.",
            choices=(
                "design",
                "sweep",
                "tca",
                "ltca",
                "pitch",
                "approach",
                "tables",
                "dynamics",
                "spectra",
                "waterfall",
                "campbell",
                "report",
                "fmu",
            ),
        ),
        "mesh_tables": _s(
            "auto",
            "Source of the mesh tables for the dynamics: 'loaded_tca' (gearbox.ltca), "
            "'analytical' (ISO 6336-1 mean stiffness with contact-line-length variation, "
            "gearbox.mesh_analytical), or 'auto' (loaded TCA where this installation has it, "
            "else analytical; the report names the one used).",
            ("auto", "loaded_tca", "analytical"),
        ),
    },
}


def _modification_fields(name: str) -> dict[str, Field]:
    """Flank-modification keys of one gear (``pinion`` or ``gear``) besides tip relief
    (gearbox.ltca.modification; all zero by default: the paper's flanks)."""
    the = f"the {name}'s"
    shape = "'linear' or 'parabolic'"
    return {
        f"{name}_root_relief_um": _f(
            0.0,
            f"Root relief C_f of {the} flanks (um): removed normal to the flank at the form "
            "circle (where the involute starts), falling to 0 at the relief's start.",
            0,
            100,
        ),
        f"{name}_root_relief_length_mm": _f(
            0.0,
            f"Length of {the} root relief (mm), radially up from the form circle at each "
            "face position; must be > 0 when the relief is, and end below the tip circle.",
            0,
            50,
        ),
        f"{name}_root_relief_shape": _s(
            "linear",
            f"Shape of {the} root relief over the roll length: {shape}.",
            ("linear", "parabolic"),
        ),
        f"{name}_profile_crowning_um": _f(
            0.0,
            f"Profile crowning C_alpha of {the} flanks (um): a parabola over the roll length, "
            "0 in the middle of the form-to-tip range and C_alpha at both its ends.",
            0,
            100,
        ),
        f"{name}_lead_crowning_um": _f(
            0.0,
            f"Lead crowning C_beta of {the} flanks (um): C_beta (2 w / b)^2, w the axial "
            "distance from the face middle, b the face width (C_beta at both face ends).",
            0,
            100,
        ),
        f"{name}_end_relief_um": _f(
            0.0,
            f"End relief of {the} flanks at both face ends (um).",
            0,
            100,
        ),
        f"{name}_end_relief_length_mm": _f(
            0.0,
            f"Length of {the} end relief from each face end along the axis (mm); must be "
            "> 0 when the relief is, and at most half the face width.",
            0,
            500,
        ),
        f"{name}_end_relief_shape": _s(
            "linear", f"Shape of {the} end relief along the face: {shape}.", ("linear", "parabolic")
        ),
        f"{name}_helix_slope_um": _f(
            0.0,
            f"Helix slope modification f_H of {the} flanks (um): removal f_H w / b across the "
            "face (either sign; tilts the flank against a known misalignment).",
            -100,
            100,
        ),
        f"{name}_profile_slope_um": _f(
            0.0,
            f"Profile slope modification f_Halpha of {the} flanks (um): removal "
            "f_Halpha (t - 1/2), t the place in the form-to-tip range of the roll length "
            "(0 at the form circle, 1 at the tip); either sign, + removes at the tip (as a "
            "smaller pressure angle).",
            -100,
            100,
        ),
        f"{name}_flank_twist_um": _f(
            0.0,
            f"Flank twist S of {the} flanks (um): a profile slope that changes linearly "
            "across the face, removal S (t - 1/2) w / b (-S/2 at w = -b/2 to +S/2 at "
            "w = +b/2; t as for the profile slope); either sign.",
            -100,
            100,
        ),
        f"{name}_topography_profile_mm": _fl(
            [],
            f"Profile positions of {the} topography (mm): roll length along the base "
            "tangent from the reference circle (a checker's roll length less "
            "sqrt(r^2 - r_b^2) at the reference radius), strictly increasing. Empty: no "
            "topography.",
            -1000,
            1000,
            min_len=0,
            increasing=True,
        ),
        f"{name}_topography_face_mm": _fl(
            [],
            f"Face positions of {the} topography (mm): axial position from the face "
            "middle, + towards the heel (+z on parallel axes), strictly increasing.",
            -1000,
            1000,
            min_len=0,
            increasing=True,
        ),
        f"{name}_topography_um": _rows(
            [],
            f"{the.capitalize()} flank topography (um): material removed normal to both "
            f"flanks, one row per position of {name}_topography_profile_mm, one value "
            f"per position of {name}_topography_face_mm; added to the other terms, "
            "interpolated as ltca.topography_interpolation says and held beyond the grid. "
            "Or the name of a CSV file (relative to the scene file): one line per "
            "profile position, values separated by commas, # starts a comment.",
            -1000,
            1000,
        ),
    }


for _gear in ("pinion", "gear"):
    SCHEMA["ltca"].update(_modification_fields(_gear))
del _gear


def _check_value(f: Field, path: str, v: Any, probs: Problems) -> Any:
    """Check one value against its field; return it normalised (int -> float etc.)."""
    kind = f.kind
    if kind == "bool":
        if not isinstance(v, bool):
            probs.add(path, v, "must be true or false")
        return v
    if kind in ("float", "int"):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            probs.add(path, v, f"must be a number ({kind})")
            return v
        if kind == "int" and not isinstance(v, int):
            probs.add(path, v, "must be an integer")
            return v
        if isinstance(v, float) and not math.isfinite(v):
            probs.add(path, v, "must be finite")
            return v
        probs.in_range(path, v, f.lo, f.hi, lo_open=f.lo_open, hi_open=f.hi_open)
        return float(v) if kind == "float" else v
    if kind == "str":
        if not isinstance(v, str):
            probs.add(path, v, "must be a string")
        elif f.choices and v not in f.choices:
            probs.add(path, v, f"must be one of {', '.join(f.choices)}")
        return v
    if kind == "rows":
        if not isinstance(v, list):
            probs.add(path, v, "must be a list of lists (one row each)")
            return v
        row = Field("floats", None, "", f.lo, f.hi, f.lo_open, f.hi_open)
        return [_check_value(row, f"{path}[{i}]", x, probs) for i, x in enumerate(v)]
    if kind in ("floats", "strs"):
        if not isinstance(v, list):
            probs.add(path, v, "must be a list")
            return v
        if len(v) < f.min_len or (f.max_len is not None and len(v) > f.max_len):
            probs.add(path, v, _length_text(f))
        elif f.increasing and kind == "floats":
            if all(map(is_real, v)) and any(b <= a for a, b in zip(v[:-1], v[1:], strict=True)):
                probs.add(path, v, "must be strictly increasing")
        sub = Field(
            "float" if kind == "floats" else "str",
            None,
            "",
            f.lo,
            f.hi,
            f.lo_open,
            f.hi_open,
            f.choices,
        )
        return [_check_value(sub, f"{path}[{i}]", x, probs) for i, x in enumerate(v)]
    raise AssertionError(kind)  # pragma: no cover - schema defect


def _length_text(f: Field) -> str:
    if f.max_len == f.min_len:
        return f"must have exactly {f.min_len} {'entry' if f.min_len == 1 else 'entries'}"
    if f.max_len is not None:
        return f"must have {f.min_len} to {f.max_len} entries"
    return f"must have at least {f.min_len} {'entry' if f.min_len == 1 else 'entries'}"


@dataclass(frozen=True)
class Scene(PicklesReadOnly):
    """A validated scene: every section with defaults filled in (scene units).

    ``scene["pair"]["offset_mm"]`` reads a value; ``scene.path`` is the file it came
    from (``None`` for scenes built from a dict).
    """

    data: Mapping[str, Mapping[str, Any]]
    path: Path | None = None

    def __getitem__(self, section: str) -> Mapping[str, Any]:
        return self.data[section]

    @property
    def name(self) -> str:
        name = self.data[""]["name"]
        if name:
            return name
        return self.path.stem if self.path else "scene"

    def to_dict(self) -> dict[str, Any]:
        """Plain nested dict in TOML layout (top-level keys first); unset keys left out."""
        out: dict[str, Any] = {k: v for k, v in self.data[""].items() if v is not None}
        for sec, values in self.data.items():
            if sec:
                out[sec] = {k: v for k, v in values.items() if v is not None}
        return out

    def replaced(self, **sections: Mapping[str, Any]) -> Scene:
        """A new, re-validated scene with keys of the named sections replaced.

        ``scene.replaced(drivetrain={"propeller_inertia_kgm2": 6.0})``
        """
        d = self.to_dict()
        for sec, values in sections.items():
            if sec not in SCHEMA:
                raise InputError([], f"unknown section {sec!r}")
            d.setdefault(sec, {}).update(values)
        return scene_from_dict(d, path=self.path)


def _check_relations(data: Mapping[str, Mapping[str, Any]], probs: Problems) -> None:
    """Checks that involve more than one key (after the per-key checks)."""
    lt = data.get("ltca", {})
    for name in ("pinion", "gear"):
        for kind, unit in (("tip_relief", "um"), ("root_relief", "um"), ("end_relief", "um")):
            amount = lt.get(f"{name}_{kind}_{unit}")
            length = lt.get(f"{name}_{kind}_length_mm")
            if (
                isinstance(amount, float)
                and isinstance(length, float)
                and amount > 0
                and not length > 0
            ):
                probs.add(
                    f"ltca.{name}_{kind}_length_mm",
                    length,
                    f"must be > 0 when ltca.{name}_{kind}_{unit} is > 0 ({amount:g})",
                )

    _check_tool(data, probs)

    rng = data.get("simulation", {}).get("operating_range_rpm")
    if isinstance(rng, list) and len(rng) == 1:
        probs.add("simulation.operating_range_rpm", rng, "must be [min, max] (rpm), or []")

    pitch = data.get("pitch", {})
    applied = data.get("drivetrain", {}).get("pitch_deviations") is True
    if applied and pitch.get("flank") == "coast":
        probs.add(
            "drivetrain.pitch_deviations",
            True,
            "the dynamics carry the drive flank's deviations: set pitch.flank = 'drive' "
            "(it is 'coast')",
        )


def _check_tool(data: Mapping[str, Mapping[str, Any]], probs: Problems) -> None:
    """The rack tooth must not be pointed: its two tip roundings (radius rho_a0) fit
    in its tip, ``rho_a0 <= (cos a pi / 4 - sin a h_a0) / (1 - sin a)`` in units of m_n
    (gearbox.surface.ToothBlank checks the same in metres)."""
    a = data.get("pair", {}).get("normal_pressure_angle_deg")
    tool = data.get("tool", {})
    h, rho = tool.get("addendum_coefficient"), tool.get("tip_radius_coefficient")
    if not all(isinstance(v, float) for v in (a, h, rho)) or not 0 < a < 90:
        return
    sa, ca = math.sin(math.radians(a)), math.cos(math.radians(a))
    most = (ca * math.pi / 4 - sa * h) / (1 - sa)
    if most < 0:
        probs.add(
            "tool.addendum_coefficient",
            h,
            f"must be at most {ca * math.pi / 4 / sa:.4g} at pair.normal_pressure_angle_deg = "
            f"{a:g}: the rack tooth is pointed above that depth even without tip rounding",
        )
    elif rho > most:
        probs.add(
            "tool.tip_radius_coefficient",
            rho,
            f"must be in [0, {most:.4g}] with tool.addendum_coefficient = {h:g} and "
            f"pair.normal_pressure_angle_deg = {a:g}: the rack tooth's tip roundings "
            "would overlap (a pointed tooth)",
        )


def _read_rows(name: str, scene_path: Path | None, key: str, probs: Problems) -> list:
    """A ``rows`` value given as a CSV file's name (relative to the scene file, else to
    the working directory): one row per line, values separated by commas, ``#`` starts
    a comment. The numbers take the name's place in the scene (its key and provenance
    hold them)."""
    import numpy as np

    file = Path(name)
    if not file.is_absolute() and scene_path is not None:
        file = Path(scene_path).parent / file
    try:
        rows = np.loadtxt(file, delimiter=",", comments="#", ndmin=2, dtype=float)
    except OSError as exc:
        probs.add(key, name, f"cannot read {file}: {exc.strerror or exc}")
        return []
    except ValueError as exc:
        probs.add(key, name, f"{file} must hold rows of comma-separated numbers: {exc}")
        return []
    return rows.tolist()


def scene_from_dict(raw: Mapping[str, Any], path: Path | None = None) -> Scene:
    """Validate a nested dict (TOML layout) and fill defaults; raise on any problem."""
    probs = Problems()
    data: dict[str, dict[str, Any]] = {}
    for sec, fields in SCHEMA.items():
        if sec == "":
            given = {k: v for k, v in raw.items() if not isinstance(v, dict)}
        else:
            given = raw.get(sec, {})
            if not isinstance(given, dict):
                probs.add(sec, given, "must be a table [" + sec + "]")
                given = {}
        out = {}
        for key, f in fields.items():
            path_ = f"{sec}.{key}" if sec else key
            if key in given:
                v = given[key]
                if f.kind == "rows" and isinstance(v, str):
                    v = _read_rows(v, path, path_, probs)
                out[key] = _check_value(f, path_, v, probs)
            elif f.required:
                probs.add(path_, "<missing>", f"is required ({f.doc})")
            else:
                out[key] = f.default
        for key in given:
            if key not in fields:
                path_ = f"{sec}.{key}" if sec else key
                probs.add(path_, given[key], f"unknown key; valid keys: {', '.join(fields)}")
        data[sec] = MappingProxyType(out)
    for sec, v in raw.items():
        if isinstance(v, dict) and sec not in SCHEMA:
            probs.add(
                sec,
                "{...}",
                f"unknown section; valid sections: {', '.join(s for s in SCHEMA if s)}",
            )
    _check_relations(data, probs)
    where = f"scene {path}" if path else "scene"
    probs.raise_if_any(f"invalid {where}")
    return Scene(MappingProxyType(data), path)


def load_scene(path: str | Path) -> Scene:
    """Read and validate a scene TOML file."""
    p = Path(path)
    try:
        text = p.read_text(encoding="utf-8-sig")  # a byte-order mark is not TOML's
    except OSError as exc:
        raise InputError([], f"cannot read scene {p}: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise InputError(
            [], f"scene {p} is not UTF-8 text (byte {exc.start}: {exc.reason}): TOML files are"
        ) from None
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError([], f"scene {p} is not valid TOML: {exc}") from None
    return scene_from_dict(raw, path=p)


#: Notes printed under a section's heading in the generated reference.
_SECTION_NOTES = {
    "ltca": (
        "Flank modifications (`*_tip_relief_*`, `*_root_relief_*`, `*_profile_crowning_um`, "
        "`*_lead_crowning_um`, `*_end_relief_*`, `*_helix_slope_um`; "
        "`gearbox.ltca.modification`): the material removed normal to both flanks of a "
        "gear enters the separation field of crossed beveloid pairs and the "
        "closed-form grid of parallel-axis pairs "
        "(unloaded TE, loaded contact and edge detection see the modified flanks). Profile "
        "terms act over the roll length sqrt(r^2 - r_b^2) of each transverse section, "
        "lead terms along the gear's own axis across its face width. All zero by default: "
        "the paper's unmodified flanks. "
        'Measured effects in docs/ltca.md, sections "Tip relief" and "Flank modifications".'
    ),
}


def schema_markdown() -> str:
    """The scene schema as a Markdown reference (``docs/scene.md``)."""
    lines = [
        "# Scene file reference (schema 1)",
        "",
        "Generated from `gearbox.scene.SCHEMA` by `gearbox scene-doc`; do not edit by hand.",
        "Units are in the key names. `required` keys have no default.",
        "",
    ]
    for sec, fields in SCHEMA.items():
        lines += [
            f"## `[{sec}]`" if sec else "## top level",
            "",
            *([_SECTION_NOTES[sec], ""] if sec in _SECTION_NOTES else []),
            "| key | kind | default | range | meaning |",
            "|---|---|---|---|---|",
        ]
        for key, f in fields.items():
            default = "required" if f.required else ("-" if f.default is None else repr(f.default))
            if f.choices:
                rng = " / ".join(f.choices)
            elif f.lo is not None or f.hi is not None:
                rng = Problems.range_text(f.lo, f.hi, f.lo_open, f.hi_open)
            else:
                rng = ""
            lines.append(f"| `{key}` | {f.kind} | {default} | {rng} | {f.doc} |")
        lines.append("")
    return "\n".join(lines)

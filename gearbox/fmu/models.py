"""The FMUs of the drivetrain, built from one :class:`~gearbox.drivetrain.model.DrivetrainModel`.

- :func:`drivetrain_fmu`: the whole chain (engine, shafts, mesh, propeller) in one FMU,
  with an additive engine torque and propeller load torque as inputs.
- :func:`gearbox_fmu`: the gearbox alone (input shaft, pinion, mesh, gear, output
  shaft); the flange angles and speeds of engine and propeller are inputs, the shaft
  torques outputs, for coupling to the user's own engine and propeller models.
- :func:`engine_fmu`, :func:`propeller_fmu`: the two ends, for co-simulation with
  :func:`gearbox_fmu` (``gearbox cosim``).

Every FMU integrates the equations of docs/drivetrain.md (the same as
``gearbox.drivetrain.model.rhs``); the mesh tables travel as samples per torque level
in ``resources/`` and are fitted at instantiation, so the mean torque stays a
parameter. A table with the sliding friction's moment arms (``friction_arm_pinion_m``,
``friction_arm_gear_m``) ships them too: the mesh FMUs then have the parameter
``mesh.friction_coefficient`` (start: the model's ``mesh_friction_coefficient``) and
the friction torques as outputs (docs/drivetrain.md §3a). The mesh FMUs of a model
built from a table (whose flanks carry ``MeshFlank.transverse``) have the pinion's
and the gear's eccentricities as parameters (``pinion.eccentricity``,
``pinion.eccentricity_angle``, ``gear.*``; start: the model's) and their approach of
the flanks as an output (docs/drivetrain.md §3b). A model with pitch deviations
(``DrivetrainModel.pitch``) ships the drive flank's approach samples in ``resources/``
too: the mesh FMUs fit the same periodic cubic spline at instantiation, add its
approach to the drive flank's gap and have it as an output (docs/drivetrain.md §3c).
"""

from __future__ import annotations

from dataclasses import replace
from importlib import resources as ilr

import numpy as np

from ..meshtable import FRICTION_ARMS
from .spec import FmuModel, Variable

__all__ = [
    "drivetrain_fmu",
    "engine_fmu",
    "gearbox_fmu",
    "mesh_resources",
    "model_from_scene",
    "propeller_fmu",
]

_DOFS = ("engine", "pinion", "gear", "propeller", "pinion_bearing", "gear_bearing")


def _template(name: str) -> str:
    return ilr.files("gearbox.fmu").joinpath("c").joinpath(name).read_text(encoding="utf-8")


def _harmonics(model) -> int:
    return (len(model.drive.k_coef) - 1) // 2


def _friction(model, table) -> bool:
    """Whether the table carries the friction arms (then the FMU applies the friction
    torques with ``mesh.friction_coefficient``); InputError naming
    ``mesh_friction_coefficient`` when the model has friction and the table no arms."""
    from ..errors import InputError, Problem

    arms = all(k in table.extra for k in FRICTION_ARMS)
    mu = float(model.mesh_friction_coefficient)
    if mu > 0 and not arms:
        raise InputError(
            Problem(
                "mesh_friction_coefficient",
                mu,
                "needs the mesh table's friction arms (friction_arm_pinion_m, "
                "friction_arm_gear_m), which this table lacks; set it to 0 or use a table "
                "with them (the analytical table, or gearbox ltca with the grids' axes)",
            ),
            "cannot build the FMU with mesh friction",
        )
    return arms


def _eccentricity(model) -> bool:
    """Whether the FMU has the eccentricities (docs §3b): where the model's flanks carry
    the transverse projections, which the C code recomputes from the table at
    ``engine.mean_torque`` like the rotation radii (a model built before them has
    neither, and no eccentricity)."""
    return model.drive.transverse is not None


def _pitch(model) -> bool:
    """Whether the FMU has the pitch deviations' approach of the drive flank (docs §3c):
    where the model has one (``DrivetrainModel.pitch``). Its samples travel in
    ``resources/`` (:func:`mesh_resources`); it is the model's, at the model's torque,
    and not a parameter."""
    return getattr(model, "pitch", None) is not None


def _pitch_layout(n: int) -> tuple[int, int]:
    """(rows, columns) of ``pitch_samples.txt`` for n samples (row-major): one per row
    up to 100000, else the fewest columns that divide n into at most 100000 rows
    (InputError naming ``pitch.values`` where none does)."""
    from ..errors import InputError, Problem

    for cols in range(1, 1001):
        if n % cols == 0 and n // cols <= 100_000:
            return n // cols, cols
    raise InputError(
        Problem(
            "pitch.values",
            n,
            "the FMU reads the pitch approach as at most 100000 rows of up to 1000 samples: "
            "use a sample count with a divisor up to 1000 that leaves at most 100000 rows",
        ),
        "cannot build the FMU with pitch deviations",
    )


def _mesh_features(model, table) -> dict[str, bool]:
    """The optional parts of the mesh FMUs: ``friction`` (:func:`_friction`),
    ``eccentricity`` (:func:`_eccentricity`), ``pitch`` (:func:`_pitch`) and
    ``loaded``, the loaded mesh law (docs/drivetrain.md §3d) where the model has it."""
    return {
        "friction": _friction(model, table),
        "eccentricity": _eccentricity(model),
        "pitch": _pitch(model),
        "loaded": model.mesh_law == "loaded",
    }


def mesh_resources(model, table) -> dict[str, str]:
    """Table samples for the FMU's ``resources/``: meta, torque levels, samples, and
    with pitch deviations (:func:`_pitch`) their approach.

    ``mesh_samples.txt`` rows: (flank, torque, position) with flank drive first; columns
    tangent stiffness (N/m), LTE (m), mesh point P (m, Sf), line of action n (Sf), and
    where the table has them the friction arms about the pinion's and the gear's axis
    (m; :func:`_friction`). ``pitch_meta.txt``: n, angle0 (rad), step (rad) of
    ``DrivetrainModel.pitch``; ``pitch_samples.txt``: its n values a_j (m), row-major
    (:func:`_pitch_layout`), through which the C code fits the periodic cubic spline of
    ``PitchApproach.coefficients``.
    """
    friction = _friction(model, table)
    flanks = [f for f in ("drive", "coast") if f in table.flanks]
    if model.coast is None:
        flanks = ["drive"]
    h = _harmonics(model)
    meta = [
        table.pinion_teeth,
        table.gear_teeth,
        len(flanks),
        table.torque.size,
        table.angle.size,
        h,
        *table.pinion_axis.ravel(),
        *table.gear_axis.ravel(),
    ]
    rows = []
    for f in flanks:
        i = table.flank_index(f)
        for j in range(table.torque.size):
            for p in range(table.angle.size):
                rows.append(
                    [
                        table.tangent_stiffness[i, j, p],
                        table.lte[i, j, p],
                        *table.mesh_point[i, j, p],
                        *table.line_of_action[i, j, p],
                        *([table.extra[k][i, j, p] for k in FRICTION_ARMS] if friction else []),
                    ]
                )

    def fmt(name: str, comment: str, arr) -> str:
        arr = np.atleast_2d(np.asarray(arr, dtype=float))
        body = "\n".join(" ".join(f"{x:.17g}" for x in row) for row in arr)
        return f"gearbox-table 1 {arr.shape[0]} {arr.shape[1]}\n# {comment}\n{body}\n"

    attrs = table.attrs
    src = f"# source: mesh table of scene {attrs.get('scene', '?')}, {attrs.get('method', '?')}"
    out = {
        "mesh_meta.txt": fmt(
            "meta",
            "N_1 N_2 n_flanks n_torques n_positions harmonics pinion_axis(dir, point) "
            f"gear_axis(dir, point) (m)\n{src}",
            [meta],
        ),
        "mesh_torque.txt": fmt("torque", "pinion torque levels (N m)", table.torque[:, None]),
        "mesh_samples.txt": fmt(
            "samples",
            "rows: flank (drive, coast) x torque x position; columns: tangent stiffness (N/m), "
            "LTE (m), P_x P_y P_z (m), n_x n_y n_z"
            + (
                ", friction arm about the pinion's axis phi_1 (m), about the gear's phi_2 (m)"
                if friction
                else ""
            ),
            rows,
        ),
    }
    if model.mesh_law == "loaded":
        out["mesh_secant.txt"] = fmt(
            "secant",
            "the loaded mesh law's no-load deflection (docs/drivetrain.md 3d): secant "
            "stiffness F_n / LTE (N/m) of the lowest torque level; rows flank x position",
            [
                [table.stiffness[table.flank_index(f), 0, p]]
                for f in flanks
                for p in range(table.angle.size)
            ],
        )
    if _pitch(model):
        pa = model.pitch
        n = pa.values.size
        rows_, cols_ = _pitch_layout(n)
        out["pitch_meta.txt"] = fmt(
            "pitch_meta",
            "pitch deviations' approach of the drive flank (docs/drivetrain.md 3c): n samples, "
            "pinion angle of sample 0 (rad), step (rad)",
            [[n, pa.angle0, pa.step]],
        )
        out["pitch_samples.txt"] = fmt(
            "pitch_samples",
            f"approach a_j (m) at pinion angles angle0 + j step, j = 0..n-1, row-major, "
            f"{cols_} per row; a periodic cubic spline passes through them",
            pa.values.reshape(rows_, cols_),
        )
    return out


# ----------------------------------------------------------------- variables


def _p(name, unit, desc, start, lo=None, hi=None, *, positive=False, fixed=False) -> Variable:
    kw = {}
    if positive:
        kw.update(min=0.0, min_open=True)
        desc = f"{desc} (> 0)"
    elif lo is not None:
        kw["min"] = lo
    if hi is not None:
        kw["max"] = hi
    return Variable(name, "parameter", unit, desc, start=float(start), fixed=fixed, **kw)


def _out(name, unit, desc) -> Variable:
    return Variable(name, "output", unit, desc)


def _engine_params(model, *, full: bool) -> list[Variable]:
    v = [
        _p(
            "engine.nominal_speed",
            "rad/s",
            "Nominal engine (= pinion) speed Omega",
            model.speed,
            positive=True,
            fixed=True,
        ),
        _p(
            "engine.mean_torque",
            "N.m",
            "Mean engine torque T_op, the operating point of the mesh tables",
            model.torque,
            positive=True,
            fixed=True,
        ),
        _p(
            "engine.inertia",
            "kg.m2",
            "Engine inertia J_e incl. flywheel",
            model.engine_inertia,
            positive=True,
        ),
    ]
    if full:
        v += [
            _p(
                "engine.cylinders",
                "1",
                "Cylinders z of the four-stroke engine (firing order z/2)",
                model.engine_cylinders,
                1,
                24,
            ),
            _p(
                "engine.firing_ripple",
                "1",
                "Firing-order torque amplitude over mean torque r_f",
                model.firing_ripple,
                0,
                10,
            ),
            _p(
                "engine.half_order_ripple",
                "1",
                "Half-order torque amplitudes over mean torque r_h",
                model.half_order_ripple,
                0,
                10,
            ),
            _p(
                "engine.governor_kp",
                "N.m.s/rad",
                "Speed governor proportional gain K_p (0: off)",
                model.governor_kp if model.governor else 0.0,
                0,
            ),
            _p(
                "engine.governor_ki",
                "N.m/rad",
                "Speed governor integral gain K_i (0: off)",
                model.governor_ki if model.governor else 0.0,
                0,
            ),
        ]
    return v


def _propeller_params(model, *, full: bool) -> list[Variable]:
    v = [
        _p(
            "propeller.inertia",
            "kg.m2",
            "Propeller inertia J_pw incl. added water inertia",
            model.propeller_inertia,
            positive=True,
        )
    ]
    if full:
        v += [
            _p(
                "propeller.blades",
                "1",
                "Number of propeller blades Z",
                model.propeller_blades,
                1,
                12,
            ),
            _p(
                "propeller.blade_pass_ripple",
                "1",
                "Blade-pass torque amplitude over mean torque r_b",
                model.blade_pass_ripple,
                0,
                10,
            ),
        ]
    return v


def _gearbox_params(
    model, *, friction: bool, eccentricity: bool, pitch: bool, loaded: bool = False
) -> list[Variable]:
    """The gearbox's parameters; the pitch approach (``pitch``) has none: its spline
    is data, not tunable."""
    v = [
        _p(
            "input_shaft.stiffness",
            "N.m/rad",
            "Torsional stiffness engine - pinion k_in",
            model.input_stiffness,
            positive=True,
        ),
        _p(
            "input_shaft.damping_ratio",
            "1",
            "Modal damping ratio of the input shaft",
            model.input_damping_ratio,
            0,
            1,
        ),
        _p(
            "pinion.inertia",
            "kg.m2",
            "Pinion inertia J_1 incl. shaft share",
            model.pinion_inertia,
            positive=True,
        ),
        _p(
            "gear.inertia",
            "kg.m2",
            "Gear inertia J_2 incl. shaft share",
            model.gear_inertia,
            positive=True,
        ),
        _p(
            "output_shaft.stiffness",
            "N.m/rad",
            "Torsional stiffness gear - propeller k_out",
            model.output_stiffness,
            positive=True,
        ),
        _p(
            "output_shaft.damping_ratio",
            "1",
            "Modal damping ratio of the output shaft",
            model.output_damping_ratio,
            0,
            1,
        ),
        _p(
            "mesh.damping_ratio",
            "1",
            "Mesh damping ratio zeta_mesh",
            _mesh_damping_ratio(model),
            0,
            1,
        ),
        _p(
            "mesh.backlash",
            "m",
            "Backlash along the line of action (coast contact gap)",
            model.coast.backlash if model.coast is not None else 0.0,
            0,
            0.01,
        ),
    ]
    if friction:
        v.append(
            _p(
                "mesh.friction_coefficient",
                "1",
                "Mean sliding friction coefficient mu of the mesh (Coulomb; 0: none): torques "
                "-mu phi_1 F on the pinion and +mu phi_2 F on the gear per flank, phi the "
                "table's friction arms; their cycle means enter the static state and the "
                "propeller coefficient kappa",
                model.mesh_friction_coefficient,
                0,
                0.3,
            )
        )
    if eccentricity:
        v += _eccentricity_params(model)
    if model.bearing_dofs:
        v += [
            _p(
                "pinion_bearing.stiffness",
                "N/m",
                "Pinion bearing stiffness along the line of action",
                model.pinion_bearing_stiffness,
                positive=True,
            ),
            _p(
                "gear_bearing.stiffness",
                "N/m",
                "Gear bearing stiffness along the line of action",
                model.gear_bearing_stiffness,
                positive=True,
            ),
            _p(
                "pinion.mass",
                "kg",
                "Pinion mass (bearing translation)",
                model.pinion_mass,
                positive=True,
            ),
            _p(
                "gear.mass", "kg", "Gear mass (bearing translation)", model.gear_mass, positive=True
            ),
            _p(
                "bearing.damping_ratio",
                "1",
                "Damping ratio of each bearing translation",
                model.bearing_damping_ratio,
                0,
                1,
            ),
        ]
    return v


def _eccentricity_params(model) -> list[Variable]:
    """e_i and psi_i of the pinion and the gear (docs/drivetrain.md §3b; the scene's
    ranges, [0, 1 mm] and [-360, 360] deg)."""
    v = []
    for member, what in (("pinion", "pinion's"), ("gear", "gear's")):
        v += [
            _p(
                f"{member}.eccentricity",
                "m",
                f"Eccentricity e of the {what} teeth about its axis (radial runout 2 e; 0: "
                "none): the flanks' approach along the line of action once per revolution",
                getattr(model, f"{member}_eccentricity"),
                0,
                1e-3,
            ),
            _p(
                f"{member}.eccentricity_angle",
                "rad",
                f"Direction psi of the {what} eccentricity at the member's angle 0, from the "
                "transverse axis towards the drive flank's mean mesh point, in its driving sense",
                getattr(model, f"{member}_eccentricity_angle"),
                -2.0 * np.pi,
                2.0 * np.pi,
            ),
        ]
    return v


def _mesh_damping_ratio(model) -> float:
    """zeta_mesh back from the drive flank's damping c = 2 zeta sqrt(kbar m) (docs §3)."""
    d = model.drive
    inv_m = d.lambda1**2 / model.pinion_inertia + d.lambda2**2 / model.gear_inertia
    c_unit = 2.0 * np.sqrt(d.mean_stiffness / inv_m)
    return float(d.damping / c_unit)


def _gearbox_outputs(
    model, *, friction: bool, eccentricity: bool, pitch: bool, loaded: bool = False
) -> list[Variable]:
    v = [
        _out("pinion.phi", "rad", "Pinion angle (absolute)"),
        _out("pinion.w", "rad/s", "Pinion speed"),
        _out("gear.phi", "rad", "Gear angle (absolute, driving sense)"),
        _out("gear.w", "rad/s", "Gear speed"),
        _out(
            "input_shaft.torque",
            "N.m",
            "Input shaft torque T_in (on the pinion; the engine feels -T_in)",
        ),
        _out("output_shaft.torque", "N.m", "Output shaft torque T_out (on the propeller)"),
        _out("input_shaft.torque_rate", "N.m/s", "d T_in / dt (for extrapolation by the engine)"),
        _out(
            "output_shaft.torque_rate", "N.m/s", "d T_out / dt (for extrapolation by the propeller)"
        ),
        _out(
            "mesh.force", "N", "Dynamic mesh force F_drive - F_coast along the drive line of action"
        ),
        _out("mesh.deflection", "m", "Mesh deflection delta_drive along the line of action"),
        _out("mesh.dte", "m", "Dynamic transmission error delta_drive - LTE_drive(theta_1)"),
    ]
    if friction:
        v += [
            _out(
                "mesh.pinion_friction_torque",
                "N.m",
                "Mesh friction torque on the pinion -mu sum_f phi_1f F_f",
            ),
            _out(
                "mesh.gear_friction_torque",
                "N.m",
                "Mesh friction torque on the gear +mu sum_f phi_2f F_f",
            ),
            _out(
                "mesh.friction_power",
                "W",
                "Mesh friction loss: minus the power of the friction torques on pinion and gear",
            ),
        ]
    if eccentricity:
        v.append(
            _out(
                "mesh.eccentricity_approach",
                "m",
                "The eccentricities' approach eps_drive of the drive flanks along the line of "
                "action (in the gap beside mesh.deflection)",
            )
        )
    if pitch:
        v.append(
            _out(
                "mesh.pitch_approach",
                "m",
                "The pitch deviations' approach a of the drive flank along its line of action "
                "(in the drive flank's gap beside mesh.deflection)",
            )
        )
    if model.bearing_dofs:
        v += [
            _out("pinion_bearing.force", "N", "Pinion bearing force along the line of action"),
            _out("gear_bearing.force", "N", "Gear bearing force along the line of action"),
        ]
    return v


def _states(model, dofs: list[int]) -> tuple[list[Variable], list[Variable]]:
    scale = model.state_scale()
    n = model.n_dof
    states, ders = [], []
    for kind, off, unit, dunit in (("q", 0, "rad", "rad/s"), ("v", n, "rad/s", "rad/s2")):
        for i in dofs:
            name = f"{kind}.{_DOFS[i]}"
            u, du = (unit, dunit) if i < 4 else (("m", "m/s") if kind == "q" else ("m/s", ""))
            what = "deviation from the nominal rotation" if i < 4 else "bearing translation"
            if kind == "v":
                what = "speed " + ("deviation" if i < 4 else "of the bearing translation")
            states.append(
                Variable(name, "state", u, f"{_DOFS[i]} {what}", nominal=float(scale[off + i]))
            )
            ders.append(
                Variable(f"der({name})", "derivative", du or "", f"d/dt {name}", derivative_of=name)
            )
    return states, ders


def _mesh_c(
    model,
    identifier,
    description,
    variables,
    dofs,
    *,
    engine,
    propeller,
    friction,
    eccentricity,
    pitch,
    loaded,
    levels,
    readme,
    resources,
) -> FmuModel:
    h = _harmonics(model)
    nstate = len(dofs)
    state_of_dof = [dofs.index(i) if i in dofs else -1 for i in range(model.n_dof)]
    head = (
        f"#define GBX_WITH_ENGINE {int(engine)}\n"
        f"#define GBX_WITH_PROPELLER {int(propeller)}\n"
        f"#define GBX_BEARINGS {int(model.bearing_dofs)}\n"
        f"#define GBX_FRICTION {int(friction)}\n"
        f"#define GBX_ECCENTRICITY {int(eccentricity)}\n"
        f"#define GBX_PITCH {int(pitch)}\n"
        f"#define GBX_LOADED {int(loaded)}\n"
        f"#define GBX_MAX_LEVELS {levels}\n"
        f"#define GBX_MAX_HARMONICS {h}\n"
        f"#define GBX_ENGINE_HARMONICS {model.engine_harmonics}\n"
        f"#define GBX_BLADE_HARMONICS {model.blade_pass_harmonics}\n"
        f"static const int GBX_STATE_OF_DOF[{model.n_dof}] = "
        f"{{{', '.join(map(str, state_of_dof))}}};\n"
        f"/* {nstate} degrees of freedom as states, velocities after positions */\n\n"
    )
    code = head + (_template("loads.c.in") if engine or propeller else "")
    code += _template("drivetrain_model.c.in")
    data = """    int n1, n2, nf, nt, np, h, has_coast;
    double axis[2][6];
    int ng, ne, npg; /* grid cells per period: mesh, engine (0: none), propeller */
    double *torque, *samples, *coef, *grid, *egrid, *pgrid, *tgrid;
    double fmesh, fe, fp, lam1[2], lam2[2], dir[2][3], proj[2], kbar[2], cm[2], bl[2], G[2][6], ebound[2];
    double Omega, Omega2, T, kappa, k_in, k_out, c_in, c_out, kb[2], cb[2], minv[6];
    double x0[6], qe0;
    double mu, farm[2][2], W[2][6]; /* friction: mu, mean arms phi_1, phi_2, G + Phi */
    /* eccentricities: [A_1, B_1, A_2, B_2] of each flank (m), the pinion's and the gear's
     * revolutions per second, whether one is not 0 */
    double rc[2][4], frev[2];
    int ecc;
    /* pitch deviations: the drive flank's approach, a periodic cubic spline over npt
     * samples from the pinion angle pt0 every pts (rad), coefficients (npt, 4) */
    double *pitch, pt0, pts;
    int npt;
    /* the loaded mesh law: the lowest level's secant stiffnesses (flank x position), the
     * series of its nl = 2 J + 1 rows per flank (then work rows), the levels' forces,
     * its grid */
    double *secant, *lcoef, *lforce, *lgrid;
    int nl;"""
    return FmuModel(identifier, description, tuple(variables), data, code, resources, readme)


def drivetrain_fmu(model, table, *, identifier: str = "BeveloidDrivetrain") -> FmuModel:
    """The whole drivetrain as one FMU (engine torque and propeller load as extra inputs)."""
    features = _mesh_features(model, table)
    dofs = list(range(model.n_dof))
    states, ders = _states(model, dofs)
    variables = (
        _engine_params(model, full=True)
        + _propeller_params(model, full=True)
        + _gearbox_params(model, **features)
        + [
            Variable(
                "engine.torque_input", "input", "N.m", "Extra engine torque added to T_e", start=0.0
            ),
            Variable(
                "propeller.torque_input",
                "input",
                "N.m",
                "Extra load torque on the propeller added to T_p",
                start=0.0,
            ),
            _out("engine.phi", "rad", "Engine angle (absolute)"),
            _out("engine.w", "rad/s", "Engine speed"),
            _out("engine.torque", "N.m", "Engine torque T_e incl. governor and torque input"),
            _out("propeller.phi", "rad", "Propeller angle (absolute)"),
            _out("propeller.w", "rad/s", "Propeller speed"),
            _out("propeller.torque", "N.m", "Propeller load torque T_p incl. torque input"),
        ]
        + _gearbox_outputs(model, **features)
        + states
        + ders
    )
    desc = (
        f"Beveloid marine drivetrain (engine, shafts, crossed beveloid mesh, propeller), "
        f"scene {model.meta.get('scene', '?')}"
    )
    return _mesh_c(
        model,
        identifier,
        desc,
        variables,
        dofs,
        engine=True,
        propeller=True,
        **features,
        readme=_readme("drivetrain", identifier, desc),
        levels=table.torque.size,
        resources=mesh_resources(model, table),
    )


def gearbox_fmu(model, table, *, identifier: str = "BeveloidGearbox") -> FmuModel:
    """The gearbox alone: engine and propeller flange angles and speeds are inputs."""
    features = _mesh_features(model, table)
    dofs = [i for i in range(model.n_dof) if i not in (0, 3)]
    states, ders = _states(model, dofs)
    y0 = model.static_state()
    variables = (
        _engine_params(model, full=False)
        + _propeller_params(model, full=False)
        + _gearbox_params(model, **features)
        + [
            Variable(
                "input_flange.phi",
                "input",
                "rad",
                "Engine-side flange angle (absolute)",
                start=float(y0[0]),
                rate="input_flange.w",
            ),
            Variable(
                "input_flange.w",
                "input",
                "rad/s",
                "Engine-side flange speed",
                start=model.speed,
                rate="input_flange.a",
            ),
            Variable(
                "input_flange.a",
                "input",
                "rad/s2",
                "Engine-side flange acceleration (extrapolates the speed; 0: hold)",
                start=0.0,
            ),
            Variable(
                "output_flange.phi",
                "input",
                "rad",
                "Propeller-side flange angle (absolute)",
                start=0.0,
                rate="output_flange.w",
            ),
            Variable(
                "output_flange.w",
                "input",
                "rad/s",
                "Propeller-side flange speed",
                start=model.gear_speed,
                rate="output_flange.a",
            ),
            Variable(
                "output_flange.a",
                "input",
                "rad/s2",
                "Propeller-side flange acceleration (extrapolates the speed; 0: hold)",
                start=0.0,
            ),
        ]
        + _gearbox_outputs(model, **features)
        + states
        + ders
    )
    notes = {
        "engine.inertia": "; only sets the input shaft damping",
        "propeller.inertia": "; only sets the output shaft damping",
    }
    variables = [
        replace(v, description=v.description + notes[v.name]) if v.name in notes else v
        for v in variables
    ]
    desc = (
        f"Crossed beveloid gearbox with flanges as inputs (for user engine and propeller "
        f"models), scene {model.meta.get('scene', '?')}"
    )
    return _mesh_c(
        model,
        identifier,
        desc,
        variables,
        dofs,
        engine=False,
        propeller=False,
        **features,
        readme=_readme("gearbox", identifier, desc),
        levels=table.torque.size,
        resources=mesh_resources(model, table),
    )


def _shaft_end(body: str, shaft: str, what: str, start: float, torque_desc: str) -> list:
    """Shaft torque input with its rate input, and the body's outputs (engine, propeller)."""
    symbol = what.split()[0]
    return [
        Variable(
            f"{shaft}.torque",
            "input",
            "N.m",
            f"Shaft torque {what}",
            start=start,
            rate=f"{shaft}.torque_rate",
        ),
        Variable(
            f"{shaft}.torque_rate",
            "input",
            "N.m/s",
            f"d {symbol} / dt (extrapolates {symbol} over a communication step; 0: hold)",
            start=0.0,
        ),
        _out(f"{body}.a", "rad/s2", f"{body.capitalize()} acceleration"),
        _out(f"{body}.phi", "rad", f"{body.capitalize()} angle (absolute)"),
        _out(f"{body}.w", "rad/s", f"{body.capitalize()} speed"),
        _out(f"{body}.torque", "N.m", torque_desc),
    ]


def engine_fmu(model, *, identifier: str = "MarineEngine") -> FmuModel:
    """Engine alone: input shaft torque in, angle and speed out (co-simulation partner)."""
    y0 = model.static_state()
    variables = _engine_params(model, full=True) + [
        _p(
            "engine.initial_deviation",
            "rad",
            "Initial angle deviation q_e(0) (static "
            "equilibrium of the whole drivetrain); governor reference",
            float(y0[0]),
            fixed=True,
        ),
        *_shaft_end(
            "engine",
            "input_shaft",
            "T_in (load on the engine)",
            model.torque,
            "Engine torque T_e incl. governor",
        ),
    ]
    states, ders = _states(model, [0])
    variables += [states[0], states[1], ders[0], ders[1]]
    code = (
        f"#define GBX_ENGINE_HARMONICS {model.engine_harmonics}\n#define GBX_BLADE_HARMONICS 1\n"
        + _template("loads.c.in").split("static double propeller_torque")[0]
        + _template("engine_model.c.in")
    )
    desc = "Four-stroke marine engine: inertia, firing-order torque, optional speed governor"
    return FmuModel(
        identifier, desc, tuple(variables), "", code, {}, _readme("engine", identifier, desc)
    )


def propeller_fmu(model, *, identifier: str = "Propeller") -> FmuModel:
    """Propeller alone: output shaft torque in, angle and speed out (co-simulation partner)."""
    tp0 = model.propeller_coefficient * model.gear_speed**2
    variables = [
        _p(
            "propeller.nominal_speed",
            "rad/s",
            "Nominal propeller (= gear) speed Omega_2",
            model.gear_speed,
            positive=True,
            fixed=True,
        ),
        _p(
            "propeller.nominal_torque",
            "N.m",
            "Propeller torque at the nominal speed T_p0",
            tp0,
            positive=True,
            fixed=True,
        ),
        *_propeller_params(model, full=True),
        *_shaft_end(
            "propeller",
            "output_shaft",
            "T_out (drives the propeller)",
            tp0,
            "Propeller load torque T_p",
        ),
    ]
    states, ders = _states(model, [3])
    variables += [states[0], states[1], ders[0], ders[1]]
    loads = _template("loads.c.in")
    code = (
        "#define GBX_ENGINE_HARMONICS 1\n"
        f"#define GBX_BLADE_HARMONICS {model.blade_pass_harmonics}\n"
        + loads[: loads.index("static double engine_torque")]
        + loads[loads.index("static double propeller_torque") :]
        + _template("propeller_model.c.in")
    )
    desc = (
        "Fixed-pitch marine propeller: inertia with added water, quadratic load, blade-pass ripple"
    )
    return FmuModel(
        identifier, desc, tuple(variables), "", code, {}, _readme("propeller", identifier, desc)
    )


def _readme(kind: str, identifier: str, description: str) -> str:
    return (
        _template("readme.md.in")
        .replace("@IDENTIFIER@", identifier)
        .replace("@DESCRIPTION@", description)
        .replace("@KIND@", kind)
    )


def model_from_scene(scene, *, table_path=None, speed_rpm: float | None = None):
    """(DrivetrainModel, MeshTable) of a scene: the table from a netCDF file (``gearbox
    ltca``) or, by default, the analytical ISO 6336-1 table; speed_rpm overrides the
    scene's engine speed."""
    import math

    from ..drivetrain.model import DrivetrainModel
    from ..errors import InputError, Problem
    from ..mesh_analytical import analytical_table, pair_from_scene
    from ..meshtable import MeshTable

    if table_path:
        table = MeshTable.from_netcdf(table_path)
    else:
        table = analytical_table(
            pair_from_scene(scene), scene["load"]["torques_Nm"], scene=scene.name
        )
    if speed_rpm is not None and not (math.isfinite(speed_rpm) and speed_rpm > 0):
        raise InputError(Problem("--speed-rpm", speed_rpm, "must be finite and > 0 rpm"))
    return DrivetrainModel.from_scene(scene, table, speed_rpm=speed_rpm), table

HELP = "Simulate the drivetrain vibration (docs/drivetrain.md) and summarise the mesh force."
EXAMPLES = """  gearbox simulate models/case03.toml --json
  gearbox simulate models/case03.toml --solver scipy --out out/sim
  gearbox simulate models/case03.toml --table out/ltca/mesh_table.nc --speed-rpm 1500
  gearbox simulate models/case03.toml --periodic --json  settled periodic response (shooting)
  gearbox simulate models/case03.toml --rtol 1e-8        diffrax with adaptive steps
  gearbox simulate models/case03.toml --no-cache         compile the solver anew
  gearbox modes models/case03.toml --json                eigenfrequencies only
"""


def add_arguments(parser):
    from ._common import add_cache_arguments, add_scene_argument

    add_scene_argument(parser)
    parser.add_argument(
        "--solver",
        choices=("diffrax", "scipy", "exudyn"),
        default=None,
        help="solver (default: simulation.solver of the scene)",
    )
    parser.add_argument(
        "--rtol",
        type=float,
        default=None,
        help="relative tolerance (default: the scene's simulation.rtol for scipy; diffrax "
        "takes fixed steps unless --rtol is given)",
    )
    add_model_arguments(parser)
    parser.add_argument(
        "--mesh-cycles", type=int, default=None, help="recorded mesh cycles (default: scene)"
    )
    parser.add_argument(
        "--periodic",
        action="store_true",
        help="start from the settled periodic response solved by shooting (diffrax)",
    )
    parser.add_argument(
        "--modes", action="store_true", help="linear modes only, no time integration"
    )
    parser.add_argument(
        "--out", default=None, help="folder for timeseries.csv/.nc, summary.json, mesh_table.nc"
    )
    parser.add_argument("--json", action="store_true", help="print the summary as one JSON object")
    add_cache_arguments(parser, "the compiled diffrax solver, as gearbox run keeps it")


def add_model_arguments(parser) -> None:
    """``--table`` and ``--speed-rpm`` (read by :func:`model_from_args`)."""
    parser.add_argument(
        "--table",
        default=None,
        help="mesh table (netCDF, from `gearbox ltca`); default: analytical ISO 6336-1 table",
    )
    parser.add_argument(
        "--speed-rpm", type=float, default=None, help="engine speed (rpm), overrides the scene"
    )


def model_option_problems(args) -> list:
    """Problems of ``--speed-rpm`` (``--table`` is checked when it is read)."""
    import math

    from ..errors import Problem

    if args.speed_rpm is not None and not (math.isfinite(args.speed_rpm) and args.speed_rpm > 0):
        return [Problem("--speed-rpm", args.speed_rpm, "must be finite and > 0 rpm")]
    return []


def model_from_args(scene, args):
    """(DrivetrainModel, MeshTable) of a scene with ``--table`` and ``--speed-rpm``
    (checked before: :func:`model_option_problems`)."""
    from ..drivetrain.model import DrivetrainModel
    from ..mesh_analytical import analytical_table, pair_from_scene
    from ..meshtable import MeshTable

    if args.table:
        table = MeshTable.from_netcdf(args.table)
    else:
        table = analytical_table(
            pair_from_scene(scene), scene["load"]["torques_Nm"], scene=scene.name
        )
    return DrivetrainModel.from_scene(scene, table, speed_rpm=args.speed_rpm), table


def modes_summary(scene, model, table) -> dict:
    """Operating point and linear modes (``gearbox modes``, head of ``gearbox simulate``)."""
    import math

    from ..drivetrain.linear import modes

    return {
        "scene": scene.name,
        "engine_speed_rpm": model.speed * 30 / math.pi,
        "pinion_torque_Nm": model.torque,
        "mesh_frequency_Hz": model.mesh_frequency,
        "mean_mesh_stiffness_N_per_m": model.drive.mean_stiffness,
        "table_method": table.attrs.get("method", ""),
        **modes(model).to_dict(),
    }


def summary(scene, args) -> tuple[dict, object, object, object]:
    """(summary dict, model, TimeSeries or None, table)."""
    from ..drivetrain.model import DrivetrainModel
    from ..drivetrain.simulate import (
        default_solver,
        friction_metrics,
        loaded_twin,
        mesh_force_metrics,
        run_with_auto_law,
        simulate,
    )

    model, table = model_from_args(scene, args)
    out = modes_summary(scene, model, table)
    if args.modes:
        return out, model, None, table
    sim = scene["simulation"]
    name = args.solver or sim["solver"]
    rtol = args.rtol if args.rtol is not None else sim["rtol"]  # both checked before
    if name == "diffrax" and args.rtol is None:
        rtol = None  # fixed steps from the model's frequencies; --rtol asks for adaptive ones
    cycles = args.mesh_cycles if args.mesh_cycles is not None else sim["settled_mesh_cycles"]
    if args.periodic and args.mesh_cycles is None and model.common_period_mesh_cycles():
        cycles = model.common_period_mesh_cycles()  # one whole common period

    def run_on(m):
        ts = simulate(
            m,
            default_solver(name, rtol, m.mesh_law),
            settle_time=sim["settle_time_s"],
            mesh_cycles=cycles,
            samples_per_cycle=sim["samples_per_mesh_cycle"],
            start="periodic" if args.periodic else "operating_point",
        )
        return ts, mesh_force_metrics(ts, m)

    loaded = loaded_twin(  # mesh_law "auto": the loaded law where the run needs it
        scene,
        lambda law: DrivetrainModel.from_scene(
            scene, table, speed_rpm=args.speed_rpm, mesh_law=law
        ),
    )
    model, ts, metrics = run_with_auto_law(run_on, model, table, loaded)
    out.update(
        {
            "mesh_law": model.mesh_law,
            "solver": name,
            "rtol": rtol,
            "status": ts.status,
            "failure": ts.failure.to_dict() if ts.failure else None,
            "wall_time_s": ts.wall_time,
            "compile_time_s": ts.attrs.get("compile_time_s", 0.0),
            "nfev": ts.nfev,
            "steps": ts.steps,
            "settling_change": ts.attrs.get("settling_change"),
            "common_period_mesh_cycles": ts.attrs.get("common_period_mesh_cycles"),
            "periodicity_residual": ts.attrs.get("periodicity_residual"),
            "shooting_converged": ts.attrs.get("shooting_converged"),
            **metrics,
            **friction_metrics(ts),
        }
    )
    return out, model, ts, table


def run(args):
    import math

    from ..errors import Problem
    from ..pipeline.cache import default_cache_dir
    from ._common import (
        cache_of,
        dumps_json,
        output_folder,
        scene_and_options,
        staged_files,
        usable_cache,
        write_atomic,
    )

    options = model_option_problems(args)
    if args.rtol is not None and not 0 < args.rtol < 1:
        options.append(Problem("--rtol", args.rtol, "must be in (0, 1)"))
    if args.mesh_cycles is not None and args.mesh_cycles < 1:
        options.append(Problem("--mesh-cycles", args.mesh_cycles, "must be >= 1"))
    scene = scene_and_options(args.scene, options)
    d = output_folder(args.out) if args.out else None
    cache = usable_cache(cache_of(args), "simulate")
    if cache is False or args.modes:
        out, model, ts, table = summary(scene, args)
    else:  # the diffrax solver's compiled programs, in the cache folder as for gearbox run
        from ..pipeline import jaxcache

        with jaxcache.jax_cache(default_cache_dir() if cache is True else cache):
            if (args.solver or scene["simulation"]["solver"]) == "diffrax":
                jaxcache.attach()
            out, model, ts, table = summary(scene, args)
    clean = {
        k: (None if isinstance(v, float) and not math.isfinite(v) else v) for k, v in out.items()
    }
    if d is not None:
        with staged_files(d) as stage:  # all the files, or none of them
            write_atomic(stage / "summary.json", dumps_json(clean) + "\n")
            table.to_netcdf(stage / "mesh_table.nc")
            if ts is not None:
                ts.to_csv(stage / "timeseries.csv")
                ts.to_netcdf(stage / "timeseries.nc")
    if args.json:
        print(dumps_json(clean))
    else:
        print(f"gearbox simulate: {scene.name}")
        for k, v in clean.items():
            if k != "modes":
                print(f"  {k}: {v}")
    if ts is not None and not ts.success:
        return 1
    return 0

"""Wrong arguments to the documented entry points: a clear error that names the
parameter and what it must be (not an AttributeError or a jax traceback from deep
inside), and a wrong value rather than a silent result."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.errors import InputError, Problems
from gearbox.geometry import PairSpec, design_pair


@pytest.fixture(scope="module")
def case03():
    return load_scene("models/case03.toml")


@pytest.fixture(scope="module")
def design(case03):
    return design_pair(PairSpec.from_scene(case03))


@pytest.fixture(scope="module")
def model(case03):
    from gearbox.drivetrain.model import DrivetrainModel

    return DrivetrainModel.from_scene(case03, None)


def test_a_scene_or_a_path_where_a_design_or_scene_belongs(case03, design):
    from gearbox.drivetrain.model import DrivetrainModel
    from gearbox.ltca.table import scene_ltca
    from gearbox.surface import blanks_from_design
    from gearbox.tca import run_tca

    with pytest.raises(TypeError, match=r"design_pair: spec must be a PairSpec.*got Scene"):
        design_pair(case03)
    with pytest.raises(TypeError, match=r"run_tca: design must be a PairDesign"):
        run_tca(case03)
    with pytest.raises(TypeError, match=r"blanks_from_design: design .* got str 'x'"):
        blanks_from_design("x")
    path = "models/case03.toml"
    with pytest.raises(TypeError, match=r"load_scene\('models/case03.toml'\)\), not a path"):
        PairSpec.from_scene(path)
    with pytest.raises(TypeError, match=r"scene_ltca: scene .* not a path"):
        scene_ltca(design, path)
    with pytest.raises(TypeError, match=r"table must be a MeshTable .*got str 'tables.nc'"):
        DrivetrainModel.from_scene(case03, "tables.nc")
    with pytest.raises(TypeError, match=r"run_tca: settings must be a TCASettings"):
        run_tca(design, settings={"positions": 61})
    spec = PairSpec.from_scene(case03)
    with pytest.raises(TypeError, match=r"PairSpec.pinion must be a GearSpec"):
        design_pair(dataclasses.replace(spec, pinion={"teeth": 29}))


def test_numbers_that_are_not_numbers_are_named():
    from gearbox.tca import AssemblyErrors

    with pytest.raises(InputError, match=r"AssemblyErrors.offset = 'a': must be a finite"):
        AssemblyErrors(offset="a")
    with pytest.raises(InputError, match=r"shaft_angle = nan"):
        AssemblyErrors(shaft_angle=float("nan"))
    p = Problems()
    assert not p.in_range("x", "3", 0, 10) and not p.in_range("y", None, 0, None)
    assert not p.in_range("z", True, 0, 10)  # a bool is not a number here
    assert p.in_range("w", np.float64(3.0), 0, 10) and p.in_range("v", np.array(2), 0, 10)
    assert [str(q) for q in p.items] == [
        "x = '3': must be a number in [0, 10]",
        "y = None: must be a number in [0, inf)",
        "z = True: must be a number in [0, 10]",
    ]


def test_a_module_in_mm_given_to_the_si_parallel_pair():
    from gearbox.ltca.parallel import ParallelPair

    kw = dict(teeth=(20, 40), normal_pressure_angle=0.35, helix_angle=0.0)
    with pytest.raises(InputError, match=r"normal_module = 4.0: must be in \(0, 0.1\] m"):
        ParallelPair(normal_module=4.0, face_width=0.02, **kw)
    with pytest.raises(InputError, match=r"face_width = 40.0: must be in \(0, 2\] m"):
        ParallelPair(normal_module=0.004, face_width=40.0, **kw)
    ParallelPair(normal_module=0.004, face_width=0.02, **kw)  # SI: fine


def test_simulate_names_its_bad_arguments_and_takes_a_solver_name(model):
    from gearbox.drivetrain.simulate import simulate

    with pytest.raises(InputError, match=r"mesh_cycles = 0: must be an integer >= 1"):
        simulate(model, mesh_cycles=0)
    with pytest.raises(InputError, match=r"settle_time = -1.0: must be >= 0 s"):
        simulate(model, mesh_cycles=5, settle_time=-1.0)
    with pytest.raises(InputError) as err:
        simulate(model, mesh_cycles=2.5, samples_per_cycle=0, start="x")
    assert [q.path for q in err.value.problems] == ["mesh_cycles", "samples_per_cycle", "start"]
    with pytest.raises(InputError, match=r"solver = 'scypi': must be one of"):
        simulate(model, "scypi", mesh_cycles=2)
    ts = simulate(model, "scipy", mesh_cycles=2, samples_per_cycle=8)
    assert ts.attrs["solver"] == "scipy" and len(ts.time) == 16


@pytest.mark.slow
def test_simulate_on_exudyn_records_its_step(model):
    """docs/exudyn.md: ``attrs["step_s"]`` is the step used, through simulate() too."""
    from gearbox.drivetrain.exudyn_backend import simulate_exudyn
    from gearbox.drivetrain.simulate import simulate

    ts = simulate(model, "exudyn", mesh_cycles=2, samples_per_cycle=8)
    assert ts.attrs["solver"] == "exudyn" and ts.attrs["step_s"] > 0
    tm = 1.0 / model.mesh_frequency
    direct = simulate_exudyn(model, 2.0 * tm, output_step=tm / 8)
    assert ts.attrs["step_s"] == pytest.approx(direct.attrs["step_s"], rel=1e-12)


def test_order_responses_take_speeds_in_rad_per_s_above_zero(model):
    from gearbox.drivetrain.linear import order_responses

    for bad in ([-100.0], [0.0], [np.nan], []):
        with pytest.raises(InputError, match=r"speeds = .*finite and > 0"):
            order_responses(model, bad)
    with pytest.raises(InputError, match=r"mesh_harmonics = -1"):
        order_responses(model, mesh_harmonics=-1)
    assert order_responses(model, [200.0, 300.0]).orders.size > 0


def test_campbell_takes_its_modes_by_name():
    from gearbox.spectrum import campbell

    with pytest.raises(TypeError, match=r"campbell: modes must be a Mapping"):
        campbell([1000.0], (), (0.0, 100.0))


def test_run_pipeline_takes_one_output_by_name(case03):
    from gearbox.pipeline import preview, run_pipeline

    run = run_pipeline(case03, "design", cache=False)
    assert run.summary.requested == ("design",) and run.summary.ok
    assert [n for n, _, _ in preview(case03, "design", cache=False)] == ["design"]


def test_fe_compliance_names_a_wrong_argument(design):
    from gearbox.fe.compliance import FECompliance, FEOptions
    from gearbox.surface import blanks_from_design

    with pytest.raises(
        TypeError, match=r"FECompliance: blanks must be \(pinion, gear\) ToothBlank"
    ):
        FECompliance(blanks="x")
    with pytest.raises(TypeError, match=r"FECompliance: blanks .* got tuple \(1, 2\)"):
        FECompliance(blanks=(1, 2))
    with pytest.raises(TypeError, match=r"FECompliance: options must be a FEOptions"):
        FECompliance("coarse")
    with pytest.raises(TypeError, match=r"FECompliance: teeth must be a dict"):
        FECompliance(teeth=[1])
    blanks = list(blanks_from_design(design))
    assert FECompliance(FEOptions(), blanks=blanks).blanks == tuple(blanks)

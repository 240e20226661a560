"""Compiled jax executables kept in the pipeline's cache folder (gearbox.pipeline.jaxcache):
jax's persistent cache under <cache>/jax for the run, the solver's executables whole under
<cache>/executables, and the fixed-step program free of Python callbacks (jax stores no
executable that calls back into Python)."""

import logging
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

pytest.importorskip("diffrax")
import jax  # noqa: E402

from gearbox.drivetrain import diffrax_backend as db  # noqa: E402
from gearbox.drivetrain import fixed_step as fs  # noqa: E402
from gearbox.drivetrain.linear import periodic_start_state  # noqa: E402
from gearbox.drivetrain.model import DrivetrainModel  # noqa: E402
from gearbox.drivetrain.simulate import default_solver, simulate  # noqa: E402
from gearbox.mesh_analytical import analytical_table, pair_from_scene  # noqa: E402
from gearbox.pipeline import jaxcache  # noqa: E402
from gearbox.pipeline.adapters.dynamics import solver_of  # noqa: E402
from gearbox.scene import load_scene  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def model():
    s = load_scene(ROOT / "models" / "case03.toml")
    table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
    return DrivetrainModel.from_scene(s, table)


def test_tsit5_tableau_is_diffraxs():
    import diffrax

    t = diffrax.Tsit5.tableau
    b_sol, c, a_lower = fs.TSIT5
    np.testing.assert_array_equal(np.asarray(t.b_sol), b_sol)
    np.testing.assert_array_equal(np.asarray(t.c), c)
    assert len(t.a_lower) == len(a_lower)
    for row, mine in zip(t.a_lower, a_lower, strict=True):
        np.testing.assert_array_equal(np.asarray(row), mine)


def test_the_pipeline_takes_fixed_steps_with_diffrax_and_rtol_elsewhere():
    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    assert scene["simulation"]["rtol"] == 1e-6  # set in the file: not for diffrax
    solver = solver_of(scene)
    assert solver.name == "diffrax" and solver.rtol is None and not solver.adaptive
    assert solver.contact_rtol is not None  # contact loss still goes to adaptive steps
    scipy = solver_of(scene.replaced(simulation={"solver": "scipy", "rtol": 1e-7}))
    assert scipy.rtol == 1e-7


def test_fixed_step_program_has_no_python_callback(model):
    p = model.params()
    ts = np.linspace(0.0, 2e-3, 9)
    plan = fs.plan_steps(model, ts, default_solver("diffrax"))
    fn = fs.fixed_solve_fn("Tsit5", 2048, terms=fs.excitation_terms(p))
    z0 = periodic_start_state(model) / p["scale"]
    text = fn.lower(p, z0, plan.t, plan.h, plan.out).as_text()
    assert "stablehlo" in text or "mhlo" in text
    assert "callback" not in text.lower()


def test_jax_cache_is_set_for_the_run_and_undone(tmp_path, monkeypatch):
    monkeypatch.delenv(jaxcache.DIR_ENV, raising=False)
    monkeypatch.delenv(jaxcache.MIN_TIME_ENV, raising=False)
    before = jax.config.jax_compilation_cache_dir
    with jaxcache.jax_cache(tmp_path) as folder:
        assert folder == tmp_path / "jax"
        assert os.environ[jaxcache.DIR_ENV] == str(folder)
        assert jax.config.jax_compilation_cache_dir == str(folder)
        assert jax.config.jax_persistent_cache_min_compile_time_secs == 0.0
        assert jaxcache._active is not None
    assert jaxcache.DIR_ENV not in os.environ
    assert jax.config.jax_compilation_cache_dir == before
    assert jaxcache._active is None and db.executable_store is None


def test_jax_cache_leaves_the_users_folder(tmp_path, monkeypatch):
    mine = tmp_path / "mine"
    monkeypatch.setenv(jaxcache.DIR_ENV, str(mine))
    with jaxcache.jax_cache(tmp_path / "cache") as folder:
        assert folder == mine
        assert os.environ[jaxcache.DIR_ENV] == str(mine)
    assert os.environ[jaxcache.DIR_ENV] == str(mine)


def test_executable_store_round_trip_and_bad_entry(tmp_path):
    f = jax.jit(lambda x: jax.numpy.sin(x) * 2.0)
    x = jax.numpy.arange(4.0)
    calls = []

    def compile_():
        calls.append(1)
        return f.lower(x).compile()

    store = jaxcache.ExecutableStore(tmp_path)
    c1 = store.get(("k", 1), compile_)
    files = list(tmp_path.glob("*.exe"))
    assert len(calls) == 1 and len(files) == 1
    c2 = jaxcache.ExecutableStore(tmp_path).get(("k", 1), compile_)  # a new store: loads
    assert len(calls) == 1
    np.testing.assert_array_equal(np.asarray(c2(x)), np.asarray(c1(x)))
    files[0].write_bytes(b"not an executable")
    c3 = jaxcache.ExecutableStore(tmp_path).get(("k", 1), compile_)
    assert len(calls) == 2  # removed and compiled again
    np.testing.assert_array_equal(np.asarray(c3(x)), np.asarray(c1(x)))
    jaxcache.ExecutableStore(tmp_path).get(("k", 2), compile_)
    assert len(calls) == 3 and len(list(tmp_path.glob("*.exe"))) == 2


def test_executable_with_host_callbacks_is_not_stored_nor_warned_of(tmp_path, caplog):
    """A program that calls back into Python (as diffrax's adaptive runs do, through
    equinox's step checks) does not serialise: compiled each time, no file, no
    warning. A folder that cannot be written is warned of."""
    host = jax.jit(lambda x: jax.pure_callback(np.sin, jax.ShapeDtypeStruct(x.shape, x.dtype), x))
    x = jax.numpy.arange(3.0)
    with caplog.at_level(logging.DEBUG, logger="gearbox.pipeline"):
        got = jaxcache.ExecutableStore(tmp_path).get(("cb",), lambda: host.lower(x).compile())
    np.testing.assert_allclose(np.asarray(got(x)), np.sin(np.arange(3.0)))
    assert not list(tmp_path.glob("*.exe"))
    assert [r.levelno for r in caplog.records if "not stored" in r.message] == [logging.DEBUG]
    caplog.clear()
    blocked = tmp_path / "a_file"
    blocked.write_text("")  # the store's folder is a file: nothing can be written there
    plain = jax.jit(lambda x: x + 1.0)
    with caplog.at_level(logging.WARNING, logger="gearbox.pipeline"):
        jaxcache.ExecutableStore(blocked).get(("p",), lambda: plain.lower(x).compile())
    assert any("not stored" in r.message for r in caplog.records)


RUN = """
import sys, numpy as np
from gearbox.drivetrain import diffrax_backend as db
from gearbox.drivetrain.model import DrivetrainModel
from gearbox.drivetrain.simulate import simulate, default_solver
from gearbox.mesh_analytical import analytical_table, pair_from_scene
from gearbox.pipeline import jaxcache
from gearbox.scene import load_scene
s = load_scene(sys.argv[2])
table = analytical_table(pair_from_scene(s), [150.0, 300.0, 450.0], positions=24)
m = DrivetrainModel.from_scene(s, table)
with jaxcache.jax_cache(sys.argv[1]):
    jaxcache.attach()
    ts = simulate(m, default_solver("diffrax"), mesh_cycles=20, samples_per_cycle=8)
print(ts.status, repr(float(np.sum(ts["mesh_force_N"]))))
"""


def test_a_second_process_loads_the_solver_and_gets_the_same_run(tmp_path):
    """Two processes: the first compiles and stores, the second loads (jax's persistent
    cache on too, as in a run) and its run is the same to the last bit."""
    env = os.environ | {"JAX_PLATFORMS": "cpu", "PYTHONPATH": str(ROOT)}
    env.pop(jaxcache.DIR_ENV, None)
    cmd = [sys.executable, "-c", RUN, str(tmp_path), str(ROOT / "models" / "case03.toml")]
    out = [subprocess.run(cmd, capture_output=True, text=True, env=env) for _ in range(2)]
    for o in out:
        assert o.returncode == 0, o.stderr[-2000:]
    assert out[0].stdout.split()[0] == "success"
    assert out[0].stdout == out[1].stdout
    assert len(list((tmp_path / "executables").glob("*.exe"))) == 1
    assert any((tmp_path / "jax").iterdir())  # jax's own cache: the smaller functions


def test_in_process_run_matches_without_store(model, tmp_path):
    ref = simulate(model, default_solver("diffrax"), mesh_cycles=10, samples_per_cycle=8)
    db._COMPILED.clear()
    with jaxcache.jax_cache(tmp_path):
        jaxcache.attach()
        ts = simulate(model, default_solver("diffrax"), mesh_cycles=10, samples_per_cycle=8)
    np.testing.assert_array_equal(ts["mesh_force_N"], ref["mesh_force_N"])
    assert len(list((tmp_path / "executables").glob("*.exe"))) == 1


def test_an_executable_from_jaxs_cache_is_not_copied(tmp_path):
    """One that jax loaded from its persistent cache is not kept (re-serialised, such a
    copy lacked code: it failed when run)."""
    from jax._src import monitoring

    f = jax.jit(lambda x: x * 2.0)
    x = jax.numpy.arange(3.0)

    def from_jax_cache():
        monitoring.record_event(jaxcache.HIT_EVENT)  # what jax records on a hit
        return f.lower(x).compile()

    store = jaxcache.ExecutableStore(tmp_path)
    got = store.get(("k",), from_jax_cache)
    np.testing.assert_array_equal(np.asarray(got(x)), [0.0, 2.0, 4.0])
    assert not list(tmp_path.glob("*.exe"))
    store.get(("k",), lambda: f.lower(x).compile())
    assert len(list(tmp_path.glob("*.exe"))) == 1


def test_jax_cache_hits_are_seen(tmp_path, monkeypatch):
    monkeypatch.delenv(jaxcache.DIR_ENV, raising=False)
    f = jax.jit(lambda x: jax.numpy.cos(x) + 3.5)
    x = jax.numpy.arange(5.0)
    with jaxcache.jax_cache(tmp_path):
        with jaxcache._jax_cache_hits() as hits:
            f.lower(x).compile()
        assert hits == []
        jax.clear_caches()
        with jaxcache._jax_cache_hits() as hits:
            f.lower(x).compile()
        assert hits == [jaxcache.HIT_EVENT]

"""Results with read-only mappings pickle with the standard pickler (process pools,
Dask, ``pickle.dumps``) and come back equal, still read-only."""

from __future__ import annotations

import pickle
from pathlib import Path
from types import MappingProxyType

import numpy as np
import pytest

from gearbox import load_scene
from gearbox._pickling import picklable
from gearbox.drivetrain.timeseries import TimeSeries
from gearbox.mesh_analytical import analytical_table, pair_from_scene
from gearbox.pipeline import run_pipeline

MARINE = Path(__file__).resolve().parents[1] / "models" / "marine_drive.toml"


def roundtrip(obj):
    return pickle.loads(pickle.dumps(obj, protocol=pickle.HIGHEST_PROTOCOL))


def test_nested_read_only_mappings_and_arrays_come_back_read_only():
    frozen = np.arange(3.0)
    frozen.setflags(write=False)
    inner = MappingProxyType({"a": frozen, "b": [MappingProxyType({"c": 1})]})
    x = {"inner": inner, "t": (inner, np.ones(2)), "plain": [1, "two"]}
    with pytest.raises(TypeError):
        pickle.dumps(x)  # what the standard pickler does with a MappingProxyType
    y = roundtrip(picklable(x))
    assert type(y["inner"]) is MappingProxyType
    assert type(y["t"][0]) is MappingProxyType and type(y["inner"]["b"][0]) is MappingProxyType
    assert y["inner"]["b"][0]["c"] == 1 and y["plain"] == [1, "two"]
    np.testing.assert_array_equal(y["inner"]["a"], frozen)
    assert not y["inner"]["a"].flags.writeable
    assert y["t"][1].flags.writeable  # a writeable array stays writeable


def test_scene_pickles():
    scene = load_scene(MARINE)
    back = roundtrip(scene)
    assert back == scene and back.path == scene.path
    assert type(back.data) is MappingProxyType and type(back["pair"]) is MappingProxyType
    with pytest.raises(TypeError):
        back["pair"]["offset_mm"] = 1.0


def test_mesh_table_and_time_series_pickle():
    table = analytical_table(pair_from_scene(load_scene(MARINE)), [300.0, 600.0], positions=12)
    back = roundtrip(table)
    assert type(back.attrs) is MappingProxyType and type(back.extra) is MappingProxyType
    assert dict(back.attrs) == dict(table.attrs) and back.extra.keys() == table.extra.keys()
    for name in ("angle", "torque", "stiffness", "tangent_stiffness", "lte", "mesh_point"):
        got, want = getattr(back, name), getattr(table, name)
        np.testing.assert_array_equal(got, want)
        assert not got.flags.writeable
    ts = TimeSeries(
        np.linspace(0.0, 1.0, 5), {"x_m": np.arange(5.0)}, {"x_m": "m"}, attrs={"solver": "t"}
    )
    back = roundtrip(ts)
    assert type(back.channels) is MappingProxyType and not back["x_m"].flags.writeable
    np.testing.assert_array_equal(back["x_m"], ts["x_m"])
    assert dict(back.units) == {"x_m": "m"} and dict(back.attrs) == {"solver": "t"}


def test_pipeline_run_pickles():
    scene = load_scene(MARINE)
    run = run_pipeline(scene, ["design"], cache=False)
    back = roundtrip(run)
    assert back.scene == scene and type(back.results) is MappingProxyType
    assert dict(back.keys) == dict(run.keys)
    assert back["design"].to_dict() == run["design"].to_dict()


def test_copies_keep_the_read_only_mappings():
    import copy

    scene = load_scene(MARINE)
    shallow, deep = copy.copy(scene), copy.deepcopy(scene)
    assert shallow == scene and deep == scene
    assert shallow.data is scene.data  # a shallow copy shares the fields
    assert type(deep.data) is MappingProxyType and type(deep["pair"]) is MappingProxyType
    assert deep.data is not scene.data


class _Holder:
    """An object that is no PicklesReadOnly, holding a read-only mapping."""

    def __init__(self, m):
        self.m = m


def test_dumps_takes_read_only_mappings_in_any_object():
    """``gearbox._pickling.dumps`` (the cache's entries, the output worker's jobs)
    takes a read-only mapping inside any object, where the standard pickler refuses it."""
    from gearbox._pickling import dumps

    held = _Holder(MappingProxyType({"a": 1}))
    with pytest.raises(TypeError):
        pickle.dumps(held)
    back = pickle.loads(dumps(held))
    assert type(back.m) is MappingProxyType and dict(back.m) == {"a": 1}

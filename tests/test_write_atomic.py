"""Files are written completely or not at all, with ordinary permissions."""

from __future__ import annotations

import os
import stat

import pytest

from gearbox.commands._common import atomic_target, write_atomic


def test_permissions_follow_the_umask(tmp_path):
    old = os.umask(0o022)
    try:
        p = write_atomic(tmp_path / "a.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(p.stat().st_mode) == 0o644
    assert p.read_text() == "x"


def test_failure_leaves_the_old_file_and_no_temporary(tmp_path):
    p = tmp_path / "b.txt"
    write_atomic(p, "old")

    with pytest.raises(TypeError):
        write_atomic(p, 12345)  # not str/bytes: the write fails midway
    assert p.read_text() == "old"
    assert not [f for f in os.listdir(tmp_path) if f.endswith(".tmp")]


def test_netcdf_tables_get_ordinary_permissions_and_no_temporary(tmp_path):
    """The netCDF writer (mesh tables, time series) goes through the same rename."""
    xr = pytest.importorskip("xarray")
    from gearbox.meshtable import write_netcdf_atomic

    ds = xr.Dataset({"x": ("n", [1.0, 2.0])})
    old = os.umask(0o022)
    try:
        p = write_netcdf_atomic(ds, tmp_path / "t.nc")
    finally:
        os.umask(old)
    assert stat.S_IMODE(p.stat().st_mode) == 0o644
    assert xr.open_dataset(p)["x"].values.tolist() == [1.0, 2.0]
    assert not [f for f in os.listdir(tmp_path) if f.endswith(".tmp")]


def test_atomic_target_removes_its_temporary_when_the_writer_fails(tmp_path):
    p = tmp_path / "c.bin"
    p.write_bytes(b"old")
    with pytest.raises(RuntimeError, match="midway"):
        with atomic_target(p) as tmp:
            tmp.write_bytes(b"half")
            raise RuntimeError("midway")
    assert p.read_bytes() == b"old"
    assert os.listdir(tmp_path) == ["c.bin"]

"""Files are written completely or not at all, with ordinary permissions."""

from __future__ import annotations

import os
import stat

import pytest

from gearbox.commands._common import write_atomic


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

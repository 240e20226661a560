"""models/example_topography.py, a script users copy: it writes a topography CSV,
runs the loaded TCA with it, and the topography sampled from a lead crowning reads as
that crowning; a waviness on it changes the result."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def test_example_topography_runs(tmp_path):
    script = runpy.run_path(str(ROOT / "models" / "example_topography.py"))
    rows = {}
    for wave in (0.0, 1.0):
        out = tmp_path / f"w{wave:g}" / "map.png"
        got = script["main"](["--positions", "8", "--waviness-um", f"{wave:g}", "--out", str(out)])
        assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
        assert got["csv"].read_text().startswith("# pinion flank topography")
        rows[wave] = got["rows"]
    plain = rows[0.0]
    crown, topo = plain["lead crowning 10 um"], plain["topography map.csv"]
    for key, value in crown.items():  # bicubic: exact for the crowning's parabola
        assert topo[key] == pytest.approx(value, rel=1e-9), key
    assert crown["stiffness_MN_per_m"] < 0.9 * plain["unmodified"]["stiffness_MN_per_m"]
    wavy = rows[1.0]["topography map.csv"]
    assert abs(wavy["stiffness_MN_per_m"] / crown["stiffness_MN_per_m"] - 1) > 0.01

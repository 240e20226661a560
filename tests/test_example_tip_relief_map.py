"""models/example_tip_relief_map.py, a script users copy, runs and shows the map's
shape: a long tip relief takes the LTE's first mesh harmonic down near the load it
matches and leaves it near the unmodified one far above it."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_example_tip_relief_map_runs(tmp_path):
    script = runpy.run_path(str(ROOT / "models" / "example_tip_relief_map.py"))
    out = tmp_path / "map.png"
    got = script["main"](
        ["--relief-um", "0", "20", "--torques-Nm", "300", "900", "--positions", "12"]
        + ["--jobs", "1", "--out", str(out)]
    )
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    res = got["results"]
    assert got["torques"] == [300.0, 900.0]
    plain, relieved = res[0.0], res[20.0]
    # unmodified: the ripple grows with the load (the pair deflects more)
    assert plain[900.0][0] > 1.5 * plain[300.0][0]
    # 12 positions measured: first harmonic 0.95 -> 0.05 um at 300 N m, 1.86 -> 0.90 um
    # at 900 N m (the valley of a 20 um relief lies near 300 N m): ratios 0.05 / 0.48
    low, high = (relieved[t][1] / plain[t][1] for t in (300.0, 900.0))
    assert low < 0.25
    assert high > 0.4 and high > 5 * low

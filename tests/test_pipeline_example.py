"""models/example_speed_sweep.py, the script users copy, runs and gives sensible lines."""

from __future__ import annotations

import runpy
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_example_speed_sweep_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("GEARBOX_CACHE", str(tmp_path / "cache"))
    script = runpy.run_path(str(ROOT / "models" / "example_speed_sweep.py"))
    out = tmp_path / "sweep.png"
    got = script["main"](["--speeds", "2", "--mesh-cycles", "60", "--jobs", "1", "--out", str(out)])
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    (n_lo, _), (n_hi, a_hi) = got["amplitudes"]
    assert (n_lo, n_hi) == (1000.0, 3500.0)  # the scene's speed_sweep_rpm
    # At the rated speed the strongest line of the mesh force is the mesh order
    # N_1 = 29 (the stiffness varies once per tooth); the flat-top window spreads a
    # line over neighbouring bins, so the peak must lie within one bin of it.
    top = got["spectra"][-1]
    keep = top.orders > 0.75
    peak = top.orders[keep][np.argmax(top.amplitudes[keep])]
    assert abs(peak - 29) <= top.resolution
    assert a_hi == pytest.approx(top.amplitudes[keep].max(), rel=1e-12)

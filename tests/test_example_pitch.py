"""models/example_pitch.py, a script users copy: the loaded TE over the hunting period
and the pitch lines of the mesh force across the speed range, checked at the rated
speed against the nonlinear run."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_example_pitch_runs(tmp_path, monkeypatch):
    pytest.importorskip("diffrax")
    monkeypatch.setenv("GEARBOX_CACHE", str(tmp_path / "cache"))
    script = runpy.run_path(str(ROOT / "models" / "example_pitch.py"))
    fp = tmp_path / "fp_pinion.txt"
    fp.write_text("\n".join(f"{3.0 * ((i * 7) % 5 - 2):.1f}" for i in range(29)))
    png = tmp_path / "pitch.png"
    argv = ["--positions", "12", "--speeds", "3", "--simulate", "--plot", str(png)]
    got = script["main"]([*argv, "--pinion", str(fp)])
    assert png.stat().st_size > 10_000
    assert len(got["cut"]) == 3
    # the harmonic balance against the simulated lines: measured within 0.06 % on the
    # six largest (24 positions, the scene's random deviations); tolerance 1 %
    assert len(got["rows"]) == 6
    for order, sim, lin in got["rows"]:
        assert lin == pytest.approx(sim, rel=0.01), order

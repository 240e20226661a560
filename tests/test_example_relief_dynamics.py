"""models/example_relief_dynamics.py, a script users copy: flank modification to
dynamic response through the pipeline. A long tip relief lowers the quasi-static LTE
harmonic and, by softening the mesh, moves the mesh mode towards the mesh frequency;
on the default drive the smaller excitation wins and the dynamic mesh force falls
(measured in the script's docstring)."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_example_relief_dynamics_runs(tmp_path, monkeypatch):
    monkeypatch.setenv("GEARBOX_CACHE", str(tmp_path / "cache"))
    script = runpy.run_path(str(ROOT / "models" / "example_relief_dynamics.py"))
    got = script["main"](["--mesh-cycles", "120", "--positions", "12"])
    plain, relieved = got["unmodified"], got["relieved"]
    assert tuple(relieved["computed"]) == ("ltca", "tables", "dynamics", "spectra")  # design cached
    # quasi-static: the relief lowers the first LTE harmonic (1.87 -> 0.06 um measured
    # on the full record)
    assert relieved["lte_harmonics_m"][0] < 0.5 * plain["lte_harmonics_m"][0]
    # the softer mesh: its mode falls towards the mesh frequency (2015 -> 1828 Hz
    # against 1692 Hz), and the mesh-order response falls with the excitation (2816 ->
    # 476 N)
    f_mesh = plain["mesh_frequency_Hz"]
    assert abs(relieved["mesh_mode_Hz"] - f_mesh) < abs(plain["mesh_mode_Hz"] - f_mesh)
    assert relieved["mesh_force_N"][0] < 0.5 * plain["mesh_force_N"][0]

"""models/example_misalignment.py, a script users copy, runs and shows what a
misalignment does to a pair designed near line contact: the paper's case 01 under a
shaft-angle error of 0.02 deg touches at a border of a flank at every position, with
unloaded TE where the aligned pair has none, and a larger loaded TE ripple and contact
pressure."""

from __future__ import annotations

import runpy
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.mark.slow
def test_example_misalignment_runs(tmp_path):
    script = runpy.run_path(str(ROOT / "models" / "example_misalignment.py"))
    out = tmp_path / "mis.png"
    got = script["main"](
        ["--values", "0", "0.02", "--torques-Nm", "150", "--positions", "9"]
        + ["--ltca-positions", "12", "--jobs", "1", "--out", str(out)]
    )
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert got["error"] == "shaft_angle_error_deg" and got["torques"] == [150.0]
    aligned, tilted = got["rows"]
    assert aligned["value"] == 0.0 and tilted["value"] == 0.02
    # conjugate flanks without the error (3e-11 arcsec measured): no TE, no border
    assert aligned["te_pp_arcsec"] < 1e-6 and aligned["edge_positions"] == 0
    # at 0.02 deg every position touches at a border (0.947 arcsec measured at 9 positions)
    assert tilted["edge_positions"] == tilted["positions"] == 9
    assert 0.5 < tilted["te_pp_arcsec"] < 2.0
    # loaded, 150 N m, 12 positions: LTE p-p 0.702 -> 1.764 um, p_max 313 -> 513 MPa
    lte0, p0, _ = aligned["loaded"][150.0]
    lte1, p1, edge1 = tilted["loaded"][150.0]
    assert lte1 > 2.0 * lte0
    assert p1 > 1.4 * p0
    assert edge1 > 0.1  # the share of the load on an edge (19.1 % measured)

"""The report in a real browser: headless Chromium loads it and decodes every figure.

Skipped only when no Chromium is installed here; CI installs it (.ci/run) and sets
GEARBOX_REQUIRE_BROWSER=1, which turns the skip into a failure.
"""

from __future__ import annotations

import os
from pathlib import Path

import pytest

from gearbox import load_scene
from gearbox.pipeline import run_pipeline
from gearbox.report import write_report
from gearbox.report.browser import browser_check, find_chromium

ROOT = Path(__file__).resolve().parents[1]

if find_chromium() is None:
    if os.environ.get("GEARBOX_REQUIRE_BROWSER"):
        raise RuntimeError("GEARBOX_REQUIRE_BROWSER is set but no chromium is on PATH")
    pytest.skip(
        "no chromium on PATH (apt-get install chromium); CI installs it", allow_module_level=True
    )


@pytest.fixture(scope="module")
def report(tmp_path_factory):
    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    # cheap stages with figures: parameter studies (4) and analytical mesh tables (2: over
    # the mesh cycle, and the mean tangent stiffness against torque)
    scene = scene.replaced(outputs={"mesh_tables": "analytical"})
    run = run_pipeline(scene, ["design", "sweep", "tables", "report"], cache=False)
    return write_report(run, tmp_path_factory.mktemp("r") / "report.html")


def test_chromium_decodes_every_figure(report):
    html = report.read_text()
    n_img = html.count("<img")
    assert n_img == 6
    seen = browser_check(report)
    assert seen.images == n_img
    assert seen.decoded == n_img, seen
    assert all(w > 100 for w in seen.widths)  # figures are hundreds of px wide
    assert seen.title == "gearbox report: marine_drive"


def test_a_corrupt_figure_is_caught(report, tmp_path):
    html = report.read_text().replace("base64,iVBOR", "base64,AAAA", 1)
    bad = tmp_path / "bad.html"
    bad.write_text(html)
    seen = browser_check(bad)
    assert seen.images == 6 and seen.decoded == 5

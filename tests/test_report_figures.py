"""Report figures are laid out with fixed margins (no layout engine): every figure of a
whole run is checked for text that leaves the canvas or runs into a neighbouring axes."""

from __future__ import annotations

from pathlib import Path

import pytest

from gearbox import load_scene
from gearbox.pipeline import run_pipeline
from gearbox.report import build_report
from gearbox.report import html as H

ROOT = Path(__file__).resolve().parents[1]
ALL = ["design", "sweep", "tca", "ltca", "tables", "dynamics", "spectra", "waterfall", "campbell"]


def test_the_check_finds_text_off_the_canvas():
    fig, ax = H.new_figure(1, 1, size=(4, 3), left=0.05)
    ax[0, 0].plot([0, 1e6], [0, 1e6])
    ax[0, 0].set_ylabel("a y label that needs room")
    problems = H.layout_problems(fig)
    assert any("a y label that needs room" in p and "leaves" in p for p in problems), problems


def test_the_check_finds_axes_that_run_into_each_other():
    fig, ax = H.new_figure(1, 2, size=(6, 3), wgap=0.05)
    for a in ax[0]:
        a.plot([0, 1], [1000, 2000])
        a.set_ylabel("force (N)")
    problems = H.layout_problems(fig)
    assert any("overlap" in p for p in problems), problems


def test_unknown_margin_is_refused():
    with pytest.raises(TypeError, match="unknown margins"):
        H.new_figure(1, 1, gutter=0.2)


@pytest.mark.slow
def test_every_figure_of_the_default_scene_fits(monkeypatch):
    scene = load_scene(ROOT / "models" / "marine_drive.toml")
    # a short record and three speeds: the same figures, in a few seconds
    scene = scene.replaced(
        simulation={"settled_mesh_cycles": 60, "samples_per_mesh_cycle": 16, "sweep_speeds": 3}
    )
    run = run_pipeline(scene, ALL, cache=False)
    assert run.summary.ok, run.summary.table()
    monkeypatch.setattr(H, "CHECK_LAYOUT", True)
    html = build_report(run)
    # a section whose figure fails the check is replaced by a warning naming it
    assert "report section could not be drawn" not in html
    assert html.count("<img") >= 12

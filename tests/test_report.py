"""The HTML report: self-contained, the design and its checks, warnings, provenance."""

from __future__ import annotations

import base64
import dataclasses
import hashlib
import math
import re
from importlib import metadata
from pathlib import Path

import pytest

import gearbox
from gearbox import load_scene
from gearbox.pipeline import Stage, StageUnavailable, run_pipeline
from gearbox.pipeline.stages import STAGES
from gearbox.report import build_report, write_report

ROOT = Path(__file__).resolve().parents[1]
CASE03 = ROOT / "models" / "case03.toml"

IMG = re.compile(r'<img alt="[^"]*" src="([^"]+)"')


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    scene = load_scene(CASE03)
    return run_pipeline(scene, ["design", "sweep", "report"], cache=tmp_path_factory.mktemp("c"))


@pytest.fixture(scope="module")
def html(run):
    return build_report(run)


def test_report_is_self_contained(html):
    srcs = IMG.findall(html)
    assert len(srcs) == html.count("<img")
    assert len(srcs) == 4  # one figure per parameter study of paper Figs. 6-9
    for src in srcs:
        assert src.startswith("data:image/png;base64,")
        png = base64.b64decode(src.split(",", 1)[1], validate=True)
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert "<script" not in html and "<link" not in html
    assert not re.search(r'(src|href)="(https?:)?//', html)


def test_design_table_shows_the_design(run, html):
    des = run["design"]
    assert ">Design</h2>" in html
    # values as the design computed them, in degrees at this edge
    for value in (math.degrees(des.fpd_angle_right), math.degrees(des.gear.helix_angle)):
        assert f"{value:.6g}" in html
    for name in des.checks:
        assert name in html


def test_failed_design_check_is_a_warning(run):
    from gearbox.geometry import Check

    des = run["design"]
    bad = dataclasses.replace(
        des,
        checks=dict(des.checks) | {"pinion_topping": Check(False, -1e-4, "m", "tip too thin")},
    )
    broken = dataclasses.replace(run, results={**run.results, "design": bad})
    html = build_report(broken)
    warn = html[html.index('id="warning-list"') : html.index('id="design"')]
    assert "check pinion_topping fails: tip too thin" in warn


def test_stage_failures_and_missing_stages_are_warnings(tmp_path):
    def boom(ctx):
        raise RuntimeError("solver exploded")

    def missing(ctx):
        raise StageUnavailable("gearbox.tca is not in this installation")

    stages = dict(STAGES) | {
        "sweep": Stage("sweep", boom, reads=("pair",)),
        "tca": Stage("tca", missing, depends=("design",)),
    }
    scene = load_scene(CASE03)
    r = run_pipeline(scene, ["design", "sweep", "tca", "report"], stages=stages, cache=False)
    html = build_report(r)
    warn = html[html.index('id="warning-list"') : html.index("</ul>")]
    assert "stage failed: RuntimeError: solver exploded" in warn
    assert "gearbox.tca is not in this installation" in warn


def test_a_broken_section_is_named_not_fatal(run):
    def bad(result, run):
        raise ValueError("cannot draw")

    html = build_report(run, renderers={"design": bad})
    assert "report section could not be drawn: ValueError: cannot draw" in html
    assert "Provenance" in html


def test_provenance(run, html):
    prov = html[html.index('id="provenance"') :]
    assert hashlib.sha256(CASE03.read_bytes()).hexdigest() in prov
    assert f"<td>{gearbox.__version__}</td>" in prov
    assert f"<td>{metadata.version('numpy')}</td>" in prov
    for r in run.summary.records:
        assert f"<td>{r.name}</td>" in prov
    assert "offset_mm = 229.0" in prov  # the scene as run


def test_text_is_escaped(tmp_path):
    raw = CASE03.read_text().replace(
        'description = "', 'description = "<script>alert(1)</script> & ', 1
    )
    p = tmp_path / "s.toml"
    p.write_text(raw)
    scene = load_scene(p)
    r = run_pipeline(scene, ["design"], cache=False)
    html = build_report(r)
    assert "<script>" not in html
    assert "&lt;script&gt;alert(1)&lt;/script&gt; &amp;" in html


def test_write_report_is_atomic(run, tmp_path, monkeypatch):
    target = tmp_path / "report.html"
    target.write_text("old")
    import gearbox.commands._common as common

    def fail(*a):
        raise OSError("disk full")

    monkeypatch.setattr(common.os, "replace", fail)
    with pytest.raises(OSError):
        write_report(run, target)
    assert target.read_text() == "old"
    assert [p.name for p in tmp_path.iterdir()] == ["report.html"]
    monkeypatch.undo()
    write_report(run, target)
    assert target.read_text().startswith("<!DOCTYPE html>")


def test_sections_are_cached_with_their_stage(run):
    from gearbox.report.build import assemble

    html, drawn = assemble(run)
    assert set(drawn) == {"design", "sweep"}
    html2, drawn2 = assemble(run)
    assert drawn2 == {"design": "cached", "sweep": "cached"}
    body = html[html.index("<nav>") : html.index('id="provenance"')]
    assert body == html2[html2.index("<nav>") : html2.index('id="provenance"')]
    assert "report sections from the cache: design, sweep." in html2
    # a result replaced by hand is not the one its key was made for: drawn again
    des = run["design"]
    other = dataclasses.replace(run, results={**run.results, "design": des})
    assert assemble(other)[1]["design"] == "cached"  # the same object: still its key
    fresh = dataclasses.replace(des)
    other = dataclasses.replace(run, results={**run.results, "design": fresh})
    assert assemble(other)[1]["design"] != "cached"
    # without a cache nothing is kept
    assert "cached" not in assemble(dataclasses.replace(run, cache=None))[1].values()


def test_a_section_sees_only_what_it_declares(run, monkeypatch):
    from gearbox.report import build

    def nosy(result, view):
        return build.Section("nosy", f"<p>{view.scene['pair']['offset_mm']}</p>")

    monkeypatch.setattr(build, "_renderers", lambda: {"design": nosy})
    plain = dataclasses.replace(run, cache=None)
    html = build.build_report(plain)
    assert "report section could not be drawn: KeyError" in html
    monkeypatch.setitem(build.SECTION_READS, "design", ("pair.offset_mm",))
    html = build.build_report(plain)
    assert "<p>229.0</p>" in html


def test_section_key_follows_what_the_section_reads(run, monkeypatch):
    from gearbox.report import build

    k0 = build.section_key(run, "design")
    monkeypatch.setitem(build.SECTION_READS, "design", ("load.operating_torque_Nm",))
    k1 = build.section_key(run, "design")
    other = dataclasses.replace(run, scene=run.scene.replaced(load={"operating_torque_Nm": 123.0}))
    assert len({k0, k1, build.section_key(other, "design")}) == 3
    assert build.section_key(run, "design") == k1  # and it is stable


def test_a_crossing_whose_mesh_force_swing_reaches_the_mean_is_beyond_the_linear_response():
    """The Campbell warnings quote each crossing's steady (linear) response; where the
    mesh force's swing reaches its mean (the flanks would part), the text says so."""
    from types import SimpleNamespace

    from gearbox.report.dynamics import _response_text

    def crossing(fraction):
        r = {
            "mesh_force_N": 1919.0 * fraction / 2.3,
            "mesh_force_fraction": fraction,
            "input_shaft_torque_Nm": 198.3,
            "input_shaft_torque_fraction": 2.91,
            "output_shaft_torque_Nm": 148.3,
            "output_shaft_torque_fraction": 1.40,
        }
        return SimpleNamespace(response=r)

    assert "the flanks would part" in _response_text(crossing(2.3))
    assert "(230 %)" in _response_text(crossing(2.3))
    assert "the flanks would part" not in _response_text(crossing(0.558))
    assert _response_text(SimpleNamespace(response={})) == ""


def test_two_operating_torques_are_warned_of():
    """The drive's torque from drivetrain.engine_power_kW against
    load.operating_torque_Nm, which the loaded TCA's figures take: within 1 % quiet."""
    from types import SimpleNamespace

    from gearbox.report.dynamics import _torque_warning

    scene = load_scene("models/marine_drive.toml")
    assert scene["load"]["operating_torque_Nm"] == 802.0
    assert _torque_warning(SimpleNamespace(torque_Nm=802.141), scene) == []
    (w,) = _torque_warning(SimpleNamespace(torque_Nm=654.8), scene)
    assert "654.8 N m" in w.text and "load.operating_torque_Nm = 802 N m" in w.text


def test_the_law_stiffness_ratios_are_shown_in_per_cent_with_their_meaning():
    """They read -0.0481784 with no unit in the operating point's table."""
    from gearbox.report.dynamics import _metric_row

    key, text = _metric_row("law_stiffness_at_min_force", -0.0481784)
    assert text == "-4.8" and "least mesh force" in key and "(%)" in key
    assert _metric_row("law_stiffness_at_max_force", float("nan"))[1] == ""
    assert _metric_row("mesh_force_rms_N", 12.5) == ("mesh_force_rms_N", 12.5)

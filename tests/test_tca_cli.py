"""`gearbox tca SCENE --out DIR --json`: files, JSON keys, exit status on bad input."""

import json
from pathlib import Path

from gearbox.cli import main

MODELS = Path(__file__).parents[1] / "models"


def test_tca_verb_writes_outputs_and_prints_json(tmp_path, capsys):
    out = tmp_path / "tca"
    rc = main(["tca", str(MODELS / "case03.toml"), "--out", str(out), "--json"])
    assert rc == 0
    s = json.loads(capsys.readouterr().out)
    assert abs(s["measured_fpd_angle_right_deg"] - s["designed_fpd_angle_right_deg"]) < 1e-3
    assert abs(s["measured_fpd_angle_left_deg"] - s["designed_fpd_angle_left_deg"]) < 1e-3
    assert set(s["unloaded_te_peak_to_peak_arcsec"]) == {"drive", "coast"}
    assert s["contact_path_straightness_um"]["drive"] < 1e-3
    assert s["path_position"]["drive"]["pinion"]["region"] == "middle"
    for name in (
        "tca_summary.json",
        "tca_path.csv",
        "pinion_tooth.csv",
        "gear_tooth.csv",
        "tca_contact_path.png",
        "tca_transmission_error.png",
        "pinion_tooth.png",
        "gear_tooth.png",
    ):
        assert (out / name).stat().st_size > 0, name
    assert json.loads((out / "tca_summary.json").read_text())["scene"] == "case03"
    header = (out / "tca_path.csv").read_text().splitlines()[0]
    assert header.startswith("side,pinion_angle_deg")
    rows = (out / "pinion_tooth.csv").read_text().splitlines()
    assert rows[0].startswith("flank,i_z,i_u,part,x_mm")
    assert {r.split(",")[3] for r in rows[1:]} == {"fillet", "involute"}


def test_tca_verb_separated_gears_exit_2(tmp_path, capsys):
    """Case 03 on axes 15 mm further apart than designed (the gear's x_t2 kept): the
    tip cylinders no longer overlap. (An offset error of 3 mm had stood for this; the
    flanks' borders still touch there, at the face ends: tests/test_tca_edge.py.)"""
    text = (
        (MODELS / "case03.toml")
        .read_text()
        .replace("offset_mm = 229.0", "offset_mm = 244.0\nbacklash_free = false")
    )
    text = text.replace("[gear]\n", "[gear]\nprofile_shift_xt = 0.2191\n")
    scene = tmp_path / "far.toml"
    scene.write_text(text)
    rc = main(["tca", str(scene), "--out", str(tmp_path / "o"), "--no-figures"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "tooth contact analysis failed" in err and "Traceback" not in err
    assert not (tmp_path / "o" / "tca_summary.json").exists()


def test_an_interrupted_verb_leaves_the_last_complete_run(tmp_path, capsys, monkeypatch):
    """Ctrl-C while a verb writes (here while tca draws its figures, after its CSV and
    JSON files): the folder keeps the previous run's files, all of them, and nothing
    half-made (the new summary beside old figures, as it was)."""
    import pytest

    import gearbox.commands.tca as tca

    out = tmp_path / "tca"
    assert main(["tca", str(MODELS / "case03.toml"), "--out", str(out), "--json"]) == 0
    capsys.readouterr()
    before = {p.name: p.read_bytes() for p in out.iterdir()}
    scene = tmp_path / "s.toml"
    scene.write_text((MODELS / "case03.toml").read_text() + "\n[tca]\npositions = 7\n")

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr(tca, "_figures", interrupted)
    with pytest.raises(KeyboardInterrupt):
        tca.run(tca_args(scene, out))
    assert {p.name: p.read_bytes() for p in out.iterdir()} == before  # no .gearbox-partial.*
    monkeypatch.undo()
    assert main(["tca", str(scene), "--out", str(out), "--json"]) == 0  # and a whole new run
    rows = [r.split(",") for r in (out / "tca_path.csv").read_text().splitlines()[1:]]
    assert len({r[1] for r in rows if r[0] == "drive"}) == 7  # the new run's positions
    assert set(p.name for p in out.iterdir()) == set(before)


def tca_args(scene, out):
    import argparse

    return argparse.Namespace(scene=str(scene), out=str(out), json=True, no_figures=False)

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
    text = (MODELS / "case03.toml").read_text() + "\n[assembly]\noffset_error_mm = 3.0\n"
    scene = tmp_path / "far.toml"
    scene.write_text(text)
    rc = main(["tca", str(scene), "--out", str(tmp_path / "o"), "--no-figures"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "tooth contact analysis failed" in err and "Traceback" not in err
    assert not (tmp_path / "o" / "tca_summary.json").exists()

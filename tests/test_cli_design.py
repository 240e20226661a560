"""The design and sweep verbs: JSON keys, bad input, files written."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from gearbox.cli import main

MODELS = Path(__file__).parents[1] / "models"
REQUIRED = [
    "normal_angular_factor",
    "fpd_angle_right_deg",
    "fpd_angle_left_deg",
    "helix_angle_deg",
    "cone_angle_deg",
    "profile_shift_xt",
    "working_normal_pressure_angle_deg",
    "working_helix_angle_deg",
    "working_cone_angle_deg",
    "working_pitch_radius_mm",
    "mounting_distance_mm",
    "checks",
]


def test_design_json_has_the_documented_keys(capsys):
    assert main(["design", str(MODELS / "case03.toml"), "--json"]) == 0
    out = json.loads(capsys.readouterr().out)
    for k in REQUIRED:
        assert k in out, k
    assert len(out["helix_angle_deg"]) == 2
    assert abs(out["fpd_angle_right_deg"] - 3.3511) < 1e-3
    for c in out["checks"].values():
        assert set(c) >= {"ok", "margin", "detail"}


def test_design_table_prints(capsys):
    assert main(["design", str(MODELS / "case01.toml")]) == 0
    assert "FPD angle" in capsys.readouterr().out


BAD = """schema = 1
[pair]
normal_module_mm = -6.0
normal_pressure_angle_deg = 50.0
shaft_angle_deg = 95.0
offset_mm = 229.0
colour = "red"
[pinion]
teeth = 3
helix_angle_deg = 20.0
cone_angle_deg = -1.0
profile_shift_xt = 0.16
[gear]
teeth = 45
cone_angle_deg = 0.8
"""


def test_bad_scene_lists_every_problem_exit_2_no_traceback(tmp_path):
    p = tmp_path / "bad.toml"
    p.write_text(BAD)
    r = subprocess.run(
        [sys.executable, "-m", "gearbox", "design", str(p)], capture_output=True, text=True
    )
    assert r.returncode == 2
    assert "Traceback" not in r.stderr
    for key in (
        "pair.normal_module_mm",
        "pair.normal_pressure_angle_deg",
        "pair.shaft_angle_deg",
        "pair.colour",
        "pinion.teeth",
        "pinion.cone_angle_deg",
    ):
        assert key in r.stderr, key
    assert "(0, 45)" in r.stderr  # the valid range is named


def test_offset_without_solution_names_the_offset_and_range(tmp_path, capsys):
    text = (MODELS / "case03.toml").read_text().replace("offset_mm = 229.0", "offset_mm = 400.0")
    p = tmp_path / "far.toml"
    p.write_text(text)
    assert main(["design", str(p)]) == 2
    err = capsys.readouterr().err
    assert "pair.offset_mm = 400.0" in err and "offset_mm <=" in err
    # and an offset that eqs (18)-(19) cannot meet at all
    p.write_text(text.replace("offset_mm = 400.0", "offset_mm = 20.0"))
    assert main(["design", str(p)]) == 2
    assert "pair.offset_mm = 20.0" in capsys.readouterr().err


def test_missing_file_is_an_input_error(capsys):
    assert main(["design", "no/such/scene.toml"]) == 2
    err = capsys.readouterr().err
    assert "cannot read scene no/such/scene.toml: No such file or directory" in err
    assert "problem" not in err  # no problem list (with no key path) to count


@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_every_paper_scene_designs(case, capsys):
    assert main(["design", str(MODELS / f"case{case}.toml"), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["all_checks_ok"] is True


def test_sweep_writes_csv_and_png(tmp_path, capsys):
    assert (
        main(["sweep", str(MODELS / "case03.toml"), "--out", str(tmp_path), "--points", "11"]) == 0
    )
    csvs = sorted(tmp_path.glob("*.csv"))
    pngs = sorted(tmp_path.glob("*.png"))
    assert len(csvs) == 4 and len(pngs) == 4
    head, *rows = csvs[0].read_text().splitlines()
    assert head.startswith("shaft_angle_deg,pinion_cone_angle_deg,normal_angular_factor")
    assert len(rows) == 44
    assert pngs[0].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert not list(tmp_path.glob(".*.tmp"))  # nothing half-written left behind


def test_console_command_delivers_all_it_printed_to_a_pipe():
    """``python -m gearbox`` leaves without the interpreter's teardown (gearbox.cli.
    console): what it printed into a pipe (block-buffered) is flushed first, and the
    exit status is main()'s."""
    r = subprocess.run(
        [sys.executable, "-m", "gearbox", "design", str(MODELS / "case03.toml"), "--json"],
        capture_output=True,
        text=True,
    )
    assert r.returncode == 0, r.stderr
    out = json.loads(r.stdout)  # the whole object, to its closing brace
    for key in REQUIRED:
        assert key in json.dumps(out)


def test_import_gearbox_loads_a_public_name_when_first_used():
    """``import gearbox`` imports no stage's code (the command starts faster); each
    public name and subpackage comes from its module on first use."""
    code = (
        "import sys, gearbox\n"
        "loaded = [m for m in ('gearbox.fe', 'gearbox.ltca', 'gearbox.drivetrain', 'scipy')"
        " if m in sys.modules]\n"
        "assert not loaded, loaded\n"
        "from gearbox import FECompliance, load_scene\n"
        "assert FECompliance.__module__ == 'gearbox.fe.compliance'\n"
        "assert gearbox.ltca.__name__ == 'gearbox.ltca' and 'run_tca' in dir(gearbox)\n"
        "assert set(gearbox.__all__) <= set(dir(gearbox))\n"
        "try:\n    gearbox.no_such_name\nexcept AttributeError as e:\n"
        "    assert 'no_such_name' in str(e)\nelse:\n    raise SystemExit('no error')\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    # the names spelled out for type checkers are the names imported on first use
    import re

    import gearbox

    source = Path(gearbox.__file__).read_text()
    typed = dict(
        (name, module)
        for module, name in re.findall(r"from (\.[\w.]+) import (\w+) as \w+", source)
    )
    assert typed == gearbox._EXPORTS


@pytest.mark.parametrize(
    "verb",
    [
        ["run"],
        ["ltca"],
        ["tca"],
        ["simulate"],
        ["sweep"],
        ["fmu", "build"],
        ["cosim"],
    ],
)
def test_an_output_folder_that_cannot_be_written_fails_before_computing(verb, tmp_path, capsys):
    """``--out`` below a plain file: exit 2 with one message naming the option, its value
    and why, before anything is computed (no stage line, nothing in the cache)."""
    blocker = tmp_path / "a_file"
    blocker.write_text("kept\n")
    out = blocker / "results"
    cache = tmp_path / "cache"
    extra = ["--cache", str(cache)] if verb == ["run"] else []
    assert main([*verb, str(MODELS / "marine_drive.toml"), "--out", str(out), *extra]) == 2
    err = capsys.readouterr().err
    assert f"--out = '{out}': must be a folder this user can write to" in err
    assert "Traceback" not in err and " computed (" not in err
    assert blocker.read_text() == "kept\n" and not cache.exists()


def test_a_cache_folder_that_cannot_be_written(tmp_path, capsys, monkeypatch):
    """``--cache`` that cannot be written: exit 2 before computing. The default cache
    folder (here ``$GEARBOX_CACHE``) that cannot be written: one warning, and the run
    goes on without a cache."""
    blocker = tmp_path / "a_file"
    blocker.write_text("")
    scene, out = str(MODELS / "case03.toml"), tmp_path / "out"
    assert main(["run", scene, "--out", str(out), "--cache", str(blocker / "c")]) == 2
    err = capsys.readouterr().err
    assert f"--cache = '{blocker / 'c'}': must be a folder this user can write to" in err
    assert " computed (" not in err and not (out / "run_summary.json").exists()
    monkeypatch.setenv("GEARBOX_CACHE", str(blocker / "c"))
    assert main(["run", scene, "--out", str(out), "--no-progress"]) == 0
    err = capsys.readouterr().err
    assert err.count("running without the cache") == 1 and "Traceback" not in err
    assert (out / "design.json").exists()


def test_the_report_alone_says_it_holds_no_stage(tmp_path, capsys):
    out = tmp_path / "out"
    assert (
        main(
            [
                "run",
                str(MODELS / "case03.toml"),
                "--only",
                "report",
                "--out",
                str(out),
                "--no-cache",
            ]
        )
        == 0
    )
    assert "the report alone holds no stage's results" in capsys.readouterr().err
    assert (out / "report.html").exists()
    assert (
        main(
            [
                "run",
                str(MODELS / "case03.toml"),
                "--only",
                "design",
                "report",
                "--out",
                str(out),
                "--no-cache",
            ]
        )
        == 0
    )
    assert "the report alone" not in capsys.readouterr().err


def test_the_offsets_named_for_a_design_without_solution_do_solve(tmp_path, capsys):
    """The hint's offset interval is where eqs (18)-(19) solve: its ends and middle do,
    just outside them does not (it once named 45.5-15234 mm for case 03, where only
    213-662 mm solve; and a negative offset for a -60 deg pinion helix)."""
    import re

    from gearbox.geometry import PairSpec
    from gearbox.geometry.design import solve_spec
    from gearbox.scene import load_scene

    text = (MODELS / "case03.toml").read_text().replace("offset_mm = 229.0", "offset_mm = 50.0")
    for edit, problem in (("", "offset_mm = 50.0"), ("helix_angle_deg = -60.0", "")):
        t = text if not edit else text.replace("helix_angle_deg = 20.0", edit)
        (tmp_path / "s.toml").write_text(t)
        assert main(["design", str(tmp_path / "s.toml")]) == 2
        err = capsys.readouterr().err
        assert problem in err
        spans = re.findall(r"([\d.]+) <= offset_mm <= ([\d.]+)", err)
        assert spans, err
        s = PairSpec.from_scene(load_scene(tmp_path / "s.toml"))
        for a, b in spans:
            a, b = float(a) * 1e-3, float(b) * 1e-3
            assert a > 0
            inside = np.array([a * 1.0005, 0.5 * (a + b), b * 0.9995])
            assert np.all(solve_spec(s, offset=inside)["ok"]), (a, b)
        lo, hi = float(spans[0][0]) * 1e-3, float(spans[-1][1]) * 1e-3
        assert not np.any(solve_spec(s, offset=np.array([lo * 0.99, hi * 1.01]))["ok"])


def test_scene_lists_that_must_increase_and_files_that_are_not_text(tmp_path, capsys):
    text = (MODELS / "case03.toml").read_text()
    p = tmp_path / "s.toml"
    p.write_text(
        text.replace("torques_Nm = [150.0, 300.0, 450.0]", "torques_Nm = [450.0, 150.0, 150.0]")
    )
    assert main(["design", str(p)]) == 2
    assert "load.torques_Nm = [450.0, 150.0, 150.0]: must be strictly increasing" in (
        capsys.readouterr().err
    )
    p.write_text(text + "\n[simulation]\nspeed_sweep_rpm = [3000.0, 500.0, 800.0]\n")
    assert main(["design", str(p)]) == 2
    assert "speed_sweep_rpm = [3000.0, 500.0, 800.0]: must have exactly 2 entries" in (
        capsys.readouterr().err
    )
    p.write_text(text + "\n[simulation]\nspeed_sweep_rpm = [3000.0, 500.0]\n")
    assert main(["design", str(p)]) == 2
    assert "must be strictly increasing" in capsys.readouterr().err
    p.write_bytes(b"\x80\x81 not text\n")
    assert main(["design", str(p)]) == 2
    err = capsys.readouterr().err
    assert "is not UTF-8 text" in err and "Traceback" not in err
    p.write_bytes(b"\xef\xbb\xbf" + text.encode())  # a byte-order mark: read as TOML
    assert main(["design", str(p)]) == 0
    capsys.readouterr()


def test_run_exits_2_when_a_stage_finds_its_input_wrong(tmp_path, capsys):
    """A problem a stage finds while it computes (no design for this offset) is bad
    input: its problems on stderr, exit 2 and no traceback, as for the scene's checks."""
    p = tmp_path / "far.toml"
    p.write_text(
        (MODELS / "case03.toml").read_text().replace("offset_mm = 229.0", "offset_mm = 1000.0")
    )
    out = tmp_path / "out"
    rc = main(["run", str(p), "--only", "design", "tca", "--out", str(out), "--no-cache"])
    captured = capsys.readouterr()
    assert rc == 2
    assert "gearbox run: design: no design exists" in captured.err
    assert "pair.offset_mm = 1000.0" in captured.err and "Traceback" not in captured.err
    assert "design  failed" in captured.out and "tca     skipped" in captured.out
    summary = json.loads((out / "run_summary.json").read_text())
    rec = {r["name"]: r for r in summary["records"]}
    assert rec["design"]["bad_input"] is True and rec["tca"]["bad_input"] is False


def test_the_options_problems_and_the_scenes_come_in_one_message(tmp_path, capsys):
    """A bad scene and bad options: one message with both (the options' problems hid
    behind the scene's, or the other way round, one fix at a time)."""
    bad = tmp_path / "bad.toml"
    bad.write_text(
        (MODELS / "case03.toml").read_text().replace("offset_mm = 229.0", "offset_mm = -1.0")
    )
    cases = (
        (["simulate", str(bad), "--rtol", "0", "--mesh-cycles", "0"], ["--rtol", "--mesh-cycles"]),
        (["run", str(bad), "--jobs", "0", "--only", "bogus"], ["--jobs", "--only = 'bogus'"]),
        (["ltca", str(bad), "--out", str(tmp_path / "o"), "--positions", "3"], ["--positions"]),
    )
    for argv, options in cases:
        assert main(argv) == 2, argv
        err = capsys.readouterr().err
        assert "invalid options; invalid scene" in err, err
        assert all(o in err for o in options) and "pair.offset_mm = -1.0" in err, err
        assert "Traceback" not in err
    good = str(MODELS / "case03.toml")  # options alone
    assert main(["run", good, "--only", "bogus", "--out", str(tmp_path / "r")]) == 2
    err = capsys.readouterr().err
    assert "invalid options (1 problem)" in err and "--only = 'bogus': unknown output" in err
    assert not (tmp_path / "r").exists()  # refused before anything was written


def test_strict_design_exits_1_when_a_check_fails(tmp_path, capsys):
    """The checks are reported with exit 0 by default; --strict makes a failed check the
    exit status (for scripts and CI), naming the checks."""
    assert main(["design", str(MODELS / "case03.toml"), "--strict"]) == 0
    capsys.readouterr()
    p = tmp_path / "xt.toml"  # a given x_t2 that the backlash-free solve does not meet
    p.write_text(
        (MODELS / "case03.toml").read_text().replace("[gear]\n", "[gear]\nprofile_shift_xt = 0.5\n")
    )
    assert main(["design", str(p), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["all_checks_ok"] is False
    assert main(["design", str(p), "--strict"]) == 1
    assert "design checks failed: gear_profile_shift_given" in capsys.readouterr().err


def test_a_reader_that_leaves_early_gets_no_traceback():
    """``gearbox design X | head -1``: the pipe closes under the command; it stops
    quietly (exit 141, as a shell reports SIGPIPE) without a traceback."""
    import subprocess
    import sys

    proc = subprocess.Popen(
        [sys.executable, "-m", "gearbox", "design", "models/case03.toml"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    proc.stdout.close()  # before the command writes anything
    err = proc.stderr.read()
    assert proc.wait(timeout=60) == 141, err
    assert "Traceback" not in err and "BrokenPipeError" not in err


def test_a_pointed_rack_tooth_names_the_tool_keys():
    """The ToothBlank's check (in mm, under a key no scene has) came only at the TCA;
    the scene now names the tool's coefficients; 0.201 m_n at 28 deg is the blank's
    1.206 mm at m_n = 6 mm."""
    from gearbox import load_scene
    from gearbox.errors import InputError

    scene = load_scene("models/case03.toml")
    with pytest.raises(
        InputError, match=r"tool.tip_radius_coefficient = 0.25: must be in \[0, 0.201\]"
    ):
        scene.replaced(pair={"normal_pressure_angle_deg": 28.0})
    with pytest.raises(InputError, match=r"tool.addendum_coefficient = 2.0: must be at most 1.36"):
        scene.replaced(pair={"normal_pressure_angle_deg": 30.0}, tool={"addendum_coefficient": 2.0})
    scene.replaced(pair={"normal_pressure_angle_deg": 28.0}, tool={"tip_radius_coefficient": 0.2})


def test_a_solved_gear_helix_beyond_60_deg_is_no_usable_design():
    """The solved beta_2 took the TCA's blank check to name gear.helix_angle_deg, a key
    the scene need not give; now the design names the offset."""
    from gearbox import load_scene
    from gearbox.errors import InputError
    from gearbox.geometry import PairSpec, design_pair

    scene = load_scene("models/case03.toml").to_dict()
    scene["pair"] |= {"normal_module_mm": 0.05, "shaft_angle_deg": 89.9, "offset_mm": 29.896}
    scene["pinion"]["teeth"] = 1000
    scene["gear"].pop("helix_angle_deg", None)
    from gearbox.scene import scene_from_dict

    with pytest.raises(
        InputError, match=r"pair.offset_mm = 29.896: gives a gear helix angle beta_2 = 69.75 deg"
    ):
        design_pair(PairSpec.from_scene(scene_from_dict(scene)))


def test_a_check_prints_its_value_apart_from_its_limit():
    """A total contact ratio of 1.99953 printed as '2.000 >= 2' beside a failed check."""
    from gearbox.geometry.checks import _beside

    assert _beside(1.99953, 2.0) == "1.9995"
    assert _beside(2.0, 2.0) == "2.000"
    assert _beside(2.3456, 2.0) == "2.346"

"""`gearbox modes SCENE`: eigenfrequencies and mode descriptions (issue 6 interface)."""

import json
import subprocess
import sys
from pathlib import Path

import pytest

from gearbox.cli import main

ROOT = Path(__file__).resolve().parents[1]
CASE03 = ROOT / "models" / "case03.toml"


def test_modes_json_lists_eigenfrequencies_and_descriptions(capsys):
    from gearbox.drivetrain.linear import modes
    from gearbox.drivetrain.model import DrivetrainModel
    from gearbox.scene import load_scene

    rc = main(["modes", str(CASE03), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0
    f = out["eigenfrequencies_Hz"]
    assert len(f) == 4 and f == sorted(f) and f[0] == pytest.approx(0.0, abs=1e-6)
    # the same numbers as the library's linear analysis of the scene's model
    ref = modes(DrivetrainModel.from_scene(load_scene(CASE03))).frequencies
    assert f == pytest.approx(ref.tolist(), rel=1e-12, abs=1e-9)
    descr = [m["description"] for m in out["modes"]]
    assert descr[0].startswith("rigid-body mode") and descr[-1].startswith("mesh mode")
    assert out["modes"][-1]["mesh_strain_energy_fraction"] > 0.5
    assert set(out["modes"][1]["shape"]) == {"engine", "pinion", "gear", "propeller"}
    assert out["mesh_frequency_Hz"] == pytest.approx(29 * 2000 / 60)


def test_modes_speed_override_and_text_output(capsys):
    # The speed moves the mesh frequency (N1 x pinion speed), not the undamped modes.
    rc = main(["modes", str(CASE03), "--speed-rpm", "1500", "--json"])
    a = json.loads(capsys.readouterr().out)
    assert rc == 0 and a["mesh_frequency_Hz"] == pytest.approx(29 * 1500 / 60)
    rc = main(["modes", str(CASE03)])
    text = capsys.readouterr().out
    assert rc == 0 and "mesh mode" in text and "Hz" in text
    assert a["eigenfrequencies_Hz"][-1] == pytest.approx(
        float(text.split("mesh mode, ")[1].split()[0]), rel=1e-3
    )


def test_modes_bad_input_exits_nonzero_without_traceback(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(CASE03.read_text() + "\n[drivetrain]\ngear_inertia_kgm2 = -0.1\n")
    assert main(["modes", str(bad), "--json"]) == 2
    err = capsys.readouterr().err
    assert "gear_inertia_kgm2" in err and "Traceback" not in err
    assert main(["modes", str(CASE03), "--speed-rpm", "-5"]) == 2
    assert "--speed-rpm" in capsys.readouterr().err
    # the console entry point, as a user runs it: a missing scene file
    r = subprocess.run(
        [sys.executable, "-m", "gearbox", "modes", str(tmp_path / "missing.toml"), "--json"],
        capture_output=True,
        text=True,
        cwd=ROOT,
    )
    assert r.returncode == 2 and r.stdout == ""
    assert "missing.toml" in r.stderr and "Traceback" not in r.stderr


def test_modes_orders_lists_the_steady_response_per_order(capsys):
    """--orders adds one row per excitation order, the library's order_responses at
    the scene's speed, by order; the text form prints the same rows."""
    from gearbox.drivetrain.linear import order_responses
    from gearbox.drivetrain.model import DrivetrainModel
    from gearbox.scene import load_scene

    rc = main(["modes", str(CASE03), "--orders", "--json"])
    rows = json.loads(capsys.readouterr().out)["order_responses"]
    assert rc == 0
    ref = order_responses(DrivetrainModel.from_scene(load_scene(CASE03)))
    assert [r["order"] for r in rows] == sorted(ref.orders.tolist())
    for r in rows:
        assert r == pytest.approx(
            {"order": r["order"], "source": r["source"]} | ref.peaks(r["order"])
        )
    mesh = [r for r in rows if r["source"] == "mesh"]
    assert [r["order"] for r in mesh[:3]] == [29.0, 58.0, 87.0]
    rc = main(["modes", str(CASE03), "--orders"])
    text = capsys.readouterr().out
    assert rc == 0 and "steady response per order" in text
    assert len([ln for ln in text.splitlines() if ln.strip().startswith(("29 ", "58 "))]) == 2


def test_the_free_rotation_is_named_rigid_body_on_the_default_scene(capsys):
    """The eigensolver leaves the line's free rotation at a few 1e-9 of the highest
    frequency, not at zero (8.5e-6 Hz on the default scene, which an absolute 1e-6 Hz
    test called a shaft mode); it is still the rigid-body mode."""
    rc = main(["modes", str(ROOT / "models" / "marine_drive.toml"), "--json"])
    out = json.loads(capsys.readouterr().out)
    assert rc == 0
    f = out["eigenfrequencies_Hz"]
    assert 0 <= f[0] < 1e-6 * f[-1]
    kinds = [m["description"].split(" mode")[0] for m in out["modes"]]
    assert kinds == ["rigid-body", "shaft", "shaft", "mesh"]


def test_a_mesh_table_of_another_pair_is_refused(tmp_path, capsys):
    """A table made for another design (here a 12-tooth pinion) read with --table:
    exit 2 naming the teeth (it ran with the table's mesh frequency, 400 Hz where the
    scene's 29 teeth give 966.7 Hz at 2000 rpm)."""
    from gearbox.drivetrain.model import DrivetrainModel
    from gearbox.errors import InputError
    from gearbox.mesh_analytical import analytical_table, pair_from_scene
    from gearbox.scene import load_scene

    scene = load_scene(CASE03)
    other = scene.replaced(pinion={"teeth": 12}, pair={"offset_mm": 175.0})
    table = analytical_table(pair_from_scene(other), [150.0, 300.0, 450.0])
    with pytest.raises(InputError, match=r"pinion.teeth = 29: the mesh table is of a pair with 12"):
        DrivetrainModel.from_scene(scene, table)
    path = table.to_netcdf(tmp_path / "other.nc")
    assert main(["modes", str(CASE03), "--table", str(path), "--json"]) == 2
    err = capsys.readouterr().err
    assert "pinion.teeth" in err and "12 pinion teeth" in err and "Traceback" not in err
    own = analytical_table(pair_from_scene(scene), [150.0, 300.0, 450.0])
    assert main(["modes", str(CASE03), "--table", str(own.to_netcdf(tmp_path / "own.nc"))]) == 0

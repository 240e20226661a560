"""The ``gearbox ltca`` verb on the parallel reference scene (shortened)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from gearbox.cli import main
from gearbox.meshtable import MeshTable

SCENE = Path(__file__).parent / "data" / "ltca_parallel_helical.toml"


def test_ltca_writes_table_summary_and_figures(tmp_path, capsys):
    out = tmp_path / "out"
    rc = main(["ltca", str(SCENE), "--out", str(out), "--json", "--positions", "8"])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    for name in (
        "mesh_table.nc",
        "mesh_table.csv",
        "ltca_summary.json",
        "contact_pattern.png",
        "mesh_stiffness.png",
        "lte.png",
        "root_stress.png",
    ):
        assert (out / name).stat().st_size > 0, name
    assert not (out / "flank_modifications.png").exists()  # no modifications, no map
    row = summary["flanks"]["drive"]["300"]
    for key in (
        "mean_mesh_stiffness_N_per_m",
        "mesh_stiffness_peak_to_peak_N_per_m",
        "lte_mean_m",
        "lte_peak_to_peak_m",
        "mesh_point_m",
        "line_of_action",
        "contact_pattern_area_fraction",
    ):
        assert key in row
    assert row["solver_converged"] and not row["edge_contact"]
    # the table reads back losslessly and its numbers are the summary's
    t = MeshTable.from_netcdf(out / "mesh_table.nc")
    assert t.flanks == ("drive", "coast") and t.n_positions == 8
    i = int(np.argmin(abs(t.torque - 300.0)))
    assert t.stiffness[0, i].mean() == pytest.approx(row["mean_mesh_stiffness_N_per_m"], rel=1e-12)
    loss = t.extra["mesh_loss_factor"][0, i]
    assert loss.mean() == pytest.approx(row["mesh_loss_factor"], rel=1e-12)
    assert np.all(t.extra["sliding_speed_per_pinion_speed_m"] > 0)
    # involute helical pair: rotation radius r_b1 cos(beta_b) on the drive flank
    lam1, _ = t.rotation_radii("drive", 300.0)
    rb1 = (
        0.5
        * 29
        * 6e-3
        / math.cos(math.radians(20))
        * math.cos(math.atan(math.tan(math.radians(20)) / math.cos(math.radians(20))))
    )
    bb = math.asin(math.sin(math.radians(20)) * math.cos(math.radians(20)))
    assert lam1 == pytest.approx(rb1 * math.cos(bb), rel=1e-9)


def test_ltca_text_output_names_the_loss_factor(tmp_path, capsys):
    rc = main(["ltca", str(SCENE), "--out", str(tmp_path), "--positions", "4", "--no-figures"])
    assert rc == 0
    lines = [ln for ln in capsys.readouterr().out.splitlines() if " N m " in ln]
    assert lines and all(" H 0." in ln for ln in lines)


def test_ltca_bad_input_exits_2(tmp_path, capsys):
    rc = main(["ltca", str(SCENE), "--out", str(tmp_path), "--positions", "3"])
    assert rc == 2
    assert "positions" in capsys.readouterr().err


def test_ltca_on_a_paper_case(tmp_path, capsys):
    # the manufactured case 03, shortened to 4 positions: both flanks, figures, and
    # the table's rotation radii keep the tooth ratio (lambda_2 / lambda_1 = N_2 / N_1
    # for the mesh point on the pitch cones, within 1 %)
    scene = Path(__file__).parent.parent / "models" / "case03.toml"
    out = tmp_path / "c03"
    assert main(["ltca", str(scene), "--out", str(out), "--json", "--positions", "4"]) == 0
    summary = json.loads(capsys.readouterr().out)
    assert set(summary["flanks"]) == {"drive", "coast"}
    assert (out / "contact_pattern.png").stat().st_size > 0
    t = MeshTable.from_netcdf(out / "mesh_table.nc")
    lam1, lam2 = t.rotation_radii("drive", 300.0)
    assert lam2 / lam1 == pytest.approx(45 / 29, rel=0.01)
    c1, c2 = t.rotation_radii("coast", 300.0)
    assert c1 < 0 and c2 < 0


def test_summary_keys_tell_close_torque_levels_apart():
    """Torque levels that '%g' rounds alike kept one summary entry only."""
    from gearbox.ltca.table import torque_keys

    assert torque_keys([150.0, 300.0, 450.0]) == ["150", "300", "450"]
    assert torque_keys([300.0, 300.0004, 300.0008]) == ["300", "300.0004", "300.0008"]
    assert torque_keys([100000.1, 100000.4]) == ["100000.1", "100000.4"]


def test_ltca_writes_the_map_of_a_topography_given_as_csv(tmp_path, capsys):
    """A pinion topography from a CSV file beside the scene: the summary names it, the
    map is drawn, and a file whose rows do not match exits 2 naming the key."""
    x = [-15.0, -5.0, 5.0, 15.0]
    y = [-20.0, -5.0, 5.0, 20.0]
    (tmp_path / "topo.csv").write_text(
        "# removal (um)\n"
        + "".join(",".join(f"{0.1 * u + 0.01 * v * v:.4f}" for v in y) + "\n" for u in x)
    )
    keys = (
        f"pinion_topography_profile_mm = {x}\npinion_topography_face_mm = {y}\n"
        'pinion_topography_um = "topo.csv"\n'
    )
    text = SCENE.read_text()
    assert "\n[ltca]\n" in text
    (tmp_path / "s.toml").write_text(text.replace("\n[ltca]\n", "\n[ltca]\n" + keys))
    out = tmp_path / "out"
    rc = main(["ltca", str(tmp_path / "s.toml"), "--out", str(out), "--json", "--positions", "4"])
    assert rc == 0
    summary = json.loads(capsys.readouterr().out)
    assert "pinion: topography 4 x 4 (cubic" in summary["attrs"]["flank_modifications"]
    assert (out / "flank_modifications.png").stat().st_size > 0
    (tmp_path / "topo.csv").write_text("1,2,3,4\n1,2,3\n1,2,3,4\n1,2,3,4\n")
    rc = main(["ltca", str(tmp_path / "s.toml"), "--out", str(tmp_path / "o2"), "--positions", "4"])
    assert rc == 2
    err = capsys.readouterr().err
    assert "pinion_topography_um" in err and "Traceback" not in err

"""The ``pitch`` stage of ``gearbox run``: scene keys, what it recomputes, the spectrum's
lines by member, the exact method through the pipeline, and input errors."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.errors import InputError
from gearbox.pipeline import run_pipeline
from gearbox.pipeline.outputs import write_outputs

ROOT = Path(__file__).resolve().parents[1]
MARINE = ROOT / "models" / "marine_drive.toml"
PARALLEL = Path(__file__).parent / "data" / "ltca_parallel_helical.toml"


@pytest.fixture(scope="module")
def marine():
    """The default scene, 12 positions per mesh cycle (a shorter loaded TCA)."""
    return load_scene(MARINE).replaced(ltca={"positions": 12})


def _statuses(run):
    return {r.name: r.status for r in run.summary.records}


def test_pitch_stage_recomputes_only_itself(marine, tmp_path):
    """Changing the deviations redoes the pitch stage, not the loaded TCA; its file
    holds the record, the deviations and the named lines."""
    scene = marine.replaced(pitch={"random_single_um": 4.0})
    first = run_pipeline(scene, ["pitch"], cache=tmp_path)
    assert first.summary.ok, first.summary.table()
    again = run_pipeline(scene.replaced(pitch={"random_single_um": 2.0}), ["pitch"], cache=tmp_path)
    got = _statuses(again)
    assert got["ltca"] == "cached" and got["pitch"] == "computed"
    write_outputs(again, tmp_path / "out")
    d = json.loads((tmp_path / "out" / "pitch.json").read_text())
    assert d["hunting_cycles"] == 29 * 45 and d["method"] == "linear"
    assert len(d["pinion_cumulative_m"]) == 29 and len(d["gear_cumulative_m"]) == 45
    single = np.diff(np.r_[d["pinion_cumulative_m"], d["pinion_cumulative_m"][0]])
    assert np.abs(single).max() <= 2 * 2e-6  # within +-2 um less their mean
    assert d["lines"][0]["amplitude_m"] == max(d["spectrum"]["amplitude_m"][1:])
    # halving the deviations halves what they add (the linear method is linear in them)
    pp = [first["pitch"].record, again["pitch"].record]
    ratio = np.ptp(pp[1].lte - pp[1].lte_nominal) / np.ptp(pp[0].lte - pp[0].lte_nominal)
    assert ratio == pytest.approx(0.5, rel=1e-9)


@pytest.mark.parametrize("member", ["pinion", "gear"])
def test_one_members_deviations_make_only_its_orders(marine, tmp_path, member):
    """Deviations on the pinion alone repeat every pinion revolution: only integer
    pinion orders carry them. On the gear alone: only gear orders (multiples of
    z1 / z2 = 29 / 45). Elsewhere below 1e-9 of the largest line."""
    other = "gear" if member == "pinion" else "pinion"
    z = {"pinion": 29, "gear": 45}
    rng = np.random.default_rng(5)
    f = rng.uniform(-3, 3, z[member])
    dev = {
        f"{member}_cumulative_um": list(np.cumsum(f - f.mean())),
        f"{other}_cumulative_um": [0.0] * z[other],
    }
    run = run_pipeline(marine.replaced(pitch=dev), ["pitch"], cache=tmp_path)
    orders, amp = run["pitch"].record.order_spectrum()
    added = (
        run["pitch"].record.order_spectrum("lte")[1]
        - run["pitch"].record.order_spectrum("lte_nominal")[1]
    )
    per_rev = orders if member == "pinion" else orders * 45 / 29
    own = np.isclose(per_rev, np.round(per_rev), atol=1e-9)
    assert np.abs(added[~own]).max() < 1e-9 * amp[1:].max()
    assert amp[own & (orders > 0)].max() > 0.1e-6


def test_pitch_input_errors_name_their_keys(marine):
    bad = marine.replaced(pitch={"pinion_cumulative_um": [1.0] * 28, "torque_Nm": 1000.0})
    with pytest.raises(InputError) as err:
        run_pipeline(bad, ["pitch"], cache=False)
    text = str(err.value)
    assert "pitch.pinion_cumulative_um" in text and "28 values" in text
    assert "pitch.torque_Nm" in text
    one_flank = marine.replaced(ltca={"flanks": ["coast"]})
    with pytest.raises(InputError, match="ltca.flanks"):
        run_pipeline(one_flank, ["pitch"], cache=False)


@pytest.mark.slow
def test_exact_method_through_the_pipeline(tmp_path):
    """The exact re-solve on the parallel helical pair (6 positions, 1305 x 6 solves):
    its nominal column equals the loaded TCA's TE, and the linear method reads it
    within 3 % of the largest change for +-1 um single deviations."""
    scene = load_scene(PARALLEL).replaced(
        ltca={"positions": 6, "grid_face": 10, "flanks": ["drive"]},
        pitch={"random_single_um": 1.0, "method": "exact"},
    )
    run = run_pipeline(scene, ["pitch"], cache=False)
    ex = run["pitch"].record
    assert ex.method == "exact"
    lt = run["ltca"].flanks["drive"]
    t = int(np.flatnonzero(lt.torque == 300.0)[0])
    np.testing.assert_allclose(ex.lte_nominal[:6], lt.lte[t], rtol=1e-9)
    lin = run_pipeline(scene.replaced(pitch={"method": "linear"}), ["pitch"], cache=False)
    dl = lin["pitch"].record.lte - lin["pitch"].record.lte_nominal
    de = ex.lte - ex.lte_nominal
    assert np.abs(dl - de).max() < 0.03 * np.abs(de).max()


def test_a_record_shorter_than_the_common_period_is_warned_of():
    """The spectra section says when the record holds less than one common period of
    the excitation orders (a pitch-deviation run needs a hunting period), and not
    otherwise."""
    from gearbox.pipeline.adapters.dynamics import Spectra
    from gearbox.report.dynamics import render_spectra
    from gearbox.spectrum import excitation_orders, order_spectrum

    exc = excitation_orders(pinion_teeth=29, gear_teeth=45, pitch_orders=1)
    runs = {}
    for revs, period in ((10, None), (45, 45.0)):
        t = np.arange(revs * 29 * 16 + 1) / (10.0 * 29 * 16)  # 600 rpm: 10 rev/s
        x = np.sin(2 * np.pi * 29 * 10 * t)
        sp = order_spectrum(t, x, speed_rpm=600.0, period_revs=period, name="mesh_force_N")
        runs[revs] = render_spectra(Spectra(600.0, {"mesh_force_N": sp}, exc), None)
    assert any("less than one common period" in w.text for w in runs[10].warnings)
    assert "45 pinion revolutions (1305 mesh cycles)" in runs[10].warnings[0].text
    assert not runs[45].warnings


def test_the_drive_reads_the_pitch_section_only_when_it_carries_the_deviations(marine):
    """The drivetrain stages' keys take ``[pitch]`` only with
    ``drivetrain.pitch_deviations``: other deviations leave the dynamics, spectra,
    waterfall and Campbell keys alone when it is off (only ``pitch`` changes) and
    change them when it is on."""
    from gearbox.pipeline import preview

    want = ["pitch", "dynamics", "spectra", "waterfall", "campbell"]
    for on in (False, True):
        scene = marine.replaced(drivetrain={"pitch_deviations": on})
        other = scene.replaced(pitch={"random_single_um": 2.0})
        a = {n: k for n, k, _ in preview(scene, want, cache=False)}
        b = {n: k for n, k, _ in preview(other, want, cache=False)}
        changed = {n for n in a if a[n] != b[n]}
        assert changed == (
            {"pitch", "dynamics", "spectra", "waterfall", "campbell"} if on else {"pitch"}
        )


def test_form_deviations_through_the_stage(marine, tmp_path):
    """Profile and helix slopes and crownings from the scene: pitch.json and the report
    carry them, the evaluation lengths default to what the loaded contact covers (the
    pinion's face 40 mm), doubling the deviations doubles what they add (linear
    method), and a wrong list or length is named before anything runs."""
    from gearbox.report.pitch import render_pitch

    slopes = {
        "random_single_um": 0.0,
        "random_profile_slope_um": 2.0,
        "gear_helix_slope_um": [1.0, -1.0] * 22 + [0.0],
        "pinion_helix_crowning_um": [1.5, 0.0, -1.5] * 9 + [0.0, 0.0],
    }
    run = run_pipeline(marine.replaced(pitch=slopes), ["pitch"], cache=tmp_path)
    write_outputs(run, tmp_path / "out")
    d = json.loads((tmp_path / "out" / "pitch.json").read_text())
    assert d["gear_helix_slope_m"][:2] == pytest.approx([1e-6, -1e-6])
    assert np.abs(d["pinion_profile_slope_m"]).max() <= 2e-6
    assert d["helix_evaluation_length_m"][0] == pytest.approx(0.040, rel=1e-9)
    assert d["pinion_helix_crowning_m"][:3] == pytest.approx([1.5e-6, 0.0, -1.5e-6])
    assert len(d["helix_evaluation_centre_m"]) == 2
    rec = run["pitch"].record
    assert np.ptp(rec.lte - rec.lte_nominal) > 0.1e-6
    html = render_pitch(run["pitch"], run).body
    assert "helix slope f_H_beta" in html and "L_alpha" in html and "C_beta" in html
    doubled = dict(
        slopes,
        random_profile_slope_um=4.0,
        gear_helix_slope_um=[2.0, -2.0] * 22 + [0.0],
        pinion_helix_crowning_um=[3.0, 0.0, -3.0] * 9 + [0.0, 0.0],
    )
    rec2 = run_pipeline(marine.replaced(pitch=doubled), ["pitch"], cache=tmp_path)["pitch"].record
    np.testing.assert_allclose(
        rec2.lte - rec2.lte_nominal, 2 * (rec.lte - rec.lte_nominal), atol=1e-15
    )
    bad = marine.replaced(
        pitch={
            "pinion_helix_slope_um": [1.0] * 30,
            "helix_evaluation_mm": [40.0, 40.0, 1.0],
            "gear_profile_crowning_um": [1.0] * 3,
        }
    )
    with pytest.raises(InputError) as err:
        run_pipeline(bad, ["pitch"], cache=False)
    text = str(err.value)
    assert "pitch.pinion_helix_slope_um" in text and "pitch.helix_evaluation_mm" in text
    assert "pitch.gear_profile_crowning_um" in text


def test_traces_through_the_stage(marine, tmp_path, monkeypatch):
    """Measured traces from the scene: pitch.json and the report carry them, the record
    moves with them (linear; the stage makes the grids it needs), and every wrong key
    is named before anything runs (the dynamics take them: tests/test_drivetrain_traces.py)."""
    from gearbox.report.pitch import render_pitch

    x = [-15.0, -5.0, 5.0, 15.0]
    rows = [[0.0, 0.5, -0.5, 0.0] if i % 2 else [0.3, 0.0, 0.0, -0.3] for i in range(29)]
    traces = {"random_single_um": 0.0, "pinion_helix_trace_mm": x, "pinion_helix_trace_um": rows}
    run = run_pipeline(marine.replaced(pitch=traces), ["pitch"], cache=tmp_path)
    write_outputs(run, tmp_path / "out")
    d = json.loads((tmp_path / "out" / "pitch.json").read_text())
    assert d["pinion_helix_trace"]["position_m"] == pytest.approx([-0.015, -0.005, 0.005, 0.015])
    assert d["pinion_helix_trace"]["deviation_m"][1] == pytest.approx([0.0, 5e-7, -5e-7, 0.0])
    rec = run["pitch"].record
    assert np.ptp(rec.lte - rec.lte_nominal) > 0.05e-6
    from gearbox.report import html

    monkeypatch.setattr(html, "CHECK_LAYOUT", True)  # no text off the canvas or overlapping
    body = render_pitch(run["pitch"], run).body
    assert "measured helix traces" in body and "Measured traces of every tooth" in body
    bad = marine.replaced(
        pitch={
            "pinion_helix_trace_mm": [0.0, -1.0],
            "pinion_helix_trace_um": [[0.0, 1.0]] * 28,
            "gear_profile_trace_um": [[1.0]] * 45,
            "gear_helix_trace_mm": [0.0, 1.0, 2.0],
            "gear_helix_trace_um": [[1.0, 2.0]] * 45,
        }
    )
    with pytest.raises(InputError) as err:
        run_pipeline(bad, ["pitch"], cache=False)
    keys = {p.path for p in err.value.problems}
    assert {
        "pitch.pinion_helix_trace_mm",
        "pitch.pinion_helix_trace_um",
        "pitch.gear_profile_trace_mm",
        "pitch.gear_helix_trace_um[0]",
    } <= keys
    assert "(45 rows are wrong)" in str(err.value)  # one problem for them all


def test_the_coast_flank_of_a_parallel_pair_is_the_drive_turned(tmp_path):
    """``pitch.flank = "coast"`` on the symmetric parallel helical pair: its coast flank
    is the drive flank turned half a turn about the centre line, which reverses both
    gears' rotation and numbers the teeth the other way, and turns the faces end for
    end. So the coast record with pitch deviations, slopes and crownings on the pinion's
    teeth t equals, sample i for sample -i, the drive record with those of tooth -t and
    the helix slopes reversed, linear and exact alike (6 positions; the pattern repeats
    every pinion revolution: 29 solves per position): to 1e-15 m (measured 2e-21 m,
    linear) against changes of about 4 um peak-to-peak. In the same time order, or with
    the helix slopes as they are, it is not. (The pair labels of the coast must count
    the cycles as the drive's do: one less where -j wraps into the cycle before;
    without that the records differed by 2.4 um.)"""
    rng = np.random.default_rng(3)
    dev = {
        "random_single_um": 0.0,
        "pinion_cumulative_um": rng.uniform(-3, 3, 29),
        "pinion_profile_slope_um": rng.uniform(-2, 2, 29),
        "pinion_helix_crowning_um": rng.uniform(-2, 2, 29),
        "pinion_helix_slope_um": rng.uniform(-3, 3, 29),
    }
    back = (-np.arange(29)) % 29  # tooth t of the coast is tooth -t of the drive
    scene = load_scene(PARALLEL).replaced(ltca={"positions": 6, "grid_face": 10})
    for method in ("linear", "exact"):
        rec = {}
        for name, flank, teeth, sign in (
            ("coast", "coast", slice(None), 1.0),
            ("turned", "drive", back, -1.0),
            ("same", "drive", back, 1.0),
        ):
            pitch = {k: v[teeth].tolist() for k, v in dev.items() if k != "random_single_um"}
            pitch["pinion_helix_slope_um"] = (sign * dev["pinion_helix_slope_um"][teeth]).tolist()
            s = scene.replaced(
                pitch={**pitch, "random_single_um": 0.0, "flank": flank, "method": method}
            )
            run = run_pipeline(s, ["pitch"], cache=tmp_path)
            assert run["pitch"].flank == flank
            rec[name] = run["pitch"].record.lte
        coast, turned, same = rec["coast"], rec["turned"], rec["same"]
        i = (-np.arange(coast.size)) % coast.size
        change = coast - run["pitch"].record.lte_nominal
        assert np.ptp(change) > 0.5e-6
        assert np.abs(coast - turned[i]).max() < 1e-15
        assert np.abs(coast - turned).max() > 0.01 * np.ptp(change)
        assert np.abs(coast - same[i]).max() > 0.01 * np.ptp(change)


def test_the_coast_flank_takes_uneven_modifications_turned_end_for_end(tmp_path):
    """As above, with flank modifications that are not even in the face position (a
    pinion flank twist and helix slope, a gear topography rising across the face): the
    coast record equals, sample i for -i, the drive record of the teeth numbered the
    other way with the modifications turned end for end (twist, slope and topography
    reflected), linear and exact alike, to 1e-15 m; with the modifications as they
    are it does not."""
    rng = np.random.default_rng(4)
    cumulative = rng.uniform(-3, 3, 29)
    back = (-np.arange(29)) % 29
    y = [-20.0, -5.0, 5.0, 20.0]
    rows = [[0.0, 1.0, 3.0, 7.0], [0.5, 1.0, 2.0, 6.0], [1.0, 1.0, 1.0, 4.0], [0.0, 0.0, 0.5, 2.0]]

    def mods(turn: float) -> dict:
        face = [turn * v for v in y][:: int(turn)]
        table = [row[:: int(turn)] for row in rows]
        return {
            "pinion_flank_twist_um": turn * 6.0,
            "pinion_helix_slope_um": turn * 4.0,
            "gear_topography_profile_mm": [-15.0, -5.0, 5.0, 15.0],
            "gear_topography_face_mm": face,
            "gear_topography_um": table,
        }

    base = load_scene(PARALLEL).replaced(ltca={"positions": 6, "grid_face": 10})
    for method in ("linear", "exact"):
        rec = {}
        for name, flank, teeth, turn in (
            ("coast", "coast", slice(None), 1.0),
            ("turned", "drive", back, -1.0),
            ("same", "drive", back, 1.0),
        ):
            s = base.replaced(
                ltca=mods(turn),
                pitch={
                    "pinion_cumulative_um": cumulative[teeth].tolist(),
                    "random_single_um": 0.0,
                    "flank": flank,
                    "method": method,
                },
            )
            rec[name] = run_pipeline(s, ["pitch"], cache=tmp_path)["pitch"].record.lte
        coast, turned, same = rec["coast"], rec["turned"], rec["same"]
        i = (-np.arange(coast.size)) % coast.size
        assert np.ptp(coast) > 1e-6
        assert np.abs(coast - turned[i]).max() < 1e-15, method
        assert np.abs(coast - same[i]).max() > 0.01 * np.ptp(coast), method


def test_the_coast_flank_of_the_default_pair(marine, tmp_path):
    """The default pair's coast flank (its own grids, side L): the record's nominal TE
    is the coast loaded TCA's at the torque, the deviations move it, pitch.json and the
    report name the flank; a scene without the coast flank, or asking the dynamics to
    carry the coast flank's deviations, is refused by name."""
    from gearbox.report.pitch import render_pitch

    scene = marine.replaced(pitch={"flank": "coast", "random_profile_slope_um": 2.0})
    run = run_pipeline(scene, ["pitch"], cache=tmp_path)
    rec = run["pitch"].record
    lt = run["ltca"].flanks["coast"]
    # the linear method interpolates the loaded TCA's levels (600 and 900 N m here)
    u = (802.0 - 600.0) / 300.0
    i = int(np.flatnonzero(lt.torque == 600.0)[0])
    nominal = (1 - u) * lt.lte[i] + u * lt.lte[i + 1]
    np.testing.assert_allclose(rec.lte_nominal[:12], nominal, rtol=1e-12)
    assert np.ptp(rec.lte - rec.lte_nominal) > 1e-6
    write_outputs(run, tmp_path / "out")
    assert json.loads((tmp_path / "out" / "pitch.json").read_text())["flank"] == "coast"
    assert "<td>coast</td>" in render_pitch(run["pitch"], run).body
    with pytest.raises(InputError, match="ltca.flanks"):
        run_pipeline(scene.replaced(ltca={"flanks": ["drive"]}), ["pitch"], cache=False)
    with pytest.raises(InputError, match="drivetrain.pitch_deviations"):
        scene.replaced(drivetrain={"pitch_deviations": True})


def test_trace_rows_from_a_csv_file(marine, tmp_path):
    """A ``rows`` value may name a CSV file beside the scene: its numbers take the
    name's place (the scene, its cache keys and its provenance hold them); a missing or
    malformed file is named with its key."""
    from gearbox.report.build import scene_toml
    from gearbox.scene import scene_from_dict

    rows = np.round(np.random.default_rng(1).uniform(-1, 1, (45, 5)), 3)
    text = "# gear profile traces (um), one tooth per line\n"
    text += "\n".join(",".join(f"{v:g}" for v in r) for r in rows) + "\n"
    (tmp_path / "traces.csv").write_text(text)
    raw = marine.to_dict()
    raw["pitch"] = {
        "gear_profile_trace_mm": [-10.0, -5.0, 0.0, 5.0, 10.0],
        "gear_profile_trace_um": "traces.csv",
    }
    scene = scene_from_dict(raw, path=tmp_path / "scene.toml")
    np.testing.assert_array_equal(scene["pitch"]["gear_profile_trace_um"], rows)
    assert "gear_profile_trace_um = [[" in scene_toml(scene)
    raw["pitch"]["gear_profile_trace_um"] = "missing.csv"
    with pytest.raises(InputError, match=r"pitch.gear_profile_trace_um.*cannot read"):
        scene_from_dict(raw, path=tmp_path / "scene.toml")
    (tmp_path / "bad.csv").write_text("1, 2, x\n")
    raw["pitch"]["gear_profile_trace_um"] = "bad.csv"
    with pytest.raises(InputError, match=r"pitch.gear_profile_trace_um.*comma-separated numbers"):
        scene_from_dict(raw, path=tmp_path / "scene.toml")

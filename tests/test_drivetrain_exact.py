"""The exact method's approach in the dynamics (``pitch.method = "exact"`` with
``drivetrain.pitch_deviations``, docs/drivetrain.md §3c): the approach stage's exact
hunting records at the loaded TCA's torque levels (gearbox.ltca.pitch.level_records),
interpolated in torque.

References: the exact hunting record itself (the contact problem re-solved at every
sample, at a level and between levels), against which the linear method's approach
(the mesh table's weights) is measured too."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.drivetrain.model import DrivetrainModel, PitchApproach
from gearbox.errors import InputError
from gearbox.pipeline import run_pipeline

MODELS = Path(__file__).resolve().parents[1] / "models"
QUIET = {"firing_torque_ripple": 0.0, "half_order_ripple": 0.0, "blade_pass_ripple": 0.0}
Z1 = 29


def _deviations() -> dict:
    """Crownings of +-4 um and helix slopes on the pinion alone: the pattern repeats
    every pinion revolution, so the exact method solves 29 distinct samples per
    position (and the crownings are where the linear method is weakest)."""
    rng = np.random.default_rng(2)
    return {
        "random_single_um": 0.0,
        "pinion_profile_crowning_um": rng.uniform(-4, 4, Z1).tolist(),
        "pinion_helix_crowning_um": rng.uniform(-4, 4, Z1).tolist(),
        "pinion_helix_slope_um": rng.uniform(-4, 4, Z1).tolist(),
    }


def scene(method: str = "exact", **pitch):
    s = load_scene(MODELS / "marine_drive.toml").replaced(ltca={"positions": 12})
    s = s.replaced(pitch={**_deviations(), "method": method, **pitch})
    return s.replaced(drivetrain={"pitch_deviations": True, **QUIET})


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="module")
def exact(cache):
    """Tables, the exact pitch stage (its record at 802 N m) and the approach stage (the
    records at the levels, the pitch stage's among them)."""
    run = run_pipeline(scene(), ["tables", "pitch", "approach"], cache=cache)
    return run["tables"], run["pitch"], run["approach"]


def _error(approach, table, rec) -> float:
    """Largest gap between an approach and minus the record's TE change, over the
    change's range."""
    change = rec.lte - rec.lte_nominal
    a, _ = approach(rec.angle + float(table.angle[0]))
    return float(np.abs(a + change).max() / np.ptp(change))


def test_at_a_level_the_approach_is_the_exact_record(exact, cache):
    """At a torque level of the loaded TCA (600 N m) the approach is minus the exact
    record's TE change, to the last bit: the same solves."""
    table, pr, ap = exact
    assert ap.levels is not None and ap.turns is None
    assert ap.levels.change.shape == (5, 29 * 45, 12)
    at600 = run_pipeline(scene(torque_Nm=600.0), ["pitch"], cache=cache)["pitch"]
    m = DrivetrainModel.from_scene(scene(), table, level_records=ap.levels)
    a = PitchApproach.from_levels(table, ap.levels, 600.0)
    rec = at600.record
    np.testing.assert_array_equal(a.values, -(rec.lte - rec.lte_nominal))
    assert m.pitch.carries == ("slopes and crownings", "exact re-solves")


def test_at_the_operating_torque_the_approach_is_its_record(exact):
    """The pitch stage's own record (802 N m) joins the levels: the model at the
    operating torque (802.14 N m, the engine's power over its speed) reads it, within
    1e-3 of the change's range (measured 2.7e-5: the 0.14 N m towards 900 N m)."""
    table, pr, ap = exact
    assert ap.levels.torque.tolist() == [50.0, 300.0, 600.0, 802.0, 900.0]
    m = DrivetrainModel.from_scene(scene(), table, level_records=ap.levels)
    assert m.torque == pytest.approx(802.14, abs=0.01)
    rec = pr.record
    assert rec.method == "exact" and np.ptp(rec.lte - rec.lte_nominal) > 1e-6
    assert _error(m.pitch, table, rec) < 1e-3


def test_between_levels_the_exact_approach_beats_the_linear(exact, cache):
    """At 700 N m, between the levels 600 and 802, against the exact record solved at
    700 N m: the exact records interpolated in torque within 3 % of the change's range
    (measured 0.53 %), the linear method's approach (the table's weights, interpolated
    between 600 and 900 N m) at least three times further off (measured 5.0 %)."""
    table, pr, ap = exact
    at700 = run_pipeline(scene(torque_Nm=700.0), ["pitch"], cache=cache)["pitch"].record
    dev = pr.deviations
    err_exact = _error(PitchApproach.from_levels(table, ap.levels, 700.0), table, at700)
    linear = PitchApproach.from_table(table, dev.pinion, dev.gear, 700.0, dev.form)
    err_linear = _error(linear, table, at700)
    assert err_exact < 0.03, err_exact
    assert err_linear > 3 * err_exact, (err_linear, err_exact)


def test_the_exact_approach_needs_its_records(exact):
    """Without the records, or with records of other deviations, the model is refused
    by name (pitch.method)."""
    table, pr, ap = exact
    with pytest.raises(InputError, match="pitch.method.*none given"):
        DrivetrainModel.from_scene(scene(), table)
    other = scene(pinion_helix_slope_um=[1.0] * Z1)
    with pytest.raises(InputError, match="other deviations"):
        DrivetrainModel.from_scene(other, table, level_records=ap.levels)


def test_the_drivetrain_stages_run_on_the_exact_records(exact, cache, tmp_path, monkeypatch):
    """``gearbox run``: with the exact method the drivetrain stages run on the
    ``approach`` stage (and it on the pitch stage) and the model carries its records;
    ``approach.json`` and the report's section list the levels."""
    import json

    from gearbox.pipeline.outputs import write_outputs
    from gearbox.report import html
    from gearbox.report.pitch import render_approach

    s = scene().replaced(simulation={"settle_time_s": 0.02, "settled_mesh_cycles": 30})
    run = run_pipeline(s, ["dynamics", "approach"], cache=cache)
    assert run.summary.ok, run.summary.table()
    status = {r.name: r.status for r in run.summary.records}
    assert status["approach"] == "cached" and status["pitch"] == "cached"  # the fixture's
    assert "exact re-solves" in run["dynamics"].model.pitch.carries
    write_outputs(run, tmp_path)
    d = json.loads((tmp_path / "approach.json").read_text())
    assert d["method"] == "exact" and d["torque_levels_Nm"] == [50.0, 300.0, 600.0, 802.0, 900.0]
    assert len(d["te_change_peak_to_peak_m"]) == 5 and min(d["te_change_peak_to_peak_m"]) > 0
    monkeypatch.setattr(html, "CHECK_LAYOUT", True)
    body = render_approach(run["approach"], run).body
    assert "802 N m" in body and "exact" in body

"""Measured flank traces in the dynamics (docs/drivetrain.md §3c, docs/ltca.md
"Measured traces"): the approach stage's trace turns put every tooth's traces into the
drive flank's approach.

References: the loaded TCA's hunting record (the contact problem's own first-order
change, solved at the torque), the form deviations' path through the mesh table's
weights (slopes and crownings sampled as traces), and the nonlinear run against the
quasi-static record and the harmonic balance."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest
from _drive import angle_spectrum

from gearbox import load_scene
from gearbox.drivetrain.linear import pitch_harmonic_balance
from gearbox.drivetrain.model import DrivetrainModel, PitchApproach
from gearbox.errors import InputError
from gearbox.ltca.pitch import form_from_section
from gearbox.meshtable import CONTACT_CENTRES, CONTACT_LENGTHS
from gearbox.pipeline import run_pipeline

MODELS = Path(__file__).resolve().parents[1] / "models"
QUIET = {"firing_torque_ripple": 0.0, "half_order_ripple": 0.0, "blade_pass_ripple": 0.0}
Z1, Z2 = 29, 45
GEAR_X_MM = np.linspace(-4.0, 8.0, 25)  # beyond the gear's covered roll lengths
PINION_X_MM = np.linspace(-22.0, 22.0, 45)  # beyond the face


def _traces() -> dict:
    """A gear profile waviness of 3 waves per gear revolution running on from tooth to
    tooth (0.6 um, a ghost at gear order 3 = pinion order 1.93) with a random ripple
    on every tooth, and random pinion helix slopes with a waviness."""
    rng = np.random.default_rng(11)
    rb2 = 0.1395  # about the gear's base radius: the waves' phase along the profile
    j = np.arange(Z2)[:, None]
    gear = 0.6 * np.sin(3 * (GEAR_X_MM[None, :] * 1e-3 / rb2 - 2 * math.pi * j / Z2))
    gear = gear + rng.uniform(-0.2, 0.2, gear.shape)
    slope = rng.uniform(-1.0, 1.0, (Z1, 1)) * PINION_X_MM[None, :] / 20.0
    pinion = slope + 0.3 * np.sin(PINION_X_MM[None, :] / 4.0 + np.arange(Z1)[:, None])
    return {
        "gear_profile_trace_mm": GEAR_X_MM.tolist(),
        "gear_profile_trace_um": gear.tolist(),
        "pinion_helix_trace_mm": PINION_X_MM.tolist(),
        "pinion_helix_trace_um": pinion.tolist(),
    }


def scene(pitch=None, **drivetrain):
    s = load_scene(MODELS / "marine_drive.toml").replaced(ltca={"positions": 12})
    s = s.replaced(pitch={**_traces(), **(pitch or {})})
    return s.replaced(drivetrain={"pitch_deviations": True, **drivetrain})


@pytest.fixture(scope="module")
def cache(tmp_path_factory):
    return tmp_path_factory.mktemp("cache")


@pytest.fixture(scope="module")
def traced(cache):
    """The default scene (12 positions) with the traces and random single pitch
    deviations (+-4 um), the record at 802 N m: tables and pitch stage."""
    run = run_pipeline(scene(), ["tables", "pitch", "approach"], cache=cache)
    return run["tables"], run["pitch"], run["approach"].turns


def _change(pr):
    rec = pr.record
    return rec.angle, rec.lte - rec.lte_nominal


def test_approach_is_the_records_change_at_a_level(traced, cache):
    """At a torque level of the loaded TCA (600 N m) the approach is minus the hunting
    record's TE change (the traces' first-order change from the tangent at the
    torque, the pitch deviations' from the table's pair weights): to 1e-11 of its
    range (measured 1.8e-13). Between levels the approach interpolates the turns
    linearly in torque as it does the pair weights, while the record takes the
    tangent at the torque itself: at 802 N m (levels 600 and 900) within 2 % of the
    range (measured 1.09 %; 0.24 % with the edge points on the last profile samples,
    whose edge loads change less between the levels)."""
    table, pr, turns = traced
    assert turns is not None
    assert turns.pinion.shape == (4, 12, 3, Z1) and turns.gear.shape == (4, 12, 3, Z2)
    at600 = run_pipeline(scene({"torque_Nm": 600.0}), ["pitch"], cache=cache)["pitch"]
    for p, tol in ((at600, 1e-11), (pr, 2e-2)):
        dev = p.deviations
        tq = p.record.torque
        approach = PitchApproach.from_table(table, dev.pinion, dev.gear, tq, dev.form, turns)
        angle, change = _change(p)
        assert np.ptp(change) > 10e-6
        a, _ = approach(angle + float(table.angle[0]))
        assert np.abs(a + change).max() < tol * np.ptp(change), tq


def test_the_model_takes_the_turns_and_names_what_is_missing(traced):
    """The scene's model carries the approach through the turns; without them, or with
    turns of other traces, it is refused by name; turns of another table too."""
    table, pr, turns = traced
    m = DrivetrainModel.from_scene(scene(**QUIET), table, trace_turns=turns)
    dev = pr.deviations
    direct = PitchApproach.from_table(table, dev.pinion, dev.gear, m.torque, None, turns)
    np.testing.assert_array_equal(m.pitch.values, direct.values)
    without = PitchApproach.from_table(table, dev.pinion, dev.gear, m.torque)
    assert np.ptp(direct.values - without.values) > 1e-6  # the traces' part
    with pytest.raises(InputError, match="drivetrain.pitch_deviations.*none given"):
        DrivetrainModel.from_scene(scene(), table)
    other = scene(
        {"gear_profile_trace_um": (np.array(_traces()["gear_profile_trace_um"]) * 2).tolist()}
    )
    with pytest.raises(InputError, match="other traces"):
        DrivetrainModel.from_scene(other, table, trace_turns=turns)
    shifted = dataclasses.replace(turns, torque=turns.torque + 1.0)
    with pytest.raises(InputError, match="trace turns"):
        PitchApproach.from_table(table, dev.pinion, dev.gear, m.torque, None, shifted)
    cut = dataclasses.replace(turns, fraction=turns.fraction[:6])
    with pytest.raises(InputError, match="12 positions"):
        PitchApproach.from_table(table, dev.pinion, dev.gear, m.torque, None, cut)


def test_slopes_and_crownings_as_traces_give_the_form_approach(traced, cache):
    """Random profile and helix slopes and crownings on every tooth of both members,
    once as form deviations (the mesh table's form weights) and once sampled as traces
    (the approach stage's turns): the same approach at 802 N m, between the torque
    levels, where both interpolate linearly in torque. Tolerance 1e-6 of the range: the
    weights come from the loaded TCA's solves, the turns from solves of their own, each
    iterating the flattening to 1e-6 of the loads (measured 6.9e-7)."""
    table, _, _ = traced
    rng = np.random.default_rng(8)
    given = {
        "random_single_um": 0.0,
        "pinion_profile_slope_um": rng.uniform(-3, 3, Z1).tolist(),
        "pinion_helix_slope_um": rng.uniform(-3, 3, Z1).tolist(),
        "gear_profile_slope_um": rng.uniform(-3, 3, Z2).tolist(),
        "gear_helix_slope_um": rng.uniform(-3, 3, Z2).tolist(),
        "pinion_profile_crowning_um": rng.uniform(-2, 2, Z1).tolist(),
        "pinion_helix_crowning_um": rng.uniform(-2, 2, Z1).tolist(),
        "gear_profile_crowning_um": rng.uniform(-2, 2, Z2).tolist(),
        "gear_helix_crowning_um": rng.uniform(-2, 2, Z2).tolist(),
    }
    clear = {k: [] for k in _traces()}
    by_form = scene({**given, **clear}, **QUIET)
    L = [table.attrs[k] for k in CONTACT_LENGTHS]
    c = [table.attrs[k] for k in CONTACT_CENTRES]
    form = form_from_section(
        by_form["pitch"], (Z1, Z2), ((L[0], L[1]), (L[2], L[3])), ((c[0], c[1]), (c[2], c[3]))
    )
    rows = {}
    for j, (member, kind) in enumerate(
        [("pinion", "profile"), ("pinion", "helix"), ("gear", "profile"), ("gear", "helix")]
    ):
        x = np.linspace(-0.03, 0.03, 2001)
        z = Z1 if member == "pinion" else Z2
        t, other = np.arange(z), np.zeros(z, dtype=int)
        k = form.coefficients(*((t, other) if member == "pinion" else (other, t)))
        rows[f"{member}_{kind}_trace_mm"] = (x * 1e3).tolist()
        rows[f"{member}_{kind}_trace_um"] = (
            (k[:, j, None] * x + k[:, 4 + j, None] * x**2) * 1e6
        ).tolist()
    by_trace = scene({"random_single_um": 0.0, **rows}, **QUIET)
    turns = run_pipeline(by_trace, ["approach"], cache=cache)["approach"].turns
    a = DrivetrainModel.from_scene(by_form, table).pitch.values
    b = DrivetrainModel.from_scene(by_trace, table, trace_turns=turns).pitch.values
    assert np.ptp(a) > 1e-6
    err = np.abs(a - b).max() / np.ptp(a)
    assert err < 3e-6, f"form against traces: {err:.2e} of the range"


def _status(run) -> dict:
    return {r.name: r.status for r in run.summary.records}


def test_the_pipeline_routes_the_turns(cache):
    """``gearbox run``: with traces and ``drivetrain.pitch_deviations`` the dynamics
    stage runs on the ``approach`` stage (the traces' turns) and its model carries
    them; a change of the traces alone redoes approach and dynamics, not the loaded
    TCA; without ``pitch_deviations`` the dynamics neither wait for it nor plan it."""
    short = {"settle_time_s": 0.02, "settled_mesh_cycles": 30}
    s = scene(**QUIET).replaced(simulation=short)
    run = run_pipeline(s, ["dynamics"], cache=cache)
    assert run.summary.ok, run.summary.table()
    status = _status(run)
    assert "approach" in status and "pitch" not in status  # the record is not needed
    turns = run["approach"].turns
    want = DrivetrainModel.from_scene(s, run["tables"], trace_turns=turns).pitch.values
    np.testing.assert_array_equal(run["dynamics"].model.pitch.values, want)
    rows = (np.array(_traces()["gear_profile_trace_um"]) * 0.5).tolist()
    moved = run_pipeline(
        s.replaced(pitch={"gear_profile_trace_um": rows}), ["dynamics"], cache=cache
    )
    got = _status(moved)
    assert got["ltca"] == "cached"
    assert got["approach"] == "computed" and got["dynamics"] == "computed"
    off = run_pipeline(
        s.replaced(drivetrain={"pitch_deviations": False}), ["dynamics"], cache=cache
    )
    assert "approach" not in _status(off) and off["dynamics"].model.pitch is None


@pytest.fixture(scope="module")
def traced_run(traced):
    """The default drive on the loaded-TCA table with the traces and pitch deviations,
    3500 rpm, engine and propeller ripple off: one hunting period (1305 mesh cycles)
    after 0.5 s."""
    pytest.importorskip("diffrax")
    from gearbox.drivetrain.simulate import default_solver, simulate

    table, pr, turns = traced
    m = DrivetrainModel.from_scene(scene(**QUIET), table, trace_turns=turns)
    ts = simulate(m, default_solver(), settle_time=0.5, mesh_cycles=1305, samples_per_cycle=24)
    assert ts.success
    return m, ts, pr


def test_quasi_static_te_follows_the_record(traced_run):
    """Against the pinion's angle, the transmission error's low lines are the loaded
    TCA's record's (the contact problem, not the drivetrain): the waviness's ghost at
    gear order 3, gear order 1 and pinion orders 1 and 2 within 1 % (measured 0.15-0.30
    %: the record takes the tangent at 802 N m, the dynamics interpolate between 600
    and 900 N m, and at pinion order 2, 117 Hz, the drive responds a little)."""
    m, ts, pr = traced_run
    dte = angle_spectrum(ts, "dynamic_transmission_error_m")
    _, want = pr.record.order_spectrum()
    for order in (3 * Z1 / Z2, Z1 / Z2, 1.0, 2.0):
        i = int(round(order * Z2))
        assert dte[i] == pytest.approx(want[i], rel=0.01), order


def test_harmonic_balance_reads_the_traced_run(traced_run):
    """The mesh force's lines from the harmonic balance against the nonlinear run's
    constant-speed spectrum over the hunting period: the ghost, its sidebands about
    the mesh order and low pinion orders within 1 % (measured 0.001-0.17 %)."""
    m, ts, _ = traced_run
    F = ts.channels["mesh_force_N"]
    amp = np.abs(np.fft.rfft(F)) / F.size * 2  # bins of 1/45 pinion order
    orders, _, f = pitch_harmonic_balance(m)
    ghost = 3 * Z1 / Z2
    for o in (ghost, 1.0, 2.0, Z1 - ghost, Z1 + ghost):
        line = abs(f[0, np.argmin(np.abs(orders - o))])
        assert line == pytest.approx(amp[int(round(o * 45))], rel=0.01), o


def test_the_report_says_what_the_approach_carries(traced):
    """The report's drivetrain parameters name what the approach holds."""
    from gearbox.report.dynamics import _parameters

    table, pr, turns = traced
    m = DrivetrainModel.from_scene(scene(**QUIET), table, trace_turns=turns)
    assert m.pitch.carries == ("pitch deviations", "measured traces")
    rows = dict(_parameters(m))
    text = rows["pitch deviations: the drive flank's approach, peak-to-peak (um)"]
    assert text.endswith("(pitch deviations, measured traces)")


def test_turns_interpolate_as_the_table_does(traced):
    """The turns at a torque are the levels' linear interpolation with the mesh table's
    own weights; outside the levels they are refused by name."""
    table, pr, turns = traced
    j0, j1, w = table._torque_weights(802.0)
    pin, gear = turns.at(802.0)
    np.testing.assert_array_equal(pin, (1 - w) * turns.pinion[j0] + w * turns.pinion[j1])
    np.testing.assert_array_equal(gear, (1 - w) * turns.gear[j0] + w * turns.gear[j1])
    np.testing.assert_array_equal(turns.at(600.0)[0], turns.pinion[2])
    with pytest.raises(InputError, match="torque_Nm"):
        turns.at(1000.0)


def test_the_campbell_diagram_flags_a_ghost_crossing(cache):
    """A grinder's waviness of 61 waves per gear revolution (0.5 um, the ghost example's)
    carried into the dynamics: the approach's largest lines beyond the named orders
    join the excitations (family pitch), and the ghost, 'mesh 1 + gear 16' at pinion
    order 39.31, crosses the mesh mode inside the speed range (about 3030 rpm, 1984
    Hz). The crossing's speed puts the ghost's frequency on the linear model's mesh
    mode there within 0.5 % (measured 0.03 %: the mode curve is sampled at 61 speeds),
    and its steady response is the harmonic balance's line at that speed (the same
    solve, to 1e-9)."""
    import runpy

    from gearbox.drivetrain.linear import modes
    from gearbox.pipeline.adapters.dynamics import model_at

    ex = runpy.run_path(str(MODELS / "example_ghost_order.py"))
    base = load_scene(MODELS / "marine_drive.toml").replaced(ltca={"positions": 12})
    design = run_pipeline(base, ["design"], cache=cache)["design"]
    x_mm = np.linspace(-20.0, 20.0, 161)
    rows, fp = ex["waviness"](design, 61, 0.5, x_mm)
    pitch = {
        "random_single_um": 0.0,
        "gear_cumulative_um": fp.tolist(),
        "gear_profile_trace_mm": x_mm.tolist(),
        "gear_profile_trace_um": rows.tolist(),
    }
    s = base.replaced(pitch=pitch, drivetrain={"pitch_deviations": True})
    run = run_pipeline(s, ["campbell"], cache=cache)
    diagram = run["campbell"]
    ghost = 61 * Z1 / Z2
    labels = {e.label: e for e in diagram.excitations if e.source == "pitch"}
    assert labels["deviations, mesh 1 + gear 16"].order == pytest.approx(ghost, abs=1e-9)
    hits = [c for c in diagram.crossings if c.excitation == "deviations, mesh 1 + gear 16"]
    assert len(hits) == 1 and hits[0].in_operating_range and hits[0].converged
    c = hits[0]
    m = model_at(s, run["tables"], c.speed_rpm, run["approach"])
    md = modes(m)
    kinds = zip(md.frequencies, md.descriptions(), strict=True)
    mesh = [f for f, d in kinds if d.startswith("mesh mode")][0]
    assert ghost * c.speed_rpm / 60.0 == pytest.approx(mesh, rel=5e-3)
    orders, _, f = pitch_harmonic_balance(m)
    line = abs(f[0, int(np.argmin(np.abs(orders - ghost)))])
    assert c.response["mesh_force_N"] == pytest.approx(line, rel=1e-9)

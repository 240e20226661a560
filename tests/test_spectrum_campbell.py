"""Campbell crossings against closed-form crossings of linear models.

For an order o (cycles per revolution) and a speed n (rpm) the excitation frequency
is o n / 60; a mode f(n) crosses it where f(n) = o n / 60. The closed forms below
are solved by hand; the root finder is asked for 1e-9 rpm, so a relative bound of
1e-10 on speeds of hundreds to thousands of rpm leaves margin for round-off.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from gearbox import load_scene
from gearbox.errors import InputError
from gearbox.spectrum import (
    CampbellDiagram,
    ExcitationOrder,
    campbell,
    excitation_orders,
    excitation_orders_from_scene,
)

MODELS = Path(__file__).resolve().parents[1] / "models"


def test_marine_excitation_orders_by_hand():
    # 29:45 pair, 8-cylinder 4-stroke, 3 blades: mesh 29, 58, 87; firing 4, 8;
    # blade pass 3 * 29 / 45; half orders 0.5 ... 3.5.
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3)
    by_source = {}
    for e in ex:
        by_source.setdefault(e.source, []).append(e.order)
    assert by_source["mesh"] == [29.0, 58.0, 87.0]
    assert by_source["engine"] == [4.0, 8.0]
    assert by_source["propeller"] == pytest.approx([87.0 / 45.0])
    assert by_source["engine-half"] == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5]
    assert [e.order for e in ex] == sorted(e.order for e in ex)
    # A 2-stroke 5-cylinder engine fires 5 times a revolution.
    two = excitation_orders(pinion_teeth=20, cylinders=5, strokes=2, half_orders=False)
    assert [e.order for e in two if e.source == "engine"] == [5.0, 10.0]
    # A 6-cylinder 4-stroke: firing order 3 coincides with no mesh order; the half
    # order 1.5 comes once.
    six = excitation_orders(pinion_teeth=31, cylinders=6, firing_harmonics=1)
    assert [e.order for e in six if e.source != "mesh"] == [0.5, 1.0, 1.5, 2.0, 2.5, 3.0]
    # further lines of the tooth deviations join the pitch family, in order; one that
    # an earlier family names already is dropped
    dev = excitation_orders(
        pinion_teeth=29, deviation_orders=(("deviations, gear 52", 52 * 29 / 45), ("x", 29.0))
    )
    assert [(e.label, e.source) for e in dev if e.source == "pitch"] == [
        ("deviations, gear 52", "pitch")
    ]
    assert [e.order for e in dev] == sorted(e.order for e in dev)


def test_excitation_orders_from_scene():
    scene = load_scene(MODELS / "case03.toml")
    ex = excitation_orders_from_scene(scene)
    dt = scene["drivetrain"]
    n1, n2 = scene["pinion"]["teeth"], scene["gear"]["teeth"]
    orders = {e.label: e.order for e in ex}
    assert orders["mesh"] == n1
    assert orders["firing " + f"{dt['engine_cylinders'] / 2:.4g}"] == dt["engine_cylinders"] / 2
    assert orders["blade pass"] == pytest.approx(dt["propeller_blades"] * n1 / n2, rel=1e-15)
    # half_order_ripple = 0 in the scene: no half orders unless asked for.
    assert dt["half_order_ripple"] == 0.0
    assert not [e for e in ex if e.source == "engine-half"]
    with_halves = excitation_orders_from_scene(scene, half_orders=True)
    # The half orders the drivetrain model drives: 0.5, 1, 1.5.
    assert [e.order for e in with_halves if e.source == "engine-half"] == [0.5, 1.0, 1.5]


def test_excitation_orders_of_a_six_cylinder_drive():
    # An in-line six 4-stroke with 3 firing harmonics and 2 % half-order
    # imbalance, one blade-pass harmonic, 3 blades, 29:45 (as
    # models/marine_drive.toml): orders by hand below.
    scene = load_scene(MODELS / "case03.toml").replaced(
        drivetrain={
            "engine_cylinders": 6,
            "engine_harmonics": 3,
            "half_order_ripple": 0.02,
            "propeller_blades": 3,
            "blade_pass_harmonics": 1,
        }
    )
    by = {}
    for e in excitation_orders_from_scene(scene):
        by.setdefault(e.source, []).append(e.order)
    assert by["engine"] == [3.0, 6.0, 9.0]
    assert by["engine-half"] == [0.5, 1.0, 1.5]
    assert by["propeller"] == pytest.approx([3 * 29 / 45])
    assert by["mesh"] == [29.0, 58.0, 87.0]


def test_constant_modes_cross_at_60f_over_order():
    modes = {"propeller shaft": 11.0, "input shaft": 47.0, "mesh": 2150.0}
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3)
    lo, hi = 300.0, 3500.0
    cd = campbell(modes, ex, (lo, hi), operating_range_rpm=(800.0, 2400.0))
    expected = sorted(
        (60.0 * f / e.order, name, e.label)
        for name, f in modes.items()
        for e in ex
        if lo <= 60.0 * f / e.order <= hi
    )
    got = sorted((c.speed_rpm, c.mode, c.excitation) for c in cd.crossings)
    assert [g[1:] for g in got] == [e[1:] for e in expected]
    for (s_got, *_), (s_exp, *_) in zip(got, expected, strict=True):
        assert s_got == pytest.approx(s_exp, rel=1e-10)
    for c in cd.crossings:
        assert c.frequency_hz == pytest.approx(modes[c.mode], rel=1e-10)
        assert c.in_operating_range == (800.0 <= c.speed_rpm <= 2400.0)
        assert c.converged
    assert cd.risks and all(c.in_operating_range for c in cd.risks)
    assert len(cd.risks) < len(cd.crossings)


def test_speed_dependent_modes():
    # Linear f = a + b n: crossing n = a / (o / 60 - b).
    # Stiffening f = f0 sqrt(1 + c n^2): f0^2 (1 + c n^2) = (o n / 60)^2, so
    # n = f0 / sqrt((o / 60)^2 - c f0^2).
    a, b = 1800.0, 0.15
    f0, c = 60.0, 1e-7
    ex = [ExcitationOrder("mesh", 29.0, "mesh"), ExcitationOrder("firing 4", 4.0, "engine")]
    cd = campbell(
        {"linear": lambda n: a + b * n, "stiffening": lambda n: f0 * np.sqrt(1 + c * n**2)},
        ex,
        (100.0, 6000.0),
    )
    found = {(x.mode, x.excitation): x for x in cd.crossings}
    n_lin = a / (29.0 / 60.0 - b)
    assert found[("linear", "mesh")].speed_rpm == pytest.approx(n_lin, rel=1e-10)
    for e in ex:
        n_st = f0 / np.sqrt((e.order / 60.0) ** 2 - c * f0**2)
        assert found[("stiffening", e.label)].speed_rpm == pytest.approx(n_st, rel=1e-10)
    # The linear mode never meets order 4: a / (4/60 - b) < 0.
    assert ("linear", "firing 4") not in found
    assert cd.operating_range_rpm is None and not cd.risks


def test_tabulated_linear_mode_is_exact():
    # A table of a linear model (as the linearised drivetrain gives per speed):
    # linear interpolation reproduces it, so the crossing is the closed form.
    speeds = np.linspace(0.0, 4000.0, 9)
    freqs = 30.0 + 0.01 * speeds
    cd = campbell(
        {"shaft": (speeds, freqs)}, [ExcitationOrder("firing 4", 4.0, "engine")], (100, 3000)
    )
    (x,) = cd.crossings
    assert x.speed_rpm == pytest.approx(30.0 / (4.0 / 60.0 - 0.01), rel=1e-10)
    with pytest.raises(InputError, match="cover the speed range"):
        campbell({"shaft": (speeds, freqs)}, [ExcitationOrder("o", 4.0, "engine")], (100, 5000))


def test_sampled_curves_and_round_trip():
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3, half_orders=False)
    cd = campbell(
        {"m1": 40.0, "m2": lambda n: 900 + 0.2 * n},
        ex,
        (500, 3000),
        operating_range_rpm=(600, 2600),
    )
    assert cd.mode_frequencies_hz.shape == (2, cd.speeds_rpm.size)
    np.testing.assert_allclose(cd.mode_frequencies_hz[1], 900 + 0.2 * cd.speeds_rpm, rtol=1e-15)
    back = CampbellDiagram.from_dict(json.loads(json.dumps(cd.to_dict())))
    assert back.crossings == cd.crossings
    assert back.excitations == cd.excitations
    np.testing.assert_array_equal(back.mode_frequencies_hz, cd.mode_frequencies_hz)


def test_responses_rank_the_risks_and_survive_the_round_trip():
    """with_responses stores a response per crossing; significant keeps the risks from
    the threshold, most severe first, and to_dict / from_dict keep both."""
    ex = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3, half_orders=False)
    cd = campbell({"m1": 40.0, "m2": 70.0}, ex, (500, 3000), operating_range_rpm=(600, 2600))
    assert cd.significant == cd.risks  # no responses yet: every risk, by speed
    assert all(c.severity is None for c in cd.crossings)

    def response(c):  # a made-up response: larger at lower speed
        return {"mesh_force_N": 1e5 / c.speed_rpm, "mesh_force_fraction": 100.0 / c.speed_rpm}

    rc = cd.with_responses(response, threshold=0.05)
    sev = {c.speed_rpm: c.severity for c in rc.risks}
    assert sev == pytest.approx({n: 100.0 / n for n in sev}, rel=1e-15)
    expect = sorted((c for c in rc.risks if 100.0 / c.speed_rpm >= 0.05), key=lambda c: c.speed_rpm)
    assert rc.significant == tuple(expect)  # the most severe (slowest) first
    assert 0 < len(rc.significant) < len(rc.risks)
    back = CampbellDiagram.from_dict(json.loads(json.dumps(rc.to_dict())))
    assert back.crossings == rc.crossings and back.response_threshold == 0.05
    assert back.significant == rc.significant
    with pytest.raises(InputError, match="threshold"):
        cd.with_responses(response, threshold=-1.0)


def test_bad_input_lists_every_problem():
    with pytest.raises(InputError) as err:
        campbell(
            {"neg": -3.0, "bad": "x"},
            [ExcitationOrder("zero", 0.0, "mesh")],
            (2000.0, 1000.0),
            operating_range_rpm=(5.0, 1.0),
        )
    paths = {p.path for p in err.value.problems}
    assert {"speed_range_rpm", "operating_range_rpm", "excitations[0]"} <= paths
    with pytest.raises(InputError) as err:
        campbell({"neg": -3.0, "bad": "x"}, [ExcitationOrder("m", 29.0, "mesh")], (100.0, 1000.0))
    assert {p.path for p in err.value.problems} == {"modes['neg']", "modes['bad']"}
    with pytest.raises(InputError) as err:
        excitation_orders(
            pinion_teeth=0, blades=3, cylinders=-1, strokes=3, deviation_orders=(("g", -1.0),)
        )
    paths = {p.path for p in err.value.problems}
    assert paths == {"pinion_teeth", "gear_teeth", "cylinders", "strokes", "deviation_orders"}


def test_cubic_table_interpolation_of_a_coarse_table():
    # The stiffening mode f = f0 sqrt(1 + c n^2) tabulated at only 11 speeds:
    # linear interpolation puts the crossings off by up to 0.39 % (measured),
    # a cubic spline by 2.5e-5 (measured); bounds 5e-3 and 5e-5 against the closed
    # form n = f0 / sqrt((o/60)^2 - c f0^2).
    f0, c = 60.0, 1e-7
    speeds = np.linspace(100.0, 6000.0, 11)
    table = (speeds, f0 * np.sqrt(1 + c * speeds**2))
    ex = [ExcitationOrder("mesh", 29.0, "mesh"), ExcitationOrder("firing 4", 4.0, "engine")]
    for interp, bound in (("linear", 5e-3), ("cubic", 5e-5)):
        cd = campbell({"m": table}, ex, (100.0, 6000.0), table_interpolation=interp)
        assert len(cd.crossings) == 2
        for x in cd.crossings:
            exact = f0 / np.sqrt((x.order / 60.0) ** 2 - c * f0**2)
            assert x.speed_rpm == pytest.approx(exact, rel=bound), interp
    with pytest.raises(InputError, match="table_interpolation"):
        campbell({"m": table}, ex, (100.0, 6000.0), table_interpolation="akima")

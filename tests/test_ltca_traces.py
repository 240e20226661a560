"""Measured flank traces per tooth in the loaded TCA's hunting record
(gearbox.ltca.pitch.FlankTraces, docs/ltca.md "Measured traces").

References: the form deviations' own path (slopes and crownings sampled as traces give
the same record), a rigid turn (a waviness that runs on around the gear offsets every
contact point alike: the TE follows it exactly), and the exact re-solve (the linear
method)."""

import dataclasses
import math

import numpy as np
import pytest
from _drive import parallel_drive

from gearbox.errors import InputError
from gearbox.ltca import ParallelPair
from gearbox.ltca.pitch import (
    FlankTraces,
    FormDeviations,
    PitchDeviations,
    Trace,
    covered_centres,
    covered_lengths,
    hunting_lte,
)
from gearbox.ltca.solver import ContactSolver

N = 12  # positions per mesh cycle


def _pair(helix_deg: float) -> ParallelPair:
    return ParallelPair(
        normal_module=0.004,
        normal_pressure_angle=math.radians(20.0),
        helix_angle=math.radians(helix_deg),
        teeth=(20, 40),
        face_width=0.016,
    )


@pytest.fixture(scope="module")
def spur():
    pair = _pair(0.0)
    return (pair, *parallel_drive(pair, N, 16))


@pytest.fixture(scope="module")
def helical():
    pair = _pair(15.0)
    return (pair, *parallel_drive(pair, N, 16))


def _span(grids, column, margin=1e-3):
    """Trace positions (m) over the grids' range of one flank coordinate, and beyond."""
    c = np.concatenate([g.flank_coordinates[:, column] for g in grids])
    return np.linspace(c.min() - margin, c.max() + margin, 4001)


def test_slopes_and_crownings_as_traces_give_the_same_record(helical):
    """Random slopes and crownings on every tooth of both members, sampled as traces
    (4001 points): the hunting record through the traces equals the one through the
    form shapes, exact method and linear method alike, at a torque level of the loaded
    TCA (400 N m: between levels the linear method interpolates the form weights, the
    traces' tangent is the torque's own), to 1e-12 m (measured 1.6e-13: the traces'
    linear interpolation of the parabolas) against changes of 3.45 um peak-to-peak."""
    pair, grids, comp, res = helical
    z1, z2 = pair.teeth
    rng = np.random.default_rng(4)
    L, m = covered_lengths(res.flank_range), covered_centres(res.flank_range)
    form = FormDeviations(
        *(rng.uniform(-3e-6, 3e-6, z) for z in (z1, z1, z2, z2)),
        *L,
        *(rng.uniform(-2e-6, 2e-6, z) for z in (z1, z1, z2, z2)),
        *m,
    )
    teeth = {"pinion": np.arange(z1), "gear": np.arange(z2)}
    traces = {}
    for j, (member, kind) in enumerate(
        [("pinion", "profile"), ("pinion", "helix"), ("gear", "profile"), ("gear", "helix")]
    ):
        x = _span(grids, j)
        t = teeth[member]
        other = np.zeros_like(t)
        c = form.coefficients(*((t, other) if member == "pinion" else (other, t)))
        traces[f"{member}_{kind}"] = Trace(x, c[:, j, None] * x + c[:, 4 + j, None] * x**2)
    r = (pair.pitch_radius(0), pair.pitch_radius(1))
    by_form = PitchDeviations(np.zeros(z1), np.zeros(z2), *r, form)
    by_trace = PitchDeviations(np.zeros(z1), np.zeros(z2), *r, traces=FlankTraces(**traces))
    # the flattening iterated to 1e-11 of the loads, not the default 1e-6: solves of
    # offsets equal to 1e-13 m then agree to that, not to the default's 1e-9 m
    tight = ContactSolver(outer_rtol=1e-11)
    kw = dict(teeth=(z1, z2), grids=grids, compliance=comp, solver=tight)
    for method in ("exact", "linear"):
        a = hunting_lte(res, by_form, 400.0, method=method, **kw)
        b = hunting_lte(res, by_trace, 400.0, method=method, **kw)
        assert np.ptp(a.lte - a.lte_nominal) > 0.5e-6
        assert np.abs(a.lte - b.lte).max() < 1e-12
        np.testing.assert_allclose(b.pair_load, a.pair_load, rtol=0, atol=1e-6 * a.pair_load.max())
        assert np.abs(a.pair_root_stress - b.pair_root_stress).max() < 1e-6 * a.root_stress()[0]
        # the nominal teeth's pair loads: the loaded TCA's (the traces' from the same
        # solves as their changes; the flattening's tolerance apart)
        top = a.pair_load_nominal.max()
        np.testing.assert_allclose(
            b.pair_load_nominal, a.pair_load_nominal, rtol=0, atol=1e-5 * top
        )


def _waviness(pair, grids, n_waves, amplitude):
    """A gear profile waviness that runs on around the gear: n_waves per revolution of
    the gear's material angle, tooth j lagging j pitches (it meets the mesh j cycles
    later), the roll length x advancing the angle by x / r_b2. Sampled as traces; and
    the pitch deviations that put back the traces' value at the reference circle (a
    trace is taken less it), so the flank is the waviness alone."""
    z2 = pair.teeth[1]
    rb2 = pair.base_radius(1)
    x = _span(grids, 2)
    j = np.arange(z2)[:, None]
    wave = amplitude * np.sin(n_waves * (x[None, :] / rb2 - 2 * math.pi * j / z2))
    at_ref = amplitude * np.sin(n_waves * (-2 * math.pi * np.arange(z2) / z2))
    fp = at_ref / math.cos(pair.transverse_pressure_angle)  # F_p on the reference arc
    return Trace(x, wave), fp


def test_a_waviness_around_the_gear_is_a_ghost_order(spur):
    """Spur pair z 20/40: a gear profile waviness of 1 um with 7 waves per gear
    revolution, continuous around the gear (with the pitch deviations of its value at
    the reference circle). Every point of every pair then meets the same phase at any
    moment, so the flanks turn rigidly: the TE change is minus the waviness at the
    contact, to 1e-12 m (measured 1.9e-14: the traces' interpolation), linear and exact
    alike; its spectrum is one line at gear order 7 (pinion order 3.5, not a mesh
    order) of 1 um within 1e-4, every other bin below 1e-6 of it."""
    pair, grids, comp, res = spur
    z1, z2 = pair.teeth
    trace, fp = _waviness(pair, grids, 7, 1e-6)
    r = (pair.pitch_radius(0), pair.pitch_radius(1))
    dev = PitchDeviations(np.zeros(z1), fp, *r, traces=FlankTraces(gear_profile=trace))
    rb2 = pair.base_radius(1)
    for method in ("linear", "exact"):
        rec = hunting_lte(
            res, dev, 300.0, teeth=(z1, z2), method=method, grids=grids, compliance=comp
        )
        d = (rec.lte - rec.lte_nominal).reshape(rec.cycles, N)
        for j, g in enumerate(grids):
            k = int(g.pair[0])
            x = g.flank_coordinates[g.pair == k, 2][0]
            tooth = np.mod(np.arange(rec.cycles) - k, z2)
            expected = -1e-6 * np.sin(7 * (x / rb2 - 2 * math.pi * tooth / z2))
            assert np.abs(d[:, j] - expected).max() < 1e-12
        ghost = replace_lte(rec, d)
        orders, amp = ghost.order_spectrum()
        i = int(np.argmax(amp))
        assert orders[i] == pytest.approx(7 * z1 / z2, abs=1e-12)
        assert amp[i] == pytest.approx(1e-6, rel=1e-4)
        rest = np.delete(amp, i)
        assert rest.max() < 1e-6 * amp[i]


def replace_lte(rec, change):
    """The record with its TE replaced by ``change`` (m)."""
    return dataclasses.replace(rec, lte=change.reshape(-1))


def test_traces_linear_against_exact(helical):
    """Random waviness (0.5 um, 3 to 9 waves over each flank's range, random phase per
    tooth) and random slopes as traces on both members' profiles and helices, 300 N m:
    the linear method within 7 % of the exact re-solve's largest TE change (measured
    4.4 % of 1.71 um) and its pair loads within 0.5 % of the largest (measured
    0.024 %)."""
    pair, grids, comp, res = helical
    z1, z2 = pair.teeth
    rng = np.random.default_rng(9)
    traces = {}
    for j, (member, kind) in enumerate(
        [("pinion", "profile"), ("pinion", "helix"), ("gear", "profile"), ("gear", "helix")]
    ):
        x = _span(grids, j)
        z = z1 if member == "pinion" else z2
        span = x[-1] - x[0]
        waves = rng.uniform(3, 9, (z, 1))
        phase = rng.uniform(0, 2 * math.pi, (z, 1))
        slope = rng.uniform(-2e-6, 2e-6, (z, 1)) * (x[None, :] - x.mean()) / span
        dev = 0.5e-6 * np.sin(2 * math.pi * waves * x[None, :] / span + phase) + slope
        traces[f"{member}_{kind}"] = Trace(x, dev)
    r = (pair.pitch_radius(0), pair.pitch_radius(1))
    dev = PitchDeviations(np.zeros(z1), np.zeros(z2), *r, traces=FlankTraces(**traces))
    kw = dict(teeth=(z1, z2), grids=grids, compliance=comp)
    lin = hunting_lte(res, dev, 300.0, **kw)
    ex = hunting_lte(res, dev, 300.0, method="exact", **kw)
    change = np.abs(ex.lte - ex.lte_nominal).max()
    assert change > 0.3e-6
    assert np.abs(lin.lte - ex.lte).max() < 0.07 * change
    assert np.abs(lin.pair_load - ex.pair_load).max() < 0.005 * ex.pair_load.max()


def test_traces_say_what_is_wrong(spur):
    pair, grids, comp, res = spur
    z1, z2 = pair.teeth
    x = np.linspace(-0.01, 0.01, 5)
    with pytest.raises(InputError, match="position"):
        Trace(x[::-1], np.zeros((z2, 5)))
    with pytest.raises(InputError, match="deviation"):
        Trace(x, np.zeros((z2, 4)))
    bad = np.zeros((z2, 5))
    bad[3, 1] = np.inf
    with pytest.raises(InputError, match=r"deviation\[16\]"):
        Trace(x, bad)
    with pytest.raises(InputError, match="traces"):
        FlankTraces()
    with pytest.raises(InputError, match="gear_helix"):
        FlankTraces(
            gear_profile=Trace(x, np.zeros((z2, 5))), gear_helix=Trace(x, np.zeros((30, 5)))
        )
    r = (pair.pitch_radius(0), pair.pitch_radius(1))
    with pytest.raises(InputError, match="traces.gear"):
        PitchDeviations(
            np.zeros(z1),
            np.zeros(z2),
            *r,
            traces=FlankTraces(gear_profile=Trace(x, np.zeros((30, 5)))),
        )
    dev = PitchDeviations(
        np.zeros(z1), np.zeros(z2), *r, traces=FlankTraces(gear_profile=Trace(x, np.zeros((z2, 5))))
    )
    with pytest.raises(InputError, match="grids"):
        hunting_lte(res, dev, 300.0, teeth=(z1, z2))
    t = Trace(x, np.arange(5.0)[None, :].repeat(z2, 0) * 1e-6)
    np.testing.assert_allclose(t.at([-0.01, 0.0, 0.0025, 0.05]), [[-2e-6, 0.0, 0.5e-6, 2e-6]] * z2)

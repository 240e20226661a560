"""The fast level's calibration on the FE level, and the FE reference it rests on.

Reference numbers: ``tests/data/fe_reference_paper_cases.json``, made by this package's
FE level (commands and settings in the file): the mean mesh stiffness of the paper's
cases 01-04, both flanks, 150/300/450 N m, at the FE level's default mesh on a segment
of the loaded teeth plus one neighbour each side with clamped cut faces, and the
extent study on a coarse mesh (segments growing by one tooth each side, clamped and
free cut faces). The whole-gear value is the default-mesh value times the coarse
mesh's ratio of the extrapolated whole gear to the first clamped segment
(:func:`gearbox.fe.extent.extent_limit`).

Rule (docs/fe.md, "Calibration of the fast level"): one coefficient, the body
compliance of :class:`~gearbox.ltca.FastCompliance`, fitted so that the largest
error over those 24 numbers is smallest. Target of issue 5: every one within 5 %.
"""

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from _benchmarks import benchmark
from _fe_grids import SAMPLE_EDGES

from gearbox.errors import InputError
from gearbox.fe.extent import aitken_limit, extent_limit
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca import BODY_COMPLIANCE, FastCompliance, LTCAOptions, ltca_cycle
from gearbox.ltca.beveloid import scene_grids
from gearbox.ltca.compliance import BODY_COMPLIANCE_MATCHING_DEPTH, CALIBRATED_BEAM
from gearbox.scene import load_scene

ROOT = Path(__file__).resolve().parents[1]
DATA = json.loads((ROOT / "tests" / "data" / "fe_reference_paper_cases.json").read_text())
SIDE = {"drive": "R", "coast": "L"}


def _extent_runs(case, side, bc):
    runs = [
        r
        for r in DATA["extent"]["runs"]
        if r["case"] == case and r["flank"] == side and r["cut_faces"] == bc
    ]
    runs.sort(key=lambda r: r["neighbours"])
    return runs


def whole_gear_stiffness(case: str, flank: str):
    """FE mean mesh stiffness of the whole gear (N/m) per torque, and its uncertainty."""
    side = SIDE[flank]
    (run,) = [r for r in DATA["default_mesh"]["runs"] if r["case"] == case and r["flank"] == flank]
    cl = _extent_runs(case, side, "clamped")
    fr = _extent_runs(case, side, "free")
    assert cl[0]["neighbours"] == 1
    lim, err = extent_limit([r["k_fe"] for r in cl], [r["k_fe"] for r in fr])
    factor = lim / np.asarray(cl[0]["k_fe"])
    k = np.asarray(run["mean_stiffness_N_per_m"]) * factor
    return k, k * err / lim


CASES = [(c, f) for c in ("01", "02", "03", "04") for f in ("drive", "coast")]


def test_aitken_limit_of_a_geometric_sequence_is_exact():
    seq = 3.0 + 2.0 * 0.7 ** np.arange(6)
    assert aitken_limit(seq) == pytest.approx(3.0, rel=1e-12)
    with pytest.raises(InputError, match="ratio of successive differences"):
        aitken_limit([1.0, 2.0, 4.0])
    with pytest.raises(InputError, match="at least 3"):
        aitken_limit([1.0, 2.0])


@pytest.mark.parametrize("case,flank", CASES)
def test_clamped_and_free_segments_bracket_the_whole_gear(case, flank):
    # the clamped sequence falls, the free one rises, and their extrapolations meet:
    # the half difference is the extent uncertainty quoted in docs/fe.md
    side = SIDE[flank]
    cl = np.array([r["k_fe"] for r in _extent_runs(case, side, "clamped")])
    fr = np.array([r["k_fe"] for r in _extent_runs(case, side, "free")])
    assert np.all(np.diff(cl, axis=0) < 0)
    assert np.all(np.diff(fr, axis=0) > 0)
    lim, err = extent_limit(cl, fr)
    assert np.all(fr[-1] < lim) and np.all(lim < cl[-1])
    assert np.all(err / lim < 0.015), err / lim


def _fast_mean_stiffness(case, flank, compliance):
    # the stored FE runs were made on grids with the edge points on the last profile
    # samples (before ltca.edge_borders became the default): compare on the same grids
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=SAMPLE_EDGES)
    design = design_pair(PairSpec.from_scene(scene))
    P = 24
    grids, _, _ = scene_grids(design, scene, SIDE[flank], P)
    res = ltca_cycle(
        lambda f: grids[int(round(f * P)) % P],
        scene["load"]["torques_Nm"],
        options=LTCAOptions(positions=P),
        compliance=compliance,
    )
    return res.stiffness.mean(axis=1)


@pytest.mark.slow
@pytest.mark.parametrize("case,flank", CASES)
def test_calibrated_beam_within_5_percent_of_the_whole_gear_fe_level(case, flank):
    k_fe, _ = whole_gear_stiffness(case, flank)
    k_fast = _fast_mean_stiffness(case, flank, CALIBRATED_BEAM)
    err = k_fast / k_fe - 1
    # measured with BODY_COMPLIANCE = 0.30: -4.2 % .. +4.2 % over the 24 numbers
    assert np.all(np.abs(err) <= 0.05), err
    # without the body term (slices and the shared body torsion) the fast level is
    # too stiff: +7.3 / +8.4 / +9.0 % on case 01 drive (measured)
    if (case, flank) == ("01", "drive"):
        k0 = _fast_mean_stiffness(case, flank, replace(CALIBRATED_BEAM, body_compliance=0.0))
        assert np.all(k0 / k_fe - 1 > 0.05)


@pytest.mark.slow
@pytest.mark.parametrize("case,flank", CASES)
def test_default_level_against_the_whole_gear_fe_level(case, flank):
    # the default (plane-strain tooth, the body's far field shared, no body term;
    # the slices' coupling length chosen on the FE level; the body's tilt BODY_TILT;
    # between tooth pairs the plane-strain whole gear's couplings): measured -4.5 ..
    # +4.8 % over the 24 numbers (`python benchmarks/ltca_ripple.py --parallel`), the
    # drive flanks of cases 01 and 02 the stiffest (+1.8 .. +4.8 %), the coast flanks
    # the softest (-4.5 .. +0.3 %); with the even share between pairs -3.4 .. +7.1 %.
    # Before the touching gear phase (2026-12): -3.9 .. +4.7 %. Band: the measured
    # range, widened by 0.4 point below and 0.9 above
    k_fe, _ = whole_gear_stiffness(case, flank)
    err = _fast_mean_stiffness(case, flank, FastCompliance()) / k_fe - 1
    assert np.all((err > -0.049) & (err < 0.057)), err
    # the FE level's split (contact to the matching depth, the plane-strain tooth read
    # there): measured -0.3 .. +4.8 %, stiffer than the default on the coast flanks
    # (by 1.7 to 5.6 points) and on the drive flanks (-0.1 to 2.5 points); its change
    # with the torque is smaller on every case and flank (0.1 .. 1.0 points between 150
    # and 450 N m against 1.2 .. 2.3). Band: the measured range widened by a point below
    # and 0.8 above
    depth = FastCompliance(contact="matching_depth")
    err_d = _fast_mean_stiffness(case, flank, depth) / k_fe - 1
    assert np.all((err_d > -0.013) & (err_d < 0.056)), err_d
    assert np.ptp(err_d) < np.ptp(err) + 0.002, (err_d, err)


@pytest.mark.slow
@pytest.mark.parametrize("case,flank", CASES)
def test_contact_to_the_matching_depth_calibrated_within_5_percent(case, flank):
    # FastCompliance(contact="matching_depth") with its own body coefficient, the
    # same minimax rule (benchmarks/ltca_ripple.py --contact matching_depth --fit-body):
    # 0.99, measured -5.1 % .. +5.2 % over the 24 numbers (0.91 and -4.2 .. +4.2 %
    # before the touching gear phase raised the coast flanks at both levels): this
    # variant no longer meets the 5 % target. Band: measured, widened by 0.1 point
    k_fe, _ = whole_gear_stiffness(case, flank)
    comp = replace(CALIBRATED_BEAM, contact="matching_depth", body_compliance=None)
    assert comp.body_compliance == BODY_COMPLIANCE_MATCHING_DEPTH
    err = _fast_mean_stiffness(case, flank, comp) / k_fe - 1
    assert np.all(np.abs(err) <= 0.053), err


def _parallel_errors(compliance):
    """benchmarks/ltca_ripple.py's comparison with the stored whole-gear FE level on
    parallel pairs (tests/data/fe_parallel_whole_gear.json), fast / FE - 1 per pair."""
    bench = benchmark("ltca_ripple")
    return np.asarray(list(bench.parallel_errors(compliance).values()))


def test_parallel_pairs_are_too_soft_against_the_whole_gear_fe_level():
    # the stored whole-gear FE level on two spur pairs and a 15 deg helical pair
    # (tests/data/fe_parallel_whole_gear.json), 400 N m: the calibrated fast level is
    # -22.7 / -18.6 / -9.3 % (measured with BODY_COMPLIANCE 0.30; -22.1 / -17.9 / -8.4 %
    # with 0.24), the contact to the matching depth with its own calibration -26.3 /
    # -22.5 / -13.3 %: the spur pairs' softness is not the contact term's (docs/ltca.md,
    # "The contact term"). Bands: each measured value +- 1.5 points, so that a change
    # that moves these pairs is seen here
    centre = _parallel_errors(CALIBRATED_BEAM)
    depth = _parallel_errors(
        replace(CALIBRATED_BEAM, contact="matching_depth", body_compliance=None)
    )
    assert centre == pytest.approx([-0.227, -0.186, -0.093], abs=0.015)
    assert depth == pytest.approx([-0.263, -0.225, -0.133], abs=0.015)
    assert np.all(depth < centre)


def test_plane_strain_tooth_brings_the_spur_pairs_to_the_whole_gear_fe_level():
    # the plane-strain tooth with Sainsot's whole foundation in the slices and the
    # calibrated body coefficient 0.30: the spur pairs, whose line load is even along
    # the face, within 4 % of the whole-gear FE (measured +1.2 / +2.3 %, against
    # -22.7 / -18.6 % with the beam); the helical pair too stiff (+12.4 %). With the
    # far field shared, the plane-strain whole gear between pairs and the coupling
    # length 0.6 (the default, no body term): -2.2 / -2.4 / +0.2 % (measured; -1.2 /
    # -0.2 / +2.8 % with the even share between pairs, the helical pair +4.6 % with the
    # earlier growth cos(beta)^-4.5 of the far field). Bands: measured +- 1.5 points
    fe_normal = FastCompliance(foundation="normal", coupling_length=1.0)
    assert fe_normal.body_compliance == BODY_COMPLIANCE
    err = _parallel_errors(fe_normal)
    assert err == pytest.approx([0.012, 0.023, 0.124], abs=0.015)
    assert np.all(np.abs(err[:2]) < 0.04)
    err = _parallel_errors(FastCompliance())
    assert err == pytest.approx([-0.022, -0.024, 0.002], abs=0.015)
    assert np.all(np.abs(err) < 0.03)
    # the FE level's split (contact to the matching depth, the tooth read there):
    # -3.3 / -3.6 / -0.4 % (measured)
    err = _parallel_errors(FastCompliance(contact="matching_depth"))
    assert err == pytest.approx([-0.034, -0.036, -0.004], abs=0.015)
    with pytest.raises(InputError, match="tooth"):
        FastCompliance(tooth="solid")


def test_contact_option_names_the_bad_value():
    with pytest.raises(InputError, match="contact"):
        FastCompliance(contact="hertz")
    with pytest.raises(InputError, match="contact_depth"):
        FastCompliance(contact="matching_depth", contact_depth=2.0)
    assert FastCompliance().body_compliance == 0.0  # the split foundation: nothing fitted
    assert CALIBRATED_BEAM.body_compliance == BODY_COMPLIANCE
    assert FastCompliance(contact="matching_depth", body_compliance=0.3).body_compliance == 0.3


def test_body_term_is_rank_one_per_gear_and_scales_with_the_face_width():
    from gearbox.ltca import ParallelPair, parallel_grid

    pair = ParallelPair(
        normal_module=4e-3,
        normal_pressure_angle=np.radians(20),
        helix_angle=np.radians(15),
        teeth=(30, 45),
        face_width=30e-3,
    )
    g = parallel_grid(pair, 0.3, n_face=12)
    C0 = FastCompliance(body_compliance=0.0).tooth_matrix(g)
    C1 = FastCompliance(body_compliance=BODY_COMPLIANCE).tooth_matrix(g)
    d = C1 - C0
    expected = 2 * BODY_COMPLIANCE / (g.youngs_modulus * pair.face_width)
    assert np.allclose(d, expected, rtol=1e-9)
    with pytest.raises(InputError, match="body_compliance"):
        FastCompliance(body_compliance=-1.0)


@pytest.mark.slow
def test_fe_reference_is_reproduced_by_the_fe_level():
    # one run of the extent study, recomputed: case 03 drive, coarse mesh, first
    # clamped segment, 8 positions; the stored numbers come from the same code
    from gearbox.fe import FECompliance, FEOptions, MeshOptions
    from gearbox.surface import blanks_from_design

    (ref,) = [
        r for r in _extent_runs("03", "R", "clamped") if r["neighbours"] == 1 and r["refine"] == 0.5
    ]
    # the stored FE runs were made on grids with the edge points on the last profile
    # samples (before ltca.edge_borders became the default): compare on the same grids
    scene = load_scene(ROOT / "models" / "case03.toml").replaced(ltca=SAMPLE_EDGES)
    design = design_pair(PairSpec.from_scene(scene))
    P = ref["positions"]
    grids, _, _ = scene_grids(design, scene, "R", P)
    fe = FECompliance(
        FEOptions(
            mesh=MeshOptions().refined(0.5), neighbours=1, cut_faces="clamped", far_field="none"
        ),
        blanks=blanks_from_design(design),
    )
    fe.reserve(grids)
    res = ltca_cycle(
        lambda f: grids[int(round(f * P)) % P],
        ref["torques"],
        options=LTCAOptions(positions=P),
        compliance=fe,
    )
    assert res.stiffness.mean(axis=1) == pytest.approx(ref["k_fe"], rel=1e-6)

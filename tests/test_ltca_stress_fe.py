"""Fast-level root stress of the paper cases against stored FE-level numbers.

References: tests/data/ltca_root_stress_fe_case03.toml (the FE level's fillet stress
over a mesh cycle of case 03, drive flank, default FE mesh; how it was made is in
the file) and the drive- and coast-flank runs of
tests/data/ltca_root_stress_fe_runs.json (``python benchmarks/bench_root_stress.py
--cases 01 02 --flanks L --json ...``, ``--cases 03 04`` and, drive flanks,
``--cases 01 02 04 --flanks R``;
default FE mesh, 24 positions; the largest fillet stress over the
cycle per torque and the pinion's envelope along the face). The fast level (ISO
6336-3 slice sections spread along the face by the moment image, gearbox.ltca.stress)
runs here in one to two seconds per case and flank.
"""

import json
import math
import tomllib
from pathlib import Path

import numpy as np
import pytest
from _fe_grids import SAMPLE_EDGES

from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca import LTCAOptions, ParallelPair, ltca_cycle, parallel_grid
from gearbox.ltca.beveloid import beveloid_ltca
from gearbox.scene import load_scene

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).parent.parent
REF = tomllib.loads((DATA / "ltca_root_stress_fe_case03.toml").read_text())


def _flank(case, flank, torques):
    """The fast level's loaded TCA of one paper case's flank at these torques."""
    # the stored FE runs were made on grids with the edge points on the last profile
    # samples (before ltca.edge_borders became the default): compare on the same grids
    scene = load_scene(ROOT / "models" / f"case{case}.toml").replaced(ltca=SAMPLE_EDGES)
    s = scene.replaced(ltca={"flanks": [flank]}, load={"torques_Nm": torques})
    return beveloid_ltca(design_pair(PairSpec.from_scene(s)), s).flanks[flank]


def _pinion_along_face(result, z):
    """The pinion's per-slot envelope (largest over the cycle) at face samples z, (T, z)."""
    a, b = result.face_range
    n = result.root_stress_face_pinion.shape[1]
    slots = a + (np.arange(n) + 0.5) * (b - a) / n
    return np.array([np.interp(z, slots, row) for row in result.root_stress_face_pinion])


@pytest.fixture(scope="module")
def drive():
    return _flank("03", "drive", REF["torques_Nm"])


@pytest.mark.parametrize("gear", ["pinion", "gear"])
def test_largest_root_stress_within_15_percent_of_fe(drive, gear):
    # measured fast / FE - 1 at 150 / 300 / 450 N m: pinion +3.7 / +3.1 / +3.1 %, gear
    # +6.3 / +6.0 / +5.3 % (the default fast compliance; before the helical face-end
    # factor pinion -4.7 / -5.8 / -6.2 %; the independent slices were +129 to +258 %);
    # bound 10 %
    got = getattr(drive, f"root_stress_{gear}").max(axis=1)
    ref = np.asarray(REF[f"max_root_stress_{gear}_Pa"])
    np.testing.assert_allclose(got, ref, rtol=0.10, err_msg=f"case 03 drive, {gear}, vs FE")


def test_pinion_root_stress_along_the_face_follows_fe(drive):
    # the largest root stress over the cycle at each FE face sample: the fast level's
    # per-slot envelope interpolated there stays within 15 % of the FE maximum
    # everywhere (measured 7.8 to 8.7 %; 9.7 to 10.9 % without the helical face-end
    # factor), and peaks at the same sample
    ref = REF["pinion_along_face"]
    along = _pinion_along_face(drive, np.asarray(ref["z_m"]))
    for fast, tq in zip(along, REF["torques_Nm"], strict=True):
        fe = np.asarray(ref[f"root_stress_Pa_{int(tq)}Nm"])
        assert np.max(np.abs(fast - fe)) < 0.15 * fe.max(), f"{tq} N m: {fast} vs FE {fe}"
        assert np.argmax(fast) == np.argmax(fe)


RUNS = json.loads((DATA / "ltca_root_stress_fe_runs.json").read_text())["runs"]


def _stored_run(case, flank):
    # the default FE mesh (4 elements across the tooth); the coarse-mesh runs of the
    # same flanks are kept in the file beside them
    (run,) = [r for r in RUNS if r["name"] == f"case {case} {flank}" and r["mesh"]["across"] == 4]
    return run


@pytest.mark.parametrize("flank", ["drive", "coast"])
@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_flank_root_stress_against_fe(case, flank):
    # measured fast / FE - 1 over 150 / 300 / 450 N m, the four cases (the FE runs
    # remade with the touching gear phase):
    # drive pinion +1.6 .. +5.5 %, gear +3.7 .. +7.4 %; coast pinion +4.5 .. +9.4 %,
    # gear +6.6 .. +13.3 %; bound 14 %. Without the helical face-end factor the drive
    # pinion was -4.5 .. -11.7 %: the pinion (helix 20 .. 25 deg) may not fall more than
    # 3 % below the FE. Along the face (the pinion's envelope at the FE's seven face
    # samples): largest difference 7.4 .. 13.4 % of the FE maximum; bound 15 %
    _flank_against_run(case, flank, _stored_run(case, flank))


def _flank_against_run(case, flank, run):
    """The fast level's flank against a stored FE run: the largest root stress per
    torque within 14 % (the pinion no more than 3 % below), the pinion's envelope
    along the face within 15 % of the FE maximum."""
    result = _flank(case, flank, run["torques"])
    fe = np.asarray(run["fe"])
    for k, gear in enumerate(("pinion", "gear")):
        got = getattr(result, f"root_stress_{gear}").max(axis=1)
        np.testing.assert_allclose(got, fe[:, k], rtol=0.14, err_msg=f"case {case} {flank}, {gear}")
    pinion = result.root_stress_pinion.max(axis=1)
    assert np.all(pinion > 0.97 * fe[:, 0]), f"case {case} {flank}: {pinion} vs FE {fe[:, 0]}"
    along = _pinion_along_face(result, np.asarray(run["envelope_z_m"]))
    for fast, tq, ref in zip(along, run["torques"], run["envelope_fe_Pa"], strict=True):
        ref = np.asarray(ref)
        assert np.max(np.abs(fast - ref)) < 0.15 * ref.max(), f"{tq} N m: {fast} vs FE {ref}"


THREE = json.loads((DATA / "ltca_root_stress_fe_three_teeth.json").read_text())["runs"]


def _three_teeth_run(pair, face_length, stress_only):
    (run,) = [
        r
        for r in THREE
        if r["pair"] == pair
        and r["three_teeth"]
        and r["mesh"]["face_length"] == face_length
        and r["stress_only"] == stress_only
    ]
    return run


def test_wide_30_deg_helical_pair_stress_model_against_fe_fine_along_the_face():
    # z 20/40, m_n 4, b 60 mm (15 m_n, eps_beta 2.39), 400 N m: a face 2.5 times the
    # widest the helical face-end factor was fitted on. The stress model alone: the FE
    # stress under the fast level's loads, elements 0.5 m_n long along the face, three
    # teeth meshed at a time (bench_root_stress.py --stress-only --three-teeth --mesh
    # face-fine; the whole loaded segment cannot be factorised at that mesh in 23 GB).
    # On the default mesh three teeth at a time read -1.8 / +0.2 % against the whole
    # segment (stored beside it); halving the face elements again (0.25 m_n) moves a
    # 30 deg tooth's fillet stress under a line load by 1 % or less
    # (fe_independent.py --stress-profile --face-length-mn 0.5 / 0.25). Measured fast /
    # FE - 1: pinion +1.3 %, gear -5.3 % (default FE mesh: +11.4 / +14.3 %, its
    # acute-end peak under-resolved); bound 8 %. Along the face (the pinion's envelope
    # at the FE's 30 face samples) the largest difference is 12.6 % of the FE maximum,
    # at the obtuse end (FE 58, fast 71 MPa); bound 15 %. Under the FE's own loads the
    # acute end carries less (docs/ltca.md, "The wide 30 deg pair against the FE"):
    # that is the fast compliance's error, not held here.
    run = _three_teeth_run("helical 30 deg z20/40 m4 b60", 0.5, True)
    pair = ParallelPair(
        normal_module=4e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=math.radians(30),
        teeth=(20, 40),
        face_width=60e-3,
    )
    r = ltca_cycle(
        lambda f: parallel_grid(pair, f, n_face=40), run["torques"], options=LTCAOptions(24)
    )
    fe = np.asarray(run["fe"])[0]
    got = np.array([r.root_stress_pinion[0].max(), r.root_stress_gear[0].max()])
    np.testing.assert_allclose(got, fe, rtol=0.08, err_msg="30 deg b 60 vs FE face-fine")
    along = _pinion_along_face(r, np.asarray(run["envelope_z_m"]))[0]
    ref = np.asarray(run["envelope_fe_Pa"][0])
    assert np.max(np.abs(along - ref)) < 0.15 * ref.max(), f"{along} vs FE {ref}"
    # the peak at the acute end (+z on the pinion) in both
    assert np.argmax(along) == np.argmax(ref) == ref.size - 1


@pytest.mark.parametrize("flank", ["drive", "coast"])
def test_case03_root_stress_against_fe_fine_along_the_face(flank):
    # The FE's own contact solution, three teeth at a time, elements 0.5 m_n long along
    # the face (bench_root_stress.py --cases 03 --three-teeth --mesh face-fine): its
    # maxima are within 0.4 % of the whole segment's on the default mesh (drive; the
    # three-teeth default-mesh run stored beside it within 0.4 % too), so the default
    # mesh's references hold on case 03. Measured fast / FE - 1 over 150 / 300 / 450
    # N m: drive pinion +2.5 .. +3.2 %, gear +4.9 .. +5.8 %; coast pinion +2.9 ..
    # +5.2 %, gear +6.8 .. +9.4 %; bound 12 %, the pinion no more than 3 % below.
    # Along the face (the pinion's envelope at the FE's 14 face samples): largest
    # difference 9.2 .. 14.1 % of the FE maximum; bound 15 %.
    _flank_against_run("03", flank, _three_teeth_run(f"case 03 {flank}", 0.5, False))

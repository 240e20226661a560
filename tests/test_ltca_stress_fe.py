"""Fast-level root stress of the paper cases against stored FE-level numbers.

References: tests/data/ltca_root_stress_fe_case03.toml (the FE level's fillet stress
over a mesh cycle of case 03, drive flank, default FE mesh; how it was made is in
the file) and the coast-flank runs of tests/data/ltca_root_stress_fe_runs.json
(``python benchmarks/bench_root_stress.py --cases 01 02 --flanks L --json ...`` and
``--cases 03 04``, default FE mesh, 24 positions; the largest fillet stress over the
cycle per torque and the pinion's envelope along the face). The fast level (ISO
6336-3 slice sections spread along the face by the moment image, gearbox.ltca.stress)
runs here in one to two seconds per case and flank.
"""

import json
import tomllib
from pathlib import Path

import numpy as np
import pytest

from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca.beveloid import beveloid_ltca
from gearbox.scene import load_scene

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).parent.parent
REF = tomllib.loads((DATA / "ltca_root_stress_fe_case03.toml").read_text())


def _flank(case, flank, torques):
    """The fast level's loaded TCA of one paper case's flank at these torques."""
    scene = load_scene(ROOT / "models" / f"case{case}.toml")
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
    # measured fast / FE - 1 at 150 / 300 / 450 N m: pinion -4.7 / -5.8 / -6.2 %, gear
    # +3.7 / +3.1 / +2.3 % (the default fast compliance; with CALIBRATED_BEAM pinion
    # -6.6 / -10.0 / -10.1 %, gear +1.7 / -1.5 / -2.1 %; the independent slices were
    # +129 to +258 %); bound 10 %
    got = getattr(drive, f"root_stress_{gear}").max(axis=1)
    ref = np.asarray(REF[f"max_root_stress_{gear}_Pa"])
    np.testing.assert_allclose(got, ref, rtol=0.10, err_msg=f"case 03 drive, {gear}, vs FE")


def test_pinion_root_stress_along_the_face_follows_fe(drive):
    # the largest root stress over the cycle at each FE face sample: the fast level's
    # per-slot envelope interpolated there stays within 15 % of the FE maximum
    # everywhere (measured 11 to 13 %), and peaks at the same sample
    ref = REF["pinion_along_face"]
    along = _pinion_along_face(drive, np.asarray(ref["z_m"]))
    for fast, tq in zip(along, REF["torques_Nm"], strict=True):
        fe = np.asarray(ref[f"root_stress_Pa_{int(tq)}Nm"])
        assert np.max(np.abs(fast - fe)) < 0.15 * fe.max(), f"{tq} N m: {fast} vs FE {fe}"
        assert np.argmax(fast) == np.argmax(fe)


RUNS = json.loads((DATA / "ltca_root_stress_fe_runs.json").read_text())["runs"]


def _coast_run(case):
    # the default FE mesh (4 elements across the tooth); the coarse-mesh runs of the
    # same flanks are kept in the file beside them
    (run,) = [r for r in RUNS if r["name"] == f"case {case} coast" and r["mesh"]["across"] == 4]
    return run


@pytest.mark.parametrize("case", ["01", "02", "03", "04"])
def test_coast_flank_root_stress_against_fe(case):
    # measured fast / FE - 1 over 150 / 300 / 450 N m: pinion -5.0 .. +2.2 %, gear
    # +3.8 .. +8.8 %; bound 12 %. Along the face (the pinion's envelope at the FE's
    # seven face samples): largest difference 8.5 .. 12.5 % of the FE maximum; bound 15 %
    run = _coast_run(case)
    coast = _flank(case, "coast", run["torques"])
    fe = np.asarray(run["fe"])
    for k, gear in enumerate(("pinion", "gear")):
        got = getattr(coast, f"root_stress_{gear}").max(axis=1)
        np.testing.assert_allclose(got, fe[:, k], rtol=0.12, err_msg=f"case {case} coast, {gear}")
    along = _pinion_along_face(coast, np.asarray(run["envelope_z_m"]))
    for fast, tq, ref in zip(along, run["torques"], run["envelope_fe_Pa"], strict=True):
        ref = np.asarray(ref)
        assert np.max(np.abs(fast - ref)) < 0.15 * ref.max(), f"{tq} N m: {fast} vs FE {ref}"

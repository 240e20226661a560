"""Fast-level root stress of a paper case against stored FE-level numbers.

Reference: tests/data/ltca_root_stress_fe_case03.toml (the FE level's fillet stress
over a mesh cycle of case 03, drive flank, default FE mesh; how it was made is in
the file). The fast level (ISO 6336-3 slice sections spread along the face by the
moment image, gearbox.ltca.stress) runs here in about a second.
"""

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


@pytest.fixture(scope="module")
def drive():
    scene = load_scene(ROOT / "models" / "case03.toml")
    s = scene.replaced(ltca={"flanks": ["drive"]}, load={"torques_Nm": REF["torques_Nm"]})
    return beveloid_ltca(design_pair(PairSpec.from_scene(s)), s).flanks["drive"]


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
    z = np.asarray(ref["z_m"])
    a, b = drive.face_range
    slots = (
        a
        + (np.arange(drive.root_stress_face_pinion.shape[1]) + 0.5)
        * (b - a)
        / (drive.root_stress_face_pinion.shape[1])
    )
    for t, tq in enumerate(REF["torques_Nm"]):
        fe = np.asarray(ref[f"root_stress_Pa_{int(tq)}Nm"])
        fast = np.interp(z, slots, drive.root_stress_face_pinion[t])
        assert np.max(np.abs(fast - fe)) < 0.15 * fe.max(), f"{tq} N m: {fast} vs FE {fe}"
        assert np.argmax(fast) == np.argmax(fe)

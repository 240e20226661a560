"""Loaded TCA of crossed beveloid pairs from the generated flanks (shortened runs).

References: the closed-form parallel-axis pair (plane of action) for the whole
surface-based path, and the paper's Table 3 (tests/data/ltca_paper_table3.toml,
copied from the paper's text as decoded in the project's reference notes).
"""

import tomllib
from pathlib import Path

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca.beveloid import beveloid_ltca
from gearbox.ltca.table import scene_ltca
from gearbox.scene import load_scene

DATA = Path(__file__).parent / "data"
ROOT = Path(__file__).parent.parent
TABLE3 = tomllib.loads((DATA / "ltca_paper_table3.toml").read_text())["table3"]


def _run(scene, **ltca):
    s = scene.replaced(ltca=ltca, load={"torques_Nm": [300.0]})
    return beveloid_ltca(design_pair(PairSpec.from_scene(s)), s), s


def test_surface_path_reproduces_the_closed_form_parallel_pair():
    # the parallel helical scene through the generated flanks and the separation
    # field must give the plane-of-action result. Measured with 40 profile points:
    # mean stiffness 1.14 % above, mean LTE 1.18 % below (0.62 / 0.67 % with 20;
    # converged 1.25 % stiffer at 320, docs/ltca.md 'Edge points on the flank
    # borders'): the edge points on the flank borders carry the corner contacts that
    # the closed form's lines, ended in the plane of action, leave out. With the edge
    # points on the last profile samples: 0.32 / 0.34 % (0.78 / 0.76 % with 20).
    # Hence 2 %.
    scene = load_scene(DATA / "ltca_parallel_helical.toml")
    b, s = _run(scene, positions=12, grid_profile=40, grid_face=20, flanks=["drive"])
    p = scene_ltca(design_pair(PairSpec.from_scene(s)), s)
    rb, rp = b.flanks["drive"], p.flanks["drive"]
    assert rb.stiffness[0].mean() == pytest.approx(rp.stiffness[0].mean(), rel=0.02)
    assert rb.lte[0].mean() == pytest.approx(rp.lte[0].mean(), rel=0.02)
    # perfect involutes: no unloaded transmission error (below 1 nm)
    assert np.ptp(rb.lte_unloaded) < 1e-9
    assert rb.success


@pytest.mark.parametrize("case", ["03"])
def test_line_of_action_and_mesh_point_against_paper_table3(case):
    scene = load_scene(ROOT / "models" / f"case{case}.toml")
    b, _ = _run(scene, positions=8, grid_profile=12, grid_face=12, flanks=["drive"])
    r = b.flanks["drive"]
    ref = next(row for row in TABLE3 if row["case"] == case)
    n = r.line_of_action[0].mean(axis=0)
    n /= np.linalg.norm(n)
    P = r.mesh_point[0].mean(axis=0)
    # Table 3 prints n to 3 decimals and orients it the other way (our n is the force
    # of the pinion on the gear): 2e-3 per component
    assert np.allclose(-n, ref["line_of_action"], atol=2e-3), f"paper Table 3 case {case}: {n}"
    # P: x and y (the paper's z origin is not stated): printed to 1 mm, 1.5 mm allowed
    assert np.allclose(P[:2], ref["mesh_point_m"][:2], atol=1.5e-3), f"paper Table 3: {P}"


def test_contact_grid_refinement_case03():
    # profile points 10 / 20 / 40 and face slices 20 / 40 at 300 N m (case 03):
    # measured 490.7 / 500.6 / 507.3 MN/m and 500.6 / 500.4 MN/m
    scene = load_scene(ROOT / "models" / "case03.toml")
    k = {}
    for gp, gf in ((10, 20), (20, 20), (40, 20), (20, 40)):
        b, _ = _run(scene, positions=8, grid_profile=gp, grid_face=gf, flanks=["drive"])
        k[gp, gf] = b.flanks["drive"].stiffness[0].mean()
    d1 = abs(k[20, 20] - k[10, 20])
    d2 = abs(k[40, 20] - k[20, 20])
    assert d2 < d1, "profile refinement must converge"
    assert d2 / k[40, 20] < 0.025
    assert abs(k[20, 40] - k[20, 20]) / k[20, 20] < 0.005


@pytest.mark.slow
def test_fpd_angle_trends_over_the_paper_cases():
    # paper section 3.2 and Table 3: with the FPD angle (1.66 -> 4.44 deg, cases
    # 01 -> 04) the mean mesh stiffness falls, the LTE rises and the contact pattern
    # shrinks; drive and coast patterns differ
    rows = []
    for case in ("01", "02", "03", "04"):
        scene = load_scene(ROOT / "models" / f"case{case}.toml")
        b, _ = _run(scene, positions=8, grid_profile=12, grid_face=16)
        d, c = b.flanks["drive"], b.flanks["coast"]
        rows.append(
            (
                d.stiffness[0].mean(),
                d.lte[0].mean(),
                d.pattern_area_fraction[0],
                c.pattern_area_fraction[0],
            )
        )
        assert d.success and c.success
    k, lte, pat, pat_c = (np.array(v) for v in zip(*rows, strict=True))
    assert np.all(np.diff(k) < 0), f"mean stiffness must fall: {k}"
    assert np.all(np.diff(lte) > 0), f"mean LTE must rise: {lte}"
    assert np.all(np.diff(pat) < 0), f"pattern must shrink: {pat}"
    assert np.all(np.abs(pat - pat_c) > 0.05), "drive and coast patterns differ"


def test_torque_beyond_the_modelled_contact_zone_is_refused():
    scene = load_scene(ROOT / "models" / "case03.toml")
    s = scene.replaced(
        ltca={"positions": 4, "grid_profile": 8, "grid_face": 8, "flanks": ["drive"]},
        load={"torques_Nm": [3.0e5], "operating_torque_Nm": 3.0e5},
    )
    with pytest.raises(InputError, match="torques_Nm"):
        beveloid_ltca(design_pair(PairSpec.from_scene(s)), s)

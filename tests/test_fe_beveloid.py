"""The FE level on a paper case: beveloid grids placed on the generated teeth."""

from pathlib import Path

import numpy as np
import pytest

from gearbox.fe import FECompliance, FEOptions, MeshOptions
from gearbox.fe.compliance import beveloid_loads
from gearbox.geometry import PairSpec, design_pair
from gearbox.ltca import FastCompliance, LTCAOptions, compliance_for, ltca_cycle
from gearbox.ltca.beveloid import beveloid_grids, separation_field
from gearbox.scene import load_scene
from gearbox.surface import blanks_from_design, flank_points

P = 4


@pytest.fixture(scope="module")
def case03():
    scene = load_scene(Path(__file__).resolve().parents[1] / "models" / "case03.toml")
    design = design_pair(PairSpec.from_scene(scene))
    field = separation_field(design, scene, "R", n_profile=12, n_face=10, positions=P)
    grids, _ = beveloid_grids(design, scene, field, P)
    return scene, design, grids


def test_grid_points_land_on_the_generated_flanks(case03):
    # the gear's axial position recovered from the local profile shift puts the gear
    # point at the grid's radius on the gear flank (Newton to 1e-12 m), and the
    # pinion point at the grid's pinion radius
    _, design, grids = case03
    blanks = blanks_from_design(design)
    g = grids[0]
    for gear, sec in ((0, g.tooth1), (1, g.tooth2)):
        loads = beveloid_loads(g, gear, blanks)
        fp = flank_points(blanks[gear], loads.side, loads.z, loads.u)
        assert np.allclose(fp.radius, sec.radius, rtol=0, atol=1e-9)
        assert loads.side == "R"
        zb = blanks[gear]
        assert np.all((loads.z >= zb.z_toe - 1e-9) & (loads.z <= zb.z_heel + 1e-9))


def test_fe_cycle_on_case03_runs_and_is_near_the_fast_level(case03):
    scene, design, grids = case03
    fe = compliance_for("fe", blanks=blanks_from_design(design))
    assert isinstance(fe, FECompliance)
    fe = FECompliance(FEOptions(mesh=MeshOptions.coarse(), far_field="none"), blanks=fe.blanks)
    # later positions load teeth the first does not: the cycle sizes the models to all
    # its grids at once (FECompliance.reserve, called by ltca_cycle), else the first
    # position's models would be factorised again, bigger, part-way through
    first = [set(fe.loads(grids[0], g).tooth.tolist()) for g in (0, 1)]
    every = [set().union(*(fe.loads(x, g).tooth.tolist() for x in grids)) for g in (0, 1)]
    assert any(e > f for e, f in zip(every, first, strict=True))
    tq = [scene["load"]["torques_Nm"][0]]
    res = ltca_cycle(
        lambda f: grids[int(round(f * P)) % P], tq, options=LTCAOptions(positions=P), compliance=fe
    )
    # the slice model alone (no body term): the FE segment models the same teeth
    # and rim locally
    fast = ltca_cycle(
        lambda f: grids[int(round(f * P)) % P],
        tq,
        options=LTCAOptions(positions=P),
        compliance=FastCompliance(body_compliance=0.0),
    )
    assert res.success
    assert fe.stats["factorisations"] == 2
    # the two levels model the same teeth: mean stiffness within 30 % (the measured
    # gap, FE against fast, is reported by benchmarks/bench_fe.py)
    ratio = res.stiffness.mean() / fast.stiffness.mean()
    assert 0.7 < ratio < 1.3, ratio
    # the root stresses are the FE fillet's, placed along the face by each gear's own
    # axial position (the gear's from its local profile shift): the envelope over the
    # cycle peaks where the fast level's does, within one of the ten slots (both
    # peak in slot 5; the FE's largest is 25 % lower on this coarse segment)
    assert res.meta["root_stress"].startswith("FE fillet")
    for name in ("pinion", "gear"):
        fe_env = getattr(res, f"root_stress_face_{name}")[0]
        fast_env = getattr(fast, f"root_stress_face_{name}")[0]
        assert abs(int(np.argmax(fe_env)) - int(np.argmax(fast_env))) <= 1, name
        assert fe_env.max() > 0.5 * fast_env.max()


def test_beveloid_grid_without_blanks_is_a_clear_error(case03):
    # without the pair's generating data the FE level cannot place a beveloid grid:
    # it says so and says what to pass, instead of meshing cylindrical teeth
    from gearbox.errors import InputError

    _, _, grids = case03
    with pytest.raises(InputError, match="blanks"):
        compliance_for("fe").tooth_matrix(grids[0])


@pytest.mark.slow
def test_both_flanks_share_one_model_per_gear(monkeypatch):
    # beveloid_ltca sizes each gear's FE model to both flanks' grids at once: one
    # factorisation per gear for the whole table (the coarse mesh keeps it cheap)
    import gearbox.ltca.beveloid as bev

    made = []

    def coarse(fidelity, *, blanks=None):
        fe = FECompliance(FEOptions(mesh=MeshOptions.coarse(), far_field="none"), blanks=blanks)
        made.append(fe)
        return fe

    monkeypatch.setattr(bev, "compliance_for", coarse)
    scene = load_scene(Path(__file__).resolve().parents[1] / "models" / "case03.toml")
    scene = scene.replaced(ltca={"fidelity": "fe", "positions": P}, load={"torques_Nm": [300.0]})
    lt = bev.beveloid_ltca(design_pair(PairSpec.from_scene(scene)), scene)
    assert set(lt.flanks) == {"drive", "coast"}
    assert all(r.success for r in lt.flanks.values())
    (fe,) = made
    assert fe.stats["factorisations"] == 2

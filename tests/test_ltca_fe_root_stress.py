"""The FE level's loaded TCA takes its root stresses from the FE fillet
(``FECompliance.grid_root_stress``), the fast level from its ISO 6336-3 slices; the
tables say which."""

import math

import numpy as np
import pytest

from gearbox.fe import FECompliance, FEOptions, MeshOptions
from gearbox.fe.stress import fillet_stress
from gearbox.ltca import LTCAOptions, ParallelPair, ltca_cycle, parallel_grid
from gearbox.ltca.solver import solve_contact
from gearbox.ltca.stress import iso_pair_root_stress
from gearbox.ltca.table import parallel_ltca

SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(20, 40),
    face_width=8e-3,
)
POSITIONS = 6
TORQUES = [150.0, 300.0]


def _grid(f):
    return parallel_grid(SPUR, f, n_face=4)


@pytest.fixture(scope="module")
def coarse():
    fe = FECompliance(FEOptions(mesh=MeshOptions.coarse(), far_field="none"))
    res = ltca_cycle(_grid, TORQUES, options=LTCAOptions(positions=POSITIONS), compliance=fe)
    return fe, res


def test_fe_cycle_carries_the_fe_fillet_stress(coarse):
    # at two positions and both torques, the cycle's root stresses are those of
    # fillet_stress under the contact loads solved again here: the largest over the
    # fillet per position, and per tooth pair its own tooth's largest
    fe, res = coarse
    assert res.meta["root_stress"].startswith("FE fillet")
    for j in (1, 4):
        g = _grid(j / POSITIONS)
        for t, tq in enumerate(TORQUES):
            load = solve_contact(g, fe, tq).load
            for gear, name in ((0, "pinion"), (1, "gear")):
                fs = fillet_stress(fe, g, load, gear)
                got = getattr(res, f"root_stress_{name}")[t, j]
                # the contact solve is repeated from another start: round-off only
                assert got == pytest.approx(fs.max, rel=1e-6)
                per_pair = res.pair_root_stress[t, j, :, gear]
                present = [k for k, p in enumerate(res.pair_index) if np.any(g.pair == p)]
                np.testing.assert_allclose(
                    np.sort(per_pair[present]), np.sort(fs.root_stress.max(axis=1)), rtol=1e-6
                )


def test_fe_cycle_face_envelope_stays_under_its_largest(coarse):
    # the per-slot envelope reads the fillet at the slots' face positions: never above
    # the largest over the whole fillet, and on this spur tooth, whose stress varies
    # little along the 8 mm face, within 10 % of it
    _, res = coarse
    for name in ("pinion", "gear"):
        env = getattr(res, f"root_stress_face_{name}")
        top = getattr(res, f"root_stress_{name}").max(axis=1)
        assert np.all(env <= top[:, None] * (1 + 1e-12))
        assert np.all(env.max(axis=1) > 0.9 * top)
    # twice the torque, about twice the stress (linear elastic teeth; the load's
    # spread over the pairs shifts a little with the contact widths)
    ratio = res.root_stress_pinion.max(axis=1)
    assert 1.8 < ratio[1] / ratio[0] < 2.2


def test_fast_level_tables_name_their_slice_stress():
    lt = parallel_ltca(SPUR, [150.0], flanks=("drive",), options=LTCAOptions(positions=4))
    assert lt.table.attrs["root_stress"].startswith("ISO 6336-3 slices")
    assert lt.flanks["drive"].meta["root_stress"] == lt.table.attrs["root_stress"]
    assert "root stress from the FE fillet" in FECompliance().describe()


@pytest.mark.slow
def test_fe_cycle_root_stress_against_iso_6336_3_and_the_fast_level():
    # default FE mesh (the level's own), segment alone, 8 positions at 150 N m.
    # Measured FE / ISO 6336-3 (method B, sigma_F0): pinion 0.920, gear 0.937; the
    # bound 12 % covers ISO's own approximations (Y_F and Y_S at the outer point of
    # single contact, the 30 deg tangent) and the default mesh being 1 to 12 % below
    # the converged fillet stress (docs/fe.md, "Fillet stress against the independent
    # model"). The fast level against it: measured +0.6 / -1.3 %, bound 10 % (its
    # calibration's bound on the paper cases, tests/test_ltca_stress_fe.py)
    fe = FECompliance(FEOptions(far_field="none"))
    res = ltca_cycle(_grid, [150.0], options=LTCAOptions(positions=8), compliance=fe)
    fast = ltca_cycle(_grid, [150.0], options=LTCAOptions(positions=8))
    for gear, name in ((0, "pinion"), (1, "gear")):
        got = float(getattr(res, f"root_stress_{name}").max())
        iso = iso_pair_root_stress(SPUR, 150.0, gear).sigma_F0
        assert got == pytest.approx(iso, rel=0.12), name
        assert float(getattr(fast, f"root_stress_{name}").max()) == pytest.approx(got, rel=0.10)

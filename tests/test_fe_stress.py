"""The FE level's fillet stress under given loads: one direct solve against the
superposed lattice responses (the same linear problem, so equal to round-off)."""

import math

import numpy as np
import pytest

from gearbox.fe import FECompliance, FEOptions, MeshOptions
from gearbox.fe.stress import fillet_stress
from gearbox.ltca import ParallelPair, parallel_grid

pytestmark = pytest.mark.slow

PAIR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=math.radians(15),
    teeth=(20, 40),
    face_width=12e-3,
)


@pytest.mark.parametrize("gear", [0, 1])
def test_direct_solve_equals_superposed_lattice_responses(gear):
    g = parallel_grid(PAIR, 0.4, n_face=6)
    # uneven: rising along each line and unequal between the pairs
    load = 1000.0 * (1.0 + np.linspace(0.0, 1.0, g.size)) * (1.0 + 0.5 * g.pair)
    fe = FECompliance(FEOptions(mesh=MeshOptions.coarse(), far_field="none"))
    direct = fillet_stress(fe, g, load, gear)
    assert fe.stats["solves"] == 1  # no lattice responses were computed
    superposed = fillet_stress(fe, g, load, gear, direct=False)
    assert fe.stats["solves"] > 50  # now they were: one solve per lattice point
    assert np.array_equal(direct.teeth, superposed.teeth)
    assert direct.max > 1e6  # a real stress, not zeros on both sides
    scale = np.abs(superposed.sigma1).max()
    assert np.max(np.abs(direct.sigma1 - superposed.sigma1)) < 1e-9 * scale
    # and with the responses cached, the default reuses them
    n = fe.stats["solves"]
    again = fillet_stress(fe, g, load, gear)
    assert fe.stats["solves"] == n
    assert np.max(np.abs(again.sigma1 - superposed.sigma1)) < 1e-12 * scale

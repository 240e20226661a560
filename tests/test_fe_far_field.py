"""The FE level's far-field correction (``FEOptions(far_field="extrapolated")``): the
compliance the segment (loaded teeth, one neighbour each side, clamped cut faces)
misses against the whole gear, extrapolated from coarse segments of growing extent
and added to each gear's block of the influence matrix (docs/fe.md, "Extent of the
segment")."""

import math
from pathlib import Path

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.fe import FECompliance, FEOptions, MeshOptions
from gearbox.ltca import ParallelPair, parallel_grid, solve_contact

ROOT = Path(__file__).resolve().parents[1]
SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(20, 40),
    face_width=16e-3,
)
POSITIONS = 8


def test_far_field_option_names_the_bad_value():
    with pytest.raises(InputError, match="fe.far_field"):
        FEOptions(far_field="whole")
    o = FEOptions(far_field="none")
    assert FEOptions.from_dict(o.to_dict()) == o
    assert FEOptions().far_field == "extrapolated"


@pytest.fixture(scope="module")
def spur_coarse():
    grid = parallel_grid(SPUR, 0.1, n_face=8)
    fe = FECompliance(FEOptions(mesh=MeshOptions.coarse()))
    C = fe.tooth_matrix(grid)
    ff = [fe.far_field(grid, g) for g in (0, 1)]
    seg = FECompliance(FEOptions(mesh=MeshOptions.coarse(), far_field="none"))
    seg._models = fe._models  # same factorised segments: only the correction differs
    return fe, seg, grid, C, seg.tooth_matrix(grid), ff


@pytest.mark.slow
def test_correction_is_one_constant_per_gear_and_paid_once(spur_coarse):
    fe, _, grid, C, C0, ff = spur_coarse
    # the whole gear is softer than the clamped segment: a positive compliance,
    # extrapolated with a clamped and a free sequence that agree within 3 %
    for f in ff:
        assert f.compliance > 0
        assert f.uncertainty < 0.03 * f.compliance
        assert f.sequence[("clamped", 5)] > f.sequence[("clamped", 1)]
        assert f.sequence[("free", 3)] > f.sequence[("free", 5)]
    # rank one per gear: the same constant on every entry (all points, both pairs)
    assert np.allclose(C - C0, ff[0].compliance + ff[1].compliance, rtol=1e-9, atol=0)
    # cached per gear model and flank: 8 coarse segments per gear, not per grid
    n = fe.stats["far_field_factorisations"]
    assert n == 16
    fe.tooth_matrix(parallel_grid(SPUR, 0.6, n_face=8))
    assert fe.stats["far_field_factorisations"] == n
    assert fe.stats["factorisations"] == 2


@pytest.mark.slow
def test_correction_leaves_the_load_distribution_unchanged(spur_coarse):
    # a series compliance: the contact loads are those of the segment, the
    # approach grows by (c_0 + c_1) times the total load
    fe, seg, grid, *_, ff = spur_coarse
    a = solve_contact(grid, fe, 400.0)
    b = solve_contact(grid, seg, 400.0)
    assert np.allclose(a.load, b.load, rtol=1e-6, atol=1e-6 * np.max(b.load))

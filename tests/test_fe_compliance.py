"""The finite-element compliance level on parallel-axis pairs (coarse meshes; the
refinement study and the references at the default mesh are in
tests/test_fe_convergence.py)."""

import dataclasses
import math

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.fe import FECompliance, FEOptions, MeshOptions
from gearbox.ltca import LTCAOptions, ParallelPair, compliance_for, ltca_cycle, parallel_grid

SPUR = ParallelPair(
    normal_module=4e-3,
    normal_pressure_angle=math.radians(20),
    helix_angle=0.0,
    teeth=(20, 40),
    face_width=8e-3,
)
# the segment alone (no far-field correction, tests/test_fe_far_field.py): these tests
# are about the level's assembly and contact, and stay cheap
COARSE = FEOptions(mesh=MeshOptions.coarse(), far_field="none")


@pytest.fixture(scope="module")
def spur_matrix():
    fe = FECompliance(COARSE)
    grid = parallel_grid(SPUR, 0.1, n_face=4)
    return fe, grid, fe.matrix(grid, np.full(grid.size, 3e5))


def test_matrix_is_symmetric_positive_definite(spur_matrix):
    _, grid, C = spur_matrix
    assert C.shape == (grid.size, grid.size)
    assert np.allclose(C, C.T, rtol=0, atol=1e-12 * np.max(np.abs(C)))
    assert np.min(np.linalg.eigvalsh(C)) > 0


def test_points_of_other_tooth_pairs_couple_weakly(spur_matrix):
    # the two tooth pairs are coupled only through the rims: the cross terms are
    # positive and smaller than the self terms of either pair
    _, grid, C = spur_matrix
    a = grid.pair == grid.pairs()[0]
    b = ~a
    assert b.any()
    cross = C[np.ix_(a, b)]
    assert np.all(cross > 0)
    assert cross.max() < min(np.diag(C)[a].min(), np.diag(C)[b].min())


def test_one_factorisation_per_gear_serves_a_cycle():
    fe = FECompliance(COARSE)
    res = ltca_cycle(
        lambda f: parallel_grid(SPUR, f, n_face=4),
        [150.0, 300.0],
        options=LTCAOptions(positions=6),
        compliance=fe,
    )
    assert res.success
    assert fe.stats["factorisations"] == 2
    # secant stiffness times the elastic LTE is the transmitted normal load
    # (definition of gearbox.ltca.analysis; rounding only)
    elastic = res.lte - res.lte_unloaded[None, :]
    assert np.allclose(res.stiffness * elastic, res.normal_load, rtol=1e-10)
    # a stiffer-than-linear contact: the mean stiffness rises with the torque
    assert res.stiffness[1].mean() > res.stiffness[0].mean()


def test_helical_pair_runs_and_is_stiffer_per_width_than_its_transverse_share():
    helical = dataclasses.replace(SPUR, helix_angle=math.radians(15), face_width=12e-3)
    fe = FECompliance(COARSE)
    res = ltca_cycle(
        lambda f: parallel_grid(helical, f, n_face=6),
        [300.0],
        options=LTCAOptions(positions=4),
        compliance=fe,
    )
    assert res.success
    k = res.stiffness.mean() / helical.face_width
    # per face width between 10 and 40 N/(mm um): the band of ISO 6336-1 c_gamma for
    # steel gears of any proportion (a gross check that the helical lattice and the
    # contact lines meet; the ISO comparison is the spur pair's)
    assert 10e9 < k < 40e9


def test_fidelity_fe_is_the_fe_level():
    assert isinstance(compliance_for("fe"), FECompliance)


def test_beveloid_like_grid_is_refused_with_the_reason():
    grid = parallel_grid(SPUR, 0.0, n_face=4)
    t1 = dataclasses.replace(grid.tooth1, profile_shift=np.linspace(0.0, 0.1, grid.size))
    bad = dataclasses.replace(grid, tooth1=t1)
    with pytest.raises(InputError, match="tooth1.profile_shift"):
        FECompliance(COARSE).tooth_matrix(bad)


def test_options_name_the_bad_value():
    with pytest.raises(InputError, match="fe.matching_depth"):
        FEOptions(matching_depth=2.0)


def test_meshes_finer_across_the_tooth_place_their_matching_points():
    # with six elements across, a matching point 0.25 m_n below the flank lies beyond
    # the second element column near the tip: the level must still find it (it raised
    # FEBuildError before). The finer mesh is a little softer, as the level converges
    # from above (+0.5 % here); 3 % allows for the mesh, not for points placed wrong
    grid = parallel_grid(SPUR, 0.1, n_face=4)
    q = np.full(grid.size, 3e5)
    e = np.ones(grid.size)
    base = FECompliance(FEOptions(far_field="none")).matrix(grid, q)
    fine = FECompliance(
        FEOptions(mesh=MeshOptions(across=6, profile=12, fillet=6, land=3), far_field="none")
    ).matrix(grid, q)
    ratio = (e @ fine @ e) / (e @ base @ e)
    assert 1.0 <= ratio < 1.03


def test_threaded_solves_equal_one_thread(spur_matrix, monkeypatch):
    # the lattice solves shared over threads (ToothModel.solve) are the same solves
    # as on one thread: the matrices agree bit for bit
    _, grid, C = spur_matrix
    monkeypatch.setenv("GEARBOX_FE_THREADS", "1")
    one = FECompliance(COARSE).matrix(grid, np.full(grid.size, 3e5))
    assert np.array_equal(one, C)
    monkeypatch.setenv("GEARBOX_FE_THREADS", "3")  # more threads than cores is allowed
    assert np.array_equal(FECompliance(COARSE).matrix(grid, np.full(grid.size, 3e5)), C)


@pytest.mark.parametrize("value", ["0", "two", "-1"])
def test_bad_thread_count_names_the_variable(monkeypatch, value):
    from gearbox.fe.model import solve_threads

    monkeypatch.setenv("GEARBOX_FE_THREADS", value)
    with pytest.raises(InputError, match="GEARBOX_FE_THREADS"):
        solve_threads()

"""The 27-node element and the tooth mesh of gearbox.fe against analytic references,
and the clear errors of models that cannot be built."""

import math

import numpy as np
import pytest

from gearbox.fe import FEBuildError, MeshOptions, build_model, build_tooth_mesh
from gearbox.fe.mesh import _Q2_LOCAL, element_map
from gearbox.fe.model import assemble_stiffness
from gearbox.surface.blank import ToothBlank


def _box(L, h, w, nx, ny, nz):
    """Structured 27-node mesh of the box [0, L] x [0, h] x [0, w]."""
    xs, ys, zs = (np.linspace(0, s, 2 * n + 1) for s, n in ((L, nx), (h, ny), (w, nz)))
    X, Y, Z = np.meshgrid(xs, ys, zs, indexing="ij")
    p = np.stack([X.ravel(), Y.ravel(), Z.ravel()])
    idx = np.arange(X.size).reshape(X.shape)
    els = []
    for i in range(nx):
        for j in range(ny):
            for k in range(nz):
                els.append([idx[2 * i + a, 2 * j + b, 2 * k + c] for a, b, c in _Q2_LOCAL])
    return p, np.array(els).T, idx


def _cantilever(E, nu, L, h, w, n):
    p, t, idx = _box(L, h, w, *n)
    K = assemble_stiffness(p, t, E, nu).tocsc()
    fixed = np.zeros(K.shape[0], bool)
    for c in range(3):
        fixed[3 * idx[0].ravel() + c] = True
    free = np.flatnonzero(~fixed)
    f = np.zeros(K.shape[0])
    tip = idx[-1].ravel()
    f[3 * tip + 1] = -1.0 / tip.size  # 1 N shear at the free end, along -y
    from scipy.sparse.linalg import spsolve

    u = np.zeros(K.shape[0])
    u[free] = spsolve(K[free][:, free], f[free])
    return -float(np.mean(u[3 * tip + 1]))


def test_cantilever_matches_timoshenko_beam():
    # end-loaded cantilever, L = 10 h: Timoshenko beam theory (Timoshenko & Gere,
    # Mechanics of Materials, section 9.7) delta = P L^3 / (3 E I) + P L / (k G A),
    # k = 5/6; nu = 0 so that the clamped face adds no Poisson constraint. The beam
    # formula itself is exact to O((h/L)^2) ~ 1 % at this slenderness: 1.5 % bound.
    E, nu, L, h, w = 200e9, 0.0, 0.1, 0.01, 0.01
    got = _cantilever(E, nu, L, h, w, (10, 2, 1))
    inertia = w * h**3 / 12
    G = E / (2 * (1 + nu))
    ref = L**3 / (3 * E * inertia) + L / (5 / 6 * G * w * h)
    assert got == pytest.approx(ref, rel=0.015)


def test_patch_of_linear_displacement_has_no_strain_energy_error():
    # patch test on a distorted element: a linear displacement field u = A x gives the
    # energy of the constant strain exactly (quadratic elements reproduce it)
    p, t, _ = _box(1.0, 1.0, 1.0, 1, 1, 1)
    rng = np.random.default_rng(3)
    p = p + 0.05 * rng.standard_normal(p.shape) * (np.abs(p - 0.5) < 0.4)  # inner nodes only
    E, nu = 1.0, 0.25
    K = assemble_stiffness(p, t, E, nu)
    A = np.array([[1e-3, 2e-4, 0], [0, -5e-4, 3e-4], [1e-4, 0, 2e-4]])
    u = (A @ p).T.ravel()
    eps = 0.5 * (A + A.T)
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    sig = 2 * mu * eps + lam * np.trace(eps) * np.eye(3)
    X = np.array(
        [[a, b, c] for a in (0.1, 0.5, 0.9) for b in (0.1, 0.5, 0.9) for c in (0.1, 0.5, 0.9)]
    )
    _, J = element_map(p, np.repeat(t, X.shape[0], axis=1), X)
    vol = 1.0  # the inner nodes move, the box's volume stays 1
    assert np.all(np.linalg.det(J) > 0)
    energy = 0.5 * u @ (K @ u)
    assert energy == pytest.approx(0.5 * np.sum(sig * eps) * vol, rel=1e-10)


def _blank(**kw):
    d = dict(
        teeth=20,
        normal_module=4e-3,
        normal_pressure_angle=math.radians(20),
        helix_angle=0.0,
        cone_angle=0.0,
        profile_shift_xt=0.0,
        face_width=8e-3,
        tool_addendum=5e-3,
        tool_tip_radius=1.52e-3,
        addendum=4e-3,
    )
    d.update(kw)
    return ToothBlank(**d)


COARSE = MeshOptions(across=2, profile=3, fillet=2, land=1, rim=1, face_length=2.0)


def test_tooth_mesh_nodes_lie_on_the_generated_flank():
    from gearbox.surface import flank_points

    b = _blank()
    m = build_tooth_mesh(b, (0,), bore_radius=0.03, options=COARSE)
    nodes = m.flank_nodes[(0, "R")]
    z = m.z_layers[:, None] * np.ones(nodes.shape)
    fp = flank_points(b, "R", z, m.flank_u["R"])
    assert np.max(np.abs(m.p[:, nodes].transpose(1, 2, 0) - fp.position)) < 1e-12
    # the volume of one tooth segment: the mesh's 27-point quadrature of det J against
    # the section area of a tooth pitch (pi (r_f^2 - r_bore^2) / N) plus the tooth above r_f
    model = build_model(m, 206e9, 0.3)
    assert model.residual < 1e-10


def test_overlapping_fillets_are_a_clear_error():
    # a tool tip radius so large (near the rack's pointed tip, 1.888 mm) that
    # neighbouring fillets meet: no root land
    b = _blank(teeth=8, tool_tip_radius=1.887e-3)
    with pytest.raises(FEBuildError, match="root_land"):
        build_tooth_mesh(b, (0,), bore_radius=0.005, options=COARSE)


def test_an_undercut_tooth_is_meshed_up_to_the_fillets_cut():
    """8 teeth, tool tip radius 1.85 mm: undercut deeply (the fold at u* = 2.0 mm, the
    fillet's cut at 2.8 mm of involute profile). The fillet rows end and the involute
    rows start where the fillet cuts the regular involute, every node on the generated
    flank, the model sound (before, the undercut loop was refused)."""
    from gearbox.surface import flank_points, form_point

    b = _blank(teeth=8, tool_tip_radius=1.85e-3)
    m = build_tooth_mesh(b, (0,), bore_radius=0.005, options=COARSE)
    for side in ("R", "L"):
        u = m.flank_u[side]
        z = m.z_layers[:, None] * np.ones(u.shape)
        uf, ui = form_point(b, side, m.z_layers)
        assert np.all(ui > 2e-3) and np.all(uf < 0)
        # the row at the cut is the involute's (the same point as the fillet's uf), the
        # fillet's last mid-side node halfway between its last node and uf
        k = int(np.argmax(u[0] > 0))
        assert np.allclose(u[:, k], ui, atol=1e-15) and np.all(u[:, :k] < uf[:, None])
        assert np.allclose(2 * u[:, k - 1] - u[:, k - 2], uf, atol=1e-15)
        nodes = m.flank_nodes[(0, side)]
        fp = flank_points(b, side, z, u)
        assert np.max(np.abs(m.p[:, nodes].transpose(1, 2, 0) - fp.position)) < 1e-12
    assert build_model(m, 206e9, 0.3).residual < 1e-10


def test_bore_outside_the_root_is_a_clear_error():
    with pytest.raises(FEBuildError, match="bore_radius"):
        build_tooth_mesh(_blank(), (0,), bore_radius=0.05, options=COARSE)


def test_unclamped_model_fails_to_factorise_with_a_clear_error():
    import dataclasses

    m = build_tooth_mesh(_blank(), (0,), bore_radius=0.03, options=COARSE)
    free = dataclasses.replace(m, clamped=np.zeros(0, dtype=np.int64))
    with pytest.raises(FEBuildError, match="factoris"):
        build_model(free, 206e9, 0.3)


def test_mesh_options_name_the_bad_count():
    from gearbox.errors import InputError

    with pytest.raises(InputError, match="fe.mesh.across"):
        MeshOptions(across=0)


def test_element_matches_scikit_fem():
    # the same cantilever with scikit-fem's own triquadratic vector element
    # (ElementHex2 on the same box, its generic form assembly): an independent
    # implementation of the same discretisation, so the tip deflections agree to
    # rounding (1e-9 relative)
    skfem = pytest.importorskip("skfem")
    from skfem.models.elasticity import lame_parameters, linear_elasticity

    E, nu, L, h, w = 200e9, 0.3, 0.1, 0.01, 0.01
    mesh = skfem.MeshHex1.init_tensor(
        np.linspace(0, L, 6), np.linspace(0, h, 2), np.linspace(0, w, 2)
    )
    basis = skfem.Basis(mesh, skfem.ElementVector(skfem.ElementHex2()))
    K = skfem.asm(linear_elasticity(*lame_parameters(E, nu)), basis)
    clamped = basis.get_dofs(lambda x: np.isclose(x[0], 0.0)).all()
    tip = basis.get_dofs(lambda x: np.isclose(x[0], L)).all("u^2")
    f = np.zeros(K.shape[0])
    f[tip] = -1.0 / tip.size
    u = skfem.solve(*skfem.condense(K, f, D=clamped))
    ref = -float(np.mean(u[tip]))
    assert _cantilever(E, nu, L, h, w, (5, 1, 1)) == pytest.approx(ref, rel=1e-9)

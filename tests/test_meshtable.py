"""MeshTable: interpolation, persistence, validation; the analytical ISO 6336-1 table."""

import math
from pathlib import Path

import numpy as np
import pytest

from gearbox.errors import InputError
from gearbox.mesh_analytical import (
    HelicalPair,
    analytical_table,
    contact_line_length,
    iso_mesh_stiffness,
)
from gearbox.meshtable import MeshTable, fourier_eval, fourier_fit, from_periodic_samples

N1 = 29


def make_table(
    npos=24,
    torques=(100.0, 300.0),
    k=lambda th: 5e8 * (1 + 0.1 * np.cos(N1 * th)),
    flanks=("drive", "coast"),
):
    """A table from closed-form stiffness (N/m); LTE = F/k with F = T / 0.08 m."""
    angle = np.arange(npos) * (2 * math.pi / N1 / npos)
    tq = np.asarray(torques)
    kk = np.broadcast_to(k(angle), (len(flanks), tq.size, npos)).copy()
    lte = (tq / 0.08)[None, :, None] / kk
    P = np.broadcast_to([0.08, 0.0, 0.0], kk.shape + (3,)).copy()
    n = np.empty(kk.shape + (3,))
    for i, f in enumerate(flanks):
        n[i] = [0.0, 1.0, 0.0] if f == "drive" else [0.0, -1.0, 0.0]
    return MeshTable(
        pinion_teeth=N1,
        gear_teeth=45,
        angle=angle,
        torque=tq,
        flanks=flanks,
        stiffness=kk,
        tangent_stiffness=kk,
        lte=lte,
        mesh_point=P,
        line_of_action=n,
        pinion_axis=[[0, 0, 1.0], [0, 0, 0]],
        gear_axis=[[0, 0, -1.0], [0.08 * (1 + 45 / N1), 0, 0]],
        extra={"load_sharing": np.ones_like(kk)},
        attrs={"scene": "test", "method": "closed form"},
    )


def test_fourier_interpolates_samples_and_derivative_is_exact_for_a_harmonic():
    # A band-limited signal (harmonics 1 and 3 of 24 samples): the series must reproduce
    # it exactly between samples too, and its derivative analytically (1e-12: round-off).
    th = np.arange(24) * (2 * math.pi / N1 / 24)
    f = lambda t: 3.0 + 0.5 * np.cos(N1 * t) - 0.2 * np.sin(3 * N1 * t)  # noqa: E731
    df = lambda t: -0.5 * N1 * np.sin(N1 * t) - 0.6 * N1 * np.cos(3 * N1 * t)  # noqa: E731
    a0, a, b = fourier_fit(f(th))
    t = np.linspace(0, 0.5, 37)[:, None]
    v, d = fourier_eval(a0, a, b, N1, t)
    assert np.allclose(v, f(t[:, 0]), atol=1e-12)
    assert np.allclose(d, df(t[:, 0]), atol=1e-10)
    # Arbitrary samples (even count, Nyquist term included) are reproduced at the samples.
    rng = np.random.default_rng(1)
    y = rng.normal(size=24)
    a0, a, b = fourier_fit(y)
    assert np.allclose(fourier_eval(a0, a, b, N1, th[:, None])[0], y, atol=1e-12)


def test_jax_evaluation_matches_numpy():
    jnp = pytest.importorskip("jax.numpy")
    import jax

    jax.config.update("jax_enable_x64", True)
    t = make_table()
    s = t.series("stiffness", "drive", 200.0)
    th = 0.0123
    v_np, d_np = s(th), s.derivative(th)
    v_j = jax.jit(lambda x: s(x, xp=jnp))(th)
    d_j = jax.grad(lambda x: s(x, xp=jnp))(th)
    assert abs(float(v_j) - v_np) <= 1e-12 * abs(v_np)
    assert abs(float(d_j) - d_np) <= 1e-10 * abs(d_np) + 1e-6


def test_torque_interpolation_is_linear_and_bounded():
    t = make_table()
    mid = t.values_at("lte", "drive", 200.0)
    assert np.allclose(mid, 0.5 * (t.lte[0, 0] + t.lte[0, 1]), rtol=1e-14)
    with pytest.raises(InputError, match="torque_Nm"):
        t.values_at("lte", "drive", 500.0)


def test_netcdf_round_trip_is_lossless(tmp_path):
    pytest.importorskip("xarray")
    t = make_table()
    t.to_netcdf(tmp_path / "t.nc")
    r = MeshTable.from_netcdf(tmp_path / "t.nc")
    for name in (
        "angle",
        "torque",
        "stiffness",
        "tangent_stiffness",
        "lte",
        "mesh_point",
        "line_of_action",
        "pinion_axis",
        "gear_axis",
    ):
        assert np.array_equal(getattr(r, name), getattr(t, name)), name
    assert r.flanks == t.flanks and r.pinion_teeth == N1 and r.gear_teeth == 45
    assert np.array_equal(r.extra["load_sharing"], t.extra["load_sharing"])
    assert r.attrs["method"] == "closed form"


def test_csv_has_angle_first_and_one_row_per_entry(tmp_path):
    t = make_table()
    text = t.to_csv(tmp_path / "t.csv")
    lines = text.strip().splitlines()
    assert lines[0].startswith("angle_rad,flank,torque_Nm,stiffness_N_per_m")
    assert len(lines) == 1 + 24 * 2 * 2
    assert float(lines[1].split(",")[0]) == 0.0


def test_validation_names_the_parameter():
    t = make_table()
    import dataclasses

    with pytest.raises(InputError, match="angle"):
        dataclasses.replace(t, angle=t.angle * 1.01)  # not one mesh cycle
    bad = t.stiffness.copy()
    bad[0, 1, 3] = -1.0
    with pytest.raises(InputError, match=r"stiffness\[drive, 300 N m, position 3\]"):
        dataclasses.replace(t, stiffness=bad)
    with pytest.raises(InputError, match="positions"):
        make_table(npos=3)


def test_non_periodic_samples_are_rejected():
    npos = 24
    angle = np.arange(npos + 1) * (2 * math.pi / N1 / npos)
    k = 5e8 * (1 + 0.1 * angle / angle[-1])  # a ramp: first != last
    kk = np.broadcast_to(k, (1, 1, npos + 1))
    P = np.broadcast_to([0.08, 0, 0], kk.shape + (3,))
    n = np.broadcast_to([0, 1.0, 0], kk.shape + (3,))
    with pytest.raises(InputError, match="stiffness.*not periodic"):
        from_periodic_samples(
            angle,
            pinion_teeth=N1,
            gear_teeth=45,
            torque=[300.0],
            flanks=("drive",),
            stiffness=kk,
            tangent_stiffness=kk,
            lte=1e-6 * np.ones_like(kk),
            mesh_point=P,
            line_of_action=n,
            pinion_axis=[[0, 0, 1.0], [0, 0, 0]],
            gear_axis=[[0, 0, -1.0], [0.2, 0, 0]],
        )


# ---------------------------------------------------------------- analytical table


def spur(z=(29, 45), b=0.04, beta=0.0):
    return HelicalPair(
        teeth=z,
        normal_module=0.006,
        normal_pressure_angle=math.radians(20),
        helix_angle=beta,
        face_width=b,
    )


def test_contact_line_length_means_and_constant_for_integer_overlap():
    # Mean total contact-line length = eps_alpha b / cos(beta_b) (field of action area
    # over base pitch); for an integer overlap ratio the total length is constant
    # (a classical property of helical gears). Tolerances: 1e-9 relative (exact geometry
    # sampled on 4096 points, piecewise linear functions).
    p = spur()
    th = np.arange(4096) * (2 * math.pi / 29 / 4096)
    L = contact_line_length(p, th)
    assert L.mean() == pytest.approx(p.contact_ratio * p.face_width, rel=1e-3)
    beta = math.radians(20.0)
    b1 = 1.0 * math.pi * 0.006 / math.sin(beta)  # eps_beta = 1
    h = HelicalPair(
        teeth=(29, 45),
        normal_module=0.006,
        normal_pressure_angle=math.radians(20),
        helix_angle=beta,
        face_width=b1,
    )
    assert h.overlap_ratio == pytest.approx(1.0)
    Lh = contact_line_length(h, th)
    expected = h.contact_ratio * b1 / math.cos(h.base_helix_angle)
    assert np.allclose(Lh, expected, rtol=1e-9)


def test_iso_single_stiffness_near_the_standard_values():
    # ISO 6336-1:2019 gives c' ~ 14 and c_gamma_alpha ~ 20 N/(mm um) as the typical values
    # of solid steel spur gears (basic rack 20 deg, x = 0) at high load (F_t/b >= 100 N/mm);
    # method B for such a pair must land near them (15 %: the typical values are rounded
    # for a range of tooth numbers).
    c1, cg = iso_mesh_stiffness(spur(z=(40, 80)), torque=2000.0)
    assert c1 == pytest.approx(14.0, rel=0.15)
    assert cg == pytest.approx(20.0, rel=0.15)


def test_analytical_table_statics_and_shape():
    p = spur(beta=math.radians(20))
    t = analytical_table(p, [150.0, 300.0], positions=24)
    lam1, lam2 = t.rotation_radii("drive", 300.0)
    # Rotation radii: r_b cos(beta_b) on the pinion, and the tooth ratio between them.
    assert lam1 == pytest.approx(p.base_radius(0) * math.cos(p.base_helix_angle), rel=1e-12)
    assert lam2 / lam1 == pytest.approx(45 / 29, rel=1e-12)
    # Secant stiffness x LTE = transmitted normal load T / lambda_1 (issue 4's identity).
    fn = 300.0 / lam1
    assert np.allclose(t.stiffness[0, 1] * t.lte[0, 1], fn, rtol=1e-12)
    # Coast lines of action are the mirror images: radii of opposite sign.
    c1, c2 = t.rotation_radii("coast", 300.0)
    assert c1 == pytest.approx(-lam1) and c2 == pytest.approx(-lam2)


def test_coast_line_of_action_reverses_tangential_force_and_axial_thrust():
    """Reversing the torque of a helical pair reverses the tangential force and the
    axial thrust of the teeth; the radial (separating) component keeps its sign. So the
    drive and coast lines of action sum to a purely radial vector."""
    p = spur(beta=math.radians(20))
    t = analytical_table(p, [300.0], positions=8)
    nd = t.line_of_action[t.flanks.index("drive"), 0, 0]
    nc = t.line_of_action[t.flanks.index("coast"), 0, 0]
    radial = np.array([1.0, 0.0, 0.0])  # the mesh point lies on +x of the pinion axis
    s = nd + nc
    assert np.allclose(s - (s @ radial) * radial, 0.0, atol=1e-15)
    assert nd[2] != 0.0 and np.sign(nc[2]) == -np.sign(nd[2])
    # n is the force of the pinion on the gear: its radial part pushes the gear away from
    # the pinion (the separating force F_t tan(alpha_wt)), on both flanks
    aw = p.working_pressure_angle
    bb = p.base_helix_angle
    assert nd @ radial == pytest.approx(math.sin(aw) * math.cos(bb), rel=1e-12)
    assert nc @ radial == pytest.approx(nd @ radial, rel=1e-12)


def test_summary_gives_the_lte_mesh_harmonics():
    # LTE = 2 um + 0.3 um cos(N1 theta + 0.4) + 0.1 um sin(3 N1 theta): harmonic peak
    # amplitudes 0.3, 0, 0.1 um (1e-15 m: round-off of the 24-point Fourier fit)
    t = make_table()
    th = t.angle
    lte = 2e-6 + 0.3e-6 * np.cos(N1 * th + 0.4) + 0.1e-6 * np.sin(3 * N1 * th)
    t = MeshTable(**{**t.__dict__, "lte": np.broadcast_to(lte, t.lte.shape).copy()})
    row = t.summary()["drive"]["300"]
    assert row["lte_harmonics_m"] == pytest.approx([0.3e-6, 0.0, 0.1e-6], abs=1e-15)
    assert len(t.summary(harmonics=5)["coast"]["100"]["lte_harmonics_m"]) == 5


def test_analytical_line_of_action_has_the_signs_of_the_tca_normal():
    """The default scene's analytical stand-in (a parallel helical pair, pinion axis z,
    mesh point on +x) against the unloaded TCA of the beveloid pair itself (the pinion
    flank's outward normal at the middle of the drive flank's path, in a frame with the
    same layout): the radial part (separating), the tangential part and the axial thrust
    have the same signs, each above 0.3 in size on both."""
    from gearbox import PairSpec, design_pair
    from gearbox.mesh_analytical import pair_from_scene
    from gearbox.scene import load_scene
    from gearbox.tca.analysis import run_tca

    scene = load_scene(Path(__file__).resolve().parents[1] / "models" / "marine_drive.toml")
    design = design_pair(PairSpec.from_scene(scene))
    fc = run_tca(design, scene).sides["R"]
    i = tuple(np.argwhere(fc.active)[len(np.argwhere(fc.active)) // 2])
    P, n = fc.point[i], fc.normal[i]
    u = np.array([P[0], P[1], 0.0]) / math.hypot(P[0], P[1])  # from the pinion's axis (z)
    v = np.cross([0.0, 0.0, 1.0], u)
    tca = np.array([u @ n, v @ n, n[2]])
    t = analytical_table(pair_from_scene(scene), [300.0], positions=8)
    nd = t.line_of_action[t.flanks.index("drive"), 0, 0]  # mesh point on +x: u = x, v = y
    assert np.all(np.sign(nd) == np.sign(tca)), (nd, tca)
    assert np.all(np.abs(nd) > 0.3) and np.all(np.abs(tca) > 0.3)

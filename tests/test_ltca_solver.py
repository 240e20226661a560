"""The contact solver against closed forms and an independent QP solver."""

import numpy as np
import pytest
from scipy.optimize import minimize

from gearbox.ltca.solver import ContactSolver, solve_lcp


def _random_problem(rng, n):
    A = rng.normal(size=(n, n))
    C = (A @ A.T / n + np.eye(n)) * 1e-9  # SPD, m/N
    s = rng.uniform(0.0, 20e-6, size=n)  # separations up to 20 um
    m = rng.uniform(0.05, 0.07, size=n)  # arms (m)
    return C, s, m


def test_two_springs_closed_form():
    # two independent springs c1, c2 with separations 0 and s: both loaded when
    # phi m > s; loads F1 = m phi / c1, F2 = (m phi - s) / c2, m (F1 + F2) = T
    c1, c2, s, m, T = 1e-9, 2e-9, 1e-6, 0.05, 100.0
    C = np.diag([c1, c2])
    F, phi, gap, it, ok = solve_lcp(C, np.array([0.0, s]), np.array([m, m]), T)
    phi_exact = (T / m + s / c2) / (m / c1 + m / c2)
    assert ok
    assert phi == pytest.approx(phi_exact, rel=1e-12)
    assert F[0] == pytest.approx(m * phi_exact / c1, rel=1e-12)
    assert F[1] == pytest.approx((m * phi_exact - s) / c2, rel=1e-12)
    # a small torque loads the first spring only
    F, phi, gap, it, ok = solve_lcp(C, np.array([0.0, s]), np.array([m, m]), 1.0)
    assert F[1] == 0.0 and gap[1] > 0
    assert phi == pytest.approx(1.0 / m * c1 / m, rel=1e-12)


@pytest.mark.parametrize("seed", range(6))
def test_kkt_and_agreement_with_an_independent_qp_solver(seed):
    rng = np.random.default_rng(seed)
    n = 25
    C, s, m = _random_problem(rng, n)
    T = 200.0
    F, phi, gap, it, ok = solve_lcp(C, s, m, T, solver=ContactSolver())
    assert ok and it < 200  # work bound: finite active-set steps
    scale = np.mean(np.diag(C)) * T / np.mean(m)
    # KKT conditions of the complementarity problem
    assert np.all(F >= 0)
    assert np.min(gap) > -1e-8 * scale
    assert np.max(np.abs(F * gap)) < 1e-8 * scale * F.max()
    assert m @ F == pytest.approx(T, rel=1e-12)
    # independent solver: SLSQP on the equivalent QP, in scaled variables
    x0 = np.full(n, T / m.sum())
    fs = T / m.mean()

    def obj(x):
        f = x * fs
        return (0.5 * f @ C @ f + s @ f) / (scale * fs)

    def jac(x):
        f = x * fs
        return (C @ f + s) / scale

    res = minimize(
        obj,
        x0 / fs,
        jac=jac,
        bounds=[(0, None)] * n,
        constraints=[
            {"type": "eq", "fun": lambda x: (m @ x) * fs / T - 1.0, "jac": lambda x: m * fs / T}
        ],
        method="SLSQP",
        options={"ftol": 1e-14, "maxiter": 1000},
    )
    assert res.success
    # SLSQP stops at ftol 1e-14 on a scaled objective: loads agree to 1e-4 of the largest
    assert np.max(np.abs(res.x * fs - F)) < 1e-4 * F.max()


def test_warm_start_gives_the_same_solution_in_fewer_iterations():
    rng = np.random.default_rng(7)
    C, s, m = _random_problem(rng, 40)
    F, phi, gap, it, ok = solve_lcp(C, s, m, 300.0)
    F2, phi2, gap2, it2, ok2 = solve_lcp(C, s, m, 310.0, start=F > 0)
    F3, phi3, *_ = solve_lcp(C, s, m, 310.0)
    assert ok2 and it2 <= it
    assert phi2 == pytest.approx(phi3, rel=1e-10)
    assert np.allclose(F2, F3, rtol=0, atol=1e-9 * F3.max())


def test_newton_on_the_flattening_meets_the_fixed_point():
    """The default scene's drive flank at 12 positions, all its torques: the flattening's
    Newton update and the secant fixed point converge to the same loaded TCA (TE,
    stiffness, largest pressure within 1e-6 relative, the solver's load tolerance;
    measured 6e-8 at 24 positions), Newton in fewer outer iterations from a cold start
    (measured 5 against 8)."""
    from pathlib import Path

    from gearbox import load_scene
    from gearbox.geometry import PairSpec, design_pair
    from gearbox.ltca import LTCAOptions, ltca_cycle
    from gearbox.ltca.beveloid import scene_compliance, scene_grids
    from gearbox.ltca.solver import solve_contact

    scene = load_scene(Path(__file__).resolve().parents[1] / "models" / "marine_drive.toml")
    design = design_pair(PairSpec.from_scene(scene))
    grids, _, _ = scene_grids(design, scene, "R", 12)
    comp = scene_compliance(design, scene)
    out = {}
    for mode in ("fixed_point", "newton"):
        out[mode] = ltca_cycle(
            lambda f: grids[round(f * 12)],
            scene["load"]["torques_Nm"],
            options=LTCAOptions(positions=12),
            compliance=comp,
            solver=ContactSolver(flattening=mode),
        )
        assert out[mode].success
    for name in ("lte", "stiffness", "max_pressure"):
        a, b = getattr(out["fixed_point"], name), getattr(out["newton"], name)
        assert np.abs(a - b).max() < 1e-6 * np.abs(a).max()
    cold = [
        solve_contact(grids[3], comp, 802.0, solver=ContactSolver(flattening=mode))
        for mode in ("fixed_point", "newton")
    ]
    assert cold[1].outer_iterations < cold[0].outer_iterations
    assert cold[1].gap_residual <= cold[0].gap_residual + 1e-12
    with pytest.raises(Exception, match="flattening"):
        ContactSolver(flattening="broyden")

"""The settled periodic response solved directly by shooting (Newton on the period map).

The excitations (mesh, engine and propeller orders) share a common period T
(``DrivetrainModel.common_period_mesh_cycles``). A settled response returns to its
state after T, except for the rigid-body rotation, which may drift by a constant
(the mean speed settles slightly off nominal). Unknowns: the start state with the
propeller angle fixed at 0 (the rigid-body phase) and the drift d per period;
equations: ``y(T; y0) - y0 - d r = 0`` with r the rigid-body displacement (angles
1, 1, lambda_1/lambda_2, lambda_1/lambda_2; translations and speeds 0). Newton's
Jacobian is the monodromy matrix from forward-mode differentiation through diffrax
(``jax.jacfwd`` with ``diffrax.ForwardMode``). Reference: Nayfeh & Balachandran,
Applied Nonlinear Dynamics (1995), sec. 7.3 (shooting for periodic solutions).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..errors import InputError, Problem
from .diffrax_backend import DiffraxSolver, _jax
from .linear import periodic_start_state
from .model import DrivetrainModel, rhs

__all__ = ["PeriodicResponse", "periodic_response"]


@dataclass(frozen=True)
class PeriodicResponse:
    """Start state (unscaled, shape (2 n,)) of the periodic response, the period (s),
    the rigid-body drift per period (rad of engine angle), Newton iterations, the
    residual history (scaled state, max norm) and whether it converged."""

    y0: np.ndarray
    period: float
    drift: float
    iterations: int
    residuals: tuple[float, ...]
    converged: bool

    def to_dict(self) -> dict:
        return {
            "y0": self.y0.tolist(),
            "period_s": self.period,
            "drift_rad": self.drift,
            "iterations": self.iterations,
            "residuals": list(self.residuals),
            "converged": self.converged,
        }


def periodic_response(
    model: DrivetrainModel,
    solver: DiffraxSolver | None = None,
    *,
    max_iterations: int = 8,
    tol: float = 1e-7,
    y0: np.ndarray | None = None,
) -> PeriodicResponse:
    """Newton shooting over one common excitation period (see module docstring).

    solver: DiffraxSolver (default Tsit5, rtol 1e-9). tol: on the max norm of the scaled residual (states scaled by
    ``DrivetrainModel.state_scale``). Starts from ``periodic_start_state`` unless
    ``y0`` is given. Raises InputError when the model has no common period within
    100,000 mesh cycles.
    """
    jax, jnp = _jax()
    import diffrax

    solver = solver if solver is not None else DiffraxSolver(rtol=1e-9)
    cycles = model.common_period_mesh_cycles()
    if not cycles:
        raise InputError(
            Problem(
                "excitation orders", "incommensurate", "need a common period <= 1e5 mesh cycles"
            )
        )
    period = cycles / model.mesh_frequency
    p = {k: jnp.asarray(v) for k, v in model.params().items()}
    scale = np.asarray(model.params()["scale"])
    n = model.n_dof
    r = np.zeros(2 * n)
    ratio = model.drive.lambda1 / model.drive.lambda2
    r[:4] = [1.0, 1.0, ratio, ratio]
    r_s = jnp.asarray(r / scale)
    free = [i for i in range(2 * n) if i != 3]
    term = diffrax.ODETerm(lambda t, z, args: rhs(t, z, args, xp=jnp))
    ctrl = diffrax.PIDController(
        rtol=solver.rtol,
        atol=solver.atol or solver.rtol,
        pcoeff=solver.pcoeff,
        icoeff=solver.icoeff,
    )

    def flow(z0):
        sol = diffrax.diffeqsolve(
            term,
            getattr(diffrax, solver.solver)(),
            0.0,
            period,
            period / cycles / 20,
            z0,
            args=p,
            stepsize_controller=ctrl,
            max_steps=solver.max_steps,
            saveat=diffrax.SaveAt(t1=True),
            adjoint=diffrax.ForwardMode(),
        )
        return sol.ys[-1]

    def residual(u):
        z0 = jnp.zeros(2 * n).at[jnp.asarray(free)].set(u[:-1])
        return flow(z0) - z0 - u[-1] * r_s

    res_j = jax.jit(residual)
    jac_j = jax.jit(jax.jacfwd(residual))
    z = (periodic_start_state(model) if y0 is None else np.asarray(y0, float)) / scale
    z = z - z[3] * (r / scale) / (r[3] / scale[3])  # put the propeller angle at 0
    u = jnp.asarray(np.concatenate([z[free], [0.0]]))
    history = []
    converged = False
    it = 0
    for it in range(1, max_iterations + 1):
        f = res_j(u)
        norm = float(jnp.max(jnp.abs(f)))
        history.append(norm)
        if not math.isfinite(norm):
            break
        if norm < tol:
            converged = True
            it -= 1
            break
        u = u - jnp.linalg.solve(jac_j(u), f)
    else:
        f = res_j(u)
        history.append(float(jnp.max(jnp.abs(f))))
        converged = history[-1] < tol
    zf = np.zeros(2 * n)
    zf[free] = np.asarray(u[:-1])
    return PeriodicResponse(
        y0=zf * scale,
        period=period,
        drift=float(u[-1]),
        iterations=it,
        residuals=tuple(history),
        converged=converged,
    )

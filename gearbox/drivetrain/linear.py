"""Linear analysis about the operating point: modes and the periodic start state.

The model linearised about the static equilibrium with the mean drive-flank mesh
stiffness (docs/drivetrain.md §7): ``M x'' + C_lin x' + K_lin x = f``, with

    K_lin = K_s + kbar G_d^T G_d (+ K_i on the engine with a governor)
    C_lin = C_s + c_d G_d^T G_d + 2 kappa Omega_2 on the propeller (+ K_p on the engine)
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..meshtable import fourier_eval
from .model import DrivetrainModel

__all__ = [
    "Modes",
    "largest_stable_step",
    "linear_matrices",
    "modes",
    "periodic_start_state",
    "periodic_start_states",
]

#: Accepted growth per step of a mode in :func:`largest_stable_step`: |R(h lambda)| <=
#: 1 + 1e-8 amplifies an undamped mode by 1 % only after 1e6 steps.
STEP_GROWTH = 1e-8


def largest_stable_step(lam: np.ndarray, poly: np.ndarray, growth: float = STEP_GROWTH):
    """Largest fixed step h (s) with |R(h lambda_j)| <= 1 + growth for every eigenvalue.

    lam: eigenvalues (1/s) of a linear first-order system, shape (m,) or (B, m) for B
    systems at once (zeros are ignored); poly: coefficients c_0, c_1, ... of the
    explicit method's stability polynomial R(z) = sum c_k z^k (Hairer, Wanner, Solving
    ODEs II, Sec. IV.2). A scan over [0, 6 / max |lambda|] finds the first unstable
    step, 50 bisections refine it. Returns a float, or shape (B,).
    """
    lam = np.asarray(lam, dtype=complex)
    single = lam.ndim == 1
    lam = np.atleast_2d(lam)
    c = np.asarray(poly, dtype=float)
    mag = np.abs(lam)
    top = mag.max(axis=1)

    def ok(h: np.ndarray) -> np.ndarray:  # h shape (B, k) -> (B, k)
        z = h[..., None] * lam[:, None, :]
        r = np.abs(np.polyval(c[::-1], z))
        return np.all((r <= 1.0 + growth) | (mag[:, None, :] == 0), axis=-1)

    hi = 6.0 / top
    grid = np.linspace(0.0, 1.0, 241)[1:][None, :] * hi[:, None]
    good = ok(grid)
    first_bad = np.where(good.all(axis=1), grid.shape[1], np.argmin(good, axis=1))
    rows = np.arange(lam.shape[0])
    lo = np.where(first_bad > 0, grid[rows, np.maximum(first_bad - 1, 0)], 0.0)
    up = grid[rows, np.minimum(first_bad, grid.shape[1] - 1)]
    for _ in range(50):
        mid = 0.5 * (lo + up)
        good_mid = ok(mid[:, None])[:, 0]
        lo = np.where(good_mid, mid, lo)
        up = np.where(good_mid, up, mid)
    out = np.where(first_bad == grid.shape[1], hi, lo)
    return float(out[0]) if single else out


def linear_matrices(model: DrivetrainModel) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M, C_lin, K_lin), each shape (n, n), SI."""
    K, C = model.structural_matrices()
    g = model.mesh_vectors()[0]
    K = K + model.drive.mean_stiffness * np.outer(g, g)
    C = C + model.drive.damping * np.outer(g, g)
    C[3, 3] += 2 * model.propeller_coefficient * model.gear_speed
    if model.governor:
        C[0, 0] += model.governor_kp
        K[0, 0] += model.governor_ki
    return np.diag(model.mass_vector()), C, K


@dataclass(frozen=True)
class Modes:
    """Undamped modes: frequencies (Hz), shape (n,), ascending; shapes (n, n), columns
    mass-normalised; names of the coordinates; descriptions (dominant coordinates and
    the share of modal strain energy in the mesh)."""

    frequencies: np.ndarray
    shapes: np.ndarray
    dof_names: tuple[str, ...]
    mesh_energy_fraction: np.ndarray

    def descriptions(self) -> list[str]:
        out = []
        for i, f in enumerate(self.frequencies):
            phi = self.shapes[:, i]
            order = np.argsort(-np.abs(phi))[:2]
            dom = " and ".join(self.dof_names[j] for j in order)
            kind = (
                "rigid-body"
                if f < 1e-6
                else ("mesh" if self.mesh_energy_fraction[i] > 0.5 else "shaft")
            )
            out.append(
                f"{kind} mode, {f:.4g} Hz, largest motion at {dom}, "
                f"mesh strain energy {100 * self.mesh_energy_fraction[i]:.0f} %"
            )
        return out

    def to_dict(self) -> dict:
        return {
            "eigenfrequencies_Hz": self.frequencies.tolist(),
            "modes": [
                {
                    "frequency_Hz": float(f),
                    "description": d,
                    "shape": dict(zip(self.dof_names, self.shapes[:, i].tolist(), strict=True)),
                    "mesh_strain_energy_fraction": float(self.mesh_energy_fraction[i]),
                }
                for i, (f, d) in enumerate(zip(self.frequencies, self.descriptions(), strict=True))
            ],
        }


def modes(model: DrivetrainModel) -> Modes:
    """Eigenfrequencies and mass-normalised mode shapes of ``K_lin phi = w^2 M phi``."""
    import scipy.linalg  # here: unpickling Modes (the report's worker) needs no scipy

    M, _, K = linear_matrices(model)
    w2, phi = scipy.linalg.eigh(K, M)
    w2 = np.clip(w2, 0.0, None)
    g = model.mesh_vectors()[0]
    kbar = model.drive.mean_stiffness
    mesh_e = kbar * (g @ phi) ** 2
    tot = np.einsum("ij,ik,kj->j", phi, K, phi)
    frac = np.where(tot > 0, mesh_e / np.where(tot > 0, tot, 1.0), 0.0)
    return Modes(np.sqrt(w2) / (2 * math.pi), phi, model.dof_names, frac)


def _mesh_forcing(model: DrivetrainModel, x_static: np.ndarray, samples: int = 256):
    """Fourier coefficients (complex, per mesh harmonic) of the first-order mesh forcing.

    f(theta) = k(theta) (delta_s - e(theta)) - kbar (delta_s - ebar), N; generalised force
    -G_d f. Returns (harmonic numbers h, complex amplitudes F_h with f = sum Im(F_h e^{i h N1 theta}))
    """
    fl = model.drive
    th = np.arange(samples) * (2 * math.pi / model.pinion_teeth / samples)
    hk = (fl.k_coef.size - 1) // 2
    he = (fl.e_coef.size - 1) // 2
    k, _ = fourier_eval(
        fl.k_coef[0], fl.k_coef[1 : 1 + hk], fl.k_coef[1 + hk :], model.pinion_teeth, th[:, None]
    )
    e, _ = fourier_eval(
        fl.e_coef[0], fl.e_coef[1 : 1 + he], fl.e_coef[1 + he :], model.pinion_teeth, th[:, None]
    )
    ds = model.mesh_vectors()[0] @ x_static
    f = k * (ds - e) - fl.k_coef[0] * (ds - fl.e_coef[0])
    c = np.fft.rfft(f) / samples
    h = np.arange(1, samples // 2)
    # f = sum 2 Re(c_h e^{i h w}) = sum Im(2 i c_h e^{i h w})
    return h, 2j * c[1 : samples // 2]


def periodic_start_state(model: DrivetrainModel, *, mesh_harmonics: int = 12) -> np.ndarray:
    """Static equilibrium plus the linear steady response to every periodic excitation.

    Engine and propeller orders and the first ``mesh_harmonics`` harmonics of the mesh
    forcing (parametric stiffness and error, to first order) are each solved as
    ``(K_lin - w^2 M + i w C_lin) X = F``; their sum at t = 0 starts the nonlinear run
    close to its periodic response, so only small transients remain. Shape (2 n,).
    """
    return periodic_start_states(model, np.array([model.speed]), mesh_harmonics=mesh_harmonics)[0]


def periodic_start_states(
    model: DrivetrainModel, speeds: np.ndarray, *, mesh_harmonics: int = 12
) -> np.ndarray:
    """:func:`periodic_start_state` of ``model.with_speed(w)`` for every w in ``speeds``
    (rad/s, shape (B,)), as batched linear algebra. Shape (B, 2 n).

    Only the excitation frequencies and the propeller's speed damping 2 kappa Omega_2
    change with the speed (kappa Omega_2^2 = T_op lambda_2 / lambda_1 does not, nor do
    the static state and the mesh forcing): one batched solve of shape (B, L, n, n) for
    the L excitations.
    """
    speeds = np.asarray(speeds, dtype=float).ravel()
    n = model.n_dof
    y = model.static_state()
    M, C, K = linear_matrices(model)
    C = C.copy()
    ratio = model.pinion_teeth / model.gear_teeth
    C[3, 3] -= 2 * model.propeller_coefficient * model.gear_speed  # speed part, re-added below
    tp = model.propeller_coefficient * model.gear_speed**2  # independent of the speed
    eo, ea, po, pa = model.excitation_orders()
    orders, forces = [], []  # order per engine radian, force vector
    for o, a in zip(eo, ea, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[0] = model.torque * a
            orders.append(o)
            forces.append(f)
    for o, a in zip(po, pa, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[3] = -tp * a
            orders.append(o * ratio)
            forces.append(f)
    g = model.mesh_vectors()[0]
    h, F = _mesh_forcing(model, y[:n])
    for hh, Fh in zip(h[:mesh_harmonics], F[:mesh_harmonics], strict=True):
        orders.append(hh * model.pinion_teeth)
        forces.append(-g * Fh)
    out = np.broadcast_to(y, (speeds.size, 2 * n)).copy()
    if not orders:
        return out
    w = speeds[:, None] * np.asarray(orders)[None, :]  # (B, L)
    c_prop = 2 * model.torque * (model.drive.lambda2 / model.drive.lambda1) / (speeds * ratio)
    Cb = np.broadcast_to(C, (speeds.size, n, n)).copy()
    Cb[:, 3, 3] += c_prop
    A = (
        K[None, None]
        - (w**2)[..., None, None] * M[None, None]
        + 1j * w[..., None, None] * Cb[:, None]
    )
    X = np.linalg.solve(A, np.broadcast_to(np.asarray(forces), w.shape + (n,))[..., None])[..., 0]
    # forcing Im(f e^{iwt}) -> response Im(X e^{iwt}); at t = 0: Im(X), Im(i w X)
    out[:, :n] += X.imag.sum(axis=1)
    out[:, n:] += (1j * w[..., None] * X).imag.sum(axis=1)
    return out

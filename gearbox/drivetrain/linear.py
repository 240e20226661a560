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
import scipy.linalg

from ..meshtable import fourier_eval
from .model import DrivetrainModel

__all__ = ["Modes", "linear_matrices", "modes", "periodic_start_state"]


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
    n = model.n_dof
    y = model.static_state().copy()
    M, C, K = linear_matrices(model)
    eo, ea, po, pa = model.excitation_orders()
    loads = []
    for o, a in zip(eo, ea, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[0] = model.torque * a
            loads.append((o * model.speed, f))
    tp = model.propeller_coefficient * model.gear_speed**2
    for o, a in zip(po, pa, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[3] = -tp * a
            loads.append((o * model.gear_speed, f))
    g = model.mesh_vectors()[0]
    h, F = _mesh_forcing(model, y[:n])
    for hh, Fh in zip(h[:mesh_harmonics], F[:mesh_harmonics], strict=True):
        loads.append((hh * model.pinion_teeth * model.speed, -g * Fh))
    for w, f in loads:
        X = np.linalg.solve(K - w**2 * M + 1j * w * C, f)
        # forcing Im(f e^{iwt}) -> response Im(X e^{iwt}); at t = 0: Im(X), Im(i w X)
        y[:n] += X.imag
        y[n:] += (1j * w * X).imag
    return y

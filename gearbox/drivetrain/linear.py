"""Linear analysis about the operating point: modes and the periodic start state.

The model linearised about the static equilibrium with the mean drive-flank mesh
stiffness (docs/drivetrain.md §7): ``M x'' + C_lin x' + K_lin x = f``, with

    K_lin = K_s + kbar W_d^T G_d (+ K_i on the engine with a governor)
    C_lin = C_s + c_d W_d^T G_d + 2 kappa Omega_2 on the propeller (+ K_p on the engine)

W_d = G_d + Phi_d, Phi_d the mesh friction's mean generalised direction (§3a; zero
without friction, and then both matrices are symmetric).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .model import DrivetrainModel, _series_rows

__all__ = [
    "Modes",
    "OrderResponse",
    "RESPONSE_CHANNELS",
    "largest_stable_step",
    "linear_matrices",
    "eccentricity_harmonic_balance",
    "excitation_harmonic_balance",
    "mesh_harmonic_balance",
    "modes",
    "order_responses",
    "periodic_start_state",
    "pitch_harmonic_balance",
    "pitch_lines",
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


def linear_matrices(
    model: DrivetrainModel, *, friction: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(M, C_lin, K_lin), each shape (n, n), SI. friction: keep the mesh friction's
    mean generalised direction (non-conservative: the matrices lose their symmetry);
    False for the undamped modes."""
    K, C = model.structural_matrices()
    g = model.mesh_vectors()[0]
    w = g + model.friction_vectors()[0] if friction else g
    K = K + model.drive.mean_stiffness * np.outer(w, g)
    C = C + model.drive.damping * np.outer(w, g)
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
        """Kind (rigid-body, shaft or mesh mode), frequency, the two coordinates moving
        most and the share of strain energy in the mesh, per mode. A mode is rigid-body
        below 1e-6 of the highest frequency: the eigensolver leaves the line's free
        rotation at a few 1e-9 of it (8.5e-6 Hz beside 2170 Hz on the default scene),
        not at zero."""
        out = []
        rigid = 1e-6 * max(float(np.max(self.frequencies, initial=0.0)), 1.0)
        for i, f in enumerate(self.frequencies):
            phi = self.shapes[:, i]
            order = np.argsort(-np.abs(phi))[:2]
            dom = " and ".join(self.dof_names[j] for j in order)
            kind = (
                "rigid-body"
                if f < rigid
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
    """Eigenfrequencies and mass-normalised mode shapes of ``K_lin phi = w^2 M phi``,
    the undamped and frictionless linear model (friction, like damping, is left out of
    the modes)."""
    import scipy.linalg  # here: unpickling Modes (the report's worker) needs no scipy

    M, _, K = linear_matrices(model, friction=False)
    w2, phi = scipy.linalg.eigh(K, M)
    w2 = np.clip(w2, 0.0, None)
    g = model.mesh_vectors()[0]
    kbar = model.drive.mean_stiffness
    mesh_e = kbar * (g @ phi) ** 2
    tot = np.einsum("ij,ik,kj->j", phi, K, phi)
    frac = np.where(tot > 0, mesh_e / np.where(tot > 0, tot, 1.0), 0.0)
    return Modes(np.sqrt(w2) / (2 * math.pi), phi, model.dof_names, frac)


def _drive_laws(model: DrivetrainModel, samples: int):
    """The drive flank's laws at ``samples`` pinion angles over one mesh cycle: k (N/m),
    e (m), de/dtheta_1 (m/rad), each (S,), and the mesh force's generalised direction
    W(theta) = G_d + Phi_d(theta), (S, n) (docs/drivetrain.md §3a; G_d without friction)."""
    fl = model.drive
    th = np.arange(samples) * (2 * math.pi / model.pinion_teeth / samples)
    n1 = model.pinion_teeth
    k = _series_rows(th, fl.k_coef, n1, np)
    e, de = _series_rows(th, fl.e_coef, n1, np, derivative=True)
    W = np.broadcast_to(model.mesh_vectors()[0], (samples, model.n_dof)).copy()
    mu = model.mesh_friction_coefficient
    if mu > 0 and fl.friction_coef is not None:
        arms = _series_rows(th, fl.friction_coef, n1, np)  # (S, 2)
        W[:, 1] += mu * arms[:, 0]
        W[:, 2] -= mu * arms[:, 1]
    return k, e, de, W


def _mesh_forcing(model: DrivetrainModel, x_static: np.ndarray, samples: int = 256):
    """Fourier coefficients (complex, per mesh harmonic) of the first-order mesh forcing.

    f(theta) = k(theta) (delta_s - e(theta)) - kbar (delta_s - ebar), N; its generalised
    force -W(theta) (f(theta) + F) with F the static mesh force (the friction's arms
    vary along the cycle under the static load too; -G_d f without friction). Returns
    (harmonic numbers h, complex amplitudes F_h with f = sum Im(F_h e^{i h N1 theta}),
    generalised force amplitudes, (H, n), likewise)
    """
    fl = model.drive
    k, e, _, W = _drive_laws(model, samples)
    ds = model.mesh_vectors()[0] @ x_static
    f = k * (ds - e) - fl.k_coef[0] * (ds - fl.e_coef[0])
    q = -W * (f + fl.k_coef[0] * (ds - fl.e_coef[0]))[:, None]
    c = np.fft.rfft(f) / samples
    cq = np.fft.rfft(q, axis=0) / samples
    h = np.arange(1, samples // 2)
    # f = sum 2 Re(c_h e^{i h w}) = sum Im(2 i c_h e^{i h w})
    return h, 2j * c[1 : samples // 2], 2j * cq[1 : samples // 2]


def periodic_start_state(model: DrivetrainModel, *, mesh_harmonics: int = 12) -> np.ndarray:
    """Static equilibrium plus the linear steady response to every periodic excitation.

    Engine and propeller orders and the first ``mesh_harmonics`` harmonics of the mesh
    forcing (parametric stiffness and error, to first order) are each solved as
    ``(K_lin - w^2 M + i w C_lin) X = F``, the eccentricities with their sidebands by
    harmonic balance (:func:`eccentricity_harmonic_balance`); their sum at t = 0
    starts the nonlinear run close to its periodic response, so only small transients
    remain. Shape (2 n,).
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
    out = np.broadcast_to(y, (speeds.size, 2 * n)).copy()
    exc = _excitations(model, y[:n], mesh_harmonics)
    if exc.orders.size:
        w, X = _steady_amplitudes(model, speeds, exc)
        # forcing Im(f e^{iwt}) -> response Im(X e^{iwt}); at t = 0: Im(X), Im(i w X)
        out[:, :n] += X.imag.sum(axis=1)
        out[:, n:] += (1j * w[..., None] * X).imag.sum(axis=1)
    # the eccentricities and pitch deviations with their sidebands (harmonic balance,
    # docs §3b, §3c)
    lines = [
        (orders, X)
        for _, orders, X, _ in eccentricity_harmonic_balance(
            model, speeds, harmonics=max(mesh_harmonics, 1)
        )
    ]
    if model.pitch is not None:
        lines.append(pitch_harmonic_balance(model, speeds, harmonics=max(mesh_harmonics, 1))[:2])
    for orders, X in lines:
        w = speeds[:, None] * orders[None, :]
        out[:, :n] += X.imag.sum(axis=1)
        out[:, n:] += (1j * w[..., None] * X).imag.sum(axis=1)
    return out


@dataclass(frozen=True)
class _Excitations:
    """The model's periodic excitations: orders (per pinion revolution), shape (L,);
    sources ('engine', 'engine-half', 'propeller', 'mesh'); generalised force
    amplitudes (complex, (L, n)); the first-order mesh force itself (complex, (L,),
    nonzero for the mesh harmonics)."""

    orders: np.ndarray
    sources: tuple[str, ...]
    forces: np.ndarray
    mesh_forcing: np.ndarray


def _excitations(model: DrivetrainModel, x_static: np.ndarray, mesh_harmonics: int) -> _Excitations:
    """Engine and propeller orders with a nonzero amplitude and the first
    ``mesh_harmonics`` harmonics of the mesh forcing, as force amplitudes F with the
    forcing Im(F e^{i w t})."""
    n = model.n_dof
    ratio = model.pinion_teeth / model.gear_teeth
    tp = model.propeller_coefficient * model.gear_speed**2  # independent of the speed
    eo, ea, po, pa = model.excitation_orders()
    firing = model.engine_cylinders / 2.0
    orders, sources, forces, mesh = [], [], [], []
    for o, a in zip(eo, ea, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[0] = model.torque * a
            orders.append(o)
            sources.append(
                "engine" if math.isclose(o / firing, round(o / firing)) else "engine-half"
            )
            forces.append(f)
            mesh.append(0j)
    for o, a in zip(po, pa, strict=True):
        if a != 0:
            f = np.zeros(n, complex)
            f[3] = -tp * a
            orders.append(o * ratio)
            sources.append("propeller")
            forces.append(f)
            mesh.append(0j)
    h, F, Q = _mesh_forcing(model, x_static) if mesh_harmonics > 0 else ((), (), ())
    for hh, Fh, Qh in zip(h[:mesh_harmonics], F[:mesh_harmonics], Q[:mesh_harmonics], strict=True):
        orders.append(hh * model.pinion_teeth)
        sources.append("mesh")
        forces.append(Qh)
        mesh.append(Fh)
    return _Excitations(
        np.asarray(orders, dtype=float),
        tuple(sources),
        np.asarray(forces, dtype=complex).reshape(len(orders), n),
        np.asarray(mesh, dtype=complex),
    )


def _steady_amplitudes(model: DrivetrainModel, speeds: np.ndarray, exc: _Excitations):
    """Excitation circular frequencies w (rad/s, (B, L)) and the complex steady
    amplitudes X of the linear model, (B, L, n): ``(K_lin - w^2 M + i w C_lin(Omega))
    X = F`` with the propeller's speed damping 2 kappa Omega_2 at each speed."""
    n = model.n_dof
    M, C, K = linear_matrices(model)
    w = speeds[:, None] * exc.orders[None, :]  # (B, L)
    Cb = _damping_at(model, C, speeds)
    A = (
        K[None, None]
        - (w**2)[..., None, None] * M[None, None]
        + 1j * w[..., None, None] * Cb[:, None]
    )
    F = np.broadcast_to(exc.forces, w.shape + (n,))[..., None]
    return w, np.linalg.solve(A, F)[..., 0]


#: The response channels: output name, OrderResponse array, its mean load, unit.
RESPONSE_CHANNELS = (
    ("mesh_force_N", "mesh_force", "mean_mesh_force", "N"),
    ("input_shaft_torque_Nm", "input_shaft_torque", "mean_input_torque", "N m"),
    ("output_shaft_torque_Nm", "output_shaft_torque", "mean_output_torque", "N m"),
)


@dataclass(frozen=True)
class OrderResponse:
    """The steady response about the operating point to each periodic excitation
    (:func:`order_responses`: engine and propeller orders each alone on the linear
    model, the mesh orders together by harmonic balance); an amplitude A stands for
    Im(A e^{i w t}), so its modulus is the peak value of that order's sinusoid.

    speeds: engine (= pinion) speeds (rad/s), shape (B,); orders: cycles per pinion
    revolution, shape (L,); sources: 'engine' (firing order and harmonics),
    'engine-half', 'propeller' or 'mesh' per order; states: complex amplitudes of the
    coordinates (rad, m), shape (B, L, n); mesh_force: dynamic drive-flank mesh force
    along the line of action (N), (k_bar + i w c) G X plus the mesh forcing itself for
    the mesh orders; input_shaft_torque, output_shaft_torque: (N m), (k + i w c) times
    the shaft's twist; each (B, L). mean_mesh_force, mean_input_torque,
    mean_output_torque: the static values they vibrate about (N, N m, N m).
    """

    speeds: np.ndarray
    orders: np.ndarray
    sources: tuple[str, ...]
    states: np.ndarray
    mesh_force: np.ndarray
    input_shaft_torque: np.ndarray
    output_shaft_torque: np.ndarray
    mean_mesh_force: float
    mean_input_torque: float
    mean_output_torque: float

    def order_index(self, order: float) -> int | None:
        """Index of ``order`` (cycles per pinion revolution) among the excitations, or
        None when the model does not excite it."""
        hit = np.flatnonzero(np.isclose(self.orders, order, rtol=1e-9, atol=0.0))
        return int(hit[0]) if hit.size else None

    def peaks(self, order: float, speed: int = 0) -> dict[str, float]:
        """Peak amplitudes at ``order`` and the ``speed``-th speed: ``mesh_force_N``,
        ``input_shaft_torque_Nm``, ``output_shaft_torque_Nm`` and each over its mean
        (``*_fraction``); zeros for an order the model does not excite."""
        i = self.order_index(order)
        out = {}
        for name, field, mean_field, _ in RESPONSE_CHANNELS:
            arr, mean = getattr(self, field), getattr(self, mean_field)
            a = 0.0 if i is None else float(abs(arr[speed, i]))
            out[name] = a
            out[name.rsplit("_", 1)[0] + "_fraction"] = a / abs(mean) if mean else math.inf
        return out


def _damping_at(model: DrivetrainModel, C: np.ndarray, speeds: np.ndarray) -> np.ndarray:
    """C_lin at each of ``speeds`` (rad/s), (B, n, n): the propeller's speed damping
    2 kappa Omega_2 = 2 T_op (T_2 / T_1) / Omega_2 taken at that speed
    (:attr:`DrivetrainModel.torque_ratio`)."""
    ratio = model.pinion_teeth / model.gear_teeth
    Cb = np.broadcast_to(C, (speeds.size,) + C.shape).copy()
    Cb[:, 3, 3] += -2 * model.propeller_coefficient * model.gear_speed + 2 * model.torque * (
        model.torque_ratio
    ) / (speeds * ratio)
    return Cb


@dataclass(frozen=True)
class _Hill:
    """The linear time-periodic model's harmonic-balance system for one family of
    frequencies w_h = w_0 + h w_m, h = -H..H (w_m = N_1 Omega, w_0 = o_0 Omega): the
    drive flank's laws in theta_1 (Fourier coefficients at index j mod S: kap of k, wk
    of W k, wc of c W, (S, n)), the matrix A (B, m n, m n) and w_h (B, m)."""

    hs: np.ndarray
    freq: np.ndarray
    A: np.ndarray
    kap: np.ndarray
    wk: np.ndarray
    wc: np.ndarray
    g: np.ndarray
    fq: np.ndarray  # (B, S): the mesh force's stiffness on q_1, coefficients
    fd: np.ndarray  # (S,): its damping on v_1, coefficients
    k: np.ndarray
    e: np.ndarray
    de: np.ndarray
    W: np.ndarray
    samples: int

    def solve(self, rhs: np.ndarray, drop: int | None = None) -> np.ndarray:
        """X (B, m, n) of A X = rhs (B, m, n); ``drop``: an unknown held at 0."""
        B, m, n = rhs.shape
        A = self.A
        keep = np.ones(m * n, bool)
        if drop is not None:
            keep[drop] = False
        X = np.zeros((B, m * n), complex)
        r = rhs.reshape(B, m * n)
        X[:, keep] = np.linalg.solve(A[:, keep][:, :, keep], r[:, keep][..., None])[..., 0]
        return X.reshape(B, m, n)

    def mesh_force(self, X: np.ndarray, damping: float) -> np.ndarray:
        """The dynamic mesh force's part from the vibration X, (B, m): sum_j kap_{h-j}
        G.X_j + i w_h c G.X_h, and with the pinion angle followed sum_j [(f_q)_{h-j} +
        i w_j (f_v)_{h-j}] X_j1."""
        gx = X @ self.g
        dh = (self.hs[:, None] - self.hs[None, :]) % self.samples
        f = np.einsum("hj,bj->bh", self.kap[dh], gx) + 1j * self.freq * damping * gx
        q1 = X[..., 1]
        f += np.einsum("bhj,bj->bh", self.fq[:, dh], q1)
        f += np.einsum("hj,bj->bh", self.fd[dh], 1j * self.freq * q1)
        return f


def _d_theta(v: np.ndarray, teeth: int) -> np.ndarray:
    """d/d theta_1 of samples over one mesh cycle (axis 0), spectrally (the samples are
    truncated Fourier series below the Nyquist harmonic)."""
    S = v.shape[0]
    j = np.fft.fftfreq(S, 1.0 / S) * teeth
    j[S // 2] = 0.0 if S % 2 == 0 else j[S // 2]
    c = np.fft.fft(v, axis=0)
    return np.fft.ifft(1j * j.reshape((S,) + (1,) * (v.ndim - 1)) * c, axis=0).real


def _hill(
    model: DrivetrainModel,
    sp: np.ndarray,
    harmonics: int,
    samples: int,
    order0: float,
    follow_angle: bool = True,
    base: tuple[np.ndarray, np.ndarray] | None = None,
):
    """:class:`_Hill` at the speeds ``sp`` (rad/s, (B,)) for the family w_0 + h w_m,
    w_0 = ``order0`` Omega: for h = -H..H the blocks

        (K_s - w_h^2 M + i w_h C_s) X_h + sum_j [(W k)_{h-j} + i w_j c W_{h-j}] G.X_j
            + sum_j [(W f_q + W' F_0)_{h-j} + i w_j (W f_v)_{h-j}] X_j1

    (docs of :func:`mesh_harmonic_balance`). The last line (``follow_angle``) is the
    mesh laws' dependence on the pinion's vibration q_1 (theta_1 = Omega t + q_1):
    f_q = k' s_0 - k e' - c e'' Omega, f_v = -c e', F_0 = k s_0 + c s_0' the force
    along the motion linearised about, whose approach s_0 is delta_s - e(theta_1) (the
    static state), plus ``base`` = (deflection, rate) samples (B, S) of a periodic
    motion (the mesh orders' response, for the eccentricities)."""
    return _hill_families(model, sp, harmonics, samples, follow_angle, base)(order0)


def _hill_families(
    model: DrivetrainModel,
    sp: np.ndarray,
    harmonics: int,
    samples: int,
    follow_angle: bool = True,
    base: tuple[np.ndarray, np.ndarray] | None = None,
):
    """``assemble(order0) -> _Hill`` of :func:`_hill`: the parts that do not depend on
    the family's w_0 computed once for every family."""
    n, H = model.n_dof, int(harmonics)
    fl = model.drive
    k, e, de, W = _drive_laws(model, samples)
    g = model.mesh_vectors()[0]
    kap = np.fft.fft(k) / samples  # kappa_j at index j mod samples
    wk = np.fft.fft(W * k[:, None], axis=0) / samples  # (S, n)
    wc = fl.damping * np.fft.fft(W, axis=0) / samples
    wbar = g + model.friction_vectors()[0]  # the linear model's mean direction
    hs = np.arange(-H, H + 1)
    M, C, K = linear_matrices(model)
    Cb = _damping_at(model, C, sp)  # (B, n, n)
    m = hs.size
    B = sp.size
    # blocks (h, j): (W k)_{h-j} g^T + i w_j (W c)_{h-j} g^T, less the linear model's
    # share on the diagonal, which holds K_lin - w_h^2 M + i w_h C_lin
    dh = (hs[:, None] - hs[None, :]) % samples
    eye = (hs[:, None] == hs[None, :])[..., None]
    stiff = wk[dh] - eye * fl.mean_stiffness * wbar  # (m, m, n)
    damp = wc[dh] - eye * fl.damping * wbar
    fq = np.zeros((B, samples), complex)
    fd = np.zeros(samples, complex)
    sq = sv = None
    if follow_angle:
        t1 = model.pinion_teeth
        c = fl.damping
        # the motion linearised about: the static deflection, plus a periodic one
        s0 = g @ model.static_state()[:n] - e + np.zeros((B, 1))  # (B, S)
        r0 = -de[None] * sp[:, None]
        if base is not None:
            s0 = s0 + base[0]
            r0 = r0 + base[1]
        dk, dde, dW = _d_theta(k, t1), _d_theta(de, t1), _d_theta(W, t1)
        f0 = k * s0 + c * r0  # the mesh force along that motion
        q = dk * s0 - k * de - c * dde * sp[:, None]  # its change per radian of q_1
        sq = (np.fft.fft(W * q[..., None] + dW * f0[..., None], axis=1) / samples)[:, dh]
        sv = (np.fft.fft(-c * W * de[:, None], axis=0) / samples)[dh]  # damping on v_1
        fq = np.fft.fft(q, axis=1) / samples
        fd = np.fft.fft(-c * de) / samples
    idx = np.arange(m)

    def assemble(order0: float) -> _Hill:
        freq = (order0 + hs[None, :] * float(model.pinion_teeth)) * sp[:, None]  # (B, m)
        jw = freq[:, None, :, None]  # (B, 1, m, 1): column j
        blk = stiff[None] + 1j * jw * damp[None]  # (B, m, m, n)
        A = blk.transpose(0, 1, 3, 2)[..., None] * g  # (B, m, n, m, n): [b, h, row, j, col]
        if sq is not None:
            A[:, :, :, :, 1] += (sq + 1j * jw * sv[None]).transpose(0, 1, 3, 2)
        wh = freq[:, :, None, None]  # (B, m, 1, 1)
        diag = K - wh**2 * M + 1j * wh * Cb[:, None]  # (B, m, n, n)
        A[:, idx, :, idx, :] += diag.transpose(1, 0, 2, 3)
        A = A.reshape(B, m * n, m * n)
        return _Hill(hs, freq, A, kap, wk, wc, g, fq, fd, k, e, de, W, samples)

    return assemble


def mesh_harmonic_balance(
    model: DrivetrainModel,
    speeds=None,
    *,
    harmonics: int = 12,
    samples: int = 256,
    follow_angle: bool = True,
) -> tuple[np.ndarray, np.ndarray]:
    """Steady response to the mesh excitation with the mesh stiffness varying in time.

    The drive flank in contact throughout, about the static state x_s: the mesh force
    f = k(theta) (G (x_s + x) - e(theta)) + c (G x' - e'(theta) Omega) keeps its
    parametric stiffness k(theta) x, which :func:`periodic_start_states` drops (it
    takes k_bar x), and acts along W(theta) = G + Phi(theta), the friction's varying
    arms included (docs/drivetrain.md §3a; W = G without friction). With
    x = sum_h X_h exp(i h w_m t), w_m = N_1 Omega, harmonic balance (Hill's method)
    gives for h = -H..H

        (K_s - (h w_m)^2 M + i h w_m C_s) X_h
            + sum_j [(W k)_{h-j} + i j w_m c W_{h-j}] G.X_j = -[W p]_h,

    (.)_j the Fourier coefficients in theta, K_s and C_s the linear model's without
    the mesh, p = k(theta) (delta_s - e(theta)) - c e'(theta) Omega less the static
    mesh force (whose balance the static state holds). The mean X_0 holds the
    propeller angle at 0 (as the static state). Exact for the time-periodic linear model up to the truncation H (the
    nonlinear model adds contact loss and theta_1's dependence on the vibration).

    Returns (X, f): peak amplitudes A of the coordinates (rad, m), shape (B, H, n),
    and of the dynamic mesh force (N), (B, H), for the mesh orders h N_1, h = 1..H,
    each as Im(A exp(i h w_m t)).
    """
    sp = np.atleast_1d(np.asarray(model.speed if speeds is None else speeds, dtype=float))
    n, H = model.n_dof, int(harmonics)
    fl = model.drive
    hill = _hill(model, sp, H, samples, 0.0, follow_angle)
    k, e, de, W = hill.k, hill.e, hill.de, hill.W
    g = hill.g
    ds = g @ model.static_state()[:n]
    F0 = fl.k_coef[0] * (ds - fl.e_coef[0])  # the static mesh force
    pk = np.fft.fft(k * (ds - e)) / samples
    pk[0] -= F0
    cd = np.fft.fft(de) / samples  # coefficients of de/dtheta_1
    # the generalised force -W(theta) F: the forcing W k (ds - e), W e'
    wbar = g + model.friction_vectors()[0]
    wp = np.fft.fft(W * (k * (ds - e))[:, None], axis=0) / samples
    wp[0] -= wbar * F0  # the static state's balance
    wd = np.fft.fft(W * de[:, None], axis=0) / samples
    hs = hill.hs
    # forcing -W (k (ds - e) - F0 - c e' Omega), Omega the speed
    rhs = -(wp[hs % samples][None] - fl.damping * sp[:, None, None] * wd[hs % samples][None])
    X = hill.solve(rhs, drop=H * n + 3)  # h = 0: the propeller angle stays at 0
    P = pk[hs % samples][None, :] - fl.damping * sp[:, None] * cd[hs % samples][None, :]
    f = hill.mesh_force(X, fl.damping) + P
    # real signal sum_h c_h e^{i h w t}: order h > 0 is Im(2 i c_h e^{i h w t})
    pos = slice(H + 1, None)
    return 2j * X[:, pos], 2j * f[:, pos]


#: The eccentric members: name, eccentricity attribute, columns of
#: :meth:`DrivetrainModel.eccentricity_coefficients`.
ECCENTRIC_MEMBERS = (("pinion", "pinion_eccentricity", 0), ("gear", "gear_eccentricity", 2))


def _vibration_samples(model, sp, Xm, samples):
    """The mesh orders' steady vibration of the approach, G.x and its rate, at
    ``samples`` pinion angles over one mesh cycle: two arrays (B, S), from the
    coordinates' amplitudes Xm (B, H, n) of :func:`mesh_harmonic_balance`."""
    gx = Xm @ model.mesh_vectors()[0]  # (B, H), Im(A e^{i h N1 theta})
    hh = np.arange(1, gx.shape[1] + 1) * float(model.pinion_teeth)
    th = np.arange(samples) * (2 * math.pi / model.pinion_teeth / samples)
    ph = np.exp(1j * hh[:, None] * th[None, :])  # (H, S)
    return (gx @ ph).imag, ((1j * gx * hh * sp[:, None]) @ ph).imag


def _family(model, sp, assemble, order0, phi0, *, approach=0j, force=None):
    """Steady response of the family w_0 + h w_m (w_0 = ``order0`` Omega) to a forcing
    in the frame theta = Omega t + phi0, phi0 = q_1s + theta_10 (the pinion's angle at
    the static state): the drive flank's approach Re(sum_h E_h e^{i (o_0 + h N_1)
    theta}) (``approach`` = E_0, or E_h over h = -H..H, shape (2 H + 1,)), or the
    generalised force Re(F e^{i o_0 theta}) (``force`` = F, (n,)). Returns (orders
    |o_0 + h N_1|, coordinates (B, L, n), mesh force (B, L)), each as Im(A e^{i w t}) in
    the model's time t."""
    fl = model.drive
    n = model.n_dof
    hill = assemble(order0)
    hs, samples, harmonics = hill.hs, hill.samples, (hill.hs.size - 1) // 2
    E = np.asarray(approach, dtype=complex)
    if E.ndim == 0:
        E = np.where(hs == 0, E, 0j)
    wj = (order0 + hs * float(model.pinion_teeth))[None, :] * sp[:, None]  # (B, m)
    dh = (hs[:, None] - hs[None, :]) % samples
    on = np.flatnonzero(E)
    # k(theta) W a and c W a': sum over the approach's components j
    rhs = -np.einsum("j,hjn->hn", E[on], hill.wk[dh[:, on]])[None]
    rhs = rhs - 1j * np.einsum("bj,j,hjn->bhn", wj[:, on], E[on], hill.wc[dh[:, on]])
    if force is not None:
        rhs = rhs + np.where((hs == 0)[None, :, None], np.asarray(force)[None, None, :], 0)
    drop = harmonics * n + 3 if order0 == 0 else None  # w_0 = 0: the propeller angle at 0
    X = hill.solve(np.broadcast_to(rhs, (sp.size, hs.size, n)).astype(complex), drop=drop)
    f = hill.mesh_force(X, fl.damping) + (hill.kap[dh[:, on]] @ E[on])[None]
    f = f + 1j * wj * fl.damping * E[None, :]
    # theta = Omega t + q_1s + theta_10: back to the time's origin; Re(X e^{iwt}) with
    # w < 0 is Re(conj(X) e^{i|w|t}); Re(Y e^{i|w|t}) = Im(i Y e^{i|w|t})
    orders = order0 + hs * float(model.pinion_teeth)
    shift = np.exp(1j * orders * phi0)
    X = X * shift[None, :, None]
    f = f * shift[None, :]
    neg = orders < 0
    X[:, neg] = np.conj(X[:, neg])
    f[:, neg] = np.conj(f[:, neg])
    return np.abs(orders), 1j * X, 1j * f


def _mesh_base(model, sp, harmonics, samples, mesh_response):
    """:func:`_vibration_samples` of ``mesh_response`` (the mesh orders' harmonic
    balance, computed when None)."""
    Xm = mesh_response
    if Xm is None:
        Xm, _ = mesh_harmonic_balance(model, sp, harmonics=harmonics, samples=samples)
    return _vibration_samples(model, sp, Xm, samples)


def eccentricity_harmonic_balance(
    model: DrivetrainModel,
    speeds=None,
    *,
    harmonics: int = 12,
    samples: int = 256,
    mesh_response: np.ndarray | None = None,
) -> list[tuple[str, np.ndarray, np.ndarray, np.ndarray]]:
    """Steady response to each eccentricity (docs/drivetrain.md §3b) with the mesh
    stiffness varying in time: the same Hill system as :func:`mesh_harmonic_balance`
    for the frequencies w_0 + h w_m, w_0 = o_0 Omega the member's once per revolution
    (o_0 = 1 for the pinion, N_1 / N_2 for the gear), forced by the approach
    eps = Re(E exp(i o_0 theta_1)) of the drive flank:

        rhs_h = -E [(W k)_h + i w_0 c W_h],     mesh force  ... + E kap_h + i w_0 c E [h = 0].

    The modulation k(theta) eps puts the response at the sidebands |o_0 + h N_1|.
    The system is linearised about the mesh orders' steady vibration: ``mesh_response``,
    the coordinates' amplitudes X of :func:`mesh_harmonic_balance` at the same speeds,
    harmonics and samples (computed when None).

    Returns, per eccentric member: (name, orders |o_0 + h N_1| (L = 2 H + 1,),
    coordinate amplitudes (B, L, n), mesh-force amplitudes (B, L)), each as Im(A exp(i
    w t)) with w = order x Omega and t the model's time.
    """
    sp = np.atleast_1d(np.asarray(model.speed if speeds is None else speeds, dtype=float))
    if not model.has_eccentricity:
        return []
    rc = model.eccentricity_coefficients()[0]
    ratio = model.pinion_teeth / model.gear_teeth
    ys = model.static_state()
    phi0 = float(model.phase + ys[1])  # theta_1 - Omega t at the static state
    base = _mesh_base(model, sp, harmonics, samples, mesh_response)
    assemble = _hill_families(model, sp, harmonics, samples, base=base)
    out = []
    for name, attr, col in ECCENTRIC_MEMBERS:
        if getattr(model, attr) <= 0:
            continue
        o0 = 1.0 if name == "pinion" else ratio
        E = rc[col] - 1j * rc[col + 1]  # A cos + B sin = Re((A - i B) e^{i theta})
        if name == "gear":  # theta_2 = (N1/N2) theta_1 + q_2s - (N1/N2) q_1s
            E = E * np.exp(1j * (ys[2] - ratio * ys[1]))
        out.append((name, *_family(model, sp, assemble, o0, phi0, approach=E)))
    return out


def pitch_lines(model: DrivetrainModel, max_order: float, rel_floor: float = 1e-4):
    """The pitch deviations' approach as lines Re(A e^{i o theta_1}) (docs §3c): orders
    o = j / R (R = the hunting period in pinion revolutions) up to ``max_order`` whose
    amplitude reaches ``rel_floor`` of the largest; (orders, A). From the samples' DFT
    times the periodic cubic spline's transfer sinc(pi j / n)^4 / ((2 + cos(2 pi j /
    n)) / 3), the spline's own Fourier coefficients (images above the Nyquist order
    left out)."""
    pa = model.pitch
    v = pa.values
    n = v.size
    revs = pa.period / (2 * math.pi)
    jmax = min(int(math.floor(max_order * revs + 1e-9)), n // 2 - 1)
    c = np.fft.rfft(v)[: jmax + 1] / n
    j = np.arange(jmax + 1)
    x = np.pi * j / n
    sinc = np.ones_like(x)
    sinc[1:] = np.sin(x[1:]) / x[1:]
    c = c * sinc**4 / ((2.0 + np.cos(2 * x)) / 3.0)
    orders = j / revs
    A = 2.0 * c * np.exp(-1j * orders * pa.angle0)  # a = Re(A e^{i o theta_1})
    keep = (j > 0) & (np.abs(A) >= rel_floor * np.abs(A[1:]).max())
    return orders[keep], A[keep]


def deviation_lines(
    model: DrivetrainModel, listed=(), *, count: int = 3, share: float = 0.1, max_order=None
) -> list[tuple[float, float]]:
    """The tooth deviations' approach's ``count`` largest lines (pinion order, amplitude
    m) up to ``max_order`` (default three mesh orders) that reach ``share`` of its
    largest, leaving out the orders in ``listed`` (the excitation orders already named):
    a ghost order, a wobble's sidebands. [] without an approach."""
    if model.pitch is None:
        return []
    top = 3.0 * model.pinion_teeth if max_order is None else float(max_order)
    orders, A = pitch_lines(model, top)
    amp = np.abs(A)
    if amp.size == 0:
        return []
    known = np.asarray(list(listed), dtype=float)
    fresh = ~np.any(np.isclose(orders[:, None], known[None, :], rtol=0, atol=1e-9), axis=1)
    keep = np.flatnonzero(fresh & (amp >= share * amp.max()))
    pick = keep[np.argsort(amp[keep])[::-1][:count]]
    return [(float(orders[i]), float(amp[i])) for i in pick]


def pitch_harmonic_balance(
    model: DrivetrainModel,
    speeds=None,
    *,
    harmonics: int = 12,
    samples: int = 256,
    mesh_response: np.ndarray | None = None,
    rel_floor: float = 1e-4,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steady response to the pitch deviations' approach (docs §3c) with the mesh
    stiffness varying in time: the Hill system of :func:`eccentricity_harmonic_balance`
    for each family o_0 + h N_1, forced by the approach's lines in that family
    (:func:`pitch_lines` up to order (``harmonics`` + 1) N_1, amplitudes above
    ``rel_floor`` of the largest), linearised about the mesh orders' steady vibration.
    The lines of one order from several families add up.

    Returns (orders (L,), coordinate amplitudes (B, L, n), mesh-force amplitudes
    (B, L)), each as Im(A exp(i w t)), w = order x Omega; empty without pitch
    deviations.
    """
    sp = np.atleast_1d(np.asarray(model.speed if speeds is None else speeds, dtype=float))
    n = model.n_dof
    if model.pitch is None:
        return np.zeros(0), np.zeros((sp.size, 0, n), complex), np.zeros((sp.size, 0), complex)
    H = int(harmonics)
    z1 = float(model.pinion_teeth)
    revs = model.pitch.period / (2 * math.pi)
    per = int(round(z1 * revs))  # lines per mesh order
    o, A = pitch_lines(model, (H + 1) * z1, rel_floor)
    jj = np.rint(o * revs).astype(int)
    cls, hh = jj % per, jj // per
    ys = model.static_state()
    phi0 = float(model.phase + ys[1])
    base = _mesh_base(model, sp, H, samples, mesh_response)
    assemble = _hill_families(model, sp, H, samples, base=base)
    out_o, out_X, out_f = [], [], []
    for r in np.unique(cls):
        E = np.zeros(2 * H + 1, complex)
        sel = (cls == r) & (hh <= H)
        E[H + hh[sel]] = A[sel]
        if not np.any(E):
            continue
        orders, X, f = _family(model, sp, assemble, r / revs, phi0, approach=E)
        out_o.append(orders)
        out_X.append(X)
        out_f.append(f)
    orders = np.concatenate(out_o)
    X = np.concatenate(out_X, axis=1)
    f = np.concatenate(out_f, axis=1)
    w = sp[:, None] * orders[None, :]
    orders, _, _, X, f = _merge_orders(orders, ("pitch",) * orders.size, w, X, f)
    o = np.argsort(orders)
    return orders[o], X[:, o], f[:, o]


def excitation_harmonic_balance(
    model: DrivetrainModel,
    speeds=None,
    *,
    harmonics: int = 12,
    samples: int = 256,
    mesh_response: np.ndarray | None = None,
) -> list[tuple[str, float, np.ndarray, np.ndarray, np.ndarray]]:
    """Steady response to each engine and propeller order with the mesh stiffness
    varying in time (the Hill system of :func:`eccentricity_harmonic_balance`, forced
    by the order's torque on the engine or the propeller): besides the order o_0
    itself, the sidebands |o_0 + h N_1| that the order's vibration of the pinion puts
    on the mesh orders (the mesh laws follow theta_1 = Omega t + q_1).

    Returns, per order with a nonzero amplitude: (source, o_0, orders, coordinate
    amplitudes (B, L, n), mesh-force amplitudes (B, L)), as
    :func:`eccentricity_harmonic_balance`.
    """
    sp = np.atleast_1d(np.asarray(model.speed if speeds is None else speeds, dtype=float))
    ys = model.static_state()
    exc = _excitations(model, ys[: model.n_dof], 0)
    if not exc.orders.size:
        return []
    base = _mesh_base(model, sp, harmonics, samples, mesh_response)
    assemble = _hill_families(model, sp, harmonics, samples, base=base)
    phi0 = float(model.phase + ys[1])  # theta_1 - Omega t at the static state
    out = []
    for o, src, F in zip(exc.orders, exc.sources, exc.forces, strict=True):
        # Im(F e^{i o Omega t}) = Re(-i F e^{-i o phi0} e^{i o theta})
        Fth = -1j * F * np.exp(-1j * o * phi0)
        out.append((src, float(o), *_family(model, sp, assemble, o, phi0, force=Fth)))
    return out


def _merge_orders(orders, sources, w, X, mesh):
    """One entry per order: the responses of sources that excite the same order (an
    eccentricity's once per revolution and an engine half order, say) add up, all
    amplitudes referring to one time origin; their sources joined with '+'."""
    keys = np.round(orders, 9)
    uniq, first, inv = np.unique(keys, return_index=True, return_inverse=True)
    if uniq.size == keys.size:
        return orders, sources, w, X, mesh
    rank = np.argsort(np.argsort(first))  # unique orders in their first appearance's order
    pos = rank[inv.ravel()]
    keep = np.sort(first)
    Xs = np.zeros((X.shape[0], keep.size) + X.shape[2:], complex)
    ms = np.zeros((mesh.shape[0], keep.size), complex)
    np.add.at(Xs, (slice(None), pos), X)
    np.add.at(ms, (slice(None), pos), mesh)
    names = [[] for _ in keep]
    for j, src in enumerate(sources):
        if src not in names[pos[j]]:
            names[pos[j]].append(src)
    return orders[keep], tuple("+".join(n) for n in names), w[:, keep], Xs, ms


def _check_order_arguments(speeds: np.ndarray, mesh_harmonics, sideband_harmonics) -> None:
    from ..errors import Problems

    p = Problems()
    bad = speeds[~(np.isfinite(speeds) & (speeds > 0))]
    p.check(
        speeds.ndim == 1 and speeds.size > 0 and bad.size == 0,
        "speeds",
        bad.tolist() if bad.size else speeds.shape,
        "must be pinion speeds in rad/s, finite and > 0 (rpm * pi / 30), a 1-D array",
    )
    p.integer("mesh_harmonics", mesh_harmonics, 0)
    p.integer("sideband_harmonics", sideband_harmonics, 0)
    p.raise_if_any("invalid order response arguments")


def order_responses(
    model: DrivetrainModel, speeds=None, *, mesh_harmonics: int = 12, sideband_harmonics: int = 3
) -> OrderResponse:
    """Steady response of the model about its operating point to each engine,
    propeller and mesh excitation, at ``speeds`` (rad/s; default the model's).

    Engine and propeller orders: harmonic balance of each with its sidebands |o +
    h N_1|, h = -``sideband_harmonics``..``sideband_harmonics``, about the mesh
    orders (:func:`excitation_harmonic_balance`); with ``mesh_harmonics`` or
    ``sideband_harmonics`` = 0 each alone on the linear model (mean mesh stiffness),
    as :func:`periodic_start_states`: the order's own line within 0.03 % of the
    harmonic balance's (default scene, ten speeds 1000-3500 rpm at its torque), no
    sidebands, a third of the time.
    Eccentricities (docs §3b): their once per revolution and its sidebands by
    harmonic balance (:func:`eccentricity_harmonic_balance`), sources 'pinion
    eccentricity' and 'gear eccentricity'; an order two sources excite is one entry,
    their responses added (sources joined with '+'). Pitch deviations (docs §3c): every
    line of their approach above 1e-4 of the largest, with its sidebands
    (:func:`pitch_harmonic_balance`), source 'pitch deviations'. Mesh orders: harmonic balance with
    the time-varying mesh stiffness (:func:`mesh_harmonic_balance`, the first
    ``mesh_harmonics`` harmonics), which the mean-stiffness model underestimates near
    a mesh mode (on the default scene's 2x and 3x mesh crossings by 9.3 and 29 %
    against the nonlinear simulation, which the harmonic balance meets within 0.17 %). The excitation amplitudes are those at the
    model's torque; only the frequencies and the propeller's speed damping follow
    ``speeds``. For a speed on the propeller law, pass the model of that speed and
    torque (:meth:`DrivetrainModel.with_speed` keeps the torque). Speeds that are not
    finite and > 0, and harmonic counts below 0, raise one InputError naming each.
    """
    sp = np.atleast_1d(np.asarray(model.speed if speeds is None else speeds, dtype=float))
    _check_order_arguments(sp, mesh_harmonics, sideband_harmonics)
    n = model.n_dof
    y = model.static_state()
    fl = model.drive
    g = model.mesh_vectors()[0]
    w, X = np.zeros((sp.size, 0)), np.zeros((sp.size, 0, n), complex)
    mesh = np.zeros((sp.size, 0), complex)
    orders, sources = np.zeros(0), ()

    def add(o, src, Xo, fo):
        nonlocal orders, sources, w, X, mesh
        orders = np.concatenate([orders, o])
        sources = sources + src
        w = np.concatenate([w, sp[:, None] * o[None, :]], axis=1)
        X = np.concatenate([X, Xo], axis=1)
        mesh = np.concatenate([mesh, fo], axis=1)

    Xm = None
    if mesh_harmonics > 0:
        Xm, fm = mesh_harmonic_balance(model, sp, harmonics=mesh_harmonics)
        add(
            np.arange(1, mesh_harmonics + 1) * float(model.pinion_teeth),
            ("mesh",) * mesh_harmonics,
            Xm,
            fm,
        )
    if Xm is not None and sideband_harmonics > 0:
        # engine and propeller orders with the sidebands their pinion vibration puts
        # on the mesh orders
        for src, _, oe, Xe, fe in excitation_harmonic_balance(
            model,
            sp,
            harmonics=min(sideband_harmonics, mesh_harmonics),
            mesh_response=Xm[:, :sideband_harmonics],
        ):
            add(oe, (src,) * oe.size, Xe, fe)
    else:
        exc = _excitations(model, y[:n], 0)  # engine and propeller orders, mean k
        if exc.orders.size:
            we, Xe = _steady_amplitudes(model, sp, exc)
            add(exc.orders, exc.sources, Xe, (fl.mean_stiffness + 1j * we * fl.damping) * (Xe @ g))
    for name, oe, Xe, fe in eccentricity_harmonic_balance(
        model, sp, harmonics=max(mesh_harmonics, 1), mesh_response=Xm
    ):
        add(oe, (f"{name} eccentricity",) * oe.size, Xe, fe)
    if model.pitch is not None:
        op, Xp, fp = pitch_harmonic_balance(
            model, sp, harmonics=max(mesh_harmonics, 1), mesh_response=Xm
        )
        add(op, ("pitch deviations",) * op.size, Xp, fp)
    orders, sources, w, X, mesh = _merge_orders(orders, sources, w, X, mesh)
    K, C = model.structural_matrices()
    t_in = (-K[0, 1] - 1j * w * C[0, 1]) * (X[..., 0] - X[..., 1])
    t_out = (-K[2, 3] - 1j * w * C[2, 3]) * (X[..., 2] - X[..., 3])
    return OrderResponse(
        speeds=sp,
        orders=orders,
        sources=sources,
        states=X,
        mesh_force=mesh,
        input_shaft_torque=t_in,
        output_shaft_torque=t_out,
        mean_mesh_force=model.mean_mesh_force,
        mean_input_torque=model.torque,
        mean_output_torque=model.torque * model.torque_ratio,
    )

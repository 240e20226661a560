"""Fixed-step explicit Runge-Kutta in ``jax.lax.scan``: the default path of the jax backend.

``DiffraxSolver()`` (no ``rtol``) integrates here; ``DiffraxSolver(rtol=...)`` keeps
diffrax's adaptive PID stepping. docs/drivetrain.md §11 has the measurements behind
the choice (one second at 2000 rpm on the shared 2-core CPU: adaptive diffrax Tsit5
24-26 us per step, this scan 1.6-3.5 us per step at the same number of stages).

Step: ``h_target = 1 / (steps_per_period * max(f_mode, f_mesh))`` with ``f_mode`` the
highest eigenfrequency of the linearised model with the drive mesh at its largest
stiffness (damped first-order system) and ``f_mesh = N_1 Omega / (2 pi)``, at most 0.8
x the method's stability limit on that system (:func:`stability_limit`). Every interval
between output times gets ``ceil(d / h_target)`` equal steps, so the samples lie on the
step grid (the exudyn backend's rule, docs/exudyn.md). A fixed step has no error
estimate and cannot collapse; a run that blows up anyway (a step chosen by hand) is
caught after the run as NaN or divergence with its time and state, as for the adaptive
path. Steps that end out of the nominal contact are counted (impacts: the caller
repeats the run with adaptive steps, ``DiffraxSolver.contact_rtol``).

Right-hand side (:func:`lean_rhs`): the equations of :func:`gearbox.drivetrain.model.rhs`
(docs/drivetrain.md §2-7) in scalar arithmetic, which XLA on the CPU fuses into a few
kernels (the small matrix products of ``rhs`` call one BLAS kernel each), with

- the mesh laws k_f, e_f, e_f' (both flanks) from a cubic Hermite table over one mesh
  cycle (:func:`mesh_law_table`, values and derivatives from the Fourier series, built
  once per run inside the jitted function, so it stays differentiable);
- the engine torque and propeller ripple, functions of time only, evaluated for every
  step and stage before the scan, vectorised.

Both are tested against ``model.rhs`` (tests/test_drivetrain_fixed_step.py).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from .linear import largest_stable_step, linear_matrices
from .model import approach_terms, contact_forces

__all__ = [
    "FixedStepPlan",
    "bucket",
    "excitation_terms",
    "explicit_tableau",
    "fixed_solve_fn",
    "lean_rhs",
    "mesh_law_table",
    "plan_steps",
    "stability_limit",
    "stability_polynomial",
    "step_targets",
]

#: Default steps per period of the highest frequency, per method: the errors they give on
#: the default scene are in docs/drivetrain.md §11 (work-precision table).
STEPS_PER_PERIOD = {"Tsit5": 12.0, "Dopri8": 6.0}


#: diffrax's ``Tsit5.tableau`` (b_sol, c, a_lower), written out: importing diffrax costs a
#: new process 0.6-1.9 s that the default fixed-step path needs for nothing else
#: (tests/test_pipeline_jaxcache.py compares it with diffrax's).
TSIT5 = (
    (0.09646076681806523, 0.01, 0.4798896504144996, 1.379008574103742, -3.290069515436081)
    + (2.324710524099774, 0.0),
    (0.161, 0.327, 0.9, 0.9800255409045097, 1.0, 1.0),
    (
        (0.161,),
        (-0.008480655492356989, 0.335480655492357),
        (2.8971530571054935, -6.359448489975075, 4.3622954328695815),
        (5.325864828439257, -11.748883564062828, 7.4955393428898365, -0.09249506636175525),
        (5.86145544294642, -12.92096931784711, 8.159367898576159, -0.071584973281401)
        + (-0.028269050394068383,),
        (0.09646076681806523, 0.01, 0.4798896504144996, 1.379008574103742, -3.290069515436081)
        + (2.324710524099774,),
    ),
)


def _diffrax_tableau(name: str) -> tuple:
    """(b_sol, c, a_lower) of diffrax's ``name`` (:data:`TSIT5` without importing it)."""
    if name == "Tsit5":
        return TSIT5
    import diffrax

    t = getattr(diffrax, name).tableau
    return t.b_sol, t.c, t.a_lower


def explicit_tableau(name: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(A, b, c) of diffrax's explicit Runge-Kutta ``name``, trailing stages with b = 0
    dropped (the FSAL stage only serves the error estimate). Shapes (s, s), (s,), (s,)."""
    b_sol, c_, a_lower = _diffrax_tableau(name)
    b = np.asarray(b_sol, dtype=float)
    s = len(b)
    A = np.zeros((s, s))
    for i, row in enumerate(a_lower):
        A[i + 1, : len(row)] = row
    c = np.concatenate([[0.0], np.asarray(c_, dtype=float)])
    while s > 1 and b[s - 1] == 0.0:
        s -= 1
    return A[:s, :s], b[:s], c[:s]


def stability_polynomial(A: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Coefficients c_0..c_s of R(z) = 1 + z b^T (I - z A)^-1 1 = 1 + sum_k b^T A^(k-1) 1 z^k
    of an explicit method (A strictly lower triangular; Hairer, Wanner, Solving ODEs II,
    Sec. IV.2)."""
    s = len(b)
    out = [1.0]
    v = np.ones(s)
    for _ in range(s):
        out.append(float(b @ v))
        v = A @ v
    return np.array(out)


def _eigenvalues_at_peak_stiffness(model, speeds=None) -> np.ndarray:
    """Eigenvalues (1/s) of the linearised first-order system, drive mesh at its largest
    stiffness a0 + sum |c_k| (an upper bound of k(theta)), shape (B, 2 n) for the
    ``speeds`` (rad/s, shape (B,); default the model's). Only the propeller's speed
    damping 2 kappa Omega_2 changes with the speed (docs/drivetrain.md §6)."""
    M, C, K = linear_matrices(model)
    speeds = np.atleast_1d(model.speed if speeds is None else np.asarray(speeds, float))
    kc = model.drive.k_coef
    h = (kc.size - 1) // 2
    g = model.mesh_vectors()[0]
    kmax = float(kc[0] + np.hypot(kc[1 : 1 + h], kc[1 + h :]).sum())
    K = K + (kmax - model.drive.mean_stiffness) * np.outer(g, g)
    n = model.n_dof
    m = np.diag(M)
    A = np.zeros((speeds.size, 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    A[:, n:, :n] = -K / m[:, None]
    A[:, n:, n:] = -C / m[:, None]
    # C holds 2 kappa Omega_2 = 2 T_op (T_2 / T_1) / Omega_2 at the model's speed
    ratio = model.gear_speed / model.speed
    dc = 2 * model.torque * model.torque_ratio / ratio
    A[:, n + 3, n + 3] -= (dc / speeds - dc / model.speed) / m[3]
    return np.linalg.eigvals(A)


def stability_limit(model, method: str = "Tsit5", speeds=None):
    """Largest stable fixed step (s) of ``method`` on the linearised model (drive mesh at
    its largest stiffness): :func:`gearbox.drivetrain.linear.largest_stable_step` with the
    method's stability polynomial. A float, or shape (B,) for ``speeds`` (rad/s).
    Contact loss and impacts are not covered: divergence is still checked after every
    run."""
    A, b, _ = explicit_tableau(method)
    lam = _eigenvalues_at_peak_stiffness(model, speeds)
    out = largest_stable_step(lam, stability_polynomial(A, b))
    return float(out[0]) if speeds is None else out


def step_targets(model, solver, speeds=None):
    """(target step (s), stability limit (s), f_max (Hz)), each shape (B,), for the
    ``speeds`` (rad/s; default the model's): ``solver.step``, or 1 / (steps_per_period
    f_max) capped at 0.8 x the stability limit."""
    A, b, _ = explicit_tableau(solver.solver)
    speeds = np.atleast_1d(model.speed if speeds is None else np.asarray(speeds, float))
    lam = _eigenvalues_at_peak_stiffness(model, speeds)
    limit = largest_stable_step(lam, stability_polynomial(A, b))
    f_mesh = model.pinion_teeth * speeds / (2 * math.pi)
    f_max = np.maximum(np.abs(lam).max(axis=1) / (2 * math.pi), f_mesh)
    if solver.step is not None:
        target = np.full(speeds.size, float(solver.step))
    else:
        spp = solver.steps_per_period or STEPS_PER_PERIOD[solver.solver]
        target = np.minimum(1.0 / (spp * f_max), 0.8 * limit)
    return target, limit, f_max


@dataclass(frozen=True)
class FixedStepPlan:
    """Steps of one run: start time t (s) and size h (s) of every step, shape (S,); out:
    index of the step that ends at each output time, shape (n_t,); target: the step
    asked for (s); limit: the stability limit (s); f_max: the frequency the step
    resolves (Hz)."""

    t: np.ndarray
    h: np.ndarray
    out: np.ndarray
    target: float
    limit: float
    f_max: float

    @property
    def n_steps(self) -> int:
        return int(self.t.size)

    def padded(self, size: int) -> FixedStepPlan:
        """The same run with h = 0 steps appended up to ``size`` steps (they leave the
        state unchanged): runs of nearby lengths share one compilation."""
        extra = size - self.n_steps
        if extra <= 0:
            return self
        t_end = self.t[-1] + self.h[-1] if self.n_steps else 0.0
        return dataclasses.replace(
            self,
            t=np.concatenate([self.t, np.full(extra, t_end)]),
            h=np.concatenate([self.h, np.zeros(extra)]),
        )


def bucket(n: int) -> int:
    """``n`` rounded up to a multiple of 2^(bit length - 5): at most 1/16 more steps,
    about 16 distinct sizes per doubling of the run length."""
    q = 1 << max(int(n).bit_length() - 5, 0)
    return -(-int(n) // q) * q


def plan_steps(model, ts: np.ndarray, solver, *, targets=None) -> FixedStepPlan:
    """Step grid from ``ts[0]`` through the output times ``ts[1:]`` (s, increasing):
    ``ceil(d / target)`` equal steps per interval d. targets: one row of
    :func:`step_targets` (computed for the model when None).

    Raises :class:`gearbox.errors.InputError` when an explicit ``solver.step`` exceeds
    the stability limit.
    """
    from ..errors import InputError, Problem

    ts = np.asarray(ts, dtype=float)
    if targets is None:
        targets = tuple(float(v[0]) for v in step_targets(model, solver))
    target, limit, f_max = targets
    if solver.step is not None and target > limit:
        raise InputError(
            Problem("step", target, f"must be <= {limit:.4g} s (stability limit)"),
            "invalid diffrax solver settings",
        )
    d = np.diff(ts)
    counts = np.maximum(np.ceil(d / target * (1 - 1e-12)), 1).astype(np.int64)
    h = np.repeat(d / counts, counts)
    first = np.cumsum(counts) - counts
    t = np.repeat(ts[:-1], counts) + (np.arange(h.size) - np.repeat(first, counts)) * h
    return FixedStepPlan(t, h, np.cumsum(counts) - 1, target, limit, f_max)


def mesh_law_table(p, cells: int, xp):
    """Cubic Hermite table of the mesh laws over one mesh cycle, shape (R, 2, cells + 1).

    Rows: k_drive, k_coast (N/m), e_drive, e_coast (m), e'_drive, e'_coast (m/rad,
    d e / d theta_1), and with friction (``p['fc']`` not empty) mu phi_1 and mu phi_2 of
    drive and coast (m; R = 10, else 6); [:, 0] values, [:, 1] derivatives with respect
    to phi = N_1 theta_1 times the cell width, at phi_j = 2 pi j / cells. From the
    Fourier coefficients ``p['kc']``, ``p['ec']``, ``p['fc']`` (docs/drivetrain.md §3).
    With the loaded mesh law (docs §3d) its 2 J + 1 rows of the drive flank and then
    of the coast flank follow (``p['lc']``).
    """
    kc, ec = p["kc"], p["ec"]
    h = (kc.shape[-1] - 1) // 2
    kk = xp.arange(1, h + 1)
    rows = xp.concatenate([kc, ec], axis=0)  # (4, 1 + 2h)
    a, b = rows[:, 1 : 1 + h], rows[:, 1 + h :]
    # e' = N1 sum k (b cos - a sin): its own series, coefficients (-N1 k a -> b, N1 k b -> a)
    ad, bd = p["N1"] * kk * ec[:, 1 + h :], -p["N1"] * kk * ec[:, 1 : 1 + h]
    a = xp.concatenate([a, ad], axis=0)  # (6, h)
    b = xp.concatenate([b, bd], axis=0)
    a0 = xp.concatenate([rows[:, 0], xp.zeros(2)])
    if p["fc"].shape[-1]:
        fr = xp.swapaxes(p["fc"], 0, 1).reshape(4, -1)  # phi_1 drive, coast, phi_2 drive, coast
        a = xp.concatenate([a, fr[:, 1 : 1 + h]], axis=0)
        b = xp.concatenate([b, fr[:, 1 + h :]], axis=0)
        a0 = xp.concatenate([a0, fr[:, 0]])
    if p["lc"].shape[1]:
        lr = p["lc"].reshape(-1, p["lc"].shape[-1])  # drive rows, then coast rows
        a = xp.concatenate([a, lr[:, 1 : 1 + h]], axis=0)
        b = xp.concatenate([b, lr[:, 1 + h :]], axis=0)
        a0 = xp.concatenate([a0, lr[:, 0]])
    phi = xp.arange(cells + 1) * (2 * math.pi / cells)
    arg = kk[:, None] * phi[None, :]  # (h, cells + 1)
    c, s = xp.cos(arg), xp.sin(arg)
    val = a0[:, None] + a @ c + b @ s
    der = ((b * kk) @ c - (a * kk) @ s) * (2 * math.pi / cells)
    return xp.stack([val, der], axis=1)


def _hermite(table, phi, cells: int, jnp, lax):
    """The mesh-law rows at phi = N_1 theta_1 (rad) from :func:`mesh_law_table`."""
    u = phi * (cells / (2 * math.pi))
    fl = jnp.floor(u)
    s = u - fl
    i = jnp.mod(fl, cells).astype(jnp.int32)
    T = lax.dynamic_slice_in_dim(table, i, 2, axis=2)  # (R, 2, 2)
    s2 = s * s
    s3 = s2 * s
    return (
        (2 * s3 - 3 * s2 + 1) * T[:, 0, 0]
        + (s3 - 2 * s2 + s) * T[:, 1, 0]
        + (3 * s2 - 2 * s3) * T[:, 0, 1]
        + (s3 - s2) * T[:, 1, 1]
    )


def _flank_force(r, fl, s, sdot, p, xp):
    """Contact force (N) of flank ``fl`` (0 drive, 1 coast) at gap s and rate sdot
    from the mesh-law rows r of :func:`mesh_law_table` (the first axis):
    :func:`gearbox.drivetrain.model.contact_forces` with the tangent law or the loaded
    law's rows (docs/drivetrain.md §3, §3d)."""
    m = p["lc"].shape[1]
    rows = None
    if m:
        first = 10 if p["fc"].shape[-1] else 6
        rows = xp.moveaxis(r[first + fl * m : first + (fl + 1) * m], 0, -1)
    return contact_forces(s, sdot, r[fl], r[2 + fl], rows, p["cm"][fl], p["lF"][fl], xp)


def lean_rhs(t, z, p, laws_at, te0, rp):
    """d z / dt of the scaled state, as :func:`gearbox.drivetrain.model.rhs`, in scalar
    arithmetic. laws_at(phi) -> the mesh-law rows of :func:`mesh_law_table`; te0: engine
    torque without governor (N m) at t; rp: propeller ripple factor at t (-). Shape (2 n,).
    """
    import jax
    import jax.numpy as jnp

    sc = p["scale"]
    n = z.shape[0] // 2
    x = [z[i] * sc[i] for i in range(n)]
    v = [z[n + i] * sc[n + i] for i in range(n)]
    theta1 = p["Omega"] * t + x[1] + p["phase"]
    # materialise the six laws once (XLA would otherwise repeat their evaluation in
    # every consumer of the fused kernel)
    r = jax.lax.optimization_barrier(laws_at(p["N1"] * theta1))
    K, C, G = p["K"], p["C"], p["G"]
    ecc = approach_terms(t, x[1], x[2], v[1], v[2], p, jnp)
    f = []
    for fl in range(2):
        s = sum(G[fl, j] * x[j] for j in range(n)) - r[2 + fl] - p["bl"][fl]
        sdot = sum(G[fl, j] * v[j] for j in range(n)) - r[4 + fl] * (p["Omega"] + v[1])
        if ecc is not None:
            s = s + ecc[0][fl]
            sdot = sdot + ecc[1][fl]
        f.append(_flank_force(r, fl, s, sdot, p, jnp))
    te = te0 - p["Kp"] * v[0] - p["Ki"] * (x[0] - p["qe0"])
    wp = p["Omega2"] + v[3]
    tp = p["kappa"] * wp * wp * rp
    friction = p["fc"].shape[-1] > 0  # docs/drivetrain.md §3a
    acc = []
    for i in range(n):
        q = -sum(K[i, j] * x[j] + C[i, j] * v[j] for j in range(n))
        q = q - G[0, i] * f[0] - G[1, i] * f[1]
        if i == 0:
            q = q + te
        elif i == 3:
            q = q - tp
        elif friction and i == 1:
            q = q - r[6] * f[0] - r[7] * f[1]
        elif friction and i == 2:
            q = q + r[8] * f[0] + r[9] * f[1]
        acc.append(q * p["Minv"][i] / sc[n + i])
    return jnp.stack([v[i] / sc[i] for i in range(n)] + acc)


def _time_excitations(p, t, jnp, terms=None):
    """Engine torque without governor (N m) and propeller ripple factor at times t (any
    shape): docs/drivetrain.md §5-6. terms: (engine, propeller) index tuples of the
    orders to evaluate (:func:`excitation_terms`); None: all."""
    eo, ea, po, pa = p["eo"], p["ea"], p["po"], p["pa"]
    if terms is not None:
        ie, ip = (np.asarray(i, dtype=int) for i in terms)
        eo, ea, po, pa = eo[ie], ea[ie], po[ip], pa[ip]
    tt = t[..., None]
    te0 = p["T"] * (1.0 + jnp.sum(ea * jnp.sin(eo * p["Omega"] * tt), axis=-1))
    rp = 1.0 + jnp.sum(pa * jnp.sin(po * p["Omega2"] * tt), axis=-1)
    return te0, rp


def excitation_terms(params) -> tuple[tuple[int, ...], tuple[int, ...]]:
    """Indices of the engine and propeller orders with non-zero amplitude in ``params``
    (shape (..., k) each: a batch counts a term when any member has it). The others
    add nothing to the torques; leaving them out of :func:`fixed_solve_fn` saves the
    sines (on the default scene 2 of 5 terms remain), and their amplitudes' derivative
    with them."""

    def nz(a):
        a = np.asarray(a).reshape(-1, np.shape(a)[-1])
        return tuple(int(i) for i in np.flatnonzero(np.any(a != 0, axis=0)))

    return nz(params["ea"]), nz(params["pa"])


#: Steps per chunk of :func:`fixed_solve_fn` with ``chunked=True``.
CHUNK = 64


@lru_cache(maxsize=16)
def fixed_solve_fn(method: str, cells: int, chunked: bool = False, terms=None):
    """A jitted ``f(params, z0, t, h, out) -> (zs, lost)``: the scaled states after the
    steps ``out`` (shape (n_t, 2 n)) of the fixed-step run with step starts ``t`` and
    sizes ``h`` (shape (S,), a :class:`FixedStepPlan`; a step with h = 0 leaves the
    state unchanged), and the number of steps that end out of the nominal contact (drive
    flank carrying no load or coast flank carrying load, gap or force clipped: the fixed
    step crosses these kinks unlocated). Compiled once per method, table size and array shapes (pad plans with
    :meth:`FixedStepPlan.padded` to :func:`bucket` sizes to share compilations).
    Differentiable (``jax.grad`` through the scan).

    chunked: ``f(params, z0, t, h, out, n_chunks)`` runs only the first ``n_chunks``
    chunks of :data:`CHUNK` steps (S a multiple of it) in a ``while_loop``: runs of
    different lengths padded to one capacity share one compilation without paying for
    the padding (a speed sweep in a loop). Forward-mode differentiable only.

    terms: the engine and propeller orders to evaluate (:func:`excitation_terms`);
    None: all of them.
    """
    import jax
    import jax.numpy as jnp

    A, b, c = explicit_tableau(method)
    s = len(b)

    def setup(p, t, h):
        table = mesh_law_table(p, cells, jnp)

        def laws_at(phi):
            return _hermite(table, phi, cells, jnp, jax.lax)

        def body(z, xs):
            tj, hj, te_j, rp_j = xs
            ks = []
            for i in range(s):
                zi = z
                for j in range(i):
                    if A[i, j] != 0.0:
                        zi = zi + (hj * A[i, j]) * ks[j]
                ks.append(lean_rhs(tj + c[i] * hj, zi, p, laws_at, te_j[i], rp_j[i]))
            for i in range(s):
                if b[i] != 0.0:
                    z = z + (hj * b[i]) * ks[i]
            return z, z

        # time-only excitations of every step and stage, vectorised before the scan
        te0, rp = _time_excitations(p, t[:, None] + h[:, None] * c[None, :], jnp, terms)

        def lost(zs, valid):
            """Steps that end with the drive flank carrying no load or the coast flank
            carrying load: a flank carries load where its gap is closed and k s + c s'
            > 0 (the force law's two kinks, docs/drivetrain.md §3)."""
            y = zs * p["scale"]
            n = y.shape[-1] // 2
            phi = p["N1"] * (p["Omega"] * (t + h) + y[:, 1] + p["phase"])
            r = jax.vmap(laws_at)(phi)  # (S, R)
            gap = y[:, :n] @ p["G"].T - r[:, 2:4] - p["bl"]
            rate = y[:, n:] @ p["G"].T - r[:, 4:6] * (p["Omega"] + y[:, n + 1])[:, None]
            ecc = approach_terms(t + h, y[:, 1], y[:, 2], y[:, n + 1], y[:, n + 2], p, jnp)
            if ecc is not None:
                gap = gap + jnp.stack(ecc[0], axis=-1)
                rate = rate + jnp.stack(ecc[1], axis=-1)
            rt = r.T  # (R, S)
            load = jnp.stack(
                [_flank_force(rt, fl, gap[:, fl], rate[:, fl], p, jnp) > 0 for fl in range(2)],
                axis=-1,
            )
            return jnp.sum(valid & (~load[:, 0] | load[:, 1]))

        return body, (t, h, te0, rp), lost

    def run(p, z0, t, h, out):
        body, xs, lost = setup(p, t, h)
        _, zs = jax.lax.scan(body, z0, xs)
        return zs[out], lost(zs, h > 0)

    def run_chunked(p, z0, t, h, out, n_chunks):
        body, xs, lost = setup(p, t, h)

        def chunk(carry):
            i, z, buf = carry
            part = tuple(jax.lax.dynamic_slice_in_dim(x, i * CHUNK, CHUNK) for x in xs)
            z, zs = jax.lax.scan(body, z, part)
            return i + 1, z, jax.lax.dynamic_update_slice_in_dim(buf, zs, i * CHUNK, 0)

        buf = jnp.zeros((t.shape[0], z0.shape[0]), z0.dtype)
        _, _, buf = jax.lax.while_loop(lambda c: c[0] < n_chunks, chunk, (0, z0, buf))
        ran = jnp.arange(t.shape[0]) < n_chunks * CHUNK
        return buf[out], lost(buf, ran & (h > 0))

    return jax.jit(run_chunked if chunked else run)

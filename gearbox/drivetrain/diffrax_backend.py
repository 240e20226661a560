"""jax/diffrax solver: jit-compiled, float64, batched over speeds with ``vmap``.

The right-hand side is :func:`gearbox.drivetrain.model.rhs` with ``xp = jax.numpy``;
parameters travel as a dict of arrays (``DrivetrainModel.params``), so results are
differentiable with respect to them (``jax.grad`` through ``diffeqsolve``).

Importing this module enables jax's float64 mode (``jax_enable_x64``): the mesh
deflection is micrometres on top of millimetre shaft twists.
"""

from __future__ import annotations

import threading
import time as _time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import Problems
from .model import DrivetrainModel, rhs
from .timeseries import SolverFailure

__all__ = [
    "DiffraxSolver",
    "integrate_diffrax",
    "integrate_diffrax_batch",
    "integrate_speeds",
    "solve_fn",
]


def _enable_x64() -> None:
    import jax

    jax.config.update("jax_enable_x64", True)


_enable_x64()  # at import, as the module docstring says: arrays made later are float64

_SOLVERS = ("Tsit5", "Dopri5", "Dopri8", "Heun", "Kvaerno5")
_FIXED = ("Tsit5", "Dopri8")


def _jax():
    import jax

    jax.config.update("jax_enable_x64", True)
    import jax.numpy as jnp

    return jax, jnp


@dataclass(frozen=True)
class DiffraxSolver:
    """jax settings: fixed-step ``Tsit5`` by default; diffrax's adaptive stepping with ``rtol``.

    rtol None (default): the fixed-step explicit Runge-Kutta of
    :mod:`gearbox.drivetrain.fixed_step` (``solver`` names the diffrax tableau: Tsit5 or
    Dopri8) at the step ``step`` (s) or, when None, ``1 / (steps_per_period
    f_max)`` (f_max: highest eigenfrequency of the linearised model or the mesh
    frequency; ``steps_per_period`` None: 12 for Tsit5, 6 for Dopri8), capped at 0.8 x
    the stability limit; mesh laws from a Hermite table of ``table_cells`` cells per
    mesh cycle.

    rtol given: ``diffrax.diffeqsolve`` with a PID step-size controller on the scaled
    state; atol (None = rtol); dtmin_fraction: smallest step as a fraction of the mesh
    period, below which the run stops as a step collapse. pcoeff, icoeff: PID step-size
    controller (Hairer, Norsett & Wanner, Solving ODEs I, sec. II.4; diffrax
    ``PIDController``). Measured on the default scene (200 mesh cycles, rtol 1e-6): the
    plain integral controller (0, 1) rejected 3,074 of 10,046 steps, error 3.1e-5 in the
    mesh-order amplitude; (0.1, 0.3) rejected 1,067 of 8,712, error 3.7e-6.

    contact_rtol: a fixed-step run in which the mesh leaves its nominal contact (drive
    flank open or coast flank closed at a step end: impacts, whose kinks a fixed step
    crosses unlocated) is repeated with adaptive steps at this rtol (``info['stepping']``
    says so); None keeps the fixed-step result, with the count of such steps in
    ``info['contact_loss_steps']``. docs/drivetrain.md §11 has the errors that motivate it.

    Both: max_steps caps the steps of a run (reported as ``max_steps``);
    divergence_factor: see :func:`gearbox.drivetrain.scipy_backend.divergence_bound`.
    """

    solver: str = "Tsit5"
    rtol: float | None = None
    atol: float | None = None
    max_steps: int = 2_000_000
    dtmin_fraction: float = 1e-9
    divergence_factor: float = 1e3
    pcoeff: float = 0.1
    icoeff: float = 0.3
    step: float | None = None
    steps_per_period: float | None = None
    table_cells: int = 2048
    contact_rtol: float | None = 1e-9

    name = "diffrax"

    @property
    def adaptive(self) -> bool:
        """True when diffrax chooses the steps (``rtol`` given)."""
        return self.rtol is not None

    def validate(self) -> None:
        p = Problems()
        p.check(self.solver in _SOLVERS, "solver", self.solver, f"must be one of {_SOLVERS}")
        if self.adaptive:
            p.in_range("rtol", self.rtol, 1e-14, 1, hi_open=True)
            if self.atol is not None:
                p.in_range("atol", self.atol, 0, None, lo_open=True)
            for name in ("step", "steps_per_period"):
                v = getattr(self, name)
                p.check(v is None, name, v, "only with fixed steps (rtol None)")
        else:
            p.check(
                self.solver in _FIXED,
                "solver",
                self.solver,
                f"fixed steps (rtol None) need an explicit method, one of {_FIXED}",
            )
            p.check(self.atol is None, "atol", self.atol, "only with rtol (adaptive steps)")
            if self.step is not None:
                p.in_range("step", self.step, 0, 1, lo_open=True)
            if self.steps_per_period is not None:
                p.in_range("steps_per_period", self.steps_per_period, 2, 1e6)
            p.in_range("table_cells", self.table_cells, 64, 2**20)
            if self.contact_rtol is not None:
                p.in_range("contact_rtol", self.contact_rtol, 1e-14, 1, hi_open=True)
        p.check(self.max_steps >= 1, "max_steps", self.max_steps, "must be >= 1")
        p.raise_if_any("invalid diffrax solver settings")


@lru_cache(maxsize=16)
def solve_fn(solver: DiffraxSolver):
    """A jitted ``f(params, z0, ts) -> (zs, result_code, steps, rejected)``.

    ``ts[0]`` is the start time; ``zs`` shape (len(ts), 2 n) scaled states. Compiled
    once per solver setting and array shapes. Adaptive settings only (``rtol`` given).
    """
    if not solver.adaptive:
        from ..errors import InputError, Problem

        raise InputError(Problem("rtol", None, "solve_fn needs adaptive steps: give rtol"))
    jax, jnp = _jax()
    import diffrax

    def vf(t, z, p):
        return rhs(t, z, p, xp=jnp)

    term = diffrax.ODETerm(vf)
    method = getattr(diffrax, solver.solver)()
    atol = solver.atol if solver.atol is not None else solver.rtol

    def run(p, z0, ts):
        period = 2 * jnp.pi / (p["N1"] * p["Omega"])
        ctrl = diffrax.PIDController(
            rtol=solver.rtol,
            atol=atol,
            dtmin=solver.dtmin_fraction * period,
            pcoeff=solver.pcoeff,
            icoeff=solver.icoeff,
        )
        sol = diffrax.diffeqsolve(
            term,
            method,
            ts[0],
            ts[-1],
            period / 20,
            z0,
            args=p,
            saveat=diffrax.SaveAt(ts=ts),
            stepsize_controller=ctrl,
            max_steps=solver.max_steps,
            throw=False,
        )
        code = jnp.asarray(sol.result._value, dtype=jnp.int32)
        return sol.ys, code, sol.stats["num_accepted_steps"], sol.stats["num_rejected_steps"]

    return jax.jit(run)


def _result_kind(code: int) -> tuple[str, str]:
    import diffrax

    if code == 0:
        return "success", ""
    names = {}
    for name in (
        "max_steps_reached",
        "dt_min_reached",
        "singular",
        "breakdown",
        "internal_error",
        "event_occurred",
    ):
        r = getattr(diffrax.RESULTS, name, None)
        if r is not None:
            names[int(r._value)] = name
    name = names.get(int(code), f"code {code}")
    kind = {"max_steps_reached": "max_steps", "dt_min_reached": "step_collapse"}.get(
        name, "solver_error"
    )
    return kind, f"diffrax: {name}"


def _check(model: DrivetrainModel, ts: np.ndarray, Y: np.ndarray, code: int, factor: float):
    from .scipy_backend import divergence_bound

    n = model.n_dof
    g = model.mesh_vectors()[0]
    bad = ~np.all(np.isfinite(Y), axis=1)
    bound = divergence_bound(model, factor)
    with np.errstate(invalid="ignore", over="ignore"):
        over = np.abs(np.nan_to_num(Y[:, :n] @ g, nan=np.inf)) > bound
    if code != 0:
        kind, msg = _result_kind(code)
        first = int(np.argmax(bad)) if bad.any() else len(ts) - 1
        # the last finite sample is the last known state before the stop
        k = max(first - 1, 0)
        return SolverFailure(kind, float(ts[k]), msg, tuple(Y[k].tolist()))
    if bad.any():
        i = int(np.argmax(bad))
        return SolverFailure(
            "nan", float(ts[i]), "non-finite state", tuple(Y[max(i - 1, 0)].tolist())
        )
    if over.any():
        i = int(np.argmax(over))
        return SolverFailure(
            "divergence",
            float(ts[i]),
            f"mesh deflection beyond {bound:.3g} m",
            tuple(Y[i].tolist()),
        )
    return None


def integrate_diffrax(
    model: DrivetrainModel,
    y0: np.ndarray,
    t_eval: np.ndarray,
    solver: DiffraxSolver = DiffraxSolver(),
    *,
    t0: float = 0.0,
):
    """As :func:`gearbox.drivetrain.scipy_backend.integrate_scipy`, with diffrax.

    ``info['compile_time']`` is the first-call overhead (0 when already compiled).
    """
    solver.validate()
    if not solver.adaptive:
        return _integrate_fixed(model, y0, t_eval, solver, t0=t0)
    jax, jnp = _jax()
    p = model.params()
    ts = np.concatenate([[t0], np.asarray(t_eval, float)])
    fn = solve_fn(solver)
    # numpy arrays, not jnp.asarray: that compiles a conversion per new shape (the
    # fixed-step path's 13 cost a new process 0.14 s, profiled); the compiled call takes
    # numpy arrays as they are
    pj = {k: np.asarray(v) for k, v in p.items()}
    z0 = np.asarray(y0, float) / p["scale"]
    key = (model.n_dof, ts.size, tuple((k, np.shape(v)) for k, v in p.items()))
    start = _time.perf_counter()
    compiled = _compiled((solver, key), fn, (pj, z0, ts))
    compile_time = _time.perf_counter() - start
    start = _time.perf_counter()
    zs, code, steps, rej = compiled(pj, z0, ts)
    zs = np.asarray(jax.block_until_ready(zs))
    wall = _time.perf_counter() - start
    Y = zs[1:] * p["scale"]
    failure = _check(model, ts[1:], Y, int(code), solver.divergence_factor)
    stages = 6 if solver.solver in ("Tsit5", "Dopri5") else 1
    info = {
        "status": "success" if failure is None else failure.kind,
        "failure": failure,
        "nfev": int(steps + rej) * stages,
        "steps": int(steps),
        "rejected": int(rej),
        "wall_time": wall,
        "compile_time": compile_time,
    }
    return ts[1:], Y, info


_COMPILED: dict = {}
_COMPILING: dict = {}
_LOCK = threading.Lock()

#: Compiled executables kept between processes, or None (default): an object whose
#: ``get(key, compile)`` returns the executable stored for ``key`` (this module's tuples)
#: or calls ``compile()`` and stores what it returns. ``gearbox run`` sets one in its
#: cache folder for a run (:mod:`gearbox.pipeline.jaxcache`): a new process then
#: neither traces nor compiles.
executable_store = None


def _compiled(key, fn, args):
    """``fn`` compiled for ``args``, once per ``key`` in this process: runs on threads (a
    pipeline's speed sweep) that need the same executable wait for one compilation."""
    with _LOCK:
        lock = _COMPILING.setdefault(key, threading.Lock())
    with lock:
        compiled = _COMPILED.get(key)
        if compiled is None:
            store = executable_store
            if store is not None:
                compiled = store.get(key, lambda: fn.lower(*args).compile())
            else:
                compiled = fn.lower(*args).compile()
            _COMPILED[key] = compiled
    return compiled


def _fixed_plan(model: DrivetrainModel, ts: np.ndarray, solver: DiffraxSolver, targets=None):
    """(plan, reached): the step plan cut at ``solver.max_steps`` and the number of
    output times reached within it."""
    import dataclasses

    from .fixed_step import plan_steps

    plan = plan_steps(model, ts, solver, targets=targets)
    if plan.n_steps <= solver.max_steps:
        return plan, plan.out.size
    reached = int(np.searchsorted(plan.out, solver.max_steps - 1, side="right"))
    cut = dataclasses.replace(
        plan,
        t=plan.t[: solver.max_steps],
        h=plan.h[: solver.max_steps],
        out=np.minimum(plan.out, solver.max_steps - 1),
    )
    return cut, reached


#: Steps per call of the compiled fixed-step program (a multiple of
#: :data:`gearbox.drivetrain.fixed_step.CHUNK`). A run of any length goes through the one
#: chunked program in segments of this many steps, the state carried from one to the
#: next, so every run of a method, table size and set of excitation orders shares one
#: compilation (and one entry of the pipeline's executable store); the last segment runs
#: only its own chunks. The default scene's operating point (29,133 steps) and its
#: slowest waterfall speed (58,636 steps) each had a compilation of their own (1.0 to
#: 1.3 s on the 2-core development machine), and came out the same to the bit in
#: segments, as fast (0.065 against 0.079 s and 0.136 against 0.130 s;
#: benchmarks/bench_fixed_segments.py).
SEGMENT = 16384


def _integrate_fixed(model, y0, t_eval, solver: DiffraxSolver, *, t0: float = 0.0):
    from .fixed_step import CHUNK, excitation_terms, fixed_solve_fn

    jax, _ = _jax()
    p = model.params()
    ts = np.concatenate([[t0], np.asarray(t_eval, float)])
    plan, reached = _fixed_plan(model, ts, solver)
    steps = plan.n_steps
    n_seg = max(1, -(-steps // SEGMENT))
    plan = plan.padded(n_seg * SEGMENT)
    fn = fixed_solve_fn(solver.solver, solver.table_cells, chunked=True, terms=excitation_terms(p))
    params = {k: np.asarray(v) for k, v in p.items()}  # numpy arrays, as in integrate_diffrax
    every = np.arange(SEGMENT)
    z = np.asarray(y0, float) / p["scale"]

    def segment(k, z, n_chunks):
        cut = slice(k * SEGMENT, (k + 1) * SEGMENT)
        return (params, z, plan.t[cut], plan.h[cut], every, np.int32(n_chunks))

    key = ("fixed segments", solver.solver, solver.table_cells, SEGMENT)
    key += excitation_terms(p)
    key += tuple((k, np.shape(v)) for k, v in p.items())
    start = _time.perf_counter()
    compiled = _compiled(key, fn, segment(0, z, SEGMENT // CHUNK))
    compile_time = _time.perf_counter() - start
    start = _time.perf_counter()
    zs = np.full((plan.out.size, z.size), np.nan)
    lost = 0
    for k in range(n_seg):
        own = min(SEGMENT, steps - k * SEGMENT)  # steps of this segment
        if own <= 0:
            break
        buf, n_lost = jax.block_until_ready(compiled(*segment(k, z, -(-own // CHUNK))))
        buf = np.asarray(buf)
        lost += int(n_lost)
        here = (plan.out >= k * SEGMENT) & (plan.out < (k + 1) * SEGMENT)
        zs[here] = buf[plan.out[here] - k * SEGMENT]
        z = buf[own - 1]
    wall = _time.perf_counter() - start
    if lost and solver.contact_rtol is not None:
        t, Y, info = integrate_diffrax(model, y0, t_eval, _contact_solver(solver), t0=t0)
        info["wall_time"] += wall
        info["compile_time"] += compile_time
        return t, Y, info | {"stepping": "adaptive (contact loss)", "contact_loss_steps": lost}
    Y = np.asarray(zs) * p["scale"]
    code = 0
    if reached < len(Y):
        Y[reached:] = np.nan
        code = _max_steps_code()
    failure = _check(model, ts[1:], Y, code, solver.divergence_factor)
    info = {
        "status": "success" if failure is None else failure.kind,
        "failure": failure,
        "nfev": steps * _stages(solver.solver),
        "steps": steps,
        "rejected": 0,
        "wall_time": wall,
        "compile_time": compile_time,
        "step": float(plan.h.max()) if plan.h.size else 0.0,
        "stability_limit": plan.limit,
        "stepping": "fixed",
        "contact_loss_steps": lost,
    }
    return ts[1:], Y, info


def _contact_solver(solver: DiffraxSolver) -> DiffraxSolver:
    """The adaptive settings that repeat a fixed-step run after contact loss."""
    return DiffraxSolver(
        rtol=solver.contact_rtol,
        max_steps=solver.max_steps,
        divergence_factor=solver.divergence_factor,
    )


def _stages(method: str) -> int:
    from .fixed_step import explicit_tableau

    return len(explicit_tableau(method)[1])


@lru_cache(maxsize=1)
def _mesh_force_fn():
    """jit(vmap over runs (vmap over samples)) of the signed mesh force F_drive - F_coast (N)
    from scaled states; shapes (B, n_t) and (B, n_t, 2 n) -> (B, n_t)."""
    jax, jnp = _jax()
    from .model import mesh_forces

    def one(p, ts, zs):
        y = zs * p["scale"]
        n = y.shape[-1] // 2
        f = jax.vmap(lambda t, yy: mesh_forces(t, yy[:n], yy[n:], p, xp=jnp)[0])(ts, y)
        return f[:, 0] - f[:, 1]

    return jax.jit(jax.vmap(one))


def integrate_diffrax_batch(
    models: list[DrivetrainModel],
    y0s: np.ndarray,
    t_evals: np.ndarray,
    solver: DiffraxSolver = DiffraxSolver(rtol=1e-6),
):
    """Batched adaptive runs (``vmap``): models differing in parameter values only.

    Adaptive settings only (``rtol`` given); :func:`integrate_speeds` batches one model
    over speeds with either kind of stepping.

    y0s: shape (B, 2 n); t_evals: shape (B, n_t), each row starting after t = 0.
    Returns (Y, infos): Y shape (B, n_t, 2 n) unscaled, infos one dict per run (status,
    failure, steps, ``mesh_force`` (N, shape (n_t,), computed on the device) and the
    batch wall time in ``batch_wall_time``).
    """
    solver.validate()
    if not solver.adaptive:
        from ..errors import InputError, Problem

        raise InputError(
            Problem("rtol", None, "integrate_diffrax_batch needs rtol; see integrate_speeds")
        )
    jax, jnp = _jax()
    ps = [m.params() for m in models]
    keys = ps[0].keys()
    for p in ps[1:]:
        for k in keys:
            if np.shape(p[k]) != np.shape(ps[0][k]):
                raise ValueError(f"batched models differ in the shape of {k!r}")
    P = {k: jnp.asarray(np.stack([p[k] for p in ps])) for k in keys}
    scale = np.stack([p["scale"] for p in ps])
    ts = np.concatenate([np.zeros((len(models), 1)), np.asarray(t_evals, float)], axis=1)
    Z0 = jnp.asarray(np.asarray(y0s, float) / scale)
    fn = jax.jit(jax.vmap(solve_fn(solver)))
    start = _time.perf_counter()
    compiled = fn.lower(P, Z0, jnp.asarray(ts)).compile()
    compile_time = _time.perf_counter() - start
    start = _time.perf_counter()
    zs, codes, steps, rej = compiled(P, Z0, jnp.asarray(ts))
    zs = np.asarray(jax.block_until_ready(zs))
    wall = _time.perf_counter() - start
    Y = zs[:, 1:] * scale[:, None, :]
    start = _time.perf_counter()
    force = np.asarray(_mesh_force_fn()(P, jnp.asarray(ts[:, 1:]), jnp.asarray(zs[:, 1:])))
    force_time = _time.perf_counter() - start
    infos = []
    for i, m in enumerate(models):
        failure = _check(m, ts[i, 1:], Y[i], int(codes[i]), solver.divergence_factor)
        infos.append(
            {
                "mesh_force": force[i],
                "force_time": force_time,
                "status": "success" if failure is None else failure.kind,
                "failure": failure,
                "steps": int(steps[i]),
                "rejected": int(rej[i]),
                "batch_wall_time": wall,
                "compile_time": compile_time,
            }
        )
    return Y, infos


@lru_cache(maxsize=1)
def _batch_summary_fn():
    """jit(vmap) of (signed mesh force (N), finite flags, drive mesh deflection (m)) per
    sample from scaled states; shapes (B, n_t) each."""
    jax, jnp = _jax()
    from .model import mesh_forces

    def one(p, ts, zs):
        y = zs * p["scale"]
        n = y.shape[-1] // 2
        f = jax.vmap(lambda t, yy: mesh_forces(t, yy[:n], yy[n:], p, xp=jnp)[0])(ts, y)
        return f[:, 0] - f[:, 1], jnp.all(jnp.isfinite(y), axis=-1), y[:, :n] @ p["G"][0]

    return jax.jit(jax.vmap(one))


def integrate_speeds(
    model: DrivetrainModel,
    speeds,
    y0s: np.ndarray,
    t_evals: np.ndarray,
    solver: DiffraxSolver = DiffraxSolver(),
    *,
    keep_states: bool = False,
    batch: str = "vmap",
) -> dict:
    """``model`` at every speed in one ``vmap`` batch, set up without one model per speed.

    speeds: Omega (rad/s), shape (B,); y0s: start states, shape (B, 2 n) (e.g.
    :func:`gearbox.drivetrain.linear.periodic_start_states`); t_evals: output times,
    shape (B, n_t), each row after t = 0. Fixed steps (default) pad every speed's step
    plan to one length (h = 0 steps), so all speeds step in lockstep; adaptive settings
    (``rtol``) step in lockstep until the slowest is done. ``batch='loop'`` (fixed steps
    only) runs the speeds one after the other through one compiled chunked run
    (:func:`gearbox.drivetrain.fixed_step.fixed_solve_fn`), each for its own steps only.

    Returns a dict: ``mesh_force`` (N, shape (B, n_t), computed on the device), ``status``
    and ``failure`` (one per speed, as :func:`integrate_diffrax`), ``steps`` (shape (B,)),
    ``wall_time`` (s, the batch run), ``compile_time`` (s), ``setup_time`` (s: parameters,
    step plans), ``contact_loss_steps`` (shape (B,): fixed steps out of the nominal
    contact; those speeds are repeated with adaptive steps at ``solver.contact_rtol``,
    their time included) and ``states`` (unscaled, shape (B, n_t, 2 n)) with
    ``keep_states``.
    """
    solver.validate()
    jax, jnp = _jax()
    t_setup = _time.perf_counter()
    speeds = np.asarray(speeds, dtype=float).ravel()
    t_evals = np.asarray(t_evals, dtype=float)
    P = model.speed_params(speeds)
    B, n_t = t_evals.shape
    ts = np.concatenate([np.zeros((B, 1)), t_evals], axis=1)
    Z0 = np.asarray(y0s, float) / P["scale"]
    reached = np.full(B, n_t)
    if solver.adaptive:
        fn = jax.jit(jax.vmap(solve_fn(solver)))
        args = (P, Z0, ts)
    else:
        from .fixed_step import CHUNK, bucket, excitation_terms, fixed_solve_fn, step_targets

        tg, lim, fmax = step_targets(model, solver, speeds)
        plans = []
        for i in range(B):
            plan, reached[i] = _fixed_plan(model, ts[i], solver, targets=(tg[i], lim[i], fmax[i]))
            plans.append(plan)
        steps = np.array([pl.n_steps for pl in plans])
        size = bucket(int(steps.max()))
        if batch == "loop":
            size = -(-size // CHUNK) * CHUNK
        plans = [pl.padded(size) for pl in plans]
        T = np.stack([pl.t for pl in plans])
        H = np.stack([pl.h for pl in plans])
        OUT = np.stack([pl.out for pl in plans])
        fn = fixed_solve_fn(solver.solver, solver.table_cells, terms=excitation_terms(P))
        fn = jax.jit(jax.vmap(fn))
        args = (P, Z0, T, H, OUT)
    args = jax.tree_util.tree_map(jnp.asarray, args)
    setup = _time.perf_counter() - t_setup
    if not solver.adaptive and batch == "loop":
        zs, compile_time, wall = _fixed_loop(solver, args, steps)
    else:
        start = _time.perf_counter()
        compiled = fn.lower(*args).compile()
        compile_time = _time.perf_counter() - start
        start = _time.perf_counter()
        zs = jax.block_until_ready(compiled(*args))
        wall = _time.perf_counter() - start
    lost = np.zeros(B, dtype=int)
    reruns: dict = {}
    if solver.adaptive:
        zs, codes, steps, _ = zs
        zs = zs[:, 1:]
        codes = np.asarray(codes)
    else:
        zs, lost = zs
        lost = np.asarray(lost)
        codes = np.where(reached < n_t, _max_steps_code(), 0)
        if solver.contact_rtol is not None and lost.any():
            # repeat the speeds with contact loss with adaptive steps, one by one
            zs = np.array(zs)
            steps = steps.copy()
            for i in np.flatnonzero(lost):
                _, Yi, info = integrate_diffrax(
                    model.with_speed(speeds[i]), y0s[i], t_evals[i], _contact_solver(solver)
                )
                zs[i] = Yi / P["scale"][i]
                steps[i] = info["steps"]
                reached[i] = n_t
                codes[i] = 0
                reruns[i] = info["failure"]
                wall += info["wall_time"]
                compile_time += info["compile_time"]
            zs = jnp.asarray(zs)
    out = _speed_results(model, args[0], zs, codes, steps, reached, t_evals, solver, keep_states)
    if reruns:  # the adaptive runs' own reports (their NaN samples are in zs already)
        fails = list(out["failure"])
        for i, f in reruns.items():
            fails[i] = f
        out["failure"] = tuple(fails)
        out["status"] = tuple("success" if f is None else f.kind for f in fails)
    return out | {
        "wall_time": wall,
        "compile_time": compile_time,
        "setup_time": setup,
        "contact_loss_steps": lost,
    }


def _max_steps_code() -> int:
    import diffrax

    return int(diffrax.RESULTS.max_steps_reached._value)


def _fixed_loop(solver: DiffraxSolver, args, steps: np.ndarray):
    """(scaled states, compile time, run time) of the speeds of :func:`integrate_speeds`
    one after the other through one compiled chunked run, each for its own steps."""
    from .fixed_step import CHUNK, excitation_terms, fixed_solve_fn

    jax, jnp = _jax()
    fn = fixed_solve_fn(solver.solver, solver.table_cells, True, excitation_terms(args[0]))
    n_chunks = -(-steps // CHUNK)

    def row(i):
        return jax.tree_util.tree_map(lambda v: v[i], args) + (int(n_chunks[i]),)

    start = _time.perf_counter()
    compiled = fn.lower(*row(0)).compile()
    compile_time = _time.perf_counter() - start
    wall = 0.0
    zs, lost = [], []
    for i in range(len(steps)):
        a = row(i)
        start = _time.perf_counter()
        z, n_lost = jax.block_until_ready(compiled(*a))
        wall += _time.perf_counter() - start
        zs.append(z)
        lost.append(n_lost)
    return (jnp.stack(zs), jnp.stack(lost)), compile_time, wall


def _speed_results(model, P, zs, codes, steps, reached, t_evals, solver, keep_states) -> dict:
    """Mesh force, status and failures per speed from the scaled states ``zs`` (device)."""
    from .scipy_backend import divergence_bound

    jax, jnp = _jax()
    B, n_t = t_evals.shape
    force, finite, defl = (np.asarray(a) for a in _batch_summary_fn()(P, jnp.asarray(t_evals), zs))
    for i in np.flatnonzero(reached < n_t):
        force[i, reached[i] :] = np.nan
        finite[i, reached[i] :] = False
    bound = divergence_bound(model, solver.divergence_factor)
    with np.errstate(invalid="ignore"):
        suspect = (codes != 0) | ~finite.all(axis=1) | (np.abs(defl) > bound).any(axis=1)
    failures: list = [None] * B
    states = None
    if keep_states or suspect.any():
        states = np.asarray(zs) * np.asarray(P["scale"])[:, None, :]
        for i in np.flatnonzero(reached < n_t):
            states[i, reached[i] :] = np.nan
    for i in np.flatnonzero(suspect):
        failures[i] = _check(model, t_evals[i], states[i], int(codes[i]), solver.divergence_factor)
    return {
        "mesh_force": force,
        "status": tuple("success" if f is None else f.kind for f in failures),
        "failure": tuple(failures),
        "steps": np.asarray(steps),
        "states": states if keep_states else None,
    }

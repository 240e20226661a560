"""exudyn backend of the drivetrain dynamics (docs/drivetrain.md, docs/exudyn.md).

The :class:`~gearbox.drivetrain.model.DrivetrainModel` becomes a real exudyn system:

- nodes: one ``Node1D`` per generalised coordinate (deviation from the nominal
  rotation, docs/drivetrain.md §1), plus a ground node;
- objects: ``ObjectRotationalMass1D`` (engine, pinion, gear, propeller with added water
  inertia) and ``ObjectMass1D`` (bearing translations);
- markers: ``MarkerNodeCoordinate`` on every coordinate and on the ground;
- connectors: ``ObjectConnectorCoordinateSpringDamper`` for the shafts, bearings and the
  speed governor (linear, evaluated in C++), and for the propeller load (quadratic in
  speed, blade-pass ripple in time: a spring-force user function);
- loads: ``LoadCoordinate`` on the engine, mean torque plus firing-order ripple in time
  (a load user function);
- the mesh: an ``ObjectGenericODE2`` over the pinion and gear coordinates (and the
  bearing translations) whose force user function evaluates both flanks' contact force
  with the pinion-angle-dependent stiffness k_f(theta_1) and the excitation
  e_f(theta_1) as truncated Fourier series (docs/drivetrain.md §3). A connector sees
  only relative motion; the pinion angle theta_1 = Omega t + q_1 + theta_10 needs the
  generic object.

User functions are exudyn *symbolic* user functions by default: the expression is
recorded once in Python and evaluated in C++, with no Python call per right-hand side
(``ExudynSolver(user_functions="python")`` keeps plain Python callbacks, for
comparison). In exudyn 1.13.6 ``CreateSymbolicUserFunction`` records the generic
object's vectors with zero length; the recording here uses symbolic vectors of the
object's size and sets the function from its dictionary.

The default integrator is exudyn's explicit RK67 at a fixed step chosen from the
model's highest frequency (docs/exudyn.md gives the measurements behind it): the
implicit solvers (generalized-alpha, trapezoidal) damp the mesh-frequency content at
practical steps. exudyn reports success even when the state has become NaN, so every
run is checked afterwards for non-finite values and for divergence (speed deviation
beyond the nominal speed, mesh deflection beyond ``divergence_deflection``); the time
and state of the first bad sample are reported.
"""

from __future__ import annotations

import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError, Problems

__all__ = [
    "ExudynRun",
    "ExudynSolver",
    "ExudynSystem",
    "build_exudyn_system",
    "simulate_exudyn",
    "stability_step_limit",
]

_METHODS = ("RK44", "RK67", "DOPRI5", "DVERK6", "ODE23")
_FIXED = {"RK44": 4, "RK67": 7}  # stages per step (Butcher tableaux of exudyn's RK44, RK67)
# Largest |lambda h| on the negative real axis for which the method is stable
# (Hairer, Norsett, Wanner, Solving ODEs I, Sec. IV.2 stability regions): RK44 2.785
# on the real axis, 2.83 on the imaginary axis; the explicit solvers are used here on
# lightly damped oscillations, so the imaginary-axis bound governs.
_IMAG_STABILITY = {"RK44": 2.83, "RK67": 3.0, "DOPRI5": 3.3, "DVERK6": 3.0, "ODE23": 1.7}


# ----------------------------------------------------------------------------- settings
@dataclass(frozen=True)
class ExudynSolver:
    """Settings of one exudyn run (a configured solver object, as in ``diffeqsolve``).

    method: exudyn explicit integrator: ``"RK67"`` (default, fixed step, 7th order),
        ``"RK44"`` (fixed step, classical RK4), or the adaptive ``"DOPRI5"``,
        ``"DVERK6"``, ``"ODE23"`` (exudyn's automatic step size control).
    step: time step (s) for the fixed-step methods, initial step for the adaptive ones;
        ``None`` chooses ``1 / (steps_per_period * f_max)`` with ``f_max`` the highest of
        the linearised eigenfrequencies and the highest mesh harmonic (Hz), rounded down
        so that ``output_step`` is a whole number of steps.
    steps_per_period: steps per period of ``f_max`` when ``step`` is None.
    rtol, atol: tolerances of the adaptive methods (relative; absolute in the model's
        coordinates, rad and m).
    user_functions: ``"symbolic"`` (recorded, evaluated in C++) or ``"python"``.
    max_steps: cap on the number of steps of one run.
    divergence_deflection: |mesh deflection| (m) beyond which the run is declared
        divergent; ``None``: 1000 x (static deflection + backlash).
    """

    method: str = "RK67"
    step: float | None = None
    steps_per_period: float = 20.0
    rtol: float = 1e-8
    atol: float = 1e-12
    user_functions: str = "symbolic"
    max_steps: int = 20_000_000
    divergence_deflection: float | None = None

    def check(self, path: str = "solver") -> None:
        """Raise :class:`InputError` listing every invalid setting."""
        p = Problems()
        p.check(
            self.method in _METHODS, f"{path}.method", self.method, f"must be one of {_METHODS}"
        )
        if self.step is not None:
            p.in_range(f"{path}.step", self.step, 0.0, 1.0, lo_open=True)
        p.in_range(f"{path}.steps_per_period", self.steps_per_period, 2.0, 1e6)
        p.in_range(f"{path}.rtol", self.rtol, 1e-14, 1.0, lo_open=False)
        p.in_range(f"{path}.atol", self.atol, 0.0, 1.0, lo_open=True)
        p.check(
            self.user_functions in ("symbolic", "python"),
            f"{path}.user_functions",
            self.user_functions,
            "must be 'symbolic' or 'python'",
        )
        p.check(int(self.max_steps) >= 1, f"{path}.max_steps", self.max_steps, "must be >= 1")
        if self.divergence_deflection is not None:
            p.in_range(
                f"{path}.divergence_deflection", self.divergence_deflection, 0.0, lo_open=True
            )
        p.raise_if_any("invalid exudyn solver settings")

    def to_dict(self) -> dict[str, Any]:
        return asdict(self)

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> ExudynSolver:
        return cls(**d)


# ----------------------------------------------------------------- model description
@dataclass(frozen=True)
class _Flank:
    """One flank's contact law (docs/drivetrain.md §3), SI.

    G: ndarray, shape (n,): delta_f = G . x (m per coordinate unit).
    k, e: FourierSeries in theta_1: tangent stiffness (N/m), no-load excitation (m).
    c: mesh damping (N s/m); b: gap offset (m, 0 for drive, backlash for coast).
    """

    name: str
    G: np.ndarray
    k: Any
    e: Any
    c: float
    b: float


@dataclass(frozen=True)
class _Plan:
    """Everything the exudyn system needs, in SI, read once from the model."""

    names: tuple[str, ...]
    inertia: np.ndarray  # (n,) kg m^2 or kg
    rotational: tuple[bool, ...]
    x0: np.ndarray  # (n,) initial coordinates (rad, m)
    v0: np.ndarray  # (n,) initial velocities (rad/s, m/s)
    springs: tuple[
        tuple[str, int, int, float, float, float], ...
    ]  # name, i, j(-1 ground), k, c, offset
    omega: float  # engine = pinion nominal speed (rad/s)
    omega2: float  # gear = propeller nominal speed (rad/s)
    theta10: float  # pinion angle at t = 0 (rad)
    flanks: tuple[_Flank, ...]
    engine_index: int
    engine_mean: float  # N m
    engine_ripple: tuple[
        tuple[float, float], ...
    ]  # (angular frequency rad/s, amplitude N m): A sin(w t)
    prop_index: int
    prop_kappa: float  # N m s^2
    prop_ripple: tuple[tuple[float, float], ...]  # (angular frequency rad/s, relative amplitude)

    @property
    def n(self) -> int:
        return len(self.names)


def _plan_from_model(model) -> _Plan:
    """Read a DrivetrainModel into a :class:`_Plan` (adapter to the model module)."""
    return model._exudyn_plan() if hasattr(model, "_exudyn_plan") else _plan_generic(model)


def _plan_generic(model) -> _Plan:  # pragma: no cover - replaced once the model lands
    raise InputError([], f"cannot build an exudyn system from {type(model).__name__}")


# ------------------------------------------------------------ user-function builders
def _fourier_terms(series, theta, cos, sin):
    """a0 + sum a_k cos(k N (theta - angle0)) + b_k sin(...) as an expression."""
    f = float(series.a0)
    arg0 = theta - float(series.angle0) if float(series.angle0) != 0.0 else theta
    for k, (a, b) in enumerate(zip(series.a, series.b, strict=True), start=1):
        w = k * series.teeth
        if a != 0.0:
            f = f + float(a) * cos(w * arg0)
        if b != 0.0:
            f = f + float(b) * sin(w * arg0)
    return f


def _fourier_derivative_terms(series, theta, cos, sin):
    f = 0.0
    arg0 = theta - float(series.angle0) if float(series.angle0) != 0.0 else theta
    for k, (a, b) in enumerate(zip(series.a, series.b, strict=True), start=1):
        w = k * series.teeth
        if b != 0.0:
            f = f + float(w * b) * cos(w * arg0)
        if a != 0.0:
            f = f - float(w * a) * sin(w * arg0)
    return f


def _mesh_force_symbolic(plan: _Plan, mesh_dofs: list[int]):
    """Symbolic force function of the mesh object over ``mesh_dofs``."""
    import exudyn as exu

    esym = exu.symbolic
    ip = mesh_dofs.index(1)
    zero = esym.Real(0.0)

    def mesh(mbs, t, itemNumber, q, q_t):
        theta = plan.omega * t + q[ip] + plan.theta10
        forces = []
        for fl in plan.flanks:
            delta = 0.0
            ddelta = 0.0
            for j, dof in enumerate(mesh_dofs):
                g = float(fl.G[dof])
                if g != 0.0:
                    delta = delta + g * q[j]
                    ddelta = ddelta + g * q_t[j]
            e = _fourier_terms(fl.e, theta, esym.cos, esym.sin)
            de = _fourier_derivative_terms(fl.e, theta, esym.cos, esym.sin)
            k = _fourier_terms(fl.k, theta, esym.cos, esym.sin)
            s = delta - e - fl.b
            sdot = ddelta - de * (plan.omega + q_t[ip])
            F = esym.IfThenElse(s > 0.0, esym.max(zero, k * s + fl.c * sdot), zero)
            forces.append((fl, F))
        out = []
        for dof in mesh_dofs:
            r = 0.0
            for fl, F in forces:
                g = float(fl.G[dof])
                if g != 0.0:
                    r = r - g * F
            out.append(r if not isinstance(r, float) else esym.Real(r))
        return out

    return mesh


def _mesh_force_python(plan: _Plan, mesh_dofs: list[int]):
    """Plain Python/numpy force function of the mesh object (same law)."""
    ip = mesh_dofs.index(1)
    G = np.array([[fl.G[d] for d in mesh_dofs] for fl in plan.flanks])  # (n_flanks, m)
    data = []
    for fl in plan.flanks:
        kk = np.arange(1, len(fl.k.a) + 1) * fl.k.teeth
        ke = np.arange(1, len(fl.e.a) + 1) * fl.e.teeth
        data.append((fl, kk, ke))

    def mesh(mbs, t, itemNumber, q, q_t):
        theta = plan.omega * t + q[ip] + plan.theta10
        qa = np.asarray(q)
        va = np.asarray(q_t)
        out = np.zeros(len(mesh_dofs))
        for i, (fl, kk, ke) in enumerate(data):
            ak = kk * (theta - fl.k.angle0)
            ae = ke * (theta - fl.e.angle0)
            ce, se = np.cos(ae), np.sin(ae)
            k = fl.k.a0 + fl.k.a @ np.cos(ak) + fl.k.b @ np.sin(ak)
            e = fl.e.a0 + fl.e.a @ ce + fl.e.b @ se
            de = ke @ (fl.e.b * ce - fl.e.a * se)
            s = G[i] @ qa - e - fl.b
            if s > 0.0:
                sdot = G[i] @ va - de * (plan.omega + va[ip])
                F = max(0.0, k * s + fl.c * sdot)
                out -= G[i] * F
        return out.tolist()

    return mesh


def _engine_load(plan: _Plan, symbolic: bool):
    """LoadCoordinate user function: T_e(t) = T_mean + sum A sin(w t) (N m)."""
    if symbolic:
        import exudyn as exu

        sin = exu.symbolic.sin
    else:
        sin = math.sin

    def engine(mbs, t, load):
        T = load
        for w, A in plan.engine_ripple:
            T = T + A * sin(w * t)
        return T

    return engine


def _propeller_force(plan: _Plan, symbolic: bool):
    """Spring-force user function of the propeller connector (ground -> propeller).

    The connector applies -f to the propeller coordinate (its displacement is
    q_p - 0), so f = +T_p = kappa (Omega_2 + v_p)^2 [1 + sum r sin(w t)] (N m).
    """
    if symbolic:
        import exudyn as exu

        sin = exu.symbolic.sin
    else:
        sin = math.sin
    W2 = plan.omega2
    kappa = plan.prop_kappa

    def propeller(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
        w = W2 + velocity
        r = 1.0
        for wr, A in plan.prop_ripple:
            r = r + A * sin(wr * t)
        return kappa * w * w * r

    return propeller


def _record_symbolic(mbs, fn, kind: str, vector_size: int = 0):
    """Record ``fn`` as an exudyn symbolic user function; returns (UserFunction, keepalive).

    kind: ``"generic"`` (ObjectGenericODE2.forceUserFunction, vectors of ``vector_size``),
    ``"spring"`` (ObjectConnectorCoordinateSpringDamper.springForceUserFunction),
    ``"load"`` (LoadCoordinate.loadUserFunction).
    """
    import exudyn as exu

    esym = exu.symbolic
    was = esym.GetRecording()
    esym.SetRecording(True)
    try:
        if kind == "generic":
            args = [
                mbs,
                esym.Real("t", 0.0),
                esym.Real("itemNumber", 0),
                esym.Vector("q", [0.0] * vector_size),
                esym.Vector("q_t", [0.0] * vector_size),
            ]
            types = ["MainSystem", "Real", "Index", "StdVector", "StdVector"]
            item, uname = "ObjectGenericODE2", "forceUserFunction"
        elif kind == "spring":
            names = [
                "t",
                "itemNumber",
                "displacement",
                "velocity",
                "stiffness",
                "damping",
                "offset",
            ]
            args = [mbs] + [esym.Real(nm, 0.0) for nm in names]
            types = ["MainSystem", "Real", "Index", "Real", "Real", "Real", "Real", "Real"]
            item, uname = "ObjectConnectorCoordinateSpringDamper", "springForceUserFunction"
        else:
            args = [mbs, esym.Real("t", 0.0), esym.Real("load", 0.0)]
            types = ["MainSystem", "Real", "Real"]
            item, uname = "LoadCoordinate", "loadUserFunction"
        ret = fn(*args)
        if isinstance(ret, list):
            ret = esym.Vector(ret)
            rtype = "StdVector"
        else:
            if isinstance(ret, float):
                ret = esym.Real(ret)
            rtype = "Real"
        spec = {
            "functionName": fn.__name__,
            "argList": args,
            "argTypeList": types,
            "returnValue": ret,
            "returnType": rtype,
        }
        uf = esym.UserFunction()
        uf.SetUserFunctionFromDict(mbs, spec, uname, None, item)
    finally:
        esym.SetRecording(was)
    return uf, (spec, args, ret)


# ---------------------------------------------------------------------- the system
@dataclass
class ExudynSystem:
    """A built exudyn system and the item indices that belong to the model.

    system_container, mbs: the exudyn ``SystemContainer`` and ``MainSystem``.
    nodes: one Node1D per model coordinate (same order as the model's names).
    bodies, markers, connectors, loads, mesh_object, sensors: exudyn item indices.
    """

    system_container: Any
    mbs: Any
    names: tuple[str, ...]
    nodes: list
    bodies: list
    markers: list
    connectors: dict
    loads: list
    mesh_object: Any
    sensors: list = field(default_factory=list)
    keepalive: list = field(default_factory=list)


def build_exudyn_system(
    model, solver: ExudynSolver = ExudynSolver(), *, plan: _Plan | None = None
) -> ExudynSystem:
    """Build the exudyn system of ``model`` (nodes, bodies, markers, connectors, loads).

    The system is assembled; sensors are not yet added (``simulate_exudyn`` adds them).
    """
    import exudyn as exu
    import exudyn.itemInterface as ii

    solver.check()
    if plan is None:
        plan = _plan_from_model(model)
    symbolic = solver.user_functions == "symbolic"
    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    keep: list = []
    nodes, bodies, markers = [], [], []
    for i, name in enumerate(plan.names):
        nd = mbs.AddNode(
            ii.Node1D(
                name=name,
                referenceCoordinates=[0.0],
                initialCoordinates=[float(plan.x0[i])],
                initialVelocities=[float(plan.v0[i])],
            )
        )
        nodes.append(nd)
        if plan.rotational[i]:
            bodies.append(
                mbs.AddObject(
                    ii.ObjectRotationalMass1D(
                        name=f"{name}_inertia", nodeNumber=nd, inertia=float(plan.inertia[i])
                    )
                )
            )
        else:
            bodies.append(
                mbs.AddObject(
                    ii.ObjectMass1D(name=f"{name}_mass", nodeNumber=nd, mass=float(plan.inertia[i]))
                )
            )
        markers.append(mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=nd, coordinate=0)))
    ground = mbs.AddNode(ii.NodePointGround(name="ground"))
    m_ground = mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))

    connectors = {}
    for name, i, j, k, c, off in plan.springs:
        m0 = m_ground if j < 0 else markers[j]
        # CoordinateSpringDamper: force k (q[m1] - q[m0] - offset) + c (v[m1] - v[m0]),
        # pulling the markers together; marker order gives T = k (q_i - q_j) on j.
        connectors[name] = mbs.AddObject(
            ii.ObjectConnectorCoordinateSpringDamper(
                name=name,
                markerNumbers=[m0, markers[i]],
                stiffness=float(k),
                damping=float(c),
                offset=float(off),
            )
        )

    # Engine: mean torque and firing-order ripple in time (docs/drivetrain.md §5).
    eng = _engine_load(plan, symbolic)
    if plan.engine_ripple:
        if symbolic:
            uf, kp = _record_symbolic(mbs, eng, "load")
            keep += [uf, kp]
            eng = uf
    else:
        eng = 0
    loads = [
        mbs.AddLoad(
            ii.LoadCoordinate(
                name="engine_torque",
                markerNumber=markers[plan.engine_index],
                load=float(plan.engine_mean),
                loadUserFunction=eng,
            )
        )
    ]

    # Propeller: quadratic load with blade-pass ripple (docs/drivetrain.md §6).
    prop = _propeller_force(plan, symbolic)
    if symbolic:
        uf, kp = _record_symbolic(mbs, prop, "spring")
        keep += [uf, kp]
        prop = uf
    connectors["propeller_load"] = mbs.AddObject(
        ii.ObjectConnectorCoordinateSpringDamper(
            name="propeller_load",
            markerNumbers=[m_ground, markers[plan.prop_index]],
            springForceUserFunction=prop,
        )
    )

    # Mesh: generic ODE2 object over the coordinates its flanks touch (§3).
    mesh_dofs = sorted({1} | {d for fl in plan.flanks for d in np.flatnonzero(fl.G).tolist()})
    fn = (_mesh_force_symbolic if symbolic else _mesh_force_python)(plan, mesh_dofs)
    if symbolic:
        uf, kp = _record_symbolic(mbs, fn, "generic", len(mesh_dofs))
        keep += [uf, kp]
        fn = uf
    m = len(mesh_dofs)
    mesh_object = mbs.AddObject(
        ii.ObjectGenericODE2(
            name="mesh",
            nodeNumbers=[nodes[d] for d in mesh_dofs],
            massMatrix=np.zeros((m, m)),
            forceUserFunction=fn,
        )
    )
    mbs.Assemble()
    return ExudynSystem(
        SC, mbs, plan.names, nodes, bodies, markers, connectors, loads, mesh_object, keepalive=keep
    )


# --------------------------------------------------------------------- simulation
@dataclass(frozen=True)
class ExudynRun:
    """Status and work of one exudyn run.

    status: 0 success, 1 divergence (|mesh deflection| or |speed deviation| beyond
        its bound), 2 non-finite state, 3 exudyn reported a failure (e.g. step size
        collapse of an adaptive method), 4 step limit reached.
    message: readable explanation (with the time and the state where it occurred).
    failure_time: s, or None; failure_state: dict name -> value (SI) at that time.
    steps: steps taken; rejected_steps: rejected steps (adaptive methods);
    rhs_evaluations: steps x stages (+ rejected steps x stages), the work measure.
    step: fixed step or the last step (s); build_time_s, wall_time_s: build and solve.
    """

    status: int
    message: str
    method: str
    user_functions: str
    step: float
    steps: int
    rejected_steps: int
    rhs_evaluations: int
    build_time_s: float
    wall_time_s: float
    failure_time: float | None = None
    failure_state: dict | None = None

    @property
    def success(self) -> bool:
        return self.status == 0

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["success"] = self.success
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> ExudynRun:
        d = dict(d)
        d.pop("success", None)
        return cls(**d)


def _linear_matrices(plan: _Plan) -> tuple[np.ndarray, np.ndarray]:
    """Mass and stiffness matrices about the operating point with the mean mesh stiffness.

    Returns (M, K), shape (n, n) each (kg m^2, N m/rad; kg, N/m).
    """
    n = plan.n
    M = np.diag(plan.inertia.astype(float))
    K = np.zeros((n, n))
    for _, i, j, k, _c, _off in plan.springs:
        K[i, i] += k
        if j >= 0:
            K[j, j] += k
            K[i, j] -= k
            K[j, i] -= k
    fl = plan.flanks[0]
    kmax = float(fl.k.a0 + np.abs(fl.k.a).sum() + np.abs(fl.k.b).sum())
    K += kmax * np.outer(fl.G, fl.G)
    return M, K


def stability_step_limit(model, method: str = "RK67", *, plan: _Plan | None = None) -> float:
    """Largest stable fixed step (s) of an explicit method on the linearised model.

    omega_max from ``det(K - omega^2 M) = 0`` with the *largest* drive mesh stiffness
    of the Fourier series (an upper bound of k(theta)); h_max = rho / omega_max with rho
    the method's stability bound on the imaginary axis (Hairer, Wanner, Solving ODEs II,
    Sec. IV.2).
    """
    if plan is None:
        plan = _plan_from_model(model)
    M, K = _linear_matrices(plan)
    w2 = np.linalg.eigvals(np.linalg.solve(M, K)).real
    wmax = math.sqrt(max(float(w2.max()), 1e-30))
    return _IMAG_STABILITY[method] / wmax


def _auto_step(plan: _Plan, solver: ExudynSolver, output_step: float) -> float:
    M, K = _linear_matrices(plan)
    w2 = np.linalg.eigvals(np.linalg.solve(M, K)).real
    f_mode = math.sqrt(max(float(w2.max()), 0.0)) / (2 * math.pi)
    f_mesh = plan.omega * plan.flanks[0].k.teeth / (2 * math.pi)
    harm = max(len(fl.k.a) for fl in plan.flanks)
    f_max = max(f_mode, harm * f_mesh)
    h = 1.0 / (solver.steps_per_period * f_max)
    h = min(h, 0.9 * _IMAG_STABILITY.get(solver.method, 1.7) / (2 * math.pi * f_mode))
    # a whole number of steps per output sample
    n = max(1, math.ceil(output_step / h - 1e-9))
    return output_step / n


def _check_args(t_end: float, output_step: float | None, solver: ExudynSolver) -> None:
    p = Problems()
    p.in_range("t_end", t_end, 0.0, 1e6, lo_open=True)
    if output_step is not None:
        p.in_range("output_step", output_step, 0.0, t_end, lo_open=True)
    p.raise_if_any("invalid exudyn simulation request")
    solver.check()


def _first_bad(t, x, v, plan: _Plan, bound: float) -> tuple[int, int] | None:
    """Index and kind (1 divergence, 2 non-finite) of the first bad output sample."""
    finite = np.isfinite(x).all(axis=0) & np.isfinite(v).all(axis=0)
    delta = plan.flanks[0].G @ np.where(np.isfinite(x), x, 0.0)
    speed = np.abs(np.where(np.isfinite(v), v, 0.0))
    rot = np.array(plan.rotational)
    diverged = (np.abs(delta) > bound) | (speed[rot].max(axis=0) > plan.omega)
    bad_nf = np.flatnonzero(~finite)
    bad_dv = np.flatnonzero(diverged & finite)
    cands = []
    if bad_nf.size:
        cands.append((int(bad_nf[0]), 2))
    if bad_dv.size:
        cands.append((int(bad_dv[0]), 1))
    return min(cands) if cands else None


def simulate_states(
    model,
    t_end: float,
    *,
    solver: ExudynSolver = ExudynSolver(),
    output_step: float | None = None,
    plan: _Plan | None = None,
):
    """Run exudyn; return (t, x, v, run).

    t: ndarray, shape (n_out,) (s), from 0 to t_end every ``output_step``;
    x, v: ndarray, shape (n, n_out): coordinates (rad, m) and velocities (rad/s, m/s);
    run: :class:`ExudynRun`.
    """
    import exudyn as exu
    import exudyn.itemInterface as ii

    if output_step is None:
        output_step = min(t_end, 2.5e-5 * 4)
    _check_args(t_end, output_step, solver)
    t0 = time.perf_counter()
    if plan is None:
        plan = _plan_from_model(model)
    fixed = solver.method in _FIXED
    h = solver.step if solver.step is not None else _auto_step(plan, solver, output_step)
    if fixed:
        n_out_steps = round(output_step / h)
        if abs(n_out_steps * h - output_step) > 1e-9 * output_step:
            raise InputError(
                [],
                f"output_step = {output_step!r} s must be a whole number of steps of "
                f"solver.step = {h!r} s (fixed-step {solver.method})",
            )
        n_steps = round(t_end / h)
        if abs(n_steps * h - t_end) > 1e-9 * t_end:
            raise InputError([], f"t_end = {t_end!r} s must be a whole number of steps of {h!r} s")
        if n_steps > solver.max_steps:
            p = Problems()
            p.add("solver.max_steps", solver.max_steps, f"must be >= {n_steps} for t_end/step")
            p.raise_if_any("exudyn step limit")
        hmax = stability_step_limit(model, solver.method, plan=plan)
        if h > hmax:
            p = Problems()
            p.add(
                "solver.step",
                h,
                f"must be <= {hmax:.4g} s, the {solver.method} stability limit "
                "for the model's highest eigenfrequency (mean mesh stiffness at its maximum)",
            )
            p.raise_if_any("unstable exudyn step")
    system = build_exudyn_system(model, solver, plan=plan)
    mbs = system.mbs
    for nd in system.nodes:
        system.sensors.append(
            mbs.AddSensor(
                ii.SensorNode(
                    nodeNumber=nd,
                    storeInternal=True,
                    writeToFile=False,
                    outputVariableType=exu.OutputVariableType.Coordinates,
                )
            )
        )
    for nd in system.nodes:
        system.sensors.append(
            mbs.AddSensor(
                ii.SensorNode(
                    nodeNumber=nd,
                    storeInternal=True,
                    writeToFile=False,
                    outputVariableType=exu.OutputVariableType.Coordinates_t,
                )
            )
        )
    mbs.Assemble()
    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.endTime = float(t_end)
    ti.verboseMode = 0
    ti.explicit.computeEndOfStepAccelerations = False
    if fixed:
        ti.numberOfSteps = int(n_steps)
        ti.automaticStepSize = False
    else:
        ti.automaticStepSize = True
        ti.numberOfSteps = max(1, math.ceil(t_end / h))
        ti.initialStepSize = float(h)
        ti.minimumStepSize = 1e-12
        ti.relativeTolerance = float(solver.rtol)
        ti.absoluteTolerance = float(solver.atol)
    s.solution.file.write = False
    s.solution.sensors.writePeriod = float(output_step)
    s.show.computationTime = False
    s.show.statistics = False
    build = time.perf_counter() - t0
    warn = exu.config.suppressWarnings
    console = exu.config.printToConsole
    exu.config.suppressWarnings = True
    exu.config.printToConsole = False
    failed = ""
    t1 = time.perf_counter()
    try:
        ok = exu.SolveDynamic(mbs, s, solverType=getattr(exu.DynamicSolverType, solver.method))
    except Exception as exc:  # exudyn raises its own errors (e.g. step size collapse)
        ok = False
        failed = f"{type(exc).__name__}: {exc}"
    finally:
        exu.config.suppressWarnings = warn
        exu.config.printToConsole = console
    wall = time.perf_counter() - t1
    it = mbs.sys["dynamicSolver"].it
    stages = mbs.sys["dynamicSolver"].GetNumberOfStages()
    steps = int(it.currentStepIndex) - (1 if fixed else 0)
    rejected = int(it.rejectedAutomaticStepSizeSteps)
    data = [mbs.GetSensorStoredData(sn) for sn in system.sensors]
    n = plan.n
    t = data[0][:, 0].copy()
    x = np.array([d[:, 1] for d in data[:n]])
    v = np.array([d[:, 1] for d in data[n:]])
    bound = solver.divergence_deflection
    if bound is None:
        fl = plan.flanks[0]
        static = abs(float(fl.G @ plan.x0))
        backlash = max((abs(f.b) for f in plan.flanks), default=0.0)
        bound = 1000.0 * (static + backlash) if static + backlash > 0 else 1e-2
    bad = _first_bad(t, x, v, plan, bound)
    status, msg, ftime, fstate = 0, "success", None, None
    if bad is not None:
        i, status = bad
        ftime = float(t[i])
        fstate = {nm: float(x[j, i]) for j, nm in enumerate(plan.names)}
        fstate.update({f"{nm}_velocity": float(v[j, i]) for j, nm in enumerate(plan.names)})
        fstate["mesh_deflection_m"] = float(plan.flanks[0].G @ x[:, i])
        what = (
            f"diverged: |mesh deflection| > {bound:.3g} m or |speed deviation| > nominal speed"
            if status == 1
            else "non-finite state"
        )
        msg = f"{what} at t = {ftime:.6g} s ({solver.method}, step {h:.4g} s)"
    elif not ok or failed:
        status = 3
        msg = f"exudyn {solver.method} failed at t = {float(it.currentTime):.6g} s {failed}".strip()
        ftime = float(it.currentTime)
    elif t.size and t[-1] < t_end * (1 - 1e-9) - output_step:
        status = 4
        msg = f"stopped at t = {t[-1]:.6g} s before t_end"
        ftime = float(t[-1])
    run = ExudynRun(
        status=status,
        message=msg,
        method=solver.method,
        user_functions=solver.user_functions,
        step=float(h if fixed else it.currentStepSize),
        steps=steps,
        rejected_steps=rejected,
        rhs_evaluations=int(stages * (steps + rejected)),
        build_time_s=build,
        wall_time_s=wall,
        failure_time=ftime,
        failure_state=fstate,
    )
    return t, x, v, run

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
  generic object. With mesh friction (``mesh_friction_coefficient`` mu > 0) the same
  function adds each flank's friction torques -mu phi_1f(theta_1) F_f on the pinion and
  +mu phi_2f(theta_1) F_f on the gear, the moment arms phi_1f, phi_2f again Fourier
  series in theta_1 (docs/drivetrain.md §3a); with mu = 0 nothing of it is built.
  With eccentricities (runout, docs/drivetrain.md §3b) each flank's gap gains the
  approach eps_f = R_1f cos(theta_1 - phi_1f) + R_2f cos(theta_2 - phi_2f) and its
  rate gains d eps_f/dt, theta_2 = Omega_2 t + q_2 + theta_20 the gear angle: the
  object then reads the gear coordinate for an angle too. Without eccentricity nothing
  of it is built. With pitch deviations (docs/drivetrain.md §3c) the drive flank's gap
  gains the approach a(theta_1) of a periodic cubic spline over the hunting period and
  its rate gains a'(theta_1) (Omega + v_1); the symbolic expression finds the spline's
  interval by a balanced tree of ``IfThenElse`` on the interval index (exudyn's symbolic
  vectors take no symbolic index), so a call evaluates about log2(n) comparisons, and
  the Python path indexes the coefficient table. Without pitch deviations nothing of it
  is built.

User functions are exudyn *symbolic* user functions by default: the expression is
recorded once in Python and evaluated in C++, with no Python call per right-hand side
(``ExudynSolver(user_functions="python")`` keeps plain Python callbacks, for
comparison). In exudyn 1.13.6 ``CreateSymbolicUserFunction`` records the generic
object's vectors with zero length; the recording here uses symbolic vectors of the
object's size and sets the function from its dictionary.

The default integrator is exudyn's explicit RK67 at a fixed step chosen from the
model's highest frequency (docs/exudyn.md gives the measurements behind it): the
implicit solvers (generalized-alpha, trapezoidal) damp the mesh-frequency content at
practical steps. A step beyond the stability limit of the linearised model is refused.
exudyn reports success even when the state has become NaN, so every run is checked
afterwards for non-finite values and for divergence (the scipy reference's bound on
the mesh deflection, or a speed deviation beyond the nominal speed); the time and state
of the first bad sample are reported.

Public: :class:`ExudynSolver`, :func:`integrate_exudyn` (the contract of
``scipy_backend.integrate_scipy``, used by ``gearbox.drivetrain.simulate.simulate``),
:func:`simulate_exudyn` (a :class:`~gearbox.drivetrain.timeseries.TimeSeries` from the
operating point), :func:`build_exudyn_system`, :func:`stability_step_limit`.
"""

from __future__ import annotations

import dataclasses
import math
import time
from dataclasses import asdict, dataclass, field
from typing import Any

import numpy as np

from ..errors import InputError, Problem, Problems
from .model import _series_rows, loaded_force

__all__ = [
    "ExudynSolver",
    "ExudynSystem",
    "add_state_sensors",
    "build_exudyn_system",
    "integrate_exudyn",
    "simulate_exudyn",
    "stability_step_limit",
]

_METHODS = ("RK67", "RK44")
_STEPS_PER_PERIOD = {"RK67": 20.0, "RK44": 40.0}
# Stability polynomials R(z) = sum c_k z^k of exudyn's explicit methods: one step of
# y' = lambda y multiplies y by R(h lambda). RK44: the classical RK4 (Hairer, Norsett,
# Wanner, Solving ODEs I, Sec. II.1). RK67: 6th order, so c_0..c_6 = 1/k!; c_7 was
# measured from exudyn 1.13.6's one-step map of linear oscillators (a least-squares
# fit, residual 1e-14; tests/test_drivetrain_exudyn.py repeats the measurement).
# RK67 has no stability interval on the imaginary axis (|R(i y)| = 1 + 5e-4 at y = 1):
# it relies on the model's damping.
_STABILITY = {
    "RK44": (1.0, 1.0, 1 / 2, 1 / 6, 1 / 24),
    "RK67": (1.0, 1.0, 1 / 2, 1 / 6, 1 / 24, 1 / 120, 1 / 720, -4.494538857633401e-04),
}
# Accepted growth per step of a mode, |R(h lambda)| <= 1 + _GROWTH: 1e-8 per step
# amplifies an undamped mode by 1 % only after 1e6 steps.
_GROWTH = 1e-8


# ----------------------------------------------------------------------------- settings
@dataclass(frozen=True)
class ExudynSolver:
    """Settings of the exudyn backend (a configured solver object, as in ``diffeqsolve``).

    method: exudyn explicit fixed-step integrator, ``"RK67"`` (default) or ``"RK44"``.
    step: target time step (s); ``None`` chooses ``1 / (steps_per_period f_max)``, with
        ``f_max`` the higher of the highest linearised eigenfrequency (drive mesh at its
        largest stiffness) and the mesh frequency N_1 Omega / (2 pi) (Hz), and at most
        0.8 x the stability limit. The step used is the largest one <= target that puts
        the output samples on the step grid (so the sample spacing caps the step).
    steps_per_period: ``None``: 20 for RK67, 40 for RK44 (docs/exudyn.md: 5e-7 and
        1.5e-5 sample-wise relative error of the mesh force on the default scene).
    user_functions: ``"symbolic"`` (recorded once, evaluated in C++) or ``"python"``.
    layout: ``"components"`` (bodies, connectors, loads; the mesh a generic ODE2 object)
        or ``"generic"`` (one generic ODE2 object holding mass, stiffness and damping
        matrices and one force function for mesh, engine and propeller).
    max_steps: cap on the steps of one run.
    divergence_factor: a run counts as diverged when |mesh deflection| exceeds this
        factor times the static deflection (+ 10 x backlash), as in the scipy
        reference, or a speed deviation exceeds the nominal speed.
    """

    method: str = "RK67"
    step: float | None = None
    steps_per_period: float | None = None
    user_functions: str = "symbolic"
    layout: str = "components"
    max_steps: int = 50_000_000
    divergence_factor: float = 1e3

    name = "exudyn"

    def validate(self) -> None:
        """Raise :class:`InputError` listing every invalid setting."""
        p = Problems()
        p.check(self.method in _METHODS, "method", self.method, f"must be one of {_METHODS}")
        if self.step is not None:
            p.in_range("step", self.step, 0.0, 1.0, lo_open=True)
        if self.steps_per_period is not None:
            p.in_range("steps_per_period", self.steps_per_period, 2.0, 1e6)
        p.check(
            self.user_functions in ("symbolic", "python"),
            "user_functions",
            self.user_functions,
            "must be 'symbolic' or 'python'",
        )
        p.check(
            self.layout in ("components", "generic"),
            "layout",
            self.layout,
            "must be 'components' or 'generic'",
        )
        p.check(int(self.max_steps) >= 1, "max_steps", self.max_steps, "must be >= 1")
        p.in_range("divergence_factor", self.divergence_factor, 1.0, None, lo_open=True)
        p.raise_if_any("invalid exudyn solver settings")

    @property
    def target_steps_per_period(self) -> float:
        if self.steps_per_period is not None:
            return float(self.steps_per_period)
        return _STEPS_PER_PERIOD[self.method]

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
    f1, f2: FourierSeries in theta_1 of mu phi_1 and mu phi_2, the friction coefficient
    times the friction's moment arms about the pinion's and the gear's axis (m,
    docs/drivetrain.md §3a): torques -f1 F_f on the pinion, +f2 F_f on the gear; None
    without friction.
    r1, r2: FourierSeries of one harmonic (teeth 1) in theta_1 and in theta_2 of the
    approach eps_f the pinion's and the gear's eccentricity give the flank (m, docs
    §3b: A_i cos theta_i + B_i sin theta_i); None without eccentricity.
    pitch: :class:`_Pitch`, the pitch deviations' approach a(theta_1) of the drive flank
    (docs §3c); None without them (and always on the coast flank).
    law: the loaded mesh law (docs §3d): (coefficients of its 2 J + 1 rows, shape
    (2 J + 1, 1 + 2 h), the levels' forces (J,), N_1), evaluated by the Python user
    functions with :func:`gearbox.drivetrain.model.loaded_force`; None for the tangent law.
    """

    name: str
    G: np.ndarray
    k: Any
    e: Any
    c: float
    b: float
    f1: Any = None
    f2: Any = None
    r1: Any = None
    r2: Any = None
    pitch: Any = None
    law: Any = None

    def __post_init__(self):
        object.__setattr__(self, "k_harmonics", _harmonics(self.k))
        object.__setattr__(self, "e_harmonics", _harmonics(self.e))
        if self.friction:
            object.__setattr__(self, "f1_harmonics", _harmonics(self.f1))
            object.__setattr__(self, "f2_harmonics", _harmonics(self.f2))
        if self.eccentric:
            object.__setattr__(self, "r1_harmonics", _harmonics(self.r1))
            object.__setattr__(self, "r2_harmonics", _harmonics(self.r2))

    @property
    def friction(self) -> bool:
        """Whether the flank carries friction torques (mu > 0)."""
        return self.f1 is not None

    @property
    def eccentric(self) -> bool:
        """Whether an eccentricity moves the flank's gap (docs/drivetrain.md §3b)."""
        return self.r1 is not None

    @property
    def gap_bounds(self) -> tuple[float, float]:
        """Bounds (m) of e_f - eps_f - a_f: the flank is in contact when delta_f - b_f is
        above the upper one, out of it when at or below the lower one (:func:`_bounds` of
        the error series, widened by the eccentricities' amplitudes R_1f + R_2f and by the
        pitch spline's range, :attr:`_Pitch.bounds`)."""
        lo, hi = _bounds(self.e, self.e_harmonics)
        if self.eccentric:
            r = sum(R for _, R, _ in self.r1_harmonics + self.r2_harmonics)
            r = r + 1e-9 * r
            lo, hi = lo - r, hi + r
        if self.pitch is not None:
            a_lo, a_hi = self.pitch.bounds
            lo, hi = lo - a_hi, hi - a_lo
        return lo, hi

    @property
    def W(self) -> np.ndarray:
        """Mean generalised direction of the contact force, shape (n,): the force enters
        as -W F_f with W = G + mu (phi_1 bar on the pinion, -phi_2 bar on the gear), the
        arms' cycle means (``DrivetrainModel.friction_vectors``); G without friction."""
        if not self.friction:
            return self.G
        w = self.G.copy()
        w[1] += float(self.f1.a0)
        w[2] -= float(self.f2.a0)
        return w


@dataclass(frozen=True)
class _Pitch:
    """The pitch deviations' approach of the drive flank (docs/drivetrain.md §3c): the
    periodic cubic spline of :class:`~gearbox.drivetrain.model.PitchApproach`.

    coef: shape (n, 4), ``params()['pt']``: a = c0 + d (c1 + d (c2 + d c3)) on the
    interval i, d in [0, 1) the position in it (in samples); angle0 (rad), the pinion
    angle of sample 0, ``params()['pt0']``; step (rad), the sample spacing,
    ``params()['pts']``. The interval of theta_1 is i = floor(u) mod n,
    u = (theta_1 - angle0) / step, in the model's order of operations
    (``model._pitch_eval``), so both user-function kinds give its numbers bit for bit.
    """

    coef: np.ndarray
    angle0: float
    step: float

    @property
    def n(self) -> int:
        return int(self.coef.shape[0])

    @property
    def bounds(self) -> tuple[float, float]:
        """Lower and upper bounds (m) of a(theta_1): the cubic's extremes on each interval
        (its ends and the roots of its derivative inside), widened by 1e-9 relative."""
        if "_bounds" not in self.__dict__:
            c0, c1, c2, c3 = (self.coef[:, j] for j in range(4))
            cands = [c0, c0 + c1 + c2 + c3]
            # roots of c1 + 2 c2 d + 3 c3 d^2 in (0, 1), without cancellation:
            # q = -(B + sign(B) sqrt(B^2 - 4 A C)) / 2, roots q / A and C / q
            A, B, C = 3.0 * c3, 2.0 * c2, c1
            disc = B * B - 4.0 * A * C
            ok = disc >= 0.0
            q = -0.5 * (B + np.copysign(np.sqrt(np.where(ok, disc, 0.0)), B))
            with np.errstate(divide="ignore", invalid="ignore"):
                roots = [q / A, C / q]
            for d in roots:
                inside = ok & np.isfinite(d) & (d > 0.0) & (d < 1.0)
                dd = np.where(inside, d, 0.0)
                cands.append(np.where(inside, c0 + dd * (c1 + dd * (c2 + dd * c3)), c0))
            v = np.concatenate(cands)
            lo, hi = float(v.min()), float(v.max())
            pad = 1e-9 * max(abs(lo), abs(hi)) + 1e-300
            object.__setattr__(self, "_bounds", (lo - pad, hi + pad))
        return self.__dict__["_bounds"]

    def terms(self, theta, w):
        """(a, da/dt) in m and m/s at the pinion angle theta (rad) and its absolute speed
        w = Omega + v_1 (rad/s), floats: the coefficient table indexed directly."""
        u = (theta - self.angle0) / self.step
        i0 = math.floor(u)
        d = u - i0
        c0, c1, c2, c3 = self.rows[i0 % self.n]
        a = c0 + d * (c1 + d * (c2 + d * c3))
        da = (c1 + d * (2.0 * c2 + 3.0 * d * c3)) / self.step
        return a, da * w

    @property
    def rows(self) -> list:
        """The coefficients as a list of float 4-tuples (the Python path's table)."""
        if "_rows" not in self.__dict__:
            object.__setattr__(self, "_rows", [tuple(map(float, r)) for r in self.coef])
        return self.__dict__["_rows"]

    def terms_symbolic(self, theta, w):
        """(a, da/dt) as exudyn symbolic expressions of the pinion angle expression theta
        and the speed expression w: i = i0 - n floor(i0 / n) (i0 = floor(u), exact in
        floating point; exudyn's ``mod`` keeps the sign of i0), then one balanced
        ``IfThenElse`` tree on i per quantity whose leaves are the intervals' cubics in
        d = u - i0. ``IfThenElse`` evaluates only the branch taken: ceil(log2 n)
        comparisons and one cubic per evaluation; the tree holds all n cubics.
        """
        import exudyn as exu

        esym = exu.symbolic
        n, step = self.n, self.step
        u = (theta - self.angle0) / step
        i0 = esym.floor(u)
        d = u - i0
        i = i0 - n * esym.floor(i0 / n)
        rows = self.rows

        def tree(lo, hi, leaf):
            if hi - lo == 1:
                return leaf(*rows[lo])
            mid = (lo + hi) // 2
            return esym.IfThenElse(i < mid - 0.5, tree(lo, mid, leaf), tree(mid, hi, leaf))

        def value(c0, c1, c2, c3):
            return c0 + d * (c1 + d * (c2 + d * c3))

        def slope(c0, c1, c2, c3):
            return (c1 + d * (2.0 * c2 + 3.0 * d * c3)) / step

        return tree(0, n, value), tree(0, n, slope) * w


@dataclass(frozen=True)
class _Plan:
    """Everything the exudyn system needs, in SI, read once from the model.

    inertia: shape (n,), kg m^2 (rotations) or kg (translations); x0, v0: shape (n,),
    initial coordinates (rad, m) and velocities (rad/s, m/s). springs: (name, i, j, k,
    c, offset), j = -1 for ground: torque or force k (q_i - q_j - offset) + c (v_i - v_j).
    omega, omega2: nominal engine/pinion and gear/propeller speeds (rad/s); theta10,
    theta20: pinion and gear angle at t = 0 (rad). engine_ripple: (w rad/s, A N m)
    terms A sin(w t); prop_kappa: N m s^2; prop_ripple: (w rad/s, relative amplitude
    r) terms r sin(w t).
    """

    names: tuple[str, ...]
    inertia: np.ndarray
    rotational: tuple[bool, ...]
    x0: np.ndarray
    v0: np.ndarray
    springs: tuple
    omega: float
    omega2: float
    theta10: float
    theta20: float
    flanks: tuple[_Flank, ...]
    engine_index: int
    engine_mean: float
    engine_ripple: tuple
    prop_index: int
    prop_kappa: float
    prop_ripple: tuple

    @property
    def n(self) -> int:
        return len(self.names)

    @property
    def flank_arrays(self) -> list:
        if "_arrays" not in self.__dict__:
            object.__setattr__(self, "_arrays", [_flank_arrays(fl) for fl in self.flanks])
        return self.__dict__["_arrays"]

    @property
    def friction_arrays(self) -> list:
        """Per flank, (w, R, phi) arrays of mu phi_1 and mu phi_2, or None (python path)."""
        if "_friction_arrays" not in self.__dict__:
            arrays = [_friction_arrays(fl) if fl.friction else None for fl in self.flanks]
            object.__setattr__(self, "_friction_arrays", arrays)
        return self.__dict__["_friction_arrays"]


def _series(coef: np.ndarray, teeth: int, floor: float = 0.0):
    """FourierSeries from the model's coefficient row [a0, a_1..a_h, b_1..b_h].

    Harmonics with amplitude sqrt(a_k^2 + b_k^2) below ``floor`` are set to zero: the
    symbolic expression would evaluate them on every call. The floor is 1e-12 of the
    series' scale (see :func:`_plan_from_model`), so the dropped part changes the mesh
    force by about 1e-12 of its static value; it removes the rounding noise the Fourier
    fit leaves in an error series that is zero in exact arithmetic (a linear mesh:
    tangent = secant stiffness gives e = LTE - F/k = 0, fitted as ~1e-21 m terms).
    """
    from ..meshtable import FourierSeries

    c = np.asarray(coef, dtype=float)
    h = (c.size - 1) // 2
    a, b = c[1 : 1 + h].copy(), c[1 + h :].copy()
    small = np.hypot(a, b) < floor
    a[small] = 0.0
    b[small] = 0.0
    return FourierSeries(float(c[0]), a, b, int(teeth), 0.0)


def _plan_from_model(model) -> _Plan:
    """Read a :class:`~gearbox.drivetrain.model.DrivetrainModel` into a :class:`_Plan`.

    Same parameters as :meth:`DrivetrainModel.params` (docs/drivetrain.md §4-7): the
    shafts' and bearings' damping from :meth:`structural_matrices`, the mesh vectors
    from :meth:`mesh_vectors`, the excitation orders from :meth:`excitation_orders`.
    With mesh friction (mu > 0) each flank's friction arms times mu (docs §3a), their
    harmonics floored at 1e-12 mu lambda_1 (lambda_2): about 1e-12 of the mesh torque.
    With eccentricities each flank's approach coefficients ``params()['rc']`` and the
    gear angle's phase ``params()['phase2']`` (docs §3b). With pitch deviations the
    drive flank's spline ``params()['pt']``, ``['pt0']``, ``['pts']`` (docs §3c, a
    :class:`_Pitch`).
    """
    n = model.n_dof
    K, C = model.structural_matrices()
    G = model.mesh_vectors()
    y0 = model.static_state()
    p = model.params()
    rc = p["rc"]  # shape (2, 0) without eccentricity: nothing built
    springs = [
        ("input_shaft", 0, 1, float(-K[0, 1]), float(-C[0, 1]), 0.0),
        ("output_shaft", 2, 3, float(-K[2, 3]), float(-C[2, 3]), 0.0),
    ]
    if model.bearing_dofs:
        springs += [
            ("pinion_bearing", 4, -1, float(K[4, 4]), float(C[4, 4]), 0.0),
            ("gear_bearing", 5, -1, float(K[5, 5]), float(C[5, 5]), 0.0),
        ]
    if model.governor and (model.governor_kp > 0 or model.governor_ki > 0):
        # T_gov = -K_p v_e - K_i (q_e - q_e0): a spring-damper from ground (docs §5)
        springs.append(
            ("governor", 0, -1, float(model.governor_ki), float(model.governor_kp), float(y0[0]))
        )
    static = abs(model.torque / model.drive.lambda1 / model.drive.mean_stiffness)  # m
    mu = float(model.mesh_friction_coefficient)
    flanks = []
    for r, (name, fl) in enumerate((("drive", model.drive), ("coast", model.coast))):
        if fl is None:
            continue
        extra = {}  # friction arms, eccentricities
        if mu > 0 and fl.friction_coef is not None:  # docs/drivetrain.md §3a
            fc = np.asarray(fl.friction_coef, dtype=float)
            extra = {
                f"f{i + 1}": _series(mu * fc[i], model.pinion_teeth, 1e-12 * mu * lam)
                for i, lam in enumerate((float(fl.lambda1), float(fl.lambda2)))
            }
        if rc.shape[-1]:  # docs/drivetrain.md §3b: [A_1, B_1, A_2, B_2]
            extra["r1"] = _series(np.r_[0.0, rc[r, 0:2]], 1)
            extra["r2"] = _series(np.r_[0.0, rc[r, 2:4]], 1)
        if name == "drive" and p["pt"].shape[0]:  # docs/drivetrain.md §3c
            pt = np.array(p["pt"], dtype=float)
            extra["pitch"] = _Pitch(pt, float(p["pt0"]), float(p["pts"]))
        if fl.load_coef is not None:  # docs/drivetrain.md §3d
            extra["law"] = (
                np.asarray(fl.load_coef, dtype=float),
                np.asarray(fl.load_forces, dtype=float),
                float(model.pinion_teeth),
            )
        flanks.append(
            _Flank(
                name,
                G[r].copy(),
                _series(fl.k_coef, model.pinion_teeth, 1e-12 * abs(float(fl.k_coef[0]))),
                _series(fl.e_coef, model.pinion_teeth, 1e-12 * static),
                float(fl.damping),
                float(fl.backlash),
                **extra,
            )
        )
    eo, ea, po, pa = model.excitation_orders()
    W, W2 = float(model.speed), float(model.gear_speed)
    return _Plan(
        names=tuple(model.dof_names),
        inertia=np.asarray(model.mass_vector(), dtype=float),
        rotational=tuple(i < 4 for i in range(n)),
        x0=y0[:n].copy(),
        v0=y0[n:].copy(),
        springs=tuple(springs),
        omega=W,
        omega2=W2,
        theta10=float(model.phase),
        theta20=float(p["phase2"]),
        flanks=tuple(flanks),
        engine_index=0,
        engine_mean=float(model.torque),
        engine_ripple=tuple(
            (float(o) * W, float(a) * float(model.torque))
            for o, a in zip(eo, ea, strict=True)
            if a != 0.0
        ),
        prop_index=3,
        prop_kappa=float(model.propeller_coefficient),
        prop_ripple=tuple(
            (float(o) * W2, float(a)) for o, a in zip(po, pa, strict=True) if a != 0.0
        ),
    )


# ------------------------------------------------------------ user-function builders
def _harmonics(series):
    """(w, R, phi) per non-zero harmonic: a cos(w x) + b sin(w x) = R cos(w x - phi)."""
    out = []
    for k, (a, b) in enumerate(zip(series.a, series.b, strict=True), start=1):
        R = math.hypot(float(a), float(b))
        if R != 0.0:
            out.append((float(k * series.teeth), R, math.atan2(float(b), float(a))))
    return out


def _bounds(series, harmonics) -> tuple[float, float]:
    """Lower and upper bounds of a series, a0 -/+ sum R_k, widened by 1e-9 relative."""
    r = sum(R for _, R, _ in harmonics)
    pad = 1e-9 * (abs(float(series.a0)) + r) + 1e-300
    return float(series.a0) - r - pad, float(series.a0) + r + pad


def _fourier_terms(series, harmonics, theta, cos):
    """a0 + sum R_k cos(k N (theta - angle0) - phi_k): one cosine per harmonic."""
    f = float(series.a0)
    x = theta - float(series.angle0) if float(series.angle0) != 0.0 else theta
    for w, R, phi in harmonics:
        f = f + R * cos(w * x - phi)
    return f


def _fourier_derivative_terms(series, harmonics, theta, sin):
    """d/dtheta of :func:`_fourier_terms`: -sum w_k R_k sin(w_k x - phi_k)."""
    f = 0.0
    x = theta - float(series.angle0) if float(series.angle0) != 0.0 else theta
    for w, R, phi in harmonics:
        f = f - (w * R) * sin(w * x - phi)
    return f


def _harmonic_arrays(harmonics):
    """numpy arrays (w, R, phi), each shape (h,), of a series' harmonics."""
    arr = np.array(harmonics, dtype=float).reshape(-1, 3)
    return arr[:, 0].copy(), arr[:, 1].copy(), arr[:, 2].copy()


def _flank_arrays(fl: _Flank):
    """numpy arrays (w, R, phi) of the stiffness and error series (python path)."""
    return [_harmonic_arrays(hs) for hs in (fl.k_harmonics, fl.e_harmonics)]


def _friction_arrays(fl: _Flank):
    """numpy arrays (w, R, phi) of the series mu phi_1 and mu phi_2 (python path)."""
    return [_harmonic_arrays(hs) for hs in (fl.f1_harmonics, fl.f2_harmonics)]


def _eccentricity_terms(fl: _Flank, theta1, theta2, w1, w2, cos, sin):
    """The eccentricities' approach of one flank and its rate (docs/drivetrain.md §3b):
    (eps_f, d eps_f/dt) in m and m/s, eps_f = sum_i R_if cos(theta_i - phi_if) and
    d eps_f/dt = -sum_i R_if sin(theta_i - phi_if) w_i over the eccentric members i
    (pinion, gear), theta_i their angles and w_i their absolute speeds Omega_i + v_i
    (floats with math's cos, sin, or exudyn symbolic expressions with its own); None
    when neither member moves the flank. One cosine and one sine per member.
    """
    eps = rate = None
    for series, harmonics, theta, w in (
        (fl.r1, fl.r1_harmonics, theta1, w1),
        (fl.r2, fl.r2_harmonics, theta2, w2),
    ):
        if not harmonics:
            continue
        a = _fourier_terms(series, harmonics, theta, cos)
        b = _fourier_derivative_terms(series, harmonics, theta, sin) * w
        eps = a if eps is None else eps + a
        rate = b if rate is None else rate + b
    return None if eps is None else (eps, rate)


def _approach_terms(fl: _Flank, angles, speeds, symbolic: bool):
    """The flank's kinematic approach and its rate (m, m/s), or None: the
    eccentricities' (:func:`_eccentricity_terms`, docs/drivetrain.md §3b) plus the pitch
    deviations' a(theta_1), a'(theta_1) (Omega + v_1) on the drive flank (docs §3c), in
    the order of ``model.approach_terms``. angles, speeds: (theta_1, theta_2) and
    (Omega + v_1, Omega_2 + v_2) (theta_2 and its speed None without eccentricity).
    """
    out = None
    if fl.eccentric:
        if symbolic:
            import exudyn as exu

            cos, sin = exu.symbolic.cos, exu.symbolic.sin
        else:
            cos, sin = math.cos, math.sin
        out = _eccentricity_terms(fl, *angles, *speeds, cos, sin)
    if fl.pitch is not None:
        if symbolic:
            a, rate = fl.pitch.terms_symbolic(angles[0], speeds[0])
        else:
            a, rate = fl.pitch.terms(angles[0], speeds[0])
        out = (a, rate) if out is None else (out[0] + a, out[1] + rate)
    return out


def _friction_direction_symbolic(fl: _Flank, pos: dict[int, int], size: int, theta, u, gv):
    """Symbolic direction W_f(theta_1) of one flank's generalised force -W_f F_f with
    friction, length ``size``: gv (= -G_f) plus -mu phi_1(theta_1) on the pinion and
    +mu phi_2(theta_1) on the gear (docs/drivetrain.md §3a).

    The arms are evaluated only for u = delta - b > lo (:attr:`_Flank.gap_bounds`):
    below, the flank is out of contact (F_f = 0) whatever they are, so a separated flank
    costs no series.
    """
    import exudyn as exu

    esym = exu.symbolic
    zero = esym.Real(0.0)
    e_lo, _ = fl.gap_bounds
    out = esym.Vector(gv)
    for dof, series, harmonics, sign in (
        (1, fl.f1, fl.f1_harmonics, -1.0),
        (2, fl.f2, fl.f2_harmonics, 1.0),
    ):
        unit = [0.0] * size
        unit[pos[dof]] = sign
        arm = _fourier_terms(series, harmonics, theta, esym.cos)
        out = out + esym.IfThenElse(u > e_lo, arm, zero) * esym.Vector(unit)
    return out


def flank_force_symbolic(
    plan: _Plan,
    fl: _Flank,
    pos: dict[int, int],
    size: int,
    q,
    q_t,
    k,
    e,
    de,
    theta=None,
    ecc=None,
):
    """Symbolic generalised force vector -G_f F_f of one flank, length ``size``.

    k, e, de: expressions (or symbolic variables) for k_f(theta_1) (N/m), e_f (m) and
    e_f' (m/rad). With friction (``fl.friction``) the vector is -W_f(theta) F_f, the
    friction torques included (:func:`_friction_direction_symbolic`; theta: the pinion
    angle expression, rad, needed then). ecc: (eps_f, d eps_f/dt) expressions of the
    kinematic approach (m, m/s; :func:`_approach_terms`: the eccentricities', docs §3b,
    and the pitch deviations', §3c) added to the gap and its rate, or None. Contact law
    of docs/drivetrain.md §3. The contact test uses the bounds
    lo <= e_f - eps_f <= hi (:attr:`_Flank.gap_bounds`) where they
    decide: u = delta - b > hi means contact, u <= lo none, and only in between is the
    gap s itself tested. Same result, one series evaluation fewer per call in loaded
    running and none for a flank out of contact (exudyn's trees have no common
    subexpressions: each use of e re-evaluates it).
    """
    import exudyn as exu

    esym = exu.symbolic
    zero = esym.Real(0.0)
    delta, ddelta, gv = 0.0, 0.0, [0.0] * size
    for dof, j in pos.items():
        g = float(fl.G[dof])
        if g != 0.0:
            delta = delta + g * q[j]
            ddelta = ddelta + g * q_t[j]
            gv[j] = -g
    s = delta - e - fl.b
    sdot = ddelta - de * (plan.omega + q_t[pos[1]])
    if ecc is not None:
        s = s + ecc[0]
        sdot = sdot + ecc[1]
    force = esym.max(zero, k * s + fl.c * sdot)
    e_lo, e_hi = fl.gap_bounds
    u = delta - fl.b
    F = esym.IfThenElse(
        u > e_hi, force, esym.IfThenElse(u > e_lo, esym.IfThenElse(s > 0.0, force, zero), zero)
    )
    if fl.friction:
        return F * _friction_direction_symbolic(fl, pos, size, theta, u, gv)
    return F * esym.Vector(gv)


def _mesh_generalised(plan: _Plan, pos: dict[int, int], size: int, t, q, q_t, symbolic: bool):
    """Generalised mesh forces -sum_f G_f F_f (N or N m), a vector of length ``size``.

    ``pos`` maps a model coordinate to its index in the user function's q, q_t.
    Contact law (docs/drivetrain.md §3): s_f = G_f x - e_f(theta_1) - b_f,
    sdot_f = G_f v - e_f'(theta_1) (Omega + v_1), F_f = H(s_f) max(0, k_f s_f + c_f sdot_f),
    theta_1 = Omega t + q_1 + theta_10. With friction (docs §3a) each flank adds
    -mu phi_1f(theta_1) F_f on the pinion and +mu phi_2f(theta_1) F_f on the gear. With
    eccentricities (docs §3b) s_f gains eps_f(theta_1, theta_2) and sdot_f its rate,
    theta_2 = Omega_2 t + q_2 + theta_20 (:func:`_eccentricity_terms`; ``pos`` then
    holds the gear coordinate); with pitch deviations (docs §3c) the drive flank's s_f
    gains a(theta_1) and sdot_f a'(theta_1) (Omega + v_1) (:func:`_approach_terms`).

    Symbolic: an exudyn vector expression ``sum_f (-G_f) * F_f``: each flank force is one
    sub-expression, evaluated once per call (a list of per-coordinate expressions would
    evaluate it once per coordinate); ``IfThenElse`` evaluates only the taken branch, so
    a flank out of contact costs only its gap. Python: a numpy array.
    """
    ip = pos[1]
    theta = plan.omega * t + q[ip] + plan.theta10
    if any(fl.eccentric for fl in plan.flanks):  # gear angle and both speeds (docs §3b)
        ig = pos[2]
        angles = (theta, plan.omega2 * t + q[ig] + plan.theta20)
        speeds = (plan.omega + q_t[ip], plan.omega2 + q_t[ig])
    elif any(fl.pitch is not None for fl in plan.flanks):  # pinion's alone (docs §3c)
        angles, speeds = (theta, None), (plan.omega + q_t[ip], None)
    if symbolic:
        import exudyn as exu

        esym = exu.symbolic
        total = None
        for fl in plan.flanks:
            e = _fourier_terms(fl.e, fl.e_harmonics, theta, esym.cos)
            de = _fourier_derivative_terms(fl.e, fl.e_harmonics, theta, esym.sin)
            k = _fourier_terms(fl.k, fl.k_harmonics, theta, esym.cos)
            ecc = None
            if fl.eccentric or fl.pitch is not None:
                ecc = _approach_terms(fl, angles, speeds, True)
            term = flank_force_symbolic(plan, fl, pos, size, q, q_t, k, e, de, theta, ecc)
            total = term if total is None else total + term
        return total
    out = np.zeros(size)
    qa = np.asarray(q, dtype=float)
    va = np.asarray(q_t, dtype=float)
    idx = np.array(list(pos.values()))
    dofs = np.array(list(pos.keys()))
    for fl, ((wk, Rk, pk), (we, Re, pe)), fr in zip(
        plan.flanks, plan.flank_arrays, plan.friction_arrays, strict=True
    ):
        G = fl.G[dofs]
        arg = we * theta - pe
        e = fl.e.a0 + float(Re @ np.cos(arg))
        s = float(G @ qa[idx]) - e - fl.b
        ecc = None
        if fl.eccentric or fl.pitch is not None:
            ecc = _approach_terms(fl, angles, speeds, False)
            if ecc is not None:
                s = s + ecc[0]
        if fl.law is None:
            closed = s > 0.0
        else:  # the loaded law at the deflection s + e (docs §3d)
            coef, forces, n1 = fl.law
            elastic = float(loaded_force(s + e, _series_rows(theta, coef, n1, np), forces))
            closed = elastic > 0.0
        if closed:
            de = -float((we * Re) @ np.sin(arg))
            sdot = float(G @ va[idx]) - de * (plan.omega + va[ip])
            if ecc is not None:
                sdot = sdot + ecc[1]
            if fl.law is None:
                elastic = (fl.k.a0 + float(Rk @ np.cos(wk * theta - pk))) * s
            F = max(0.0, elastic + fl.c * sdot)
            out[idx] -= G * F
            if fr is not None:  # friction torques (docs/drivetrain.md §3a)
                (w1, R1, p1), (w2, R2, p2) = fr
                out[ip] -= (fl.f1.a0 + float(R1 @ np.cos(w1 * theta - p1))) * F
                out[pos[2]] += (fl.f2.a0 + float(R2 @ np.cos(w2 * theta - p2))) * F
    return out


def _engine_torque(plan: _Plan, t, sin):
    """T_e(t) = T_op [1 + sum r_j sin(o_j Omega t)] (N m), docs/drivetrain.md §5."""
    T = plan.engine_mean
    for w, A in plan.engine_ripple:
        T = T + A * sin(w * t)
    return T


def _propeller_torque(plan: _Plan, t, velocity, sin):
    """T_p = kappa (Omega_2 + v_p)^2 [1 + sum r_j sin(o_j Omega_2 t)] (N m), docs §6."""
    w = plan.omega2 + velocity
    r = 1.0
    for wr, A in plan.prop_ripple:
        r = r + A * sin(wr * t)
    return plan.prop_kappa * w * w * r


def _sin(symbolic: bool):
    if symbolic:
        import exudyn as exu

        return exu.symbolic.sin
    return math.sin


def _engine_load(plan: _Plan, symbolic: bool):
    """LoadCoordinate user function (mbs, t, load) -> engine torque (N m)."""
    sin = _sin(symbolic)

    def engine(mbs, t, load):
        return _engine_torque(plan, t, sin)

    return engine


def _propeller_force(plan: _Plan, symbolic: bool):
    """Spring-force user function of the propeller connector (ground -> propeller).

    The connector applies -f to the propeller coordinate (its displacement is
    q_p - 0), so f = +T_p.
    """
    sin = _sin(symbolic)

    def propeller(mbs, t, itemNumber, displacement, velocity, stiffness, damping, offset):
        return _propeller_torque(plan, t, velocity, sin)

    return propeller


def _mesh_force(plan: _Plan, mesh_dofs: list[int], symbolic: bool):
    """Force user function of the mesh object (generic ODE2 over ``mesh_dofs``)."""
    pos = {d: j for j, d in enumerate(mesh_dofs)}
    size = len(mesh_dofs)

    def mesh(mbs, t, itemNumber, q, q_t):
        out = _mesh_generalised(plan, pos, size, t, q, q_t, symbolic)
        return out if symbolic else out.tolist()

    return mesh


def _all_forces(plan: _Plan, symbolic: bool):
    """Force user function of the single generic object (layout ``"generic"``).

    Mesh, engine torque (with the governor's constant K_i q_e0) and propeller load;
    shafts, bearings and the governor's K_p, K_i are its stiffness and damping matrices.
    """
    sin = _sin(symbolic)
    pos = {d: d for d in range(plan.n)}
    n = plan.n
    gov = sum(k * off for name, i, j, k, c, off in plan.springs if name == "governor")
    ue = [0.0] * n
    ue[plan.engine_index] = 1.0
    up = [0.0] * n
    up[plan.prop_index] = -1.0

    def forces(mbs, t, itemNumber, q, q_t):
        out = _mesh_generalised(plan, pos, n, t, q, q_t, symbolic)
        te = _engine_torque(plan, t, sin) + gov
        tp = _propeller_torque(plan, t, q_t[plan.prop_index], sin)
        if symbolic:
            import exudyn as exu

            esym = exu.symbolic
            return out + te * esym.Vector(ue) + tp * esym.Vector(up)
        out[plan.engine_index] += te
        out[plan.prop_index] -= tp
        return out.tolist()

    return forces


def _record_symbolic(mbs, fn, kind: str, vector_size: int = 0):
    """Record ``fn`` as an exudyn symbolic user function; returns (UserFunction, keepalive).

    kind: ``"generic"`` (ObjectGenericODE2.forceUserFunction, vectors of ``vector_size``),
    ``"spring"`` (ObjectConnectorCoordinateSpringDamper.springForceUserFunction),
    ``"load"`` (LoadCoordinate.loadUserFunction). exudyn 1.13.6's
    ``CreateSymbolicUserFunction`` would record the generic object's vectors with zero
    length (indexing q[1] then fails), hence the explicit recording here.
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
        if isinstance(ret, esym.Vector):
            rtype = "StdVector"
        elif isinstance(ret, list):
            ret = esym.Vector([esym.Real(float(r)) if isinstance(r, float) else r for r in ret])
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

    system_container, mbs: exudyn ``SystemContainer`` and ``MainSystem``.
    names: model coordinate names; nodes: one ``Node1D`` per coordinate (same order).
    bodies, markers: per coordinate (layout ``"components"``; empty for ``"generic"``).
    connectors: name -> object index; loads: load indices; mesh_object: the generic
    ODE2 object carrying the mesh force. keepalive: recorded symbolic expressions,
    which must live as long as the system.

    exudyn 1.13.6 does not free a system that holds symbolic user functions when its
    last Python reference goes (measured on the default scene: about 0.04 MB per build
    without pitch deviations, 35 MB with a pitch spline of 31,320 intervals, 24 per
    mesh cycle over the hunting period of 29 and 45 teeth); :meth:`release` frees it.
    :func:`integrate_exudyn` releases the systems it builds.
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
    keepalive: list = field(default_factory=list, repr=False)

    def release(self) -> None:
        """Reset the main system (``mbs.Reset()``: nodes, objects, markers, loads,
        sensors and their user functions and stored data) and drop the recorded
        expressions: the system is empty afterwards."""
        self.mbs.Reset()
        self.keepalive.clear()


def build_exudyn_system(model, solver: ExudynSolver = ExudynSolver(), *, y0=None) -> ExudynSystem:
    """The exudyn system of ``model``, assembled, at the state ``y0`` (default static).

    y0: ndarray, shape (2 n,), unscaled [x, v] (rad, m, rad/s, m/s).
    """
    solver.validate()
    if model.mesh_law != "tangent" and solver.user_functions == "symbolic":
        raise InputError(
            Problem(
                "user_functions",
                solver.user_functions,
                f"the {model.mesh_law} mesh law (drivetrain.mesh_law, docs/drivetrain.md "
                "section 3d) is carried by exudyn's Python user functions only: "
                "ExudynSolver(user_functions='python') (its symbolic expressions share no "
                "subexpressions, and the law uses each of its series several times)",
            ),
            "cannot build the exudyn system",
        )
    plan = _plan_from_model(model)
    if y0 is not None:
        y0 = np.asarray(y0, dtype=float)
        p = Problems()
        if p.check(
            y0.shape == (2 * plan.n,), "y0", f"shape {y0.shape}", f"must have shape ({2 * plan.n},)"
        ):
            p.check(bool(np.all(np.isfinite(y0))), "y0", y0.tolist(), "must be finite")
        p.raise_if_any("invalid initial state")
        plan = dataclasses.replace(plan, x0=y0[: plan.n].copy(), v0=y0[plan.n :].copy())
    if solver.layout == "generic":
        return _build_generic(plan, solver)
    return _build_components(plan, solver)


def _new_system(plan: _Plan):
    """(SystemContainer, MainSystem, nodes): one Node1D per coordinate at the plan's state."""
    import exudyn as exu
    import exudyn.itemInterface as ii

    SC = exu.SystemContainer()
    mbs = SC.AddSystem()
    nodes = [
        mbs.AddNode(
            ii.Node1D(
                name=name,
                referenceCoordinates=[0.0],
                initialCoordinates=[float(plan.x0[i])],
                initialVelocities=[float(plan.v0[i])],
            )
        )
        for i, name in enumerate(plan.names)
    ]
    return SC, mbs, nodes


def add_state_sensors(system: ExudynSystem) -> None:
    """Sensors storing every node's coordinate and velocity (in ``system.sensors``)."""
    import exudyn as exu
    import exudyn.itemInterface as ii

    for ov in (exu.OutputVariableType.Coordinates, exu.OutputVariableType.Coordinates_t):
        for nd in system.nodes:
            system.sensors.append(
                system.mbs.AddSensor(
                    ii.SensorNode(
                        nodeNumber=nd, storeInternal=True, writeToFile=False, outputVariableType=ov
                    )
                )
            )
    system.mbs.Assemble()


def _build_components(plan: _Plan, solver: ExudynSolver) -> ExudynSystem:
    import exudyn.itemInterface as ii

    symbolic = solver.user_functions == "symbolic"
    SC, mbs, nodes = _new_system(plan)
    keep: list = []
    bodies, markers = [], []
    for i, (name, nd) in enumerate(zip(plan.names, nodes, strict=True)):
        if plan.rotational[i]:
            item = ii.ObjectRotationalMass1D(
                name=f"{name}_inertia", nodeNumber=nd, inertia=float(plan.inertia[i])
            )
        else:
            item = ii.ObjectMass1D(name=f"{name}_mass", nodeNumber=nd, mass=float(plan.inertia[i]))
        bodies.append(mbs.AddObject(item))
        markers.append(mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=nd, coordinate=0)))
    ground = mbs.AddNode(ii.NodePointGround(name="ground"))
    m_ground = mbs.AddMarker(ii.MarkerNodeCoordinate(nodeNumber=ground, coordinate=0))

    connectors = {}
    for name, i, j, k, c, off in plan.springs:
        # CoordinateSpringDamper on markers [m0, m1]: f = k (q_m1 - q_m0 - offset)
        # + c (v_m1 - v_m0), applied -f on m1 and +f on m0. With m1 = i, m0 = j this is
        # the shaft torque T = k (q_i - q_j) + c (v_i - v_j) of docs §4 (+T on j).
        m0 = m_ground if j < 0 else markers[j]
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
    eng = _engine_load(plan, symbolic) if plan.engine_ripple else 0
    if plan.engine_ripple and symbolic:
        eng, kp = _record_symbolic(mbs, eng, "load")
        keep += [eng, kp]
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
        prop, kp = _record_symbolic(mbs, prop, "spring")
        keep += [prop, kp]
    connectors["propeller_load"] = mbs.AddObject(
        ii.ObjectConnectorCoordinateSpringDamper(
            name="propeller_load",
            markerNumbers=[m_ground, markers[plan.prop_index]],
            springForceUserFunction=prop,
        )
    )

    # Mesh: generic ODE2 object over the coordinates its flanks touch (docs §3), and the
    # gear's, where the friction torque acts (§3a) and whose angle an eccentricity reads
    # (§3b).
    gear = {2} if any(fl.friction or fl.eccentric for fl in plan.flanks) else set()
    mesh_dofs = sorted(
        {1} | gear | {d for fl in plan.flanks for d in np.flatnonzero(fl.G).tolist()}
    )
    fn = _mesh_force(plan, mesh_dofs, symbolic)
    if symbolic:
        fn, kp = _record_symbolic(mbs, fn, "generic", len(mesh_dofs))
        keep += [fn, kp]
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


def _build_generic(plan: _Plan, solver: ExudynSolver) -> ExudynSystem:
    import exudyn.itemInterface as ii

    symbolic = solver.user_functions == "symbolic"
    SC, mbs, nodes = _new_system(plan)
    keep: list = []
    K, C = _structural(plan)
    fn = _all_forces(plan, symbolic)
    if symbolic:
        fn, kp = _record_symbolic(mbs, fn, "generic", plan.n)
        keep += [fn, kp]
    obj = mbs.AddObject(
        ii.ObjectGenericODE2(
            name="drivetrain",
            nodeNumbers=nodes,
            massMatrix=np.diag(plan.inertia),
            stiffnessMatrix=K,
            dampingMatrix=C,
            forceUserFunction=fn,
        )
    )
    mbs.Assemble()
    return ExudynSystem(SC, mbs, plan.names, nodes, [], [], {}, [], obj, keepalive=keep)


def _structural(plan: _Plan) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and damping matrices of the plan's springs, shape (n, n)."""
    n = plan.n
    K = np.zeros((n, n))
    C = np.zeros((n, n))
    for _name, i, j, k, c, _off in plan.springs:
        for M, v in ((K, k), (C, c)):
            M[i, i] += v
            if j >= 0:
                M[j, j] += v
                M[i, j] -= v
                M[j, i] -= v
    return K, C


# ------------------------------------------------------------------ step choice
def _linearised(plan: _Plan) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """M (diagonal, shape (n,)), K, C (shape (n, n)) about the operating point.

    The drive flank enters with its *largest* stiffness a0 + sum R_k (an upper bound of
    k(theta)) and its damping; the propeller load adds its speed derivative
    dT_p/dv = 2 kappa Omega_2 as damping (docs/drivetrain.md §3, §6). With friction the
    mesh terms are k W G^T and c W G^T, W the force's mean direction (:attr:`_Flank.W`,
    docs §3a, as ``linear.linear_matrices``). The eccentricities (docs §3b) and the
    pitch deviations (§3c), kinematic excitations, do not enter.
    """
    K, C = _structural(plan)
    fl = plan.flanks[0]
    kmax = float(fl.k.a0) + sum(R for _, R, _ in fl.k_harmonics)
    K = K + kmax * np.outer(fl.W, fl.G)
    C = C + fl.c * np.outer(fl.W, fl.G)
    C[plan.prop_index, plan.prop_index] += 2.0 * plan.prop_kappa * plan.omega2
    return plan.inertia.astype(float), K, C


def _eigenvalues(plan: _Plan) -> np.ndarray:
    """Eigenvalues (1/s) of the linearised first-order system, shape (2 n,)."""
    m, K, C = _linearised(plan)
    n = plan.n
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n] = -K / m[:, None]
    A[n:, n:] = -C / m[:, None]
    return np.linalg.eigvals(A)


def _max_frequency(plan: _Plan) -> tuple[float, float]:
    """(highest eigenfrequency, mesh frequency) (Hz).

    Eigenfrequencies from :func:`_eigenvalues`. Only the fundamental mesh frequency
    counts: the higher mesh harmonics excite the system above its modes, where the
    response is small; docs/exudyn.md has the measurements (a rule counting every
    harmonic above 5 % of the largest cost about 10x the steps on the default scene for an
    error far below the one asked for).
    """
    f_mode = float(np.abs(_eigenvalues(plan)).max()) / (2 * math.pi)
    f_mesh = plan.omega * plan.flanks[0].k.teeth / (2 * math.pi)
    return f_mode, f_mesh


def _step_limit(plan: _Plan, method: str) -> float:
    from .linear import largest_stable_step

    return largest_stable_step(_eigenvalues(plan), np.array(_STABILITY[method]), _GROWTH)


def stability_step_limit(model, method: str = "RK67") -> float:
    """Largest stable fixed step (s) of ``method`` on the linearised model.

    The largest h with |R(h lambda_j)| <= 1 + 1e-8 for every eigenvalue lambda_j of the
    linearised, damped first-order system (drive mesh at its largest stiffness), R the
    method's stability polynomial (Hairer, Wanner, Solving ODEs II, Sec. IV.2). The
    nonlinear contact (impacts, loss of contact) is not covered: divergence is still
    checked after the run.
    """
    p = Problems()
    p.check(method in _METHODS, "method", method, f"must be one of {_METHODS}")
    p.raise_if_any("invalid method")
    return _step_limit(_plan_from_model(model), method)


def _target_step(plan: _Plan, solver: ExudynSolver) -> float:
    if solver.step is not None:
        return float(solver.step)
    f_mode, f_mesh = _max_frequency(plan)
    h = 1.0 / (solver.target_steps_per_period * max(f_mode, f_mesh))
    return min(h, 0.8 * _step_limit(plan, solver.method))


# --------------------------------------------------------------------- integration
def _settings(t_start: float, t_end: float, n_steps: int, write_period: float):
    import exudyn as exu

    s = exu.SimulationSettings()
    ti = s.timeIntegration
    ti.startTime = float(t_start)
    ti.endTime = float(t_end)
    ti.numberOfSteps = int(n_steps)
    ti.automaticStepSize = False
    ti.verboseMode = 0
    ti.explicit.computeEndOfStepAccelerations = False
    s.solution.file.write = False
    s.solution.sensors.writePeriod = float(write_period)
    s.show.computationTime = False
    s.show.statistics = False
    return s


def _solve(mbs, settings, method: str) -> tuple[bool, str, int]:
    """One exudyn run with console output and warnings off; (ok, error, steps)."""
    import exudyn as exu

    warn, console = exu.config.suppressWarnings, exu.config.printToConsole
    exu.config.suppressWarnings = True
    exu.config.printToConsole = False
    err = ""
    try:
        ok = exu.SolveDynamic(
            mbs,
            settings,
            solverType=getattr(exu.DynamicSolverType, method),
            updateInitialValues=True,
        )
    except Exception as exc:  # exudyn raises its own errors (solver, user function)
        ok, err = False, f"{type(exc).__name__}: {exc}"
    finally:
        exu.config.suppressWarnings, exu.config.printToConsole = warn, console
    it = mbs.sys["dynamicSolver"].it if "dynamicSolver" in mbs.sys else None
    steps = int(it.currentStepIndex) - 1 if it is not None else 0
    return bool(ok), err, max(steps, 0)


def _stored(system: ExudynSystem) -> tuple[np.ndarray, np.ndarray]:
    """Sensor samples: t, shape (m,); Y, shape (m, 2 n)."""
    data = [system.mbs.GetSensorStoredData(s) for s in system.sensors]
    t = np.asarray(data[0][:, 0], dtype=float)
    Y = np.column_stack([np.asarray(d[:, 1], dtype=float) for d in data])
    return t, Y


def _failure(model, t: np.ndarray, Y: np.ndarray, factor: float):
    """First non-finite or divergent sample as a SolverFailure, or None."""
    from .scipy_backend import divergence_bound
    from .timeseries import SolverFailure

    n = model.n_dof
    bad = ~np.all(np.isfinite(Y), axis=1)
    g = model.mesh_vectors()[0]
    bound = divergence_bound(model, factor)
    with np.errstate(invalid="ignore"):
        defl = np.abs(np.nan_to_num(Y[:, :n] @ g, nan=0.0))
        speed = np.abs(np.nan_to_num(Y[:, n : n + 4], nan=0.0)).max(axis=1)
    over = (defl > bound) | (speed > model.speed)
    if bad.any() and (not over.any() or np.argmax(bad) <= np.argmax(over)):
        i = int(np.argmax(bad))
        k = max(i - 1, 0)
        return SolverFailure(
            "nan",
            float(t[i]),
            f"non-finite state (last finite sample at t = {t[k]:.6g} s)",
            tuple(Y[k].tolist()),
        )
    if over.any():
        i = int(np.argmax(over))
        return SolverFailure(
            "divergence",
            float(t[i]),
            f"mesh deflection beyond {bound:.3g} m or a speed deviation beyond the nominal speed",
            tuple(Y[i].tolist()),
        )
    return None


def integrate_exudyn(model, y0, t_eval, solver: ExudynSolver = ExudynSolver(), *, t0: float = 0.0):
    """Integrate from (t0, y0) with exudyn and sample at ``t_eval`` (s).

    Same contract as :func:`gearbox.drivetrain.scipy_backend.integrate_scipy`: returns
    (t, Y, info), Y unscaled states, shape (n_t, 2 n); info: dict with status,
    failure (SolverFailure or None), nfev (steps x stages), steps, rejected (0),
    wall_time (s), message, plus step (s, the step used), build_time (s).

    t_eval must be uniformly spaced (a fixed-step method samples on its step grid): the
    run goes from t0 to t_eval[0] with a step that divides that interval, then samples
    every ``t_eval[1] - t_eval[0]`` with a step that divides the spacing, each step the
    largest one not above the target (``solver.step`` or the automatic choice).
    """

    solver.validate()
    t_eval = np.asarray(t_eval, dtype=float)
    n = model.n_dof
    p = Problems()
    p.check(
        t_eval.ndim == 1 and t_eval.size >= 1,
        "t_eval",
        f"shape {t_eval.shape}",
        "must be a 1-d array with >= 1 time",
    )
    if t_eval.ndim == 1 and t_eval.size >= 1:
        p.check(bool(np.all(np.isfinite(t_eval))), "t_eval", "non-finite", "must be finite")
        p.check(float(t_eval[0]) >= t0, "t_eval[0]", float(t_eval[0]), f"must be >= t0 = {t0:g} s")
        if t_eval.size >= 2:
            d = np.diff(t_eval)
            p.check(bool(np.all(d > 0)), "t_eval", "not increasing", "must be strictly increasing")
            if np.all(d > 0):
                p.check(
                    float(d.max() - d.min()) <= 1e-9 * float(d.mean()),
                    "t_eval",
                    f"spacing {d.min():.6g}..{d.max():.6g} s",
                    "must be uniformly spaced for the fixed-step exudyn integrators",
                )
    p.raise_if_any("invalid exudyn integration request")
    start = time.perf_counter()
    system = build_exudyn_system(model, solver, y0=y0)
    try:
        plan = _plan_from_model(model)
        h_target = _target_step(plan, solver)
        h_lim = _step_limit(plan, solver.method)
        if h_target > h_lim:
            q = Problems()
            q.add(
                "step",
                h_target,
                f"must be <= {h_lim:.4g} s, the {solver.method} stability limit "
                "of the model's highest eigenfrequency (drive mesh at its largest stiffness)",
            )
            q.raise_if_any("unstable exudyn step")
        lead = float(t_eval[0]) - t0
        n1 = math.ceil(lead / h_target - 1e-9) if lead > 0 else 0
        dt = float(t_eval[1] - t_eval[0]) if t_eval.size >= 2 else 0.0
        sub = math.ceil(dt / h_target - 1e-9) if dt > 0 else 0
        n2 = sub * (t_eval.size - 1)
        if n1 + n2 > solver.max_steps:
            q = Problems()
            q.add(
                "max_steps",
                solver.max_steps,
                f"must be >= {n1 + n2} for this run at step {h_target:.4g} s",
            )
            q.raise_if_any("exudyn step limit")
        mbs = system.mbs
        add_state_sensors(system)
        build = time.perf_counter() - start
        stages = 7 if solver.method == "RK67" else 4
        steps = 0
        wall = 0.0
        msg = ""
        ts_all, Y_all = [], []
        phases = []
        if n1 > 0:
            h1 = lead / n1
            # settling samples (for locating a failure) every `every` steps, a divisor of
            # n1 so that the last sample is the state at t_eval[0]
            every = min(n1, max(1, round(max(dt, lead / 100) / h1)))
            while n1 % every:
                every -= 1
            phases.append((t0, float(t_eval[0]), n1, h1 * every))
        if n2 > 0:
            phases.append((float(t_eval[0]), float(t_eval[-1]), n2, dt))
        ok = True
        for a, b, nst, wp in phases:
            s = _settings(a, b, nst, wp)
            t1 = time.perf_counter()
            ok, err, done = _solve(mbs, s, solver.method)
            wall += time.perf_counter() - t1
            steps += done
            tt, YY = _stored(system)
            ts_all.append(tt)
            Y_all.append(YY)
            if not ok:
                msg = err or f"exudyn {solver.method} reported failure"
                break
    finally:
        system.release()  # the symbolic user functions (see ExudynSystem.release)
    t_rec = np.concatenate(ts_all) if ts_all else np.zeros(0)
    Y_rec = np.concatenate(Y_all) if Y_all else np.zeros((0, 2 * n))
    if not phases:  # t_eval == [t0]
        t_rec = np.array([t0])
        Y_rec = (
            np.concatenate([plan.x0, plan.v0])[None, :]
            if y0 is None
            else np.asarray(y0, float)[None, :]
        )
    failure = _failure(model, t_rec, Y_rec, solver.divergence_factor)
    # samples at t_eval: the last phase's rows (one per output time)
    if n2 > 0 and ok:
        Y = Y_all[-1]
        t_out = ts_all[-1]
    elif n2 == 0 and ok:
        t_out, Y = t_rec[-1:], Y_rec[-1:]
    else:
        t_out, Y = t_rec, Y_rec
    if ok and t_out.size != t_eval.size:
        # exudyn writes a sensor sample when t passes a multiple of the write period;
        # with the step dividing the period every sample lies on t_eval.
        idx = np.searchsorted(t_out, t_eval - 0.5 * (dt if dt > 0 else 1.0) * 1e-6)
        idx = np.clip(idx, 0, t_out.size - 1)
        t_out, Y = t_out[idx], Y[idx]
    if failure is None and not ok:
        from .timeseries import SolverFailure

        failure = SolverFailure(
            "solver_error",
            float(t_rec[-1]) if t_rec.size else t0,
            msg,
            tuple(Y_rec[-1].tolist()) if Y_rec.size else (),
        )
    h_used = (dt / sub) if sub else (lead / n1 if n1 else 0.0)
    info = {
        "status": "success" if failure is None else failure.kind,
        "failure": failure,
        "nfev": int(stages * steps),
        "steps": int(steps),
        "rejected": 0,
        "wall_time": wall,
        "build_time": build,
        "step": float(h_used),
        "message": "success" if failure is None else failure.message,
    }
    return np.asarray(t_eval if failure is None else t_out, dtype=float), Y, info


def simulate_exudyn(
    model,
    t_end: float,
    *,
    solver: ExudynSolver = ExudynSolver(),
    output_step: float = 1e-4,
    t_record: float = 0.0,
    y0=None,
):
    """Simulate ``model`` with exudyn from its operating point; a :class:`TimeSeries`.

    t_end: end time (s); output_step: sample spacing (s); t_record: first recorded
    time (s), the run from 0 to t_record is not stored (settling); y0: start state,
    shape (2 n,), unscaled (default :meth:`DrivetrainModel.static_state`).
    Channels and units: :func:`gearbox.drivetrain.model.outputs`, ``CHANNEL_UNITS``.
    status, failure, nfev, steps, wall_time as for the other backends; attrs carry the
    solver settings, the step used and the build time.
    """
    from .model import CHANNEL_UNITS, outputs
    from .timeseries import TimeSeries

    p = Problems()
    p.in_range("t_end", t_end, 0.0, None, lo_open=True)
    p.in_range("output_step", output_step, 0.0, None, lo_open=True)
    p.in_range("t_record", t_record, 0.0, t_end, hi_open=True)
    p.raise_if_any("invalid exudyn simulation request")
    count = int(math.floor((t_end - t_record) / output_step + 1e-9)) + 1
    t_eval = t_record + output_step * np.arange(count)
    if y0 is None:
        y0 = model.static_state()
    t, Y, info = integrate_exudyn(model, y0, t_eval, solver, t0=0.0)
    good = np.all(np.isfinite(Y), axis=1)
    ch = outputs(model, t[good], Y[good]) if good.any() else {k: np.zeros(0) for k in CHANNEL_UNITS}
    units = {k: CHANNEL_UNITS[k] for k in ch}
    attrs = {
        "solver": "exudyn",
        "settings": str(solver.to_dict()),
        "step_s": info["step"],
        "build_time_s": info["build_time"],
        **{f"model_{k}": str(v) for k, v in dict(getattr(model, "meta", {})).items()},
    }
    return TimeSeries(
        time=t[good],
        channels=ch,
        units=units,
        status=info["status"],
        failure=info["failure"],
        nfev=info["nfev"],
        steps=info["steps"],
        rejected=0,
        wall_time=info["wall_time"],
        attrs=attrs,
    )

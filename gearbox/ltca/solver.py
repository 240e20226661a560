"""The contact problem of the loaded TCA and its solver.

Unknowns: normal loads F_i >= 0 at the grid points and the loaded pinion rotation
phi (gear held). With the influence matrix C (m/N), initial separations s (m) and
arms m (normal approach per radian of pinion rotation, m/rad):

    w = C F + s - m phi >= 0,   F >= 0,   F_i w_i = 0,   m^T F = T

(the gap w is zero where loaded, open elsewhere; the loads balance the pinion
torque T). It is the KKT system of the strictly convex quadratic programme
``min 1/2 F^T C F + s^T F  s.t.  F >= 0, m^T F = T`` (phi is the multiplier of the
equality), solved here by a primal active-set method (Nocedal, J., Wright, S.J.,
Numerical Optimization, 2nd ed., Springer 2006, Algorithm 16.3), which keeps the
loads feasible at every iteration and terminates in finitely many steps. Points are
added to the loaded set in blocks for the first iterations (all violated gaps at
once; the ratio test keeps feasibility), then one at a time, which restores the
finite termination of the textbook method.

A load-dependent compliance (contact flattening) is handled by an
iteration on the line loads around the active-set solve: Newton by default (each
loaded point's flattening linearised at its load), or the secant fixed point.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..errors import Problems

__all__ = [
    "ContactSolution",
    "ContactSolver",
    "pair_sensitivities",
    "point_sensitivities",
    "rotation_sensitivity",
    "solve_contact",
    "solve_lcp",
]


@dataclass(frozen=True)
class ContactSolver:
    """Settings of the contact solver.

    gap_tol: relative tolerance on gaps (of the mean deflection); max_iter: cap of
    active-set iterations per solve; block_iter: iterations that add violated points
    in blocks; max_outer: cap of the iterations on a load-dependent
    compliance; outer_rtol: their tolerance on the loads (relative to the largest);
    flattening: how those iterations update the flattening, ``"newton"`` (each loaded
    point's approach linearised at its current load: its tangent on the diagonal, the
    difference to the secant in the separation) or ``"fixed_point"`` (the secant at the
    current loads).
    """

    gap_tol: float = 1.0e-9
    max_iter: int = 2000
    block_iter: int = 20
    max_outer: int = 40
    outer_rtol: float = 1.0e-6
    flattening: str = "newton"

    def __post_init__(self):
        p = Problems()
        p.in_range("gap_tol", self.gap_tol, 0.0, 1.0, lo_open=True)
        p.in_range("max_iter", self.max_iter, 1, None)
        p.in_range("max_outer", self.max_outer, 1, None)
        p.in_range("outer_rtol", self.outer_rtol, 0.0, 1.0, lo_open=True)
        p.check(
            self.flattening in ("newton", "fixed_point"),
            "flattening",
            self.flattening,
            "must be 'newton' or 'fixed_point'",
        )
        p.raise_if_any("invalid contact solver settings")


@dataclass(frozen=True)
class ContactSolution:
    """Solution of the contact problem at one position and torque.

    load: ndarray, shape (n,), normal loads (N); gap: shape (n,), loaded gaps (m);
    rotation: loaded pinion rotation phi (rad) from the position of the grid;
    success, status ('converged', 'max_iter', 'outer_max_iter'), message;
    iterations: active-set iterations (all solves), outer_iterations: fixed-point
    iterations; gap_residual: largest penetration max(-w, 0) (m); complementarity:
    max |F_i w_i| / (max F * mean deflection) (-); load_residual: |m^T F - T| / T.
    """

    load: np.ndarray
    gap: np.ndarray
    rotation: float
    success: bool
    status: str
    message: str
    iterations: int
    outer_iterations: int
    gap_residual: float
    complementarity: float
    load_residual: float

    def to_dict(self) -> dict:
        d = asdict(self)
        d["load"] = self.load.tolist()
        d["gap"] = self.gap.tolist()
        return d

    @classmethod
    def from_dict(cls, d) -> ContactSolution:
        d = dict(d)
        d["load"] = np.asarray(d["load"], dtype=float)
        d["gap"] = np.asarray(d["gap"], dtype=float)
        return cls(**d)


#: Relative step in the line load of the flattening's tangent (forward difference).
_FLATTENING_STEP = 1.0e-4


def _eqp(C, s, m, T, P):
    """Loads on the set P and phi with all gaps of P closed and m^T F = T."""
    k = P.size
    A = np.empty((k + 1, k + 1))
    A[:k, :k] = C[np.ix_(P, P)]
    A[:k, k] = -m[P]
    A[k, :k] = m[P]
    A[k, k] = 0.0
    rhs = np.empty(k + 1)
    rhs[:k] = -s[P]
    rhs[k] = T
    x = np.linalg.solve(A, rhs)
    return x[:k], x[k]


def solve_lcp(C, s, m, T, *, solver: ContactSolver = ContactSolver(), start=None):
    """Primal active-set solution of the contact problem for a fixed matrix C.

    C: shape (n, n) symmetric positive definite (m/N); s, m: shape (n,); T > 0.
    start: optional boolean mask, shape (n,), of points guessed loaded (warm start);
    used only if its equality solution has positive loads.
    Returns (F, phi, gap, iterations, converged).
    """
    n = s.size
    scale = float(np.mean(np.diag(C))) * T / float(np.mean(m))  # typical deflection (m)
    tol = solver.gap_tol * scale
    F = np.zeros(n)
    P = None
    if start is not None and np.any(start):
        P0 = np.flatnonzero(start)
        FP, _ = _eqp(C, s, m, T, P0)
        if np.all(FP > 0):
            P = P0
            F[P] = FP
    if P is None:
        i0 = int(np.argmin(s / m))
        P = np.array([i0])
        F[i0] = T / m[i0]
    it = 0
    phi = 0.0
    while it < solver.max_iter:
        it += 1
        FP, phi_hat = _eqp(C, s, m, T, P)
        if np.all(FP > 0):
            F[:] = 0.0
            F[P] = FP
            phi = phi_hat
            w = C @ F + s - m * phi
            w[P] = 0.0
            viol = np.flatnonzero(w < -tol)
            if viol.size == 0:
                gap = C @ F + s - m * phi
                return F, phi, gap, it, True
            if it <= solver.block_iter:
                add = viol
            else:
                add = np.array([viol[np.argmin(w[viol])]])
            P = np.sort(np.concatenate([P, add]))
            continue
        # step towards the equality solution until the first load reaches zero
        Fp = F[P]
        dec = FP <= 0
        ratio = np.where(dec, Fp / np.where(dec, Fp - FP, 1.0), np.inf)
        alpha = float(np.min(ratio))
        F[P] = Fp + alpha * (FP - Fp)
        keep = F[P] > 1e-14 * T / float(np.mean(m))
        keep[np.argmin(ratio)] = False
        F[P[~keep]] = 0.0
        P = P[keep]
        if P.size == 0:  # cannot happen with T > 0; restart from the first contact
            i0 = int(np.argmin(s / m))
            P = np.array([i0])
            F[i0] = T / m[i0]
    gap = C @ F + s - m * phi
    return F, phi, gap, it, False


def solve_contact(
    grid,
    compliance,
    torque: float,
    *,
    solver: ContactSolver = ContactSolver(),
    start=None,
    tooth_matrix=None,
    initial_load=None,
):
    """Solve the loaded contact at one grid position and pinion torque.

    grid: :class:`~gearbox.ltca.grid.ContactGrid`; compliance: a
    :class:`~gearbox.ltca.compliance.Compliance`; torque: pinion torque T (N m, > 0);
    start: optional warm-start mask of loaded points; tooth_matrix: the
    load-independent part of the compliance if already computed (it depends on the
    position only, not on the torque); initial_load: a load estimate (N, shape
    (n,)) that starts the iteration on the contact flattening.
    Returns a :class:`ContactSolution`.
    """
    p = Problems()
    p.in_range("torque", torque, 0.0, None, lo_open=True)
    p.raise_if_any("invalid loaded TCA input")
    s = np.asarray(grid.separation, dtype=float)
    m = np.asarray(grid.arm, dtype=float)
    n = grid.size
    if compliance.load_dependent:
        C0 = compliance.tooth_matrix(grid) if tooth_matrix is None else tooth_matrix
        q = np.full(n, torque / float(np.sum(m * grid.line_length)))
        if initial_load is not None and np.any(np.asarray(initial_load) > 0):
            q = np.asarray(initial_load, dtype=float) / grid.line_length
            start = q > 0 if start is None else start
    else:
        C0 = None
        q = None
    total_it = 0
    outer = 0
    F = None
    status = "converged"
    converged = True
    prev = None
    while True:
        outer += 1
        s_k = s
        if compliance.load_dependent:
            C = C0.copy()
            sec = compliance.contact_diagonal(grid, q)
            diag = sec
            if solver.flattening == "newton" and F is not None:
                # approach c(q) F linearised at the current loads: tangent on the
                # diagonal, the secant's excess in the separation
                on = F > 0
                tan = _flattening_tangent(compliance, grid, q, _FLATTENING_STEP, sec)
                diag = np.where(on, tan, sec)
                s_k = s + np.where(on, (sec - tan) * F, 0.0)
            C[np.diag_indices_from(C)] += diag
        else:
            C = compliance.matrix(grid)
        F, phi, gap, it, ok = solve_lcp(
            C, s_k, m, torque, solver=solver, start=start if F is None else F > 0
        )
        total_it += it
        if not ok:
            converged = False
            status = "max_iter"
            break
        if not compliance.load_dependent:
            break
        q_new = F / grid.line_length
        if prev is not None and np.max(np.abs(F - prev)) <= solver.outer_rtol * np.max(F):
            break
        if outer >= solver.max_outer:
            converged = False
            status = "outer_max_iter"
            break
        prev = F
        q = q_new
    if compliance.load_dependent and s_k is not s:
        # the gaps of the flattening itself (the secant at the loads found)
        C = C0.copy()
        C[np.diag_indices_from(C)] += compliance.contact_diagonal(grid, F / grid.line_length)
        gap = C @ F + s - m * phi
    scale = float(np.mean(np.diag(C))) * torque / float(np.mean(m))
    compl = float(np.max(np.abs(F * gap)) / (np.max(F) * scale)) if np.max(F) > 0 else 0.0
    msg = {
        "converged": f"converged in {total_it} active-set iterations, "
        f"{outer} flattening iterations",
        "max_iter": f"active-set iteration cap {solver.max_iter} reached",
        "outer_max_iter": f"fixed-point cap {solver.max_outer} reached on the contact flattening",
    }[status]
    return ContactSolution(
        load=F,
        gap=gap,
        rotation=float(phi),
        success=converged,
        status=status,
        message=msg,
        iterations=total_it,
        outer_iterations=outer,
        gap_residual=float(max(-np.min(gap), 0.0)),
        complementarity=compl,
        load_residual=float(abs(m @ F - torque) / torque),
    )


def _flattening_tangent(compliance, grid, q, rel_step, secant=None):
    """d(c(q) q) / dq at line loads ``q``: each point's flattening compliance on the
    tangent (a forward difference of ``rel_step`` in the line load; the flattening is
    local). ``secant``: c(q) if made already."""
    c = compliance.contact_diagonal(grid, q) if secant is None else secant
    return (
        compliance.contact_diagonal(grid, q * (1.0 + rel_step)) * (1.0 + rel_step) - c
    ) / rel_step


def _rotation_direction(K, m):
    """dphi / ds on the loaded set (:func:`rotation_sensitivity`): K^-T m / (m^T K^-1 m)
    for the tangent compliance K and the arms m of the loaded points."""
    g = np.linalg.solve(K.T, m)
    return g / float(m @ g)


def _tangent(grid, compliance, solution, tooth_matrix, rel_step):
    """The loaded set (bool, (n,)) and the tangent compliance K on it: the tooth part
    plus, for a load-dependent level, the derivative of each point's flattening
    approach c_i(q_i) F_i with respect to F_i (a forward difference of ``rel_step`` in
    the line load; the flattening is local)."""
    F = np.asarray(solution.load, dtype=float)
    q = F / np.asarray(grid.line_length, dtype=float)
    on = F > 0
    if compliance.load_dependent:
        C0 = compliance.tooth_matrix(grid) if tooth_matrix is None else tooth_matrix
        K = C0[np.ix_(on, on)].copy()
        K[np.diag_indices_from(K)] += _flattening_tangent(compliance, grid, q, rel_step)[on]
    else:
        K = compliance.matrix(grid, q)[np.ix_(on, on)]
    return on, K


def rotation_sensitivity(grid, compliance, solution, *, tooth_matrix=None, rel_step=1.0e-4):
    """Derivative of the loaded rotation phi with respect to the initial separations,
    d phi / d s, shape (n,) (rad/m), at a solution of :func:`solve_contact`.

    With the loaded set A held (the derivative of the piecewise-smooth solution away
    from a change of the set), the closed gaps K dF_A + ds_A - m_A dphi = 0 and the
    balance m_A^T dF_A = 0 give dphi / ds_A = K^-T m_A / (m_A^T K^-1 m_A), zero off A.
    K is the tangent compliance (:func:`_tangent`).

    A normal offset of tooth pair k, ds_i = -m_i alpha on its points (its pinion tooth
    turned ahead by alpha), moves phi by -alpha sum_(i in k) m_i dphi/ds_i; those pair
    weights sum to m^T dphi/ds = 1 over the pairs (:func:`pair_sensitivities`).
    """
    on, K = _tangent(grid, compliance, solution, tooth_matrix, rel_step)
    d = np.zeros(on.size)
    d[on] = _rotation_direction(K, np.asarray(grid.arm, dtype=float)[on])
    return d


def pair_sensitivities(
    grid, compliance, solution, pair_index, *, tooth_matrix=None, rel_step=1.0e-4, bases=None
):
    """Each tooth pair's weight and load sensitivity at a solution of
    :func:`solve_contact`, for offsets ds_i = -m_i alpha_k of the points of pair k
    (pinion radians alpha_k; pairs ``pair_index``, shape (K,)).

    Returns (w, S): w (K,), the loaded rotation's change per unit alpha_k with the sign
    turned (dphi = -sum_k w_k alpha_k; :func:`rotation_sensitivity`), and S (K, K),
    S[j, k] = d(normal load of pair j) / d alpha_k (N/rad): with the loaded set held,
    dF_A = K^-1 (m_A o 1_k - w_k m_A) per unit alpha_k, K the tangent compliance.
    m^T dF = 0 (the torque stays), so a pair that takes load early takes it from the
    others.

    ``bases`` (n, J), optional: further offset shapes, ds_i = -B_ij c_kj on pair k's
    points for coefficients c_kj (a tooth's form deviations, docs/ltca.md "Form
    deviations"). Then w is (K, 1 + J) and S (K, K, 1 + J), column 0 the pitch offset
    (B = m) and column 1 + j basis j, the same formulas with m_A o 1_k replaced by
    B_Aj o 1_k.
    """
    w, dF, on = point_sensitivities(
        grid,
        compliance,
        solution,
        pair_index,
        tooth_matrix=tooth_matrix,
        rel_step=rel_step,
        bases=bases,
    )
    member = (np.asarray(grid.pair)[on][:, None] == np.asarray(pair_index)[None, :]).astype(float)
    S = np.einsum("il,ikj->lkj", member, dF)  # (K, K, J1)
    if bases is None:
        return w[:, 0], S[..., 0]
    return w, S


def point_sensitivities(
    grid, compliance, solution, pair_index, *, tooth_matrix=None, rel_step=1.0e-4, bases=None
):
    """The pair weights of :func:`pair_sensitivities` (K, 1 + J) and the loads' change at
    each loaded point per unit coefficient (n_A, K, 1 + J), with the loaded set A (bool,
    (n,)): dF_A = K^-1 (B_Aj o 1_k - w_kj m_A), column 0 the pitch offset (B = m)."""
    on, K = _tangent(grid, compliance, solution, tooth_matrix, rel_step)
    m = np.asarray(grid.arm, dtype=float)[on]
    X = m[:, None] if bases is None else np.column_stack([m, np.asarray(bases, float)[on]])
    pair = np.asarray(grid.pair)[on]
    ks = np.asarray(pair_index)
    member = (pair[:, None] == ks[None, :]).astype(float)  # (n_A, K)
    d = _rotation_direction(K, m)  # dphi/ds on the loaded set
    cols = member[:, :, None] * X[:, None, :]  # (n_A, K, J1): B_Aj o 1_k
    w = np.einsum("i,ikj->kj", d, cols)  # (K, J1)
    Kinv_m = np.linalg.solve(K, m)
    Xc = np.linalg.solve(K, cols.reshape(cols.shape[0], -1)).reshape(cols.shape)
    return w, Xc - Kinv_m[:, None, None] * w[None], on

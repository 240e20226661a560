"""Linear-elastic stiffness of a tooth mesh, one sparse factorisation, many solves.

Element: the 27-node isoparametric hexahedron (triquadratic Lagrange), integrated
with 3 x 3 x 3 Gauss points (Bathe, *Finite Element Procedures*, 2nd ed., 2014,
sections 5.3 and 5.5), isotropic Hooke's law with Lame's constants. The element
matrices are computed for all elements at once with numpy (``einsum``) and summed
into one scipy sparse matrix: scikit-fem's generic form assembly of a vector 20-node
element on the same kind of mesh took 278 s for 35 k unknowns on this 2-core machine
(it loops over the basis pairs in Python), the vectorised assembly of 64 k unknowns
6 to 8 s. ``tests/test_fe_model.py`` checks the element against scikit-fem's own
triquadratic element, beam theory and a patch test.

The bore and the radial cut faces are clamped (:attr:`ToothMesh.clamped`); the free
block is factorised once (scipy's SuperLU with a symmetric ordering) and the
factorisation is reused for every unit load (many right-hand sides).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field

import numpy as np

from ..errors import InputError, Problem
from .mesh import _G3, _G3W, FEBuildError, ToothMesh, shape_functions

__all__ = ["ToothModel", "assemble_stiffness", "build_model", "solve_threads", "thread_map"]


def solve_threads() -> int:
    """Threads for the solves of many load columns: ``GEARBOX_FE_THREADS`` where set
    (a positive integer; 1 solves in the calling thread), else the cores this process
    may run on."""
    import os

    env = os.environ.get("GEARBOX_FE_THREADS", "").strip()
    if env:
        try:
            n = int(env)
        except ValueError:
            n = 0
        if n < 1:
            raise InputError(
                Problem("GEARBOX_FE_THREADS", env, "must be a positive integer"),
                "invalid environment variable (threads of the FE level's solves)",
            )
        return n
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # pragma: no cover - not on Linux
        return os.cpu_count() or 1


def thread_map(fn, items) -> list:
    """``[fn(x) for x in items]`` on :func:`solve_threads` threads (in the calling
    thread where that is 1 or there is one item): for work that releases the GIL,
    such as SuperLU's factorisations and solves."""
    items = list(items)
    workers = min(len(items), solve_threads())
    if workers <= 1:
        return [fn(x) for x in items]
    from concurrent.futures import ThreadPoolExecutor

    with ThreadPoolExecutor(workers) as pool:
        return list(pool.map(fn, items))


_GP = np.array([[a, b, c] for c in _G3 for b in _G3 for a in _G3])
_GW = np.array([wa * wb * wc for wc in _G3W for wb in _G3W for wa in _G3W])


def _gradients(p, t, X):
    """Physical shape-function gradients and det J of elements t at points X.

    t: (27, m); X: (g, 3) reference points, the same for every element.
    Returns (G (m, g, 27, 3), det (m, g)).
    """
    _, dN = shape_functions(X)  # (g, 27, 3)
    P = p[:, t].transpose(2, 1, 0)  # (m, 27, 3)
    J = np.einsum("mai,gaj->mgij", P, dN)
    det = np.linalg.det(J)
    Jinv = np.linalg.inv(J)
    G = np.einsum("gaj,mgji->mgai", dN, Jinv)
    return G, det


def assemble_stiffness(p, t, youngs_modulus: float, poisson_ratio: float, *, chunk: int = 256):
    """Global stiffness matrix (N/m) of 27-node hexahedra, scipy CSR.

    p: (3, n_nodes) m; t: (27, m) node indices. Unknown ``3 node + i`` is the
    displacement of the node along axis i. Shape (3 n_nodes, 3 n_nodes).
    """
    import scipy.sparse as sp

    E, nu = youngs_modulus, poisson_ratio
    lam = E * nu / ((1 + nu) * (1 - 2 * nu))
    mu = E / (2 * (1 + nu))
    n = 3 * p.shape[1]
    K = sp.csr_matrix((n, n))
    eye = np.eye(3)
    for s in range(0, t.shape[1], chunk):
        tc = t[:, s : s + chunk]
        G, det = _gradients(p, tc, _GP)
        if np.any(det <= 0):
            raise FEBuildError(
                Problem("fe.mesh", "non-positive Jacobian", "degenerate element"),
                "the FE stiffness cannot be assembled",
            )
        G = G * np.sqrt(_GW[None, :] * det)[:, :, None, None]
        # sums over the Gauss points as batched matrix products (BLAS): A[m, ai, bj] =
        # sum_g G[m, g, ai] G[m, g, bj], and S its trace over i = j
        m = tc.shape[1]
        Gr = G.reshape(m, _GW.size, 81)
        A = np.matmul(Gr.transpose(0, 2, 1), Gr).reshape(m, 27, 3, 27, 3)
        S = A[:, :, 0, :, 0] + A[:, :, 1, :, 1] + A[:, :, 2, :, 2]
        Ke = lam * A + mu * A.transpose(0, 1, 4, 3, 2)
        Ke += mu * S[:, :, None, :, None] * eye[None, None, :, None, :]
        dofs = (3 * tc.T[:, :, None] + np.arange(3)[None, None, :]).reshape(m, 81)
        rows = np.broadcast_to(dofs[:, :, None], (m, 81, 81)).ravel()
        cols = np.broadcast_to(dofs[:, None, :], (m, 81, 81)).ravel()
        K = K + sp.csr_matrix((Ke.reshape(-1), (rows, cols)), shape=(n, n))
    return K


@dataclass(frozen=True)
class ToothModel:
    """A factorised tooth model: mesh, material, clamped unknowns, factorisation.

    youngs_modulus (Pa), poisson_ratio; free: indices of the free unknowns, shape
    (n_free,); factor: the sparse factorisation of the free block; n_dofs: unknowns
    in total; factor_nnz: non-zeros of the factors (memory ~ 12 bytes each);
    assemble_s, factorise_s: wall times (s); residual: relative residual of a check
    solve.
    """

    mesh: ToothMesh
    youngs_modulus: float
    poisson_ratio: float
    free: np.ndarray
    factor: object = field(repr=False)
    n_dofs: int = 0
    factor_nnz: int = 0
    assemble_s: float = 0.0
    factorise_s: float = 0.0
    residual: float = 0.0

    @property
    def factor_bytes(self) -> int:
        """Approximate memory of the factors (bytes): value and row index per entry."""
        return 12 * self.factor_nnz

    def solve(self, F) -> np.ndarray:
        """Displacements (m), shape (n_dofs, m), for loads F (N), shape (n_dofs, m)
        (a dense array or a scipy sparse matrix; shape (n_dofs,) gives (n_dofs,)).

        Several columns are solved on the machine's cores at once (threads sharing
        the factorisation: SuperLU's solve releases the GIL and only reads the
        factors; ``benchmarks/bench_fe_solve.py`` measures the gain)."""
        if hasattr(F, "tocsc"):
            F = F.toarray()
        F = np.asarray(F, dtype=float)
        one = F.ndim == 1
        F2 = F[:, None] if one else F
        U = np.zeros_like(F2)
        Ff = F2[self.free]
        m = Ff.shape[1]

        def columns(js):
            # one column at a time: scipy's SuperLU multi-column solve measured 8 to
            # 13 times slower than a loop of single solves (81 columns, 6 k unknowns)
            for j in js:
                U[self.free, j] = self.factor.solve(np.ascontiguousarray(Ff[:, j]))

        workers = max(1, min(m, solve_threads()))
        thread_map(columns, [range(w, m, workers) for w in range(workers)])
        return U[:, 0] if one else U

    def element_dofs(self, cells) -> np.ndarray:
        """Unknowns of elements, shape (n, 81), ordered ``3 a + i``."""
        t = self.mesh.t[:, np.asarray(cells)]
        return (3 * t.T[:, :, None] + np.arange(3)[None, None, :]).reshape(-1, 81)

    def point_operator(self, cells, X):
        """Sparse (3 n, n_dofs) matrix of displacement values at points.

        Row ``3 q + i`` gives component i at point q (element ``cells[q]``, reference
        coordinates ``X[q]``). Its transpose turns point forces into consistent nodal
        loads.
        """
        import scipy.sparse as sp

        N, _ = shape_functions(X)  # (n, 27)
        n = N.shape[0]
        dofs = self.element_dofs(cells).reshape(n, 27, 3)
        rows = (3 * np.arange(n)[:, None, None] + np.arange(3)[None, None, :]) + 0 * dofs
        vals = np.broadcast_to(N[:, :, None], dofs.shape)
        return sp.csr_matrix(
            (vals.ravel(), (rows.ravel(), dofs.ravel())), shape=(3 * n, self.n_dofs)
        )

    def stress(self, cells, X, U) -> np.ndarray:
        """Cauchy stress (Pa) at points for displacement columns U (n_dofs, m).

        Returns shape (n, m, 3, 3).
        """
        U = np.asarray(U)
        if U.ndim == 1:
            U = U[:, None]
        cells = np.asarray(cells)
        out = np.empty((cells.size, U.shape[1], 3, 3))
        E, nu = self.youngs_modulus, self.poisson_ratio
        lam = E * nu / ((1 + nu) * (1 - 2 * nu))
        mu = E / (2 * (1 + nu))
        for q, (c, x) in enumerate(zip(cells, np.asarray(X), strict=True)):
            G, _ = _gradients(self.mesh.p, self.mesh.t[:, [c]], x[None, :])
            Ue = U[self.element_dofs([c])[0]].reshape(27, 3, -1)
            grad = np.einsum("ai,ajm->mji", G[0, 0], Ue)  # du_j/dx_i
            eps = 0.5 * (grad + grad.transpose(0, 2, 1))
            tr = np.trace(eps, axis1=1, axis2=2)
            out[q] = 2 * mu * eps + lam * tr[:, None, None] * np.eye(3)
        return out


def build_model(mesh: ToothMesh, youngs_modulus: float, poisson_ratio: float) -> ToothModel:
    """Assemble, clamp and factorise the stiffness of a tooth mesh.

    Raises :class:`~gearbox.fe.mesh.FEBuildError` naming the cause when the
    factorisation fails (singular or ill-conditioned stiffness) or a check solve does
    not reproduce its load (relative residual above 1e-8).
    """
    import scipy.sparse.linalg as sla

    t0 = time.perf_counter()
    K = assemble_stiffness(mesh.p, mesh.t, youngs_modulus, poisson_ratio)
    n = K.shape[0]
    fixed = np.zeros(n, bool)
    for i in range(3):
        fixed[3 * mesh.clamped + i] = True
    # unknowns of nodes used by no element (none are expected) are clamped too
    used = np.zeros(mesh.n_nodes, bool)
    used[mesh.t.ravel()] = True
    for i in range(3):
        fixed[3 * np.flatnonzero(~used) + i] = True
    free = np.flatnonzero(~fixed)
    Kff = K[free][:, free].tocsc()
    t1 = time.perf_counter()
    try:
        lu = sla.splu(
            Kff,
            permc_spec="MMD_AT_PLUS_A",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
    except RuntimeError as exc:
        raise FEBuildError(
            Problem("fe.factorisation", str(exc), "the clamped stiffness must be non-singular"),
            "the FE model cannot be factorised",
        ) from exc
    t2 = time.perf_counter()
    rng = np.random.default_rng(0)
    b = rng.standard_normal(free.size)
    x = lu.solve(b)
    res = float(np.linalg.norm(Kff @ x - b) / np.linalg.norm(b))
    if not (np.isfinite(res) and res < 1e-8):
        raise FEBuildError(
            Problem(
                "fe.factorisation",
                f"relative residual {res:.3g}",
                "must be < 1e-8: the stiffness is singular or ill-conditioned "
                "(degenerate elements or an unclamped part)",
            ),
            "the FE model cannot be factorised",
        )
    return ToothModel(
        mesh=mesh,
        youngs_modulus=float(youngs_modulus),
        poisson_ratio=float(poisson_ratio),
        free=free,
        factor=lu,
        n_dofs=n,
        factor_nnz=int(lu.L.nnz + lu.U.nnz),
        assemble_s=t1 - t0,
        factorise_s=t2 - t1,
        residual=res,
    )


_ = math

"""Flank limits (tip cone, form circle), surface grids and CSV export of a tooth."""

from __future__ import annotations

import io
import math

import numpy as np

from ..errors import InputError, Problem
from .blank import SIDES, ToothBlank
from .generation import FlankPoints, flank_jets, flank_points, profile_range

__all__ = [
    "parameter_at_radius",
    "tip_parameter",
    "flank_grid",
    "tooth_grid",
    "tooth_csv",
    "SolveFailure",
]

MAX_ITER = 30


class SolveFailure(InputError):
    """A bounded iteration did not converge (names the quantity and the iterations)."""


def parameter_at_radius(
    blank: ToothBlank, side: str, z, radius, *, tol: float = 1e-12, max_iter: int = MAX_ITER
) -> tuple[np.ndarray, int]:
    """Rack-profile parameter u of the flank point at a given radius in sections z.

    Safeguarded Newton iteration on ``|r(z, u)| - radius`` with exact derivatives: the
    radius grows with u from the root cone (u_min) to beyond the tip when there is no
    undercut, so a bracket is kept and a step that leaves it is replaced by bisection
    (the radius is nearly stationary at the bottom of the fillet). Started from the rack
    height ``(radius - r_p - X(z)) cos(gamma)``. Arrays z and radius broadcast.
    Returns ``(u, iterations)``; raises :class:`SolveFailure` when ``max_iter`` steps do
    not reach ``tol`` (m).
    """
    z, radius = np.broadcast_arrays(np.asarray(z, dtype=float), np.asarray(radius, dtype=float))
    sa, ca = math.sin(blank.normal_pressure_angle), math.cos(blank.normal_pressure_angle)
    vt = -blank.tool_addendum + blank.tool_tip_radius * (1 - sa)
    height = (radius - blank.reference_pitch_radius - blank.rack_shift(z)) * math.cos(
        blank.cone_angle
    )
    lo = np.full(z.shape, profile_range(blank)[0])
    hi = np.full(z.shape, (blank.addendum + 2 * blank.normal_module - vt) / ca)
    u = np.clip((height - vt) / ca, lo, hi)
    for it in range(1, max_iter + 1):
        r, _, _ = flank_jets(blank, side, z, u)
        x, y = r[0], r[1]
        rad = np.hypot(x.val, y.val)
        f = rad - radius
        if np.all(np.abs(f) <= tol):
            return u, it
        drad = (x.val * x.d[2] + y.val * y.d[2]) / rad
        lo = np.where(f < 0, u, lo)
        hi = np.where(f > 0, u, hi)
        with np.errstate(divide="ignore", invalid="ignore"):
            newton = u - f / drad
        inside = np.isfinite(newton) & (newton > lo) & (newton < hi)
        u = np.where(inside, newton, 0.5 * (lo + hi))
    raise SolveFailure(
        Problem(
            f"parameter_at_radius[{side}]",
            float(np.max(np.abs(f))),
            f"Newton iteration for the flank radius did not reach {tol} m in {max_iter} steps",
        ),
        "flank limits",
    )


def tip_parameter(blank: ToothBlank, side: str, z, *, tol: float = 1e-12) -> tuple[np.ndarray, int]:
    """Rack-profile parameter u where the flank meets the tip cone r = r_a(z).

    :func:`parameter_at_radius` with the tip-cone radius. Returns ``(u_tip, iterations)``.
    """
    z = np.asarray(z, dtype=float)
    return parameter_at_radius(blank, side, z, blank.tip_radius(z), tol=tol)


def flank_grid(
    blank: ToothBlank,
    side: str,
    n_z: int = 21,
    n_u: int = 31,
    *,
    fillet: bool = True,
    n_fillet: int = 8,
) -> FlankPoints:
    """Flank of tooth 0 sampled on a grid, toe to heel and root to tip.

    Returns :class:`FlankPoints` of shape ``(n_z, n_u + n_fillet)`` (``n_fillet`` rows of
    fillet first when ``fillet``), z from ``blank.z_toe`` to ``blank.z_heel`` and u from
    the rack tip line (or the form circle) to the tip cone.
    """
    z = np.linspace(blank.z_toe, blank.z_heel, n_z)
    u_tip, _ = tip_parameter(blank, side, z)
    t = np.linspace(0.0, 1.0, n_u)
    u = t[None, :] * u_tip[:, None]
    if fillet and blank.tool_tip_radius > 0:
        u_min, _ = profile_range(blank)
        uf = np.linspace(u_min, 0.0, n_fillet + 1)[:-1]
        u = np.concatenate([np.broadcast_to(uf, (n_z, n_fillet)), u], axis=1)
    return flank_points(blank, side, z[:, None], u)


def tooth_grid(
    blank: ToothBlank, n_z: int = 21, n_u: int = 31, *, fillet: bool = True
) -> dict[str, FlankPoints]:
    """Both flanks of tooth 0: ``{"R": FlankPoints, "L": FlankPoints}``."""
    return {s: flank_grid(blank, s, n_z, n_u, fillet=fillet) for s in SIDES}


def tooth_csv(grid: dict[str, FlankPoints]) -> str:
    """Point cloud of a tooth as CSV (mm, unit normals, curvatures in 1/mm).

    Columns: flank, i_z, i_u, part (fillet/involute), x_mm, y_mm, z_mm, nx, ny, nz,
    k_min_per_mm, k_max_per_mm.
    """
    out = io.StringIO()
    out.write("flank,i_z,i_u,part,x_mm,y_mm,z_mm,nx,ny,nz,k_min_per_mm,k_max_per_mm\n")
    for side, fp in grid.items():
        nz_, nu_ = fp.z.shape
        for i in range(nz_):
            for j in range(nu_):
                p, n, k = fp.position[i, j] * 1e3, fp.normal[i, j], fp.curvatures[i, j] * 1e-3
                part = "fillet" if fp.on_fillet[i, j] else "involute"
                out.write(
                    f"{side},{i},{j},{part},{p[0]:.6f},{p[1]:.6f},{p[2]:.6f},"
                    f"{n[0]:.9f},{n[1]:.9f},{n[2]:.9f},{k[0]:.9g},{k[1]:.9g}\n"
                )
    return out.getvalue()

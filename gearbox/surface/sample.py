"""Flank limits (tip cone, form circle), surface grids and CSV export of a tooth."""

from __future__ import annotations

import io
import math

import numpy as np

from ..errors import InputError, Problem
from .blank import SIDES, ToothBlank
from .generation import FlankPoints, flank_jets, flank_points, profile_range

__all__ = ["tip_parameter", "flank_grid", "tooth_grid", "tooth_csv", "SolveFailure"]

MAX_ITER = 30


class SolveFailure(InputError):
    """A bounded iteration did not converge (names the quantity and the iterations)."""


def tip_parameter(blank: ToothBlank, side: str, z, *, tol: float = 1e-12) -> tuple[np.ndarray, int]:
    """Rack-profile parameter u where the flank meets the tip cone r = r_a(z).

    Bounded Newton iteration on ``|r(z, u)| - r_a(z)`` (the radius grows with u on the
    involute part). Returns ``(u_tip, iterations)``; raises :class:`SolveFailure` when
    ``MAX_ITER`` steps do not reach ``tol`` (m).
    """
    z = np.asarray(z, dtype=float)
    ra = blank.tip_radius(z)
    sa, ca = math.sin(blank.normal_pressure_angle), math.cos(blank.normal_pressure_angle)
    vt = -blank.tool_addendum + blank.tool_tip_radius * (1 - sa)
    u = np.full(z.shape, (blank.addendum - vt) / ca)
    for it in range(1, MAX_ITER + 1):
        r, _, _ = flank_jets(blank, side, z, u)
        x, y = r[0], r[1]
        rad = np.hypot(x.val, y.val)
        drad = (x.val * x.d[2] + y.val * y.d[2]) / rad
        step = (rad - ra) / drad
        u = u - np.clip(step, -blank.normal_module, blank.normal_module)
        if np.all(np.abs(rad - ra) <= tol):
            return u, it
    raise SolveFailure(
        Problem(
            f"tip_parameter[{side}]",
            float(np.max(np.abs(rad - ra))),
            f"Newton iteration for the tip cone did not reach {tol} m in {MAX_ITER} steps",
        ),
        "flank limits",
    )


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

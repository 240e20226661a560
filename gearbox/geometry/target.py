"""Design for a target FPD angle: the pinion cone angle as the cyclic variable.

Paper section 2.2.4: "the line contact condition of Eq. (10) is used to fix the cyclic
variable" gamma_1. Here gamma_1 is found so that the FPD angle of the chosen flank
(xi_R or xi_L, eqs (1), (8), (9)) equals a target value (0 for line contact on that
flank), with the gear cone angle, pinion helix angle and offset held.
"""

from __future__ import annotations

import math

import numpy as np
from scipy.optimize import brentq

from ..errors import InputError, Problem
from .design import solve_spec
from .spec import PairSpec

__all__ = ["solve_cone_angle_for_fpd"]


def _fpd(spec: PairSpec, gamma1):
    sol = solve_spec(spec, pinion_cone_angle=gamma1)
    return sol["fpd_right"] if spec.target_flank == "right" else sol["fpd_left"]


def solve_cone_angle_for_fpd(spec: PairSpec, *, n_grid: int = 600, xtol: float = 1e-13) -> float:
    """Pinion cone angle gamma_1 (rad) giving ``spec.target_fpd_angle`` on ``spec.target_flank``.

    The smallest such gamma_1 in [0, 30 deg] is returned (bracketed on a grid, then
    Brent's method to ``xtol`` rad). Raises :class:`InputError` with the achievable
    range when the target cannot be met.
    """
    grid = np.linspace(0.0, math.radians(30.0), n_grid)
    f = _fpd(spec, grid) - spec.target_fpd_angle
    ok = np.isfinite(f)
    idx = np.nonzero(ok[:-1] & ok[1:] & (np.sign(f[:-1]) != np.sign(f[1:])))[0]
    exact = np.nonzero(ok & (f == 0.0))[0]
    if exact.size and (not idx.size or exact[0] <= idx[0]):
        return float(grid[exact[0]])
    if not idx.size:
        vals = np.degrees(f[ok] + spec.target_fpd_angle)
        rng = (
            f"achievable with these inputs: {vals.min():.4f} to {vals.max():.4f} deg"
            if vals.size
            else "no gamma_1 gives a design"
        )
        raise InputError(
            Problem("pair.target_fpd_angle_deg", math.degrees(spec.target_fpd_angle), rng),
            "no pinion cone angle meets the target FPD angle",
        )
    i = idx[0]
    return float(
        brentq(
            lambda g1: float(_fpd(spec, g1)) - spec.target_fpd_angle,
            grid[i],
            grid[i + 1],
            xtol=xtol,
        )
    )

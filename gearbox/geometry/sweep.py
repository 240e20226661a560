"""Parameter studies of paper section 3.1 (Figs. 6-9), vectorised.

Each study varies one input along the x axis and another across curves, holding the
rest of the scene's pair (offset, module, pressure angle, teeth) fixed, and solves all
designs in one call of :func:`gearbox.geometry.design.solve_pair_arrays` (no Python
loop over scalar solves).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .design import solve_pair_arrays
from .spec import PairSpec

__all__ = ["Study", "parameter_study", "PAPER_STUDIES", "VARIABLES"]

#: sweepable inputs: name -> (label, unit at the edge, SI factor)
VARIABLES = {
    "pinion_cone_angle": ("pinion cone angle gamma_1", "deg", math.pi / 180),
    "gear_cone_angle": ("gear cone angle gamma_2", "deg", math.pi / 180),
    "shaft_angle": ("shaft angle delta", "deg", math.pi / 180),
    "pinion_helix_angle": ("pinion helix angle beta_1", "deg", math.pi / 180),
    "offset": ("offset E", "mm", 1e-3),
}


@dataclass(frozen=True)
class Study:
    """Result of a parameter study; arrays have shape (n_curves, n_x).

    ``x`` and ``curves`` are in edge units (deg or mm, see ``x_unit``/``curve_unit``);
    results: ``xi_n``, ``fpd_right_deg``, ``fpd_left_deg``, ``gear_helix_deg``; entries
    without a design are NaN (``ok`` False).
    """

    name: str
    x_name: str
    x_unit: str
    x: np.ndarray
    curve_name: str
    curve_unit: str
    curves: np.ndarray
    xi_n: np.ndarray
    fpd_right_deg: np.ndarray
    fpd_left_deg: np.ndarray
    gear_helix_deg: np.ndarray
    ok: np.ndarray

    def to_csv(self) -> str:
        """Long-format CSV: one row per (curve, x)."""
        head = f"{self.curve_name}_{self.curve_unit},{self.x_name}_{self.x_unit},normal_angular_factor,fpd_angle_right_deg,fpd_angle_left_deg,gear_helix_angle_deg"
        rows = [head]
        for i, c in enumerate(self.curves):
            for j, x in enumerate(self.x):
                vals = (
                    self.xi_n[i, j],
                    self.fpd_right_deg[i, j],
                    self.fpd_left_deg[i, j],
                    self.gear_helix_deg[i, j],
                )
                rows.append(
                    f"{c:.6g},{x:.6g},"
                    + ",".join("" if not np.isfinite(v) else f"{v:.10g}" for v in vals)
                )
        return "\n".join(rows) + "\n"


def _inputs(spec: PairSpec):
    p, g = spec.pinion, spec.gear
    return {
        "pinion_cone_angle": p.cone_angle,
        "gear_cone_angle": g.cone_angle,
        "shaft_angle": spec.shaft_angle,
        "pinion_helix_angle": p.helix_angle,
        "offset": spec.offset,
    }


def parameter_study(
    spec: PairSpec, x_name: str, x_values, curve_name: str, curve_values, *, name: str = ""
) -> Study:
    """Solve the design over the grid ``curve_values x x_values`` (edge units)."""
    for n in (x_name, curve_name):
        if n not in VARIABLES:
            from ..errors import InputError, Problem

            raise InputError(Problem("study variable", n, f"must be one of {', '.join(VARIABLES)}"))
    x = np.asarray(x_values, dtype=float)
    c = np.asarray(curve_values, dtype=float)
    vals = {k: np.asarray(v, dtype=float) for k, v in _inputs(spec).items()}
    vals[x_name] = x[None, :] * VARIABLES[x_name][2]
    vals[curve_name] = c[:, None] * VARIABLES[curve_name][2]
    sol = solve_pair_arrays(
        spec.normal_module,
        spec.normal_pressure_angle,
        vals["shaft_angle"],
        vals["offset"],
        spec.pinion.teeth,
        spec.gear.teeth,
        vals["pinion_helix_angle"],
        vals["pinion_cone_angle"],
        vals["gear_cone_angle"],
    )
    shape = (c.size, x.size)
    b = lambda a: np.broadcast_to(a, shape).copy()  # noqa: E731
    return Study(
        name=name or f"{x_name}_vs_{curve_name}",
        x_name=x_name,
        x_unit=VARIABLES[x_name][1],
        x=x,
        curve_name=curve_name,
        curve_unit=VARIABLES[curve_name][1],
        curves=c,
        xi_n=b(sol["xi_n"]),
        fpd_right_deg=b(np.degrees(sol["fpd_right"])),
        fpd_left_deg=b(np.degrees(sol["fpd_left"])),
        gear_helix_deg=b(np.degrees(sol["beta2"])),
        ok=b(sol["ok"]),
    )


def PAPER_STUDIES(spec: PairSpec, n: int = 101) -> list[Study]:
    """The studies of paper Figs. 6-9 around the scene's design.

    Fig. 6/7 (a): FPD angles and xi_n against gamma_1 for shaft angles 9-15 deg;
    Fig. 6/7 (b): against gamma_1 for several gamma_2; Fig. 8/9 (a): against beta_1 for
    shaft angles; Fig. 8/9 (b): against beta_1 for several gamma_2.
    """
    g1 = np.linspace(0.0, 5.0, n)
    b1 = np.linspace(10.0, 35.0, n)
    shafts = [9.0, 11.0, 13.0, 15.0]
    g2s = [0.2, 0.5, 0.8, 1.1]
    return [
        parameter_study(
            spec,
            "pinion_cone_angle",
            g1,
            "shaft_angle",
            shafts,
            name="fig6a_fig7a_cone_angle_vs_shaft_angle",
        ),
        parameter_study(
            spec,
            "pinion_cone_angle",
            g1,
            "gear_cone_angle",
            g2s,
            name="fig6b_fig7b_cone_angle_vs_gear_cone_angle",
        ),
        parameter_study(
            spec,
            "pinion_helix_angle",
            b1,
            "shaft_angle",
            shafts,
            name="fig8a_fig9a_helix_angle_vs_shaft_angle",
        ),
        parameter_study(
            spec,
            "pinion_helix_angle",
            b1,
            "gear_cone_angle",
            g2s,
            name="fig8b_fig9b_helix_angle_vs_gear_cone_angle",
        ),
    ]

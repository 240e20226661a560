"""Report section of the mesh tables: stiffness and LTE over the mesh cycle."""

from __future__ import annotations

import math

import numpy as np

from .html import ReportWarning, Section, figure, fmt, new_figure, table

__all__ = ["render"]


def render(tab, run) -> Section:
    """Mean / peak-to-peak per flank and torque; k(theta) and LTE(theta) figures."""
    method = str(tab.attrs.get("method", ""))
    warnings = []
    if tab.attrs.get("fidelity") == "analytical":
        warnings.append(
            ReportWarning(
                "tables",
                "mesh tables from the analytical model (" + method + "), not from the "
                "loaded TCA of the beveloid flanks",
            )
        )
    rows = []
    for flank, per_t in tab.summary().items():
        for t, v in per_t.items():
            rows.append(
                (
                    flank,
                    float(t),
                    v["mean_mesh_stiffness_N_per_m"] / 1e6,
                    v["mesh_stiffness_peak_to_peak_N_per_m"] / 1e6,
                    v["lte_mean_m"] * 1e6,
                    v["lte_peak_to_peak_m"] * 1e6,
                    *(1e9 * a for a in v["lte_harmonics_m"][:3]),
                )
            )
    head = [
        "flank",
        "pinion torque (N m)",
        "mean stiffness (N/um)",
        "stiffness p-p (N/um)",
        "mean LTE (um)",
        "LTE p-p (um)",
        "LTE 1st mesh harmonic (nm)",
        "2nd (nm)",
        "3rd (nm)",
    ]
    fig, ax = new_figure(1, 2, size=(10, 3.6))
    deg = np.degrees(tab.angle)
    for i, flank in enumerate(tab.flanks):
        style = "-" if flank == "drive" else "--"
        for j, t in enumerate(tab.torque):
            lab = f"{flank}, {t:g} N m"
            ax[0, 0].plot(deg, tab.stiffness[i, j] / 1e6, style, label=lab)
            ax[0, 1].plot(deg, tab.lte[i, j] * 1e6, style, label=lab)
    ax[0, 0].set(xlabel="pinion angle (deg)", ylabel="mesh stiffness (N/um)")
    ax[0, 1].set(xlabel="pinion angle (deg)", ylabel="LTE (um)")
    ax[0, 0].legend(fontsize=6)
    for a in ax[0]:
        a.grid(True, alpha=0.3)
    period = 360.0 / tab.pinion_teeth
    body = (
        f"<p>Method: {fmt(method)}. One mesh cycle = {period:.4g} deg of pinion rotation "
        f"(2 pi / N_1, N_1 = {tab.pinion_teeth}), {tab.n_positions} positions; drive = R flank, "
        "coast = L flank. LTE harmonics: peak amplitudes at 1, 2 and 3 times the mesh "
        "order, from the Fourier series of the table over one mesh cycle.</p>"
        + table(head, rows)
        + figure(fig, "Mesh stiffness and loaded transmission error over one mesh cycle")
    )
    if not math.isfinite(float(np.max(tab.stiffness))):
        warnings.append(ReportWarning("tables", "non-finite mesh stiffness in the tables"))
    gaps = torque_interpolation_gaps(tab)
    if gaps:
        body += (
            "<p>Between the torque levels: the cycle mean of the tangent stiffness as the "
            "tangent mesh law takes it (the table interpolated linearly in torque) against "
            "the loaded mesh law's slope (cubic in the deflection through the levels, "
            "docs/drivetrain.md section 3d), at a quarter, half and three quarters of each "
            "interval; the largest gap per flank and interval.</p>"
            + table(
                ["flank", "levels (N m)", "at (N m)", "linear in torque / loaded law - 1"],
                [(f, f"{a:g} - {b:g}", t, f"{100 * g:+.2f} %") for f, a, b, t, g in gaps],
            )
        )
        worst = max(gaps, key=lambda r: abs(r[4]))
        law = run.scene["drivetrain"]["mesh_law"]
        if abs(worst[4]) > INTERPOLATION_WARN and law == "tangent":
            f, a, b, t, g = worst
            warnings.append(
                ReportWarning(
                    "tables",
                    f"between {a:g} and {b:g} N m the tangent mesh law's stiffness, "
                    f"interpolated linearly in torque, departs from the loaded law's by "
                    f"{100 * g:+.1f} % ({f} flank at {t:g} N m): drivetrain models whose "
                    "mean torque lies there (speed sweeps on the propeller law) take it; "
                    "more levels in load.torques_Nm, or drivetrain.mesh_law = 'loaded', "
                    "avoid it",
                )
            )
    return Section("Mesh tables", body, tuple(warnings), anchor="tables")


#: Gap (share) between the two interpolations in torque of the tangent stiffness above
#: which the report warns (a choice: the loaded law met loaded TCA solves between the
#: default scene's levels within 0.7 %, docs/drivetrain.md section 3d).
INTERPOLATION_WARN = 0.02


def torque_interpolation_gaps(tab) -> list[tuple[str, float, float, float, float]]:
    """(flank, lower level, upper level, torque, gap) of the largest gap per flank and
    pair of neighbouring torque levels between the cycle mean of the tangent stiffness
    interpolated linearly in torque and the loaded mesh law's slope at that torque's
    mesh force (docs/drivetrain.md section 3d), at 1/4, 1/2 and 3/4 of the interval;
    empty for a table of one level or one the law cannot take (an LTE that does not
    grow with the torque)."""
    from ..drivetrain.model import loaded_law_point, loaded_law_samples
    from ..errors import InputError

    out = []
    if tab.torque.size < 2 or "drive" not in tab.flanks:
        return out
    for flank in tab.flanks:
        for a, b in zip(tab.torque[:-1], tab.torque[1:], strict=True):
            worst = None
            for t in a + (b - a) * np.array([0.25, 0.5, 0.75]):
                lam = abs(tab.rotation_radii("drive", float(t))[0])
                try:
                    rows, forces = loaded_law_samples(tab, flank, lam)
                except InputError:
                    return []
                _, k = loaded_law_point(rows, forces, float(t) / lam)
                lin = tab.values_at("tangent_stiffness", flank, float(t))
                g = float(np.mean(lin) / np.mean(k) - 1.0)
                if worst is None or abs(g) > abs(worst[4]):
                    worst = (flank, float(a), float(b), float(t), g)
            out.append(worst)
    return out

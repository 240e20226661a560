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
    return Section("Mesh tables", body, tuple(warnings), anchor="tables")

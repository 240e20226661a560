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
            "<p>Between the torque levels the dynamics take, with either mesh law, the "
            "loaded mesh law's tangent at the mean torque's mesh force (cubic in the "
            "deflection through the levels, docs/drivetrain.md sections 3 and 3d). Set "
            "beside it, the table interpolated linearly in torque: the cycle mean of "
            "both tangent stiffnesses at a quarter, half and three quarters of each "
            "interval, the largest gap per flank and interval. It measures how far the "
            "stiffness bends between the levels.</p>"
            + table(
                ["flank", "levels (N m)", "at (N m)", "linear in torque / loaded law - 1"],
                [(f, f"{a:g} - {b:g}", t, f"{100 * g:+.2f} %") for f, a, b, t, g in gaps],
            )
            + _stiffness_figure(tab)
        )
    if tab.torque.size >= 2:
        for flank in tab.flanks:
            if not law_allowed(tab, flank):
                warnings.append(
                    ReportWarning(
                        "tables",
                        f"the {flank} flank's LTE does not grow with the torque at every "
                        "position (or a tangent stiffness is not > 0): between the levels "
                        "the tangent mesh law takes that flank's table linearly in torque, "
                        "and the loaded mesh law cannot take it",
                    )
                )
    return Section("Mesh tables", body, tuple(warnings), anchor="tables")


def law_allowed(tab, flank: str) -> bool:
    """Whether the loaded mesh law can take ``flank`` of the table (its LTE grows with the
    torque and its tangent stiffnesses are > 0 at every position)."""
    from ..drivetrain.model import law_levels

    return law_levels(tab, flank, 1.0)[3]


def stiffness_against_torque(tab, flank: str, torques):
    """Cycle means of the tangent stiffness (N/m) of ``flank`` at ``torques`` (N m,
    within the levels): (the loaded mesh law's slope at the torque's mesh force, the
    table interpolated linearly in torque), each shape (len(torques),). One drive
    rotation radius, the levels' middle one's, turns torque into force; InputError when
    the law cannot take the table (docs/drivetrain.md section 3d)."""
    from ..drivetrain.model import law_mean_stiffness

    torques = np.asarray(torques, dtype=float)
    lam = abs(tab.rotation_radii("drive", float(np.median(tab.torque)))[0])
    law = law_mean_stiffness(tab, flank, lam, torques / lam)
    linear = np.array([np.mean(tab.values_at("tangent_stiffness", flank, t)) for t in torques])
    return law, linear


def torque_interpolation_gaps(tab) -> list[tuple[str, float, float, float, float]]:
    """(flank, lower level, upper level, torque, gap) of the largest gap per flank and
    pair of neighbouring torque levels between the cycle mean of the tangent stiffness
    interpolated linearly in torque and the loaded mesh law's slope at that torque's
    mesh force (:func:`stiffness_against_torque`), at 1/4, 1/2 and 3/4 of the interval;
    empty for a table of one level or one the law cannot take (an LTE that does not
    grow with the torque)."""
    from ..errors import InputError

    out = []
    if tab.torque.size < 2 or "drive" not in tab.flanks:
        return out
    lo, hi = tab.torque[:-1], tab.torque[1:]
    at = (lo[:, None] + (hi - lo)[:, None] * np.array([0.25, 0.5, 0.75])).ravel()
    for flank in tab.flanks:
        try:
            law, linear = stiffness_against_torque(tab, flank, at)
        except InputError:
            return []
        gap = (linear / law - 1.0).reshape(lo.size, 3)
        for i, g in enumerate(gap):
            j = int(np.argmax(np.abs(g)))
            out.append((flank, float(lo[i]), float(hi[i]), float(at[3 * i + j]), float(g[j])))
    return out


def _stiffness_figure(tab) -> str:
    """k (cycle mean) against torque per flank: the loaded law's slope, the linear
    interpolation in torque and the levels; empty where the law cannot take the table."""
    from ..errors import InputError

    torques = np.linspace(tab.torque[0], tab.torque[-1], 61)
    fig, ax = new_figure(1, 1, size=(6.4, 3.4))
    a = ax[0, 0]
    for flank in tab.flanks:
        try:
            law, linear = stiffness_against_torque(tab, flank, torques)
        except InputError:
            return ""
        i = tab.flank_index(flank)
        style = "-" if flank == "drive" else "--"
        a.plot(torques, law / 1e6, style, label=f"{flank}: loaded law")
        a.plot(torques, linear / 1e6, style, lw=0.8, label=f"{flank}: linear in torque")
        a.plot(tab.torque, tab.tangent_stiffness[i].mean(axis=1) / 1e6, "ko", ms=3)
    a.set(xlabel="pinion torque (N m)", ylabel="mean tangent stiffness (N/um)")
    a.grid(True, alpha=0.3)
    a.legend(fontsize=6)
    return figure(
        fig,
        "Mean tangent mesh stiffness against torque: the loaded law's slope and the "
        "table interpolated linearly in torque (dots: the levels)",
    )

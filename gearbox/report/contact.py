"""Report section of the unloaded TCA: FPD angles measured on the surfaces, contact
paths on both flanks, transmission error, and what did not converge."""

from __future__ import annotations

from .html import ReportWarning, Section, figure, fmt, new_figure, table

__all__ = ["render_tca"]


def _pair(d, key):
    v = d.get(key) or {}
    return fmt(v.get("drive")), fmt(v.get("coast"))


def _tally(t) -> str:
    """'gear heel 33, pinion heel 28' from a side's edge contact counts; '-' for none."""
    return ", ".join(f"{k} {v}" for k, v in t.items()) if t else "-"


def render_tca(res, run) -> Section:
    """Summary table, contact-path and TE figures; warnings for failed positions."""
    from ..tca.plot import plot_contact_path, plot_transmission_error

    s = res.summary()
    warnings = []
    if s["status"] != "ok":
        warnings.append(ReportWarning("tca", f"status {s['status']}"))
    for m in s["messages"]:
        warnings.append(ReportWarning("tca", m))
    for side in ("drive", "coast"):
        n = s["not_converged"].get(side, 0)
        if n:
            warnings.append(ReportWarning("tca", f"{side}: {n} contact solutions did not converge"))
        n = s["positions_without_contact"].get(side, 0)
        if n:
            warnings.append(
                ReportWarning(
                    "tca", f"{side}: {n} pinion positions without contact of the flanks' surfaces"
                )
            )
    rows = [
        (
            "FPD angle measured on the surfaces (deg): R / L",
            fmt(s["measured_fpd_angle_right_deg"]),
            fmt(s["measured_fpd_angle_left_deg"]),
        ),
        (
            "FPD angle of the design (deg): R / L",
            fmt(s.get("designed_fpd_angle_right_deg")),
            fmt(s.get("designed_fpd_angle_left_deg")),
        ),
        ("unloaded TE peak-to-peak (arcsec)", *_pair(s, "unloaded_te_peak_to_peak_arcsec")),
        ("contact path straightness (um)", *_pair(s, "contact_path_straightness_um")),
        ("contact ratio", *_pair(s, "contact_ratio")),
        ("positions without contact of the surfaces", *_pair(s, "positions_without_contact")),
        (
            "positions with edge contact, by border",
            *(_tally(s.get("edge_contact_positions", {}).get(k)) for k in ("drive", "coast")),
        ),
        ("contact solutions not converged", *_pair(s, "not_converged")),
        ("largest iteration count", *_pair(s, "max_iterations")),
    ]
    ell = s.get("contact_ellipse_semi_axes_median", {})
    rows.append(
        (
            "contact ellipse semi-axes, median (mm)",
            *(
                f"{fmt(ell.get(k, {}).get('major_mm'))} x {fmt(ell.get(k, {}).get('minor_mm'))}"
                for k in ("drive", "coast")
            ),
        )
    )
    fig, ax = new_figure(1, 2, size=(11, 3.4))
    plot_contact_path(res, "pinion", ax[0, 0])
    plot_contact_path(res, "gear", ax[0, 1])
    fig2, ax2 = new_figure(1, 1, size=(7, 3))
    plot_transmission_error(res, ax2[0, 0])
    body = (
        table(["quantity", "drive (R)", "coast (L)"], rows)
        + f'<p class="muted">Ellipses for a separation of {fmt(s["marking_compound_um"])} um '
        "(marking compound).</p>"
        + figure(fig, "Unloaded contact paths on the pinion and gear flanks (paper Fig. 10 style)")
        + figure(fig2, "Unloaded transmission error")
    )
    return Section("Unloaded tooth contact analysis", body, tuple(warnings), anchor="tca")

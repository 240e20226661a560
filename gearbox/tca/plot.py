"""Figures of the unloaded TCA (matplotlib, Agg; imported only when plotting)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_contact_path", "plot_transmission_error"]


def _plt():
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt


def plot_contact_path(result, member: str = "pinion", ax=None):
    """Contact paths of both sides on one member's flank (paper Fig. 10 style).

    Face width (mm from the face middle, toe left, heel right) against profile height
    (form circle 0 to tip 1). Drive (R) solid, coast (L) dashed; contact ellipses of
    the active contacts drawn as their major-axis extent along the path; edge contacts
    (``FlankContact.edge``) as crosses. Returns ``ax``.
    """
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3.2))
    blank = result.pinion if member == "pinion" else result.gear
    half = 0.5 * blank.face_width * 1e3
    ax.add_patch(plt.Rectangle((-half, 0), 2 * half, 1, fill=False, color="0.3", lw=1))
    for fc, style in ((result.drive, "-"), (result.coast, "--")):
        fl = fc.pinion_flank if member == "pinion" else fc.gear_flank
        a = fc.active
        f, p = fl[..., 0][a] * half, fl[..., 1][a]
        order = np.argsort(f)
        (line,) = ax.plot(
            f[order], p[order], style, marker=".", ms=3, label=f"{fc.name} ({fc.side})"
        )
        efl = fc.edge_pinion_flank if member == "pinion" else fc.edge_gear_flank
        if efl is not None and np.isfinite(efl).all(axis=1).any():
            e = efl[np.isfinite(efl).all(axis=1)]
            ax.plot(
                e[:, 0] * half,
                e[:, 1],
                "x",
                color=line.get_color(),
                ms=4,
                label=f"{fc.name}: edge contact",
            )
    ax.set_xlim(-1.1 * half, 1.1 * half)
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("face width from middle (mm): toe <- -> heel")
    ax.set_ylabel("profile: form circle 0 .. tip 1")
    ax.set_title(f"unloaded contact path on the {member} flank")
    ax.legend(loc="upper right", fontsize=8)
    return ax


#: Least span of the unloaded TE's axis (arcsec on the gear): 1.33 nm at a 137 mm
#: pitch radius. The TE of conjugate flanks is the solver's rounding (about 1e-11
#: arcsec); drawn to its own scale, that noise would look like a real error.
TE_AXIS_MIN_SPAN_ARCSEC = 2e-3


def plot_transmission_error(result, ax=None):
    """Unloaded transmission error (arcsec on the gear) against pinion angle (deg).
    The axis spans at least :data:`TE_AXIS_MIN_SPAN_ARCSEC`; when both flanks' TE
    fits in it, the axes say so (the flanks are conjugate to that precision)."""
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3))
    arcsec = 180 / np.pi * 3600
    values = []
    for fc, style in ((result.drive, "-"), (result.coast, "--")):
        phi = np.degrees(fc.pinion_angle - fc.pinion_angle[0])
        te = np.asarray(fc.transmission_error) * arcsec
        values.append(te[np.isfinite(te)])
        ax.plot(phi, te, style, label=fc.name)
    te = np.concatenate(values)
    if te.size and np.ptp(te) < TE_AXIS_MIN_SPAN_ARCSEC:
        mid, half = 0.5 * (te.min() + te.max()), TE_AXIS_MIN_SPAN_ARCSEC
        ax.set_ylim(mid - half, mid + half)
        ax.set_yticks(mid + half * np.array([-1.0, -0.5, 0.0, 0.5, 1.0]))
        ax.yaxis.set_major_formatter(lambda v, _: f"{v:.3f}")
        ax.text(
            0.02,
            0.05,
            f"peak-to-peak {np.ptp(te):.1e} arcsec: conjugate flanks "
            f"(below {TE_AXIS_MIN_SPAN_ARCSEC:g} arcsec)",
            transform=ax.transAxes,
            fontsize=8,
            color="0.3",
        )
    ax.set_xlabel("pinion angle from sweep start (deg)")
    ax.set_ylabel("unloaded TE (arcsec)")
    ax.legend(fontsize=8)
    return ax

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
    the active contacts drawn as their major-axis extent along the path. Returns ``ax``.
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
        ax.plot(f[order], p[order], style, marker=".", ms=3, label=f"{fc.name} ({fc.side})")
    ax.set_xlim(-1.1 * half, 1.1 * half)
    ax.set_ylim(-0.05, 1.05)
    ax.set_xlabel("face width from middle (mm): toe <- -> heel")
    ax.set_ylabel("profile: form circle 0 .. tip 1")
    ax.set_title(f"unloaded contact path on the {member} flank")
    ax.legend(loc="upper right", fontsize=8)
    return ax


def plot_transmission_error(result, ax=None):
    """Unloaded transmission error (arcsec on the gear) against pinion angle (deg)."""
    plt = _plt()
    if ax is None:
        _, ax = plt.subplots(figsize=(6, 3))
    arcsec = 180 / np.pi * 3600
    for fc, style in ((result.drive, "-"), (result.coast, "--")):
        phi = np.degrees(fc.pinion_angle - fc.pinion_angle[0])
        ax.plot(phi, fc.transmission_error * arcsec, style, label=fc.name)
    ax.set_xlabel("pinion angle from sweep start (deg)")
    ax.set_ylabel("unloaded TE (arcsec)")
    ax.legend(fontsize=8)
    return ax

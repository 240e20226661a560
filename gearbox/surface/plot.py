"""Figure of one generated tooth (matplotlib, Agg; imported only when plotting)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_tooth", "plot_tooth_sections"]


def plot_tooth(grid, ax=None, *, title: str = ""):
    """Wireframe of both flanks of one tooth (mm) in the gear frame; returns ``ax``.

    ``grid`` is :func:`gearbox.surface.tooth_grid`'s result. Fillet lines are grey,
    the involute part blue (R) and red (L).
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if ax is None:
        fig = plt.figure(figsize=(6, 5))
        ax = fig.add_subplot(projection="3d")
    colours = {"R": "tab:blue", "L": "tab:red"}
    for side, fp in grid.items():
        P = fp.position * 1e3
        fil = fp.on_fillet
        for i in range(0, P.shape[0], max(1, P.shape[0] // 10)):
            ax.plot(P[i, :, 0], P[i, :, 1], P[i, :, 2], color=colours[side], lw=0.8)
        for j in range(0, P.shape[1], max(1, P.shape[1] // 8)):
            c = "0.5" if np.all(fil[:, j]) else colours[side]
            ax.plot(P[:, j, 0], P[:, j, 1], P[:, j, 2], color=c, lw=0.6)
    allp = np.concatenate([fp.position.reshape(-1, 3) for fp in grid.values()]) * 1e3
    ax.set_box_aspect(tuple(np.ptp(allp, axis=0)))  # true proportions
    ax.view_init(elev=15, azim=70)  # from outside the tip, both flanks in view
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    if title:
        ax.set_title(title)
    return ax


def plot_tooth_sections(grid, ax=None, *, title: str = ""):
    """Transverse sections of one tooth at toe, middle and heel (mm); returns ``ax``.

    Each section is turned about the axis so that the tooth's centre line is vertical
    (the helix twist removed), so the growth of the tooth from toe to heel shows; both
    flanks with their root fillets, equal axis scales.
    """
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    if ax is None:
        _, ax = plt.subplots(figsize=(4.5, 5))
    any_fp = next(iter(grid.values()))
    n_z, n_u = any_fp.z.shape
    colours = {"R": "tab:blue", "L": "tab:red"}
    for i, (label, style) in zip(
        (0, n_z // 2, n_z - 1), (("toe", ":"), ("middle", "-"), ("heel", "--")), strict=True
    ):
        # turn each section so that the tooth's centre line (mid-height) is the y axis
        mids = [fp.position[i, n_u // 2] for fp in grid.values()]
        c = np.mean([np.arctan2(-p[0], p[1]) for p in mids])
        rot = np.array([[np.cos(c), np.sin(c)], [-np.sin(c), np.cos(c)]])
        for side, fp in grid.items():
            p = fp.position[i, :, :2] @ rot.T * 1e3
            ax.plot(
                p[:, 0], p[:, 1], style, color=colours.get(side, "k"), lw=1, label=f"{side} {label}"
            )
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.legend(fontsize=7, ncol=2)
    if title:
        ax.set_title(title)
    return ax

"""Figure of one generated tooth (matplotlib, Agg; imported only when plotting)."""

from __future__ import annotations

import numpy as np

__all__ = ["plot_tooth"]


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
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.set_zlabel("z (mm)")
    if title:
        ax.set_title(title)
    return ax

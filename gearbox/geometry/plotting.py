"""Figures of the geometry stage (matplotlib only here)."""

from __future__ import annotations

from .sweep import VARIABLES, Study

__all__ = ["plot_study"]


def plot_study(study: Study, axes=None):
    """FPD angles (left panel) and xi_n (right panel) of a study; returns the axes."""
    import matplotlib

    if axes is None:
        matplotlib.use("Agg", force=False)
        import matplotlib.pyplot as plt

        _, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    ax_f, ax_x = axes
    colors = matplotlib.rcParams["axes.prop_cycle"].by_key()["color"]
    for i, c in enumerate(study.curves):
        col = colors[i % len(colors)]
        lab = f"{VARIABLES[study.curve_name][0].split()[-1]} = {c:g} {study.curve_unit}"
        ax_f.plot(study.x, study.fpd_right_deg[i], "-", color=col, label=f"xi_R, {lab}")
        ax_f.plot(study.x, study.fpd_left_deg[i], "--", color=col, label=f"xi_L, {lab}")
        ax_x.plot(study.x, study.xi_n[i], "-", color=col, label=lab)
    xl = f"{VARIABLES[study.x_name][0]} ({study.x_unit})"
    ax_f.set(xlabel=xl, ylabel="FPD angle (deg)", title="FPD angles (solid R, dashed L)")
    ax_x.set(xlabel=xl, ylabel="normal angular factor xi_n", title="normal angular factor")
    ax_f.legend(fontsize=6, ncol=2)
    ax_x.legend(fontsize=7)
    for ax in axes:
        ax.grid(True, alpha=0.3)
    return axes

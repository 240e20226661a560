"""Report section of the parameter studies (paper Figs. 6-9)."""

from __future__ import annotations

from .html import Section, figure, new_figure

__all__ = ["render"]


def render(studies, run) -> Section:
    """One figure per study: FPD angles and xi_n against the swept input."""
    from ..geometry.plotting import plot_study

    parts = [
        '<p class="muted">Each study varies one input along the x axis and another across '
        "curves, holding the rest of the scene's pair fixed (paper section 3.1).</p>"
    ]
    for st in studies.studies:
        fig, axes = new_figure(1, 2, size=(10, 4))
        plot_study(st, axes[0])
        n_ok = int(st.ok.sum())
        parts.append(figure(fig, f"{st.name}: {n_ok}/{st.ok.size} designs solved"))
    return Section("Parameter studies (paper Figs. 6-9)", "".join(parts), anchor="sweep")

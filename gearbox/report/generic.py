"""Fallback section for a stage result without a dedicated renderer.

A result may render itself: ``_repr_html_()`` (the Jupyter convention) gives the
section body, and a ``report_figures()`` method returning ``[(figure, caption)]``
adds figures. Otherwise the scalar entries of ``to_dict()`` are tabulated.
"""

from __future__ import annotations

from .html import Section, figure, table

__all__ = ["render_generic"]


def _scalars(d, prefix=""):
    for k, v in d.items():
        if isinstance(v, dict):
            yield from _scalars(v, f"{prefix}{k}.")
        elif isinstance(v, (int, float, str, bool)) or v is None:
            yield (f"{prefix}{k}", v)


def render_generic(title: str, anchor: str):
    """A renderer for ``title`` that uses the result's own HTML, figures or dict."""

    def render(result, run) -> Section:
        parts = []
        if hasattr(result, "_repr_html_"):
            parts.append(result._repr_html_())
        elif hasattr(result, "to_dict"):
            rows = list(_scalars(result.to_dict()))[:200]
            parts.append(table(["quantity", "value"], rows))
        if hasattr(result, "report_figures"):
            for fig, caption in result.report_figures():
                parts.append(figure(fig, caption))
        if not parts:
            parts.append(f"<p>{type(result).__name__}: no report view in this version.</p>")
        return Section(title, "".join(parts), anchor=anchor)

    return render

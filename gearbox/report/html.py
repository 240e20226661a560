"""Small HTML building blocks for a self-contained report: escaping, tables, figures.

Figures are embedded as base64 PNG ``data:`` URIs, so the report is one file that
opens anywhere without network access. matplotlib is imported only when a figure
is rendered, with the Agg backend.
"""

from __future__ import annotations

import base64
import html
import io
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

__all__ = ["ReportWarning", "Section", "esc", "figure", "fmt", "table"]


@dataclass(frozen=True)
class ReportWarning:
    """One line of the report's warnings list; ``source`` names the stage."""

    source: str
    text: str


@dataclass(frozen=True)
class Section:
    """A titled block of the report: ``body`` is HTML, ``warnings`` go to the top."""

    title: str
    body: str
    warnings: tuple[ReportWarning, ...] = ()
    anchor: str = ""
    figures: int = field(default=0)


def esc(x: object) -> str:
    """HTML-escaped ``str(x)``."""
    return html.escape(str(x), quote=True)


def fmt(x: object, digits: int = 6) -> str:
    """A readable number: ``digits`` significant digits, ``-`` for None."""
    if x is None:
        return "-"
    if isinstance(x, bool):
        return "yes" if x else "no"
    if isinstance(x, int):
        return str(x)
    if isinstance(x, float):
        if not math.isfinite(x):
            return str(x)
        return f"{x:.{digits}g}"
    return str(x)


def table(header: Sequence[str], rows: Iterable[Sequence[object]], *, cls: str = "") -> str:
    """An HTML table; cells are escaped (numbers through :func:`fmt`).

    A cell that is a ``(text, css_class)`` tuple gets that class (``"bad"``, ``"ok"``).
    """
    out = [f'<table class="{esc(cls)}">' if cls else "<table>", "<thead><tr>"]
    out += [f"<th>{esc(h)}</th>" for h in header]
    out.append("</tr></thead><tbody>")
    for row in rows:
        out.append("<tr>")
        for cell in row:
            if isinstance(cell, tuple):
                text, klass = cell
                out.append(f'<td class="{esc(klass)}">{esc(fmt(text))}</td>')
            else:
                out.append(f"<td>{esc(fmt(cell))}</td>")
        out.append("</tr>")
    out.append("</tbody></table>")
    return "".join(out)


def figure(fig, caption: str = "", *, dpi: int = 110) -> str:
    """Render a matplotlib figure to an embedded PNG ``<figure>`` and close it."""
    import matplotlib.pyplot as plt

    buf = io.BytesIO()
    try:
        # a figure with a layout engine is laid out already; "tight" would draw it twice
        tight = None if fig.get_layout_engine() is not None else "tight"
        fig.savefig(buf, format="png", dpi=dpi, bbox_inches=tight)
    finally:
        plt.close(fig)
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    alt = esc(caption or "figure")
    return f'<figure><img alt="{alt}" src="data:image/png;base64,{data}">{cap}</figure>'


def new_figure(nrows: int = 1, ncols: int = 1, *, size=(6.4, 3.6)):
    """A matplotlib figure and axes on the Agg canvas (no display needed)."""
    import matplotlib

    matplotlib.use("Agg", force=False)
    import matplotlib.pyplot as plt

    return plt.subplots(nrows, ncols, figsize=size, squeeze=False, layout="constrained")


CSS = """
body{font-family:system-ui,-apple-system,Segoe UI,Roboto,sans-serif;margin:2em auto;
max-width:72em;padding:0 1em;color:#1a1a1a;line-height:1.4}
h1{font-size:1.6em;margin-bottom:.2em} h2{border-bottom:1px solid #ccc;margin-top:2em}
table{border-collapse:collapse;margin:.6em 0;font-size:.92em}
th,td{border:1px solid #ccc;padding:.2em .6em;text-align:right}
th{background:#f2f2f2} td:first-child,th:first-child{text-align:left}
td.bad{background:#fde2e1;color:#8a1111} td.ok{background:#e3f5e1}
td.note{background:#fff5d6}
.warnings li{margin:.2em 0} .warnings{background:#fff5d6;border:1px solid #e8cf7a;
padding:.6em 1.6em} .muted{color:#666;font-size:.9em}
figure{margin:1em 0} figure img{max-width:100%;height:auto}
figcaption{color:#444;font-size:.9em} nav a{margin-right:1em}
pre{background:#f7f7f7;padding:.6em;overflow-x:auto;font-size:.85em}
"""

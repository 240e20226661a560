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
    """Render a matplotlib figure to an embedded PNG ``<figure>``.

    The figure is drawn once, with the margins :func:`new_figure` set (no layout
    engine: constrained layout measured every text twice and took 40 % of the
    report's drawing time)."""
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi)
    if CHECK_LAYOUT:
        problems = layout_problems(fig)
        if problems:
            raise AssertionError(f"figure {caption!r}: " + "; ".join(problems))
    if getattr(fig.canvas, "manager", None) is not None:  # a pyplot figure
        import matplotlib.pyplot as plt

        plt.close(fig)
    fig.clear()
    data = base64.b64encode(buf.getvalue()).decode("ascii")
    cap = f"<figcaption>{esc(caption)}</figcaption>" if caption else ""
    alt = esc(caption or "figure")
    return f'<figure><img alt="{alt}" src="data:image/png;base64,{data}">{cap}</figure>'


#: Check every figure with :func:`layout_problems` as it is rendered (tests set it).
CHECK_LAYOUT = False


def layout_problems(fig, tol_px: float = 1.0) -> list[str]:
    """What is wrong with the layout of a figure: axes whose ticks, labels, titles or
    legends leave the canvas, figure texts that leave it, and axes that run into a
    neighbouring axes (twin axes, which share their place, count as one)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    if not isinstance(fig.canvas, FigureCanvasAgg):
        FigureCanvasAgg(fig)
    r = fig.canvas.get_renderer()
    fig.draw(r)
    box = fig.bbox
    items = []
    groups: dict = {}
    for ax in fig.axes:  # twins share their position
        key = tuple(round(v, 6) for v in ax.get_position().bounds)
        groups.setdefault(key, []).append(ax)
    for axs in groups.values():
        bbs = [a.get_tightbbox(r) for a in axs]
        ext = (min(b.x0 for b in bbs), min(b.y0 for b in bbs))
        ext += (max(b.x1 for b in bbs), max(b.y1 for b in bbs))
        names = [a.get_title() or a.get_ylabel() for a in axs]
        name = next((n for n in names if n), axs[0].get_label())
        items.append((f"axes {name!r}", ext, True))
    for t in fig.texts:
        if t.get_visible() and t.get_text().strip():
            b = t.get_window_extent(r)
            items.append((f"text {t.get_text()!r}", (b.x0, b.y0, b.x1, b.y1), False))
    out = []
    for name, (x0, y0, x1, y1), _ in items:
        if (
            x0 < box.x0 - tol_px
            or y0 < box.y0 - tol_px
            or x1 > box.x1 + tol_px
            or y1 > box.y1 + tol_px
        ):
            out.append(
                f"{name} leaves the canvas: x {x0:.0f}..{x1:.0f}, y {y0:.0f}..{y1:.0f} px "
                f"of {box.width:.0f} x {box.height:.0f}"
            )
    axes = [(n, e) for n, e, is_axes in items if is_axes]
    for i, (na, a) in enumerate(axes):
        for nb, b in axes[i + 1 :]:
            w = min(a[2], b[2]) - max(a[0], b[0])
            h = min(a[3], b[3]) - max(a[1], b[1])
            if w > tol_px and h > tol_px:
                out.append(f"{na} and {nb} overlap by {w:.0f} x {h:.0f} px")
    return out


#: Margins of report figures (inches): left (tick labels and the y label), right, bottom
#: (tick labels and the x label), top (the title), and the gaps between axes across
#: and down (the next axes' y labels; x label plus title).
MARGINS_IN = {"left": 0.8, "right": 0.25, "bottom": 0.55, "top": 0.35, "wgap": 0.85, "hgap": 0.8}


def new_figure(nrows: int = 1, ncols: int = 1, *, size=(6.4, 3.6), **margins_in: float):
    """A matplotlib figure and its axes (shape ``(nrows, ncols)``), not registered with
    pyplot (no display, no global state: safe to draw from a worker thread).

    Margins are fixed in inches (:data:`MARGINS_IN`, override any by keyword, e.g.
    ``right=0.8`` for a twin y axis), so a figure's text sits the same way at any size;
    ``tests/test_report_figures.py`` checks that no text leaves the canvas or runs into
    a neighbouring axes.
    """
    from matplotlib.figure import Figure

    unknown = set(margins_in) - set(MARGINS_IN)
    if unknown:
        raise TypeError(f"new_figure: unknown margins {sorted(unknown)}; known: {list(MARGINS_IN)}")
    m = MARGINS_IN | margins_in
    w, h = size
    fig = Figure(figsize=size)
    axes_w = (w - m["left"] - m["right"] - (ncols - 1) * m["wgap"]) / ncols
    axes_h = (h - m["bottom"] - m["top"] - (nrows - 1) * m["hgap"]) / nrows
    fig.subplots_adjust(
        left=m["left"] / w,
        right=1 - m["right"] / w,
        bottom=m["bottom"] / h,
        top=1 - m["top"] / h,
        wspace=m["wgap"] / axes_w,
        hspace=m["hgap"] / axes_h,
    )
    return fig, fig.subplots(nrows, ncols, squeeze=False)


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

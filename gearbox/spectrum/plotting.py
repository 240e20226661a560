"""Figures of order spectra, waterfalls and Campbell diagrams (matplotlib).

Every function takes an optional ``ax`` and returns the axes it drew on; none calls
``show()``. With no ``ax`` a new figure is made with the Agg backend's canvas (no
display needed).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .campbell import CampbellDiagram, Crossing, ExcitationOrder, OrderCuts
from .orders import OrderSpectrum
from .waterfall import Waterfall

__all__ = ["plot_campbell", "plot_order_cuts", "plot_order_spectrum", "plot_waterfall"]

_SOURCE_STYLE = {
    "mesh": {"color": "tab:blue", "linestyle": "-"},
    "engine": {"color": "tab:orange", "linestyle": "--"},
    "engine-half": {"color": "tab:gray", "linestyle": ":"},
    "propeller": {"color": "tab:green", "linestyle": "-."},
    "eccentricity": {"color": "tab:purple", "linestyle": (0, (5, 1, 1, 1))},
    "pitch": {"color": "tab:brown", "linestyle": (0, (1, 2))},
}


def _new_ax():
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(7.0, 4.0), layout="constrained")
    FigureCanvasAgg(fig)
    return fig.add_subplot()


def _label(name: str, unit: str) -> str:
    text = name or "amplitude"
    return f"{text} ({unit})" if unit else text


def plot_order_spectrum(
    spectrum: OrderSpectrum,
    ax=None,
    *,
    max_order: float | None = None,
    style: str = "stem",
    excitations: Sequence[ExcitationOrder] = (),
    include_mean: bool = False,
    log: bool = False,
):
    """Stem (or bar) plot of peak amplitude against order.

    ``excitations`` are marked by vertical lines with their labels;
    ``include_mean`` keeps the order-0 bin; ``log`` uses a log amplitude axis.
    """
    ax = ax if ax is not None else _new_ax()
    o, a = spectrum.orders, spectrum.amplitudes
    keep = np.ones(o.shape, bool) if include_mean else o > 0
    if max_order is not None:
        keep &= o <= max_order
    o, a = o[keep], a[keep]
    floor = 1e-3 * float(a.max()) if a.size else 0.0
    if style == "bar":
        ax.bar(o, a, width=0.8 * spectrum.resolution, color="tab:blue")
    else:
        # Stems for every bin, markers only above 1e-3 of the largest (a record
        # of whole periods leaves most bins at round-off).
        # the stems' segments as one plain array: vlines makes a masked array per stem
        # (60 ms for a spectrum's 960 bins); one NaN-broken line would be simplified
        # into a base line along zero
        from matplotlib.collections import LineCollection

        seg = np.zeros((o.size, 2, 2))
        seg[:, :, 0] = o[:, None]
        seg[:, 1, 1] = a
        ax.add_collection(LineCollection(seg, lw=0.8, color="tab:blue"))
        big = a > floor
        ax.plot(o[big], a[big], "o", ms=3, color="tab:blue")
    span = float(o[-1] - o[0]) if o.size > 1 else 1.0
    last = -np.inf
    for e in sorted(excitations, key=lambda e: e.order):
        if o.size and o[0] <= e.order <= o[-1]:
            ax.axvline(e.order, lw=0.7, alpha=0.6, **_SOURCE_STYLE.get(e.source, {}))
            if e.order - last > 0.025 * span:  # skip labels that would overlap
                ax.annotate(
                    e.label,
                    (e.order, 1.0),
                    xycoords=("data", "axes fraction"),
                    rotation=90,
                    va="top",
                    ha="right",
                    fontsize=7,
                )
                last = e.order
    if log:
        ax.set_yscale("log")
    ax.set_xlabel("order (cycles per pinion revolution)")
    ax.set_ylabel(f"peak {_label(spectrum.name, spectrum.unit)}")
    ax.set_title(
        f"{spectrum.name or 'signal'}: {spectrum.revs:g} rev at {spectrum.mean_speed_rpm:.0f} rpm, "
        f"{spectrum.window} window",
        fontsize=9,
    )
    return ax


def plot_waterfall(
    wf: Waterfall,
    ax=None,
    *,
    kind: str = "map",
    axis: str | None = None,
    max_bin: float | None = None,
    db: bool = False,
    excitations: Sequence[ExcitationOrder] = (),
    offset: float | None = None,
    cells: int | None = 300,
):
    """Waterfall as a colour map (``kind='map'``) or stacked lines (``'lines'``).

    ``axis``: ``order`` or ``frequency`` (default: the waterfall's own axis; an
    order waterfall is shown against frequency by mapping each speed's orders to
    Hz). ``max_bin`` limits the horizontal axis (orders or Hz); ``db`` plots
    20 log10(amplitude / max); ``excitations`` are drawn as order lines (on a map
    against order, as marks along its top edge: a line there would cover the
    spectrum's own line at that order); ``offset`` is the vertical step between
    lines (default: the largest amplitude). ``cells``: on a map with more bins
    across than that, each row is shown as the largest amplitude in each of
    ``cells`` equal cells (a peak hold, named in the title), so that a line
    narrower than a pixel keeps its level instead of being lost or blended with
    its neighbours; None draws every bin.
    """
    ax = ax if ax is not None else _new_ax()
    axis = axis or wf.axis
    amps = wf.amplitudes
    if db:
        ref = float(np.nanmax(amps)) or 1.0
        amps = 20.0 * np.log10(np.maximum(amps / ref, 1e-12))
    xs = wf.orders() if axis == "order" else wf.frequencies_hz()
    order_idx = np.argsort(wf.speeds_rpm)
    speeds = wf.speeds_rpm[order_idx]
    xs, amps = xs[order_idx], amps[order_idx]
    if max_bin is not None:
        amps = np.where(xs <= max_bin, amps, np.nan)
    held = False  # the map's peak hold
    if kind == "lines":
        step = offset if offset is not None else float(np.nanmax(np.abs(amps))) or 1.0
        for i in range(speeds.size):
            ax.plot(xs[i], amps[i] + i * step, lw=0.7, color="k")
        ax.set_yticks(np.arange(speeds.size) * step, [f"{s:.0f}" for s in speeds], fontsize=7)
        ax.set_ylabel("speed (rpm), lines offset")
        unit = f" {wf.unit}" if wf.unit else ""
        ax.text(  # the amplitude scale: one offset step
            0.99,
            0.99,
            f"offset between lines: {step:.3g}{unit}",
            transform=ax.transAxes,
            ha="right",
            va="top",
            fontsize=7,
        )
    else:
        # Cell edges along speed: midpoints between speeds.
        if speeds.size > 1:
            mid = 0.5 * (speeds[1:] + speeds[:-1])
            edges = np.r_[
                speeds[0] - (mid[0] - speeds[0]), mid, speeds[-1] + (speeds[-1] - mid[-1])
            ]
        else:
            edges = np.array([speeds[0] - 0.5, speeds[0] + 0.5])
        xe = _bin_edges(xs)
        style = {"cmap": "viridis", "vmin": float(np.nanmin(amps)), "vmax": float(np.nanmax(amps))}
        lo = float(np.min(xe[:, 0]))
        hi = float(np.max(xe[:, -1])) if max_bin is None else float(max_bin)
        across = int(np.max(np.sum(np.isfinite(amps) & (xs >= lo) & (xs <= hi), axis=1)))
        held = cells is not None and across > cells
        if held:
            cell_edges, amps = _peak_hold(xs, amps, lo, hi, cells)
            mesh = ax.pcolormesh(
                cell_edges, edges, np.ma.masked_invalid(amps), shading="flat", **style
            )
        elif axis == wf.axis:  # the same bins in every row: one mesh
            mesh = ax.pcolormesh(xe[0], edges, np.ma.masked_invalid(amps), shading="flat", **style)
        else:
            # One strip per speed: an order waterfall seen against frequency has
            # different bin positions in every row.
            for i in range(speeds.size):
                mesh = ax.pcolormesh(
                    np.vstack([xe[i], xe[i]]),
                    np.array([[edges[i]] * xe.shape[1], [edges[i + 1]] * xe.shape[1]]),
                    np.ma.masked_invalid(amps[i : i + 1]),
                    shading="flat",
                    **style,
                )
        ax.figure.colorbar(
            mesh, ax=ax, label=("level (dB re max)" if db else f"peak {wf.unit}".strip())
        )
        ax.set_ylabel("speed (rpm)")
    if max_bin is not None:
        ax.set_xlim(0.0, max_bin)
    for e in excitations:
        if kind == "lines":
            continue
        look = _SOURCE_STYLE.get(e.source, {"color": "w"})
        if axis == "order":  # a mark above the map, clear of the spectrum's line
            ax.plot(
                [e.order],
                [1.0],
                marker="v",
                ms=5,
                color=look["color"],
                transform=ax.get_xaxis_transform(),
                clip_on=False,
            )
        else:
            ax.plot(e.order * speeds / 60.0, speeds, lw=0.8, **look)
    ax.set_xlabel("order (cycles per pinion revolution)" if axis == "order" else "frequency (Hz)")
    title = f"{wf.name or 'signal'} waterfall, {wf.window} window"
    if held:
        unit = "order" if axis == "order" else "Hz"
        title += f", peak per {(hi - lo) / cells:.2g} {unit}"
    ax.set_title(title, fontsize=9)
    return ax


def _peak_hold(xs: np.ndarray, amps: np.ndarray, lo: float, hi: float, cells: int):
    """Each row's largest amplitude in each of ``cells`` equal cells from ``lo`` to
    ``hi``: (cell edges, shape (cells + 1,); amplitudes, shape (n_rows, cells), NaN
    where a cell holds no bin)."""
    width = (hi - lo) / cells
    out = np.full((xs.shape[0], cells), np.nan)
    for i in range(xs.shape[0]):
        keep = np.isfinite(amps[i]) & (xs[i] >= lo) & (xs[i] <= hi)
        idx = np.minimum(((xs[i][keep] - lo) / width).astype(int), cells - 1)
        np.fmax.at(out[i], idx, amps[i][keep])
    return lo + width * np.arange(cells + 1), out


def _bin_edges(xs: np.ndarray) -> np.ndarray:
    """Cell edges along the bins for each row, shape (n_rows, n_bins + 1)."""
    d = np.diff(xs, axis=1)
    first = xs[:, :1] - 0.5 * d[:, :1]
    last = xs[:, -1:] + 0.5 * d[:, -1:]
    return np.hstack([first, xs[:, :-1] + 0.5 * d, last])


def plot_campbell(
    cd: CampbellDiagram,
    ax=None,
    *,
    max_frequency_hz: float | None = None,
    label_orders: bool = True,
    log: bool = False,
):
    """Campbell diagram: mode frequencies and order lines against speed.

    Crossings are marked with circles, those inside the operating range (the
    shaded band) filled red; the order lines are labelled at their right end, each
    mode at the end where fewer order lines run through its label; the legend sits
    above the axes. ``log`` gives a log frequency axis (modes from tens of Hz to kHz
    on one plot).
    """
    ax = ax if ax is not None else _new_ax()
    n = cd.speeds_rpm
    top = (
        max_frequency_hz
        if max_frequency_hz is not None
        else 1.15 * float(cd.mode_frequencies_hz.max())
    )
    if cd.operating_range_rpm is not None:
        ax.axvspan(
            *cd.operating_range_rpm, color="tab:red", alpha=0.08, lw=0, label="operating range"
        )
    ends: list[tuple[float, float, str]] = []
    lines = []  # the order lines, for the mode labels to keep clear of
    for e in cd.excitations:
        f = e.frequency_hz(n)
        ax.plot(n, f, lw=0.8, **_SOURCE_STYLE.get(e.source, {"color": "k"}))
        lines.append(f)
        if label_orders:
            inside = np.flatnonzero(f <= top)
            if inside.size:
                i = inside[-1]
                ends.append((float(n[i]), float(f[i]), e.label))
    # Label each mode at its left (else right) end, where no order line runs through the
    # label if either end is clear, then each order line at its end, inside the axes,
    # skipping labels that would overlap one already placed.
    span = (float(n[0]), float(n[-1]))
    positive = cd.mode_frequencies_hz[cd.mode_frequencies_hz > 0]
    bottom = 0.5 * float(positive.min()) if log and positive.size else 1.0

    def frac(y: float) -> float:  # height in axes fractions
        return float(np.log(max(y, bottom) / bottom) / np.log(top / bottom)) if log else y / top

    boxes: list[tuple[float, float, float, float]] = []
    for j, name in enumerate(cd.mode_names):
        f = cd.mode_frequencies_hz[j]
        ax.plot(n, f, lw=1.6, color="k")
        free = []
        for x, y, ha in ((n[0], f[0], "left"), (n[-1], f[-1], "right")):
            if not 0 < y <= top:
                continue
            box = _text_box(ax, name, 7, (float(x), float(y)), span, frac, ha, "bottom")
            if box[3] <= 1.0 and not any(_overlap(box, b) for b in boxes):
                free.append((_crossed(box, n, lines, span, frac), x, y, ha, box))
        if free:
            _, x, y, ha, box = min(free, key=lambda c: c[0])  # the left one on a tie
            ax.annotate(name, (x, y), fontsize=7, ha=ha, va="bottom")
            boxes.append(box)
    for x_end, y_end, label in ends:
        at_top = y_end >= 0.97 * top
        va = "top" if at_top else "bottom"
        ha = "right"
        box = _text_box(ax, label, 6, (x_end, y_end), span, frac, ha, va)
        if box[0] < 0:  # a line that leaves through the top near the left edge
            ha = "left"
            box = _text_box(ax, label, 6, (x_end, y_end), span, frac, ha, va)
        if not any(_overlap(box, b) for b in boxes):
            ax.annotate(label, (x_end, y_end), fontsize=6, ha=ha, va=va)
            boxes.append(box)
    shown = [c for c in cd.crossings if c.frequency_hz <= top]
    styles = (
        (False, {"mfc": "none", "mec": "k", "label": "crossing"}),
        (True, {"color": "tab:red", "label": "crossing in operating range"}),
    )
    for risk, style in styles:
        pts = [(c.speed_rpm, c.frequency_hz) for c in shown if c.in_operating_range == risk]
        if pts:
            ax.plot(*np.array(pts).T, "o", ms=5, **style)
    ax.set_xlim(n[0], n[-1])
    if log:
        ax.set_yscale("log")
        ax.set_ylim(bottom, top)
    else:
        ax.set_ylim(0.0, top)
    ax.set_xlabel("pinion (engine) speed (rpm)")
    ax.set_ylabel("frequency (Hz)")
    # above the axes, clear of the curves and their labels (inside, "best" had put it
    # over a mode's label at the top right)
    ax.legend(loc="lower left", bbox_to_anchor=(0.0, 1.0), ncol=2, fontsize=7, frameon=False)
    return ax


def plot_order_cuts(
    cuts: OrderCuts,
    name: str,
    ax=None,
    *,
    relative: bool = False,
    crossings: Sequence[Crossing] = (),
    floor: float = 1e-3,
):
    """Order cuts: each excitation order's amplitude of channel ``name`` against speed.

    One line per order (dashes by source, as in :func:`plot_campbell`), log
    amplitude axis from ``floor`` times the largest value; ``relative`` plots the
    amplitudes over the channel's mean load in %. ``crossings`` with a response are
    marked (red circles) at their speed and response.
    """
    ax = ax if ax is not None else _new_ax()
    amps = cuts.fraction(name) * 100.0 if relative else cuts.amplitudes[name]
    top = float(np.max(amps)) if amps.size else 1.0
    top = top if top > 0 else 1.0
    for k, e in enumerate(cuts.excitations):
        y = amps[k]
        if not np.any(y > floor * top):
            continue
        dash = _SOURCE_STYLE.get(e.source, {}).get("linestyle", "-")
        ax.plot(
            cuts.speeds_rpm,
            np.maximum(y, floor * top),
            lw=1.0,
            color=f"C{k % 10}",
            linestyle=dash,
            label=e.label,
        )
    for c in crossings:
        if not c.response or name not in c.response:
            continue
        v = c.response[name]
        if relative:
            v = 100.0 * c.response[name.rsplit("_", 1)[0] + "_fraction"]
        if v > floor * top:
            ax.plot(c.speed_rpm, v, "o", ms=4, mfc="none", mec="tab:red", mew=1.0)
    ax.set_yscale("log")
    ax.minorticks_off()  # a log axis's minor ticks cost more to draw than the lines
    ax.set_ylim(floor * top, 2.0 * top)
    ax.set_xlim(float(cuts.speeds_rpm[0]), float(cuts.speeds_rpm[-1]))
    ax.set_xlabel("speed (rpm)")
    unit = "% of mean" if relative else cuts.units.get(name, "")
    ax.set_ylabel(_label(name, unit))
    ax.grid(True, which="major", alpha=0.3)
    ax.legend(fontsize=6, ncol=2, loc="lower right")
    return ax


def _text_box(ax, text, fontsize, xy, span, frac, ha, va):
    """The box (x0, y0, x1, y1) in axes fractions that ``text`` at the data point
    ``xy`` takes (``frac``: a height in axes fractions), its size estimated from the
    font size and the axes' size in inches (0.6 em per character, 1.2 em high), for
    labels that must not overlap."""
    w_in, h_in = ax.get_position().size * ax.figure.get_size_inches()
    w = 0.6 * fontsize / 72 * len(text) / w_in
    h = 1.2 * fontsize / 72 / h_in
    x = (xy[0] - span[0]) / (span[1] - span[0])
    x0 = x - w if ha == "right" else x
    y0 = frac(xy[1]) - h if va == "top" else frac(xy[1])
    return (x0, y0, x0 + w, y0 + h)


def _crossed(box, n, lines, span, frac) -> int:
    """How many of the ``lines`` (frequencies over the speeds ``n``) run through ``box``
    (axes fractions, as :func:`_text_box` gives it)."""
    x = np.linspace(max(box[0], 0.0), min(box[2], 1.0), 24)
    speeds = span[0] + x * (span[1] - span[0])
    count = 0
    for f in lines:
        y = np.array([frac(v) for v in np.interp(speeds, n, f)])
        count += bool(np.any((y >= box[1]) & (y <= box[3])))
    return count


def _overlap(a, b) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]

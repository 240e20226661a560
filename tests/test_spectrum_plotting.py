"""Spectrum figures: drawn on the given axes, returned, and rendered to PNG."""

from __future__ import annotations

import matplotlib

matplotlib.use("Agg")

import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

from gearbox.spectrum import (
    campbell,
    excitation_orders,
    order_spectrum,
    runup_waterfall,
    waterfall,
)
from gearbox.spectrum.plotting import plot_campbell, plot_order_spectrum, plot_waterfall
from gearbox.spectrum.waterfall import Waterfall

EX = excitation_orders(pinion_teeth=29, gear_teeth=45, cylinders=8, blades=3, half_orders=False)


def _png(ax, path):
    ax.figure.savefig(path, dpi=60)
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and len(data) > 2000
    return data


@pytest.fixture
def spectrum():
    rev = np.arange(8 * 512) / 512.0
    x = 2.0 * np.cos(2 * np.pi * 29 * rev) + 0.4 * np.cos(2 * np.pi * 4 * rev) + 100.0
    return order_spectrum(rev * 0.04, x, speed_rpm=1500.0, name="F_mesh", unit="N")


@pytest.mark.parametrize("style", ["stem", "bar"])
def test_order_spectrum_plot(spectrum, style, tmp_path):
    ax = Figure().add_subplot()
    out = plot_order_spectrum(spectrum, ax, max_order=100, style=style, excitations=EX)
    assert out is ax
    assert "order" in ax.get_xlabel() and "(N)" in ax.get_ylabel()
    # The mean (order 0, 100 N) is left out by default: the tallest thing drawn is
    # the 2 N mesh order.
    assert ax.get_ylim()[1] < 10.0
    _png(ax, tmp_path / f"orders_{style}.png")
    assert plot_order_spectrum(spectrum, log=True).figure is not None


def test_order_spectrum_stems_one_per_bin(spectrum):
    """The stems are one segment per bin from zero to its amplitude (drawn as one
    collection), and the axes scale to them as they did with ``vlines``."""
    ax = Figure().add_subplot()
    plot_order_spectrum(spectrum, ax, max_order=50.0)
    keep = (spectrum.orders > 0) & (spectrum.orders <= 50.0)
    segs = np.array(ax.collections[0].get_segments())
    assert segs.shape == (keep.sum(), 2, 2)
    np.testing.assert_array_equal(segs[:, 0, 0], spectrum.orders[keep])
    np.testing.assert_array_equal(segs[:, 1, 0], spectrum.orders[keep])
    np.testing.assert_array_equal(segs[:, 0, 1], 0.0)
    np.testing.assert_array_equal(segs[:, 1, 1], spectrum.amplitudes[keep])
    ref = Figure().add_subplot()
    ref.vlines(spectrum.orders[keep], 0.0, spectrum.amplitudes[keep])
    assert ax.get_xlim() == pytest.approx(ref.get_xlim())
    assert ax.get_ylim()[1] == pytest.approx(ref.get_ylim()[1], rel=0.05)


def test_waterfall_plots(tmp_path):
    t = np.arange(0.0, 2.0, 1.0 / 8192.0)
    speed = 900.0 + 600.0 * t
    rev = (900.0 * t + 300.0 * t**2) / 60.0
    x = np.cos(2 * np.pi * 29 * rev) + 0.5 * np.sin(2 * np.pi * 310.0 * t)
    wf = runup_waterfall(t, x, speed_rpm=speed, axis="order", block=4.0, samples_per_rev=128)
    for kind in ("map", "lines"):
        for axis in ("order", "frequency"):
            ax = Figure().add_subplot()
            assert (
                plot_waterfall(
                    wf,
                    ax,
                    kind=kind,
                    axis=axis,
                    max_bin=60 if axis == "order" else 1500,
                    excitations=EX,
                )
                is ax
            )
            _png(ax, tmp_path / f"wf_{kind}_{axis}.png")
    ax = plot_waterfall(wf, db=True)
    assert "dB" in ax.figure.axes[-1].get_ylabel()
    spectra = [order_spectrum(t, x, speed_rpm=s, n_periods=15) for s in (600.0, 700.0)]
    ax = plot_waterfall(waterfall(spectra), kind="lines")
    assert len(ax.lines) == 2


def test_waterfall_map_keeps_lines_narrower_than_a_pixel():
    # Whole-period order spectra of 30 revolutions have bins 1/30 order wide: 2880 of
    # them across a map a few hundred pixels wide. Each line must still show at its
    # level (the map's top colour for the largest), not vanish between pixels or blend
    # with the floor around it.
    orders = np.arange(96 * 30 + 1) / 30.0
    amps = np.full((10, orders.size), 1e-6)
    amps[:, 29 * 30] = 1.0  # 0 dB
    amps[:, 58 * 30] = 0.1  # -20 dB
    wf = Waterfall(
        speeds_rpm=np.linspace(1000.0, 3500.0, 10),
        axis="order",
        bins=orders,
        amplitudes=amps,
        unit="N",
        name="F",
        window="rectangular",
    )
    fig = Figure(figsize=(6.0, 4.0), dpi=72)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    plot_waterfall(wf, ax, db=True, max_bin=96.0, excitations=EX)
    assert "peak per" in ax.get_title()
    mesh = ax.collections[0]
    shown = np.ma.filled(mesh.get_array(), np.nan).reshape(10, -1)
    edges = mesh.get_coordinates()[0, :, 0]
    at = lambda order: np.searchsorted(edges, order, side="right") - 1  # noqa: E731
    assert np.allclose(shown[:, at(29.0)], 0.0) and np.allclose(shown[:, at(58.0)], -20.0)
    # ... and on the canvas: the map's top colour fills a column over the map's height
    fig.canvas.draw()
    rgb = np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(float)
    top = 255.0 * np.asarray(matplotlib.colormaps["viridis"](1.0)[:3])
    x0, y0, x1, y1 = ax.get_window_extent().extents
    h = rgb.shape[0]
    inside = rgb[int(h - y1) + 2 : int(h - y0) - 2, int(x0) + 2 : int(x1) - 2]
    column = (np.abs(inside - top).max(axis=-1) < 40.0).mean(axis=0)
    assert column.max() > 0.9
    # the excitation orders are marks above the map, not lines over its columns
    assert all(len(line.get_xdata()) == 1 for line in ax.lines)


def test_campbell_plot_marks_crossings(tmp_path):
    cd = campbell(
        {"shaft": 45.0, "mesh": lambda n: 1300 + 0.1 * n},
        EX,
        (300, 3000),
        operating_range_rpm=(800, 2400),
    )
    ax = Figure().add_subplot()
    assert plot_campbell(cd, ax, max_frequency_hz=1800) is ax
    xy = {line.get_label(): line.get_xydata() for line in ax.lines}
    shown = [c for c in cd.crossings if c.frequency_hz <= 1800]
    risk = np.array([(c.speed_rpm, c.frequency_hz) for c in shown if c.in_operating_range])
    safe = np.array([(c.speed_rpm, c.frequency_hz) for c in shown if not c.in_operating_range])
    np.testing.assert_allclose(xy["crossing in operating range"], risk)
    np.testing.assert_allclose(xy["crossing"], safe)
    _png(ax, tmp_path / "campbell.png")
    ax = plot_campbell(cd, log=True)
    assert ax.get_yscale() == "log" and ax.get_ylim()[0] == pytest.approx(22.5)


@pytest.mark.parametrize("log", [False, True])
def test_campbell_labels_do_not_overlap_and_stay_inside(log):
    """Two modes close together and many order lines ending near one another: the
    labels drawn (extents from the renderer, not the estimate that placed them) overlap
    neither each other nor the axes' border, and every mode is named once."""
    cd = campbell(
        {"shaft 1": 51.0, "shaft 2": 86.0, "mesh mode": lambda n: 1600 + 0.1 * n},
        EX,
        (1000, 3500),
        operating_range_rpm=(1000, 3500),
    )
    fig = Figure(figsize=(5.5, 4.4))
    ax = fig.add_subplot()
    plot_campbell(cd, ax, log=log)
    renderer = FigureCanvasAgg(fig).get_renderer()
    frame = ax.get_window_extent(renderer)
    texts = [t for t in ax.texts if t.get_text()]
    boxes = [t.get_window_extent(renderer) for t in texts]
    assert len(texts) >= 6
    for t, b in zip(texts, boxes, strict=True):
        assert frame.x0 - 1 <= b.x0 and b.x1 <= frame.x1 + 1, t.get_text()
        assert frame.y0 - 1 <= b.y0 and b.y1 <= frame.y1 + 1, t.get_text()
    for i in range(len(boxes)):
        for j in range(i):
            assert not boxes[i].overlaps(boxes[j]), (texts[i].get_text(), texts[j].get_text())
    names = [t.get_text() for t in texts]
    assert all(names.count(m) == 1 for m in cd.mode_names), names


def test_a_mode_label_keeps_clear_of_the_order_lines():
    """The mesh mode (1700 Hz at 1000 rpm) is crossed by the third mesh order at 1172
    rpm, so a label at its left end would lie on that line: it goes to the right end,
    where none runs."""
    cd = campbell({"shaft": 51.0, "mesh mode": lambda n: 1600 + 0.1 * n}, EX, (1000, 3500))
    fig = Figure(figsize=(6.4, 3.6))
    ax = fig.add_subplot()
    plot_campbell(cd, ax)
    at = {t.get_text(): t for t in ax.texts}
    assert at["mesh mode"].xy[0] == 3500 and at["mesh mode"].get_ha() == "right"
    # the label drawn: no order line passes through its box (renderer's extent)
    renderer = FigureCanvasAgg(fig).get_renderer()
    box = at["mesh mode"].get_window_extent(renderer)
    for e in EX:
        n = np.linspace(1000, 3500, 2001)
        pts = ax.transData.transform(np.column_stack([n, e.frequency_hz(n)]))
        inside = (
            (pts[:, 0] > box.x0)
            & (pts[:, 0] < box.x1)
            & (pts[:, 1] > box.y0)
            & (pts[:, 1] < box.y1)
        )
        assert not inside.any(), e.label


def test_spectrum_package_does_not_import_matplotlib():
    # matplotlib only in gearbox.spectrum.plotting (a fresh interpreter: this test
    # module has imported matplotlib itself).
    import subprocess
    import sys

    code = "import sys, gearbox.spectrum; sys.exit('matplotlib' in sys.modules)"
    from pathlib import Path

    root = Path(__file__).resolve().parents[1]  # gearbox importable from here
    assert subprocess.run([sys.executable, "-c", code], cwd=root, check=False).returncode == 0

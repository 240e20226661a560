"""Figures of the loaded TCA in the manner of the paper's Figs. 12-16.

Each function draws on an optional matplotlib ``ax`` and returns it; nothing calls
``show()``. ``results`` is a mapping label -> :class:`~gearbox.ltca.CycleResult`
(e.g. one entry per flank or per scene) and ``t`` the torque index.
"""

from __future__ import annotations

import numpy as np

__all__ = [
    "plot_contact_pattern",
    "plot_hunting_lte",
    "plot_hunting_spectrum",
    "plot_load_sharing",
    "plot_lte",
    "plot_mesh_stiffness",
    "plot_root_stress_face",
    "plot_root_stress_profile",
    "save_figures",
]


def _axes(ax):
    if ax is None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        _, ax = plt.subplots(figsize=(6, 4))
    return ax


def plot_contact_pattern(res, t: int = 0, ax=None, title: str = ""):
    """Contact pattern and pressure (MPa) over the active flank (Figs. 12-13): face
    width (mm) across, profile coordinate (mm) up."""
    ax = _axes(ax)
    p = res.pattern_pressure[t] / 1e6
    f0, f1 = res.face_range
    u0, u1 = res.profile_range
    masked = np.ma.masked_where(p <= 0, p)
    im = ax.imshow(
        masked,
        origin="lower",
        aspect="auto",
        extent=(f0 * 1e3, f1 * 1e3, u0 * 1e3, u1 * 1e3),
        cmap="viridis",
    )
    ax.figure.colorbar(im, ax=ax, label="max contact pressure (MPa)")
    ax.set_xlabel("face width (mm)")
    ax.set_ylabel("profile (mm)")
    frac = res.pattern_area_fraction[t]
    ax.set_title(f"{title} {res.torque[t]:g} N m: pattern {100 * frac:.0f} % of the flank".strip())
    return ax


def plot_mesh_stiffness(results, t: int = 0, ax=None, tangent: bool = False):
    """Mesh stiffness (MN/m) over one mesh cycle (Fig. 14)."""
    ax = _axes(ax)
    for label, res in results.items():
        k = res.tangent_stiffness[t] if tangent else res.stiffness[t]
        ax.plot(res.fraction, k / 1e6, marker="o", ms=3, label=label)
    ax.set_xlabel("pinion position (mesh cycles)")
    ax.set_ylabel(("tangent" if tangent else "secant") + " mesh stiffness (MN/m)")
    ax.legend()
    return ax


def plot_lte(results, t: int = 0, ax=None):
    """Loaded transmission error along the line of action (um) over one mesh cycle (Fig. 16)."""
    ax = _axes(ax)
    for label, res in results.items():
        ax.plot(res.fraction, res.lte[t] * 1e6, marker="o", ms=3, label=label)
    ax.set_xlabel("pinion position (mesh cycles)")
    ax.set_ylabel("LTE along the line of action (um)")
    ax.legend()
    return ax


def plot_load_sharing(results, t: int = 0, ax=None):
    """Share of the normal load carried by one tooth pair through its engagement."""
    ax = _axes(ax)
    for label, res in results.items():
        x, share = res.tooth_load_share(t)
        ax.plot(x, share, label=label)
    ax.set_xlabel("engagement of one tooth pair (mesh cycles)")
    ax.set_ylabel("load share (-)")
    ax.set_ylim(0, 1.05)
    ax.legend()
    return ax


def plot_root_stress_profile(results, t: int = 0, ax=None):
    """Largest root stress (MPa) of one tooth through its engagement, as its load moves
    along the profile (Fig. 15(a))."""
    ax = _axes(ax)
    for label, res in results.items():
        x, s = res.tooth_root_stress(t)
        ax.plot(x, s[:, 0] / 1e6, label=f"{label} pinion")
        ax.plot(x, s[:, 1] / 1e6, ls="--", label=f"{label} gear")
    ax.set_xlabel("engagement of one tooth (mesh cycles)")
    ax.set_ylabel("root stress (MPa)")
    ax.legend()
    return ax


def plot_root_stress_face(results, t: int = 0, ax=None):
    """Largest root stress (MPa) over the cycle along the face width (Fig. 15(b))."""
    ax = _axes(ax)
    for label, res in results.items():
        S = res.root_stress_face_pinion.shape[1]
        f0, f1 = res.face_range
        y = (f0 + (np.arange(S) + 0.5) * (f1 - f0) / S) * 1e3
        ax.plot(y, res.root_stress_face_pinion[t] / 1e6, label=f"{label} pinion")
        ax.plot(y, res.root_stress_face_gear[t] / 1e6, ls="--", label=f"{label} gear")
    ax.set_xlabel("face width (mm)")
    ax.set_ylabel("root stress (MPa)")
    ax.legend()
    return ax


def save_figures(results, out_dir, t: int = 0, modification_maps=None) -> list:
    """Write the figures of ``results`` (label -> CycleResult) as PNG files; return paths.
    ``modification_maps`` (``LTCAResult.modification_maps``, "<gear>, <flank> flank" ->
    map): where it holds any, ``flank_modifications.png`` with one map per modified gear
    (columns) and flank (rows)."""
    import matplotlib

    matplotlib.use("Agg")
    import io
    from pathlib import Path

    import matplotlib.pyplot as plt

    from ..commands._common import write_atomic

    out = Path(out_dir)
    paths = []

    def save(fig, name):
        buf = io.BytesIO()
        fig.tight_layout()
        fig.savefig(buf, format="png", dpi=110)
        plt.close(fig)
        paths.append(write_atomic(out / name, buf.getvalue()))

    fig, axs = plt.subplots(1, len(results), figsize=(5 * len(results), 4), squeeze=False)
    for ax, (label, res) in zip(axs[0], results.items(), strict=True):
        plot_contact_pattern(res, t, ax=ax, title=label)
    save(fig, "contact_pattern.png")
    for name, fn in (
        ("mesh_stiffness.png", plot_mesh_stiffness),
        ("lte.png", plot_lte),
        ("load_sharing.png", plot_load_sharing),
    ):
        fig, ax = plt.subplots(figsize=(6, 4))
        fn(results, t, ax=ax)
        save(fig, name)
    fig, axs = plt.subplots(1, 2, figsize=(11, 4))
    plot_root_stress_profile(results, t, ax=axs[0])
    plot_root_stress_face(results, t, ax=axs[1])
    save(fig, "root_stress.png")
    if modification_maps:  # one row per flank, one column per modified gear
        rows = list(dict.fromkeys(k.split(", ")[1] for k in modification_maps))
        cols = list(dict.fromkeys(k.split(", ")[0] for k in modification_maps))
        fig, axs = plt.subplots(
            len(rows), len(cols), figsize=(6 * len(cols), 4 * len(rows)), squeeze=False
        )
        for name, m in modification_maps.items():
            gear, flank = name.split(", ")
            plot_modification_map(m, ax=axs[rows.index(flank), cols.index(gear)], title=name)
        save(fig, "flank_modifications.png")
    return paths


def plot_hunting_lte(record, ax=None, revolutions: float = 2.0):
    """Loaded TE (um) against pinion revolutions over the first ``revolutions`` of a
    hunting period (the whole period holds z2 / gcd revolutions of mesh ripple, too
    dense to read), with and without the pitch deviations
    (:class:`gearbox.ltca.pitch.HuntingRecord`)."""
    ax = _axes(ax)
    rev = record.angle / (2 * np.pi)
    top = min(float(revolutions), float(rev[-1]))
    k = rev <= top
    ax.plot(rev[k], record.lte_nominal[k] * 1e6, lw=0.8, color="0.5", label="nominal teeth")
    ax.plot(rev[k], record.lte[k] * 1e6, lw=0.8, color="tab:blue", label="with the deviations")
    ax.set_xlabel("pinion revolutions (from the start of the hunting period)")
    ax.set_ylabel("loaded TE (um)")
    ax.set_xlim(0.0, top)
    ax.legend(loc="upper right", fontsize=8)
    return ax


def plot_tooth_deviations(deviations, ax=None):
    """Each tooth's deviations (um) against its number, pinion and gear
    (:class:`gearbox.ltca.pitch.PitchDeviations`): cumulative pitch F_p, and the
    profile and helix slopes f_H_alpha, f_H_beta and crownings C_alpha, C_beta (less
    the design's) where it has them."""
    ax = _axes(ax)
    form = deviations.form
    shapes = (
        ("profile", "^", "f_H profile"),
        ("helix", "s", "f_H helix"),
        ("profile_crowning", "v", "C profile"),
        ("helix_crowning", "D", "C helix"),
    )
    for member, color in (("pinion", "tab:blue"), ("gear", "tab:orange")):
        fp = getattr(deviations, member)
        i = np.arange(fp.size)
        ax.plot(i, fp * 1e6, "-o", ms=2.5, lw=0.8, color=color, label=f"{member} F_p")
        if form is None:
            continue
        for kind, marker, name in shapes:
            f = getattr(form, f"{member}_{kind}")
            if np.any(f):
                ax.plot(
                    i,
                    f * 1e6,
                    marker,
                    ms=3,
                    ls="none",
                    color=color,
                    alpha=0.6,
                    label=f"{member} {name}",
                )
    ax.axhline(0.0, color="0.6", lw=0.6)
    ax.set_xlabel("tooth (numbered from the reference pair at the start of the record)")
    ax.set_ylabel("deviation (um)")
    ax.legend(loc="upper right", fontsize=7, ncol=2)
    return ax


def plot_flank_traces(traces, axes=None):
    """The measured traces (:class:`gearbox.ltca.pitch.FlankTraces`), one panel per
    member and direction (``axes``: four axes, pinion profile, pinion helix, gear
    profile, gear helix; a new 2 x 2 figure's if None): every tooth's deviation (um)
    against its position (mm), thin, tooth 0 bold; empty panels say "no traces"."""
    if axes is None:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt

        _, grid = plt.subplots(2, 2, figsize=(10, 6))
        axes = grid.ravel()
    names = [("pinion", "profile"), ("pinion", "helix"), ("gear", "profile"), ("gear", "helix")]
    for ax, (member, kind) in zip(axes, names, strict=True):
        t = getattr(traces, f"{member}_{kind}")
        ax.set_title(f"{member} {kind} traces", fontsize=9)
        where = "roll length from the reference circle" if kind == "profile" else "axial position"
        ax.set_xlabel(f"{where} (mm)", fontsize=8)
        ax.set_ylabel("deviation (um)", fontsize=8)
        if t is None:
            ax.text(0.5, 0.5, "no traces", ha="center", va="center", transform=ax.transAxes)
            ax.set_xticks([])
            ax.set_yticks([])
            continue
        x = t.position * 1e3
        for i, d in enumerate(t.deviation):
            ax.plot(x, d * 1e6, lw=1.4 if i == 0 else 0.5, color="k" if i == 0 else "tab:blue")
        ax.axhline(0.0, color="0.6", lw=0.6)
    return axes


def plot_hunting_spectrum(record, ax=None, max_order: float | None = None):
    """Order spectrum of the loaded TE over a hunting period (um, single-sided peak,
    log scale; grey: the nominal teeth's mesh lines), up to ``max_order`` pinion
    orders (default: 2.5 mesh orders)."""
    from matplotlib.collections import LineCollection

    ax = _axes(ax)
    z1 = record.teeth[0]
    top = 2.5 * z1 if max_order is None else max_order
    o, a = record.order_spectrum()
    a0 = record.order_spectrum("lte_nominal")[1]
    keep = (o > 0) & (o <= top)
    o, a, a0 = o[keep], a[keep] * 1e6, a0[keep] * 1e6
    floor = max(float(a.max()) * 1e-4, 1e-6)
    seg = np.zeros((o.size, 2, 2))
    seg[:, :, 0] = o[:, None]
    seg[:, 0, 1] = floor
    seg[:, 1, 1] = np.maximum(a, floor)
    ax.add_collection(LineCollection(seg, lw=0.7, color="tab:blue"))
    mesh = a0 > floor
    ax.plot(o[mesh], a0[mesh], "_", ms=9, color="0.4", label="nominal teeth")
    ax.set_yscale("log")
    ax.set_xlim(0, top)
    ax.set_ylim(floor, 2 * float(a.max()))
    ax.set_xlabel("pinion order")
    ax.set_ylabel("loaded TE amplitude (um)")
    ax.legend(loc="upper right", fontsize=8)
    return ax


def plot_modification_map(flank_map, ax=None, title: str = ""):
    """The material a gear's flank modifications remove (um) over its flank
    (:func:`gearbox.ltca.modification.removal_map`): roll length from the reference
    circle (mm, form circle to tip) against the axial position from the face middle
    (mm), filled contours with a colour bar. Returns the axes."""
    from matplotlib.ticker import MaxNLocator

    ax = _axes(ax)
    w = np.broadcast_to(flank_map["face_m"][:, None], flank_map["roll_m"].shape) * 1e3
    roll = flank_map["roll_m"] * 1e3
    um = flank_map["removal_m"] * 1e6
    lo, hi = float(um.min()), float(um.max())
    if hi - lo < 1e-9:  # a flat map: one level
        lo, hi = lo - 0.5, hi + 0.5
    levels = MaxNLocator(12).tick_values(lo, hi)
    filled = ax.contourf(w, roll, um, levels=levels, cmap="viridis")
    ax.contour(w, roll, um, levels=levels, colors="k", linewidths=0.3)
    bar = ax.figure.colorbar(filled, ax=ax, pad=0.02, fraction=0.06)
    bar.set_label("removal (um)")
    ax.set_xlabel("axial position from the face middle (mm)")
    ax.set_ylabel("roll length from ref. circle (mm)")
    if title:
        ax.set_title(title, fontsize=9)
    return ax

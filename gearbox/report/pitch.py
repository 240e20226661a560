"""Report section of the pitch deviations (and the teeth's slopes, crownings and
measured traces, where the scene sets them): the loaded TE over a hunting period on the drive flank and its order
spectrum, with the largest lines named."""

from __future__ import annotations

import numpy as np

from .html import Section, figure, fmt, new_figure, table

__all__ = ["render_approach", "render_pitch"]


def render_pitch(pr, run) -> Section:
    """Deviations, TE peak-to-peak with and without them, the largest order lines;
    the hunting record and its spectrum."""
    from ..ltca.plot import plot_hunting_lte, plot_hunting_spectrum, plot_tooth_deviations

    rec, dev = pr.record, pr.deviations
    z1, z2 = rec.teeth
    single = [np.diff(np.r_[d, d[0]]) for d in (dev.pinion, dev.gear)]
    rows = [
        ("teeth", z1, z2),
        (
            "cumulative pitch deviation F_p, range (um)",
            *(fmt(1e6 * np.ptp(d), 4) for d in (dev.pinion, dev.gear)),
        ),
        (
            "largest single pitch deviation |f_pt| (um)",
            *(fmt(1e6 * np.abs(f).max(), 4) for f in single),
        ),
        (
            "reference pitch radius (mm)",
            fmt(dev.pinion_radius * 1e3, 5),
            fmt(dev.gear_radius * 1e3, 5),
        ),
    ]
    if dev.form is not None:
        sl = dev.form
        rows += [
            (
                "profile slope f_H_alpha, largest |value| (um)",
                *(fmt(1e6 * np.abs(a).max(), 4) for a in (sl.pinion_profile, sl.gear_profile)),
            ),
            (
                "helix slope f_H_beta, largest |value| (um)",
                *(fmt(1e6 * np.abs(a).max(), 4) for a in (sl.pinion_helix, sl.gear_helix)),
            ),
            (
                "profile evaluation length L_alpha (mm)",
                *(fmt(x * 1e3, 4) for x in sl.profile_length),
            ),
            ("helix evaluation length L_beta (mm)", *(fmt(x * 1e3, 4) for x in sl.helix_length)),
        ]
        if sl.crowned:
            rows += [
                (
                    f"{kind} crowning less the design's, {sym}, largest |value| (um)",
                    *(
                        fmt(1e6 * np.abs(getattr(sl, f"{m}_{kind}_crowning")).max(), 4)
                        for m in ("pinion", "gear")
                    ),
                )
                for kind, sym in (("profile", "C_alpha"), ("helix", "C_beta"))
            ]
            rows += [
                (
                    f"{kind} evaluation range's middle, the crownings' vertex (mm)",
                    *(fmt(x * 1e3, 4) for x in getattr(sl, f"{kind}_centre")),
                )
                for kind in ("profile", "helix")
            ]
    if dev.traces is not None:
        for kind in ("profile", "helix"):
            got = [getattr(dev.traces, f"{m}_{kind}") for m in ("pinion", "gear")]
            if all(t is None for t in got):
                continue
            rows += [
                (
                    f"measured {kind} traces: positions (mm)",
                    *(
                        "-"
                        if t is None
                        else f"{fmt(t.position[0] * 1e3, 4)} .. {fmt(t.position[-1] * 1e3, 4)}"
                        for t in got
                    ),
                ),
                (
                    f"measured {kind} traces: largest |deviation| (um)",
                    *("-" if t is None else fmt(1e6 * np.abs(t.deviation).max(), 4) for t in got),
                ),
            ]
    summary = [
        ("flank", pr.flank),
        ("pinion torque (N m)", fmt(rec.torque)),
        ("method", rec.method),
        (
            "hunting period (mesh cycles / pinion revolutions)",
            f"{rec.cycles} / {fmt(rec.pinion_revolutions)}",
        ),
        ("loaded TE peak-to-peak, nominal teeth (um)", fmt(1e6 * np.ptp(rec.lte_nominal), 4)),
        ("loaded TE peak-to-peak, with the deviations (um)", fmt(1e6 * np.ptp(rec.lte), 4)),
    ]
    if rec.pair_load is not None:
        pin, gear = rec.tooth_loads()
        f0 = rec.tooth_load_nominal
        (r1, r2), (n1, n2) = rec.root_stress(), rec.root_stress_nominal()
        summary += [
            (
                "largest tooth normal load, pinion / gear (N; nominal teeth)",
                f"{fmt(pin.max(), 5)} / {fmt(gear.max(), 5)} ({fmt(f0, 5)})",
            ),
            ("tooth load factor, pinion / gear", f"{pin.max() / f0:.3f} / {gear.max() / f0:.3f}"),
            (
                "largest root stress, pinion / gear (MPa; nominal teeth)",
                f"{r1 / 1e6:.1f} / {r2 / 1e6:.1f} ({n1 / 1e6:.1f} / {n2 / 1e6:.1f})",
            ),
        ]
    lines = [(fmt(x["order"], 5), x["kind"], fmt(x["amplitude_m"] * 1e6, 4)) for x in pr.lines()]
    fig, ax = new_figure(3, 1, size=(10, 9.0))
    plot_tooth_deviations(dev, ax[0, 0])
    plot_hunting_lte(rec, ax[1, 0])
    plot_hunting_spectrum(rec, ax[2, 0])
    body = (
        table(["quantity", "value"], summary)
        + table(["deviations", "pinion", "gear"], rows)
        + "<p>Largest lines of the loaded TE (pinion orders; single-sided peak amplitude, "
        "rectangular window over one hunting period):</p>"
        + table(["order", "kind", "amplitude (um)"], lines)
        + figure(
            fig,
            "Each tooth's deviations; the loaded transmission error over the first two "
            "pinion revolutions, and the order spectrum of the whole hunting period",
        )
        + '<p class="muted">Teeth numbered from the reference pair at the start of the '
        "record, in the order they enter the mesh (docs/ltca.md, sections Pitch deviations "
        "and Form deviations).</p>"
    )
    if dev.traces is not None:
        from ..ltca.plot import plot_flank_traces

        fig, ax = new_figure(2, 2, size=(10, 6.0))
        plot_flank_traces(dev.traces, ax.ravel())
        body += figure(
            fig,
            "Measured traces of every tooth (tooth 0 bold), as given; the record takes "
            "each less its value at the reference point (docs/ltca.md, Measured traces)",
        )
    return Section("Pitch deviations", body, anchor="pitch")


def render_approach(result, run) -> Section:
    """What the dynamics take of the tooth deviations beyond the mesh table's weights:
    the exact records at the torque levels (their TE change per level), or the measured
    traces' turns."""
    d = result.to_dict()
    rows = [("method", d["method"])]
    if "torque_levels_Nm" in d:
        rows.append(("torque levels (N m)", ", ".join(fmt(t, 4) for t in d["torque_levels_Nm"])))
        rows.append(("positions per mesh cycle", d["positions"]))
    for t, pp in zip(
        d.get("torque_levels_Nm", ()), d.get("te_change_peak_to_peak_m", ()), strict=False
    ):
        rows.append((f"exact TE change at {fmt(t, 4)} N m, peak-to-peak (um)", fmt(pp * 1e6, 4)))
    body = table(["quantity", "value"], rows) + (
        "<p class=\"muted\">The drive flank's approach in the dynamics is minus these records' "
        "TE change, linear in torque between the levels (docs/drivetrain.md section 3c).</p>"
        if result.levels is not None
        else '<p class="muted">The measured traces enter the drive flank\'s approach through '
        "these turns, linear in torque between the levels (docs/drivetrain.md section 3c).</p>"
    )
    return Section("Tooth deviations in the dynamics", body, anchor="approach")

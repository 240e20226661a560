"""Report sections of the drivetrain: parameters, modes, time traces, spectra,
waterfall and Campbell diagram, with their warnings (contact loss, resonances)."""

from __future__ import annotations

import dataclasses
import math

import numpy as np

from ..drivetrain.simulate import LAW_SPAN, law_reach
from ..errors import InputError
from .html import ReportWarning, Section, esc, figure, fmt, new_figure, table

__all__ = [
    "render_campbell",
    "render_dynamics",
    "render_fmu",
    "render_spectra",
    "render_waterfall",
]

_RPM = 30.0 / math.pi
#: At most this many crossings are listed one by one in the warnings.
MAX_LISTED = 12


def _contact_warnings(source: str, metrics, where: str) -> list[ReportWarning]:
    out = []
    loss = metrics.get("contact_loss_fraction", 0.0)
    coast = metrics.get("coast_contact_fraction", 0.0)
    if loss and loss > 0:
        out.append(
            ReportWarning(
                source,
                f"contact loss {where}: the drive flank is open during "
                f"{100 * loss:.2f} % of the record",
            )
        )
    if coast and coast > 0:
        out.append(
            ReportWarning(
                source,
                f"back-flank impacts {where}: the coast flank carries load "
                f"during {100 * coast:.2f} % of the record",
            )
        )
    return out


def law_span(metrics) -> tuple[float, float]:
    """The loaded TCA's mean tangent stiffness at a run's least and largest mesh force
    over the model's, less 1 (NaN when not recorded)."""
    return (
        float(metrics.get("law_stiffness_at_min_force", math.nan)),
        float(metrics.get("law_stiffness_at_max_force", math.nan)),
    )


def _law_warning(source: str, metrics, where: str, law: str) -> list[ReportWarning]:
    lo, hi = law_span(metrics)
    if law != "tangent" or law_reach(metrics) <= LAW_SPAN:
        return []
    return [
        ReportWarning(
            source,
            f"tangent mesh law {where}: the mesh force runs from "
            f"{metrics['mesh_force_min_N']:.0f} to {metrics['mesh_force_max_N']:.0f} N, "
            f"where the loaded TCA's tangent stiffness reads {100 * lo:+.0f} to "
            f"{100 * hi:+.0f} % of the law's constant one; drivetrain.mesh_law = "
            "'loaded' follows it ('auto' where a run needs it)",
        )
    ]


def _parameters(m) -> list[tuple]:
    rows = [
        ("engine (= pinion) speed (rpm)", m.speed * _RPM),
        ("mean pinion torque (N m)", m.torque),
        ("mesh frequency (Hz)", m.mesh_frequency),
        ("teeth N_1 / N_2", f"{m.pinion_teeth} / {m.gear_teeth}"),
        ("engine inertia (kg m^2)", m.engine_inertia),
        ("pinion inertia (kg m^2)", m.pinion_inertia),
        ("gear inertia (kg m^2)", m.gear_inertia),
        ("propeller inertia incl. water (kg m^2)", m.propeller_inertia),
        ("input shaft / coupling stiffness (N m/rad)", m.input_stiffness),
        ("input shaft damping ratio", m.input_damping_ratio),
        ("output shaft stiffness (N m/rad)", m.output_stiffness),
        ("output shaft damping ratio", m.output_damping_ratio),
        ("mean drive-flank mesh stiffness (N/m)", m.drive.mean_stiffness),
        (
            "mesh law",
            "loaded: force against deflection through every torque level of the tables"
            if m.mesh_law == "loaded"
            else "tangent at the mean torque",
        ),
        (
            "drive-flank rotation radii lambda_1 / lambda_2 (mm)",
            f"{fmt(m.drive.lambda1 * 1e3)} / {fmt(m.drive.lambda2 * 1e3)}",
        ),
        ("mesh damping (N s/m)", m.drive.damping),
        (
            "mesh friction coefficient (Coulomb)",
            m.mesh_friction_coefficient if m.mesh_friction_coefficient > 0 else "0 (none)",
        ),
        (
            "eccentricity of pinion / gear (um, at deg)",
            f"{fmt(m.pinion_eccentricity * 1e6)} at {fmt(math.degrees(m.pinion_eccentricity_angle))}"
            f" / {fmt(m.gear_eccentricity * 1e6)} at {fmt(math.degrees(m.gear_eccentricity_angle))}"
            if m.has_eccentricity
            else "0 (none)",
        ),
        (
            "pitch deviations: the drive flank's approach, peak-to-peak (um)",
            _approach(m.pitch) if getattr(m, "pitch", None) is not None else "none (nominal teeth)",
        ),
        (
            "backlash along the line of action (mm)",
            (m.coast.backlash * 1e3) if m.coast is not None else "no coast flank",
        ),
        ("engine cylinders (4-stroke)", m.engine_cylinders),
        ("firing-order torque ripple / mean", m.firing_ripple),
        ("half-order ripple / mean", m.half_order_ripple),
        ("propeller blades", m.propeller_blades),
        ("blade-pass torque ripple / mean", m.blade_pass_ripple),
        ("bearing translations", m.bearing_dofs),
    ]
    return rows


def _traces(ts, model):
    t = ts.time
    tm = 1.0 / model.mesh_frequency
    rev = 2 * math.pi / model.speed
    fig, ax = new_figure(3, 1, size=(9, 7.5), right=0.8)  # the twin y axis
    last = t >= t[-1] - 2 * rev
    zoom = t >= t[-1] - 4 * tm
    a = ax[0, 0]
    a.plot(t[last], ts["mesh_force_N"][last] / 1e3, lw=0.6)
    a.set(xlabel="time (s)", ylabel="mesh force (kN)", title="last two pinion revolutions")
    a = ax[1, 0]
    a.plot(t[zoom] * 1e3, ts["mesh_force_N"][zoom] / 1e3, label="mesh force (kN)")
    a2 = a.twinx()
    a2.plot(t[zoom] * 1e3, ts["dynamic_transmission_error_m"][zoom] * 1e6, "C1", label="DTE (um)")
    a.set(xlabel="time (ms)", ylabel="mesh force (kN)", title="last four mesh cycles")
    a2.set_ylabel("dynamic transmission error (um)", color="C1")
    a = ax[2, 0]
    for name, lab in (
        ("input_shaft_torque_Nm", "input shaft"),
        ("output_shaft_torque_Nm", "output shaft"),
    ):
        if name in ts.channels:
            a.plot(t[last], ts[name][last], lw=0.8, label=lab)
    a.set(xlabel="time (s)", ylabel="torque (N m)", title="shaft torques")
    a.legend(fontsize=7)
    for a in ax[:, 0]:
        a.grid(True, alpha=0.3)
    return fig


#: Share by which the drive's mean torque may differ from ``load.operating_torque_Nm``
#: before the report says so (the scene's two operating torques).
TORQUE_MISMATCH = 0.01


def _torque_warning(op, scene) -> list[ReportWarning]:
    """A warning when the drive runs at another mean torque (drivetrain.engine_power_kW
    at drivetrain.engine_speed_rpm) than load.operating_torque_Nm, which the loaded
    TCA's figures and the pitch deviations' analysis take."""
    try:
        given = float(scene["load"]["operating_torque_Nm"])
    except (KeyError, TypeError):
        return []
    if abs(op.torque_Nm - given) <= TORQUE_MISMATCH * given:
        return []
    return [
        ReportWarning(
            "dynamics",
            f"the drive runs at {op.torque_Nm:.4g} N m (drivetrain.engine_power_kW at "
            f"drivetrain.engine_speed_rpm), the loaded TCA's figures and the pitch "
            f"deviations' analysis at load.operating_torque_Nm = {given:.4g} N m: set "
            "that key to the drive's torque where both should be one operating point",
        )
    ]


def _metric_row(key: str, value):
    """A response metric as the report shows it: the law's stiffness ratios (loaded TCA
    tangent stiffness at the run's least / largest mesh force over the law's, less 1)
    in per cent with what they are, every other metric under its own name."""
    if key.startswith("law_stiffness_at_") and isinstance(value, float):
        where = "least" if key.endswith("min_force") else "largest"
        label = f"loaded TCA stiffness at the {where} mesh force / the law's - 1 (%)"
        return (f"{key}: {label}", f"{100 * value:+.1f}" if math.isfinite(value) else "")
    return (key, value)


def render_dynamics(op, run) -> Section:
    """Drivetrain parameters, linear modes, response metrics and time traces."""
    m, ts = op.model, op.series
    warnings = []
    if not ts.success:
        f = ts.failure
        msg = f"{f.kind} at t = {f.time:.4g} s: {f.message}" if f is not None else ts.status
        warnings.append(ReportWarning("dynamics", f"the simulation did not finish: {msg}"))
    warnings += _contact_warnings("dynamics", op.metrics, f"at {op.speed_rpm:.0f} rpm")
    warnings += _law_warning("dynamics", op.metrics, f"at {op.speed_rpm:.0f} rpm", m.mesh_law)
    warnings += _torque_warning(op, run.scene)
    modes_rows = [
        (i, f, d.split(",")[0], 100 * e)
        for i, (f, d, e) in enumerate(
            zip(
                op.modes.frequencies,
                op.modes.descriptions(),
                op.modes.mesh_energy_fraction,
                strict=True,
            )
        )
    ]
    metric_rows = [_metric_row(k, v) for k, v in op.metrics.items()]
    attrs = ts.attrs
    solver_rows = [
        ("solver", attrs.get("solver", "")),
        ("settings", attrs.get("settings", "")),
        ("status", ts.status),
        ("right-hand-side evaluations", ts.nfev),
        ("steps / rejected", f"{ts.steps} / {ts.rejected}"),
        ("integration wall time (s)", ts.wall_time),
        ("compile time (s)", attrs.get("compile_time_s", 0.0)),
        ("settling time simulated first (s)", attrs.get("settle_time_s")),
        ("recorded mesh cycles", attrs.get("mesh_cycles")),
        (
            "settling check: change of mesh-order amplitude between record halves",
            attrs.get("settling_change"),
        ),
    ]
    body = (
        "<h3>Drivetrain parameters (SI)</h3>"
        + table(["parameter", "value"], _parameters(m))
        + f'<p class="muted">Mesh table: {esc(m.meta.get("table_method", ""))}</p>'
        + "<h3>Linear modes about the operating point</h3>"
        + table(["mode", "frequency (Hz)", "kind", "mesh strain energy (%)"], modes_rows)
        + "<h3>Response at the operating point</h3>"
        + '<p class="muted">mesh_force_mesh_order_amplitude_N: the DFT at N_1 times the '
        "nominal pinion speed over the record's time; the order spectra (Spectra section) "
        "take the pinion's angle, which the speed's own fluctuation moves: the two part "
        "where a shaft mode swings the speed (docs/spectrum.md).</p>"
        + table(["quantity", "value"], metric_rows)
        + table(["solver", "value"], solver_rows)
    )
    if ts.time.size > 1:
        body += figure(
            _traces(ts, m),
            f"Time traces at {op.speed_rpm:.0f} rpm, {op.torque_Nm:.0f} N m (settled record)",
        )
    return Section("Drivetrain dynamics", body, tuple(warnings), anchor="dynamics")


def render_spectra(sp, run) -> Section:
    """Order spectra with the excitation orders marked; amplitudes at those orders."""
    from ..spectrum.plotting import plot_order_spectrum

    parts = []
    mesh_order = max((e.order for e in sp.excitations if e.source == "mesh"), default=None)
    top = 1.1 * mesh_order if mesh_order else None
    for name, s in sp.spectra.items():
        fig, ax = new_figure(1, 1, size=(9, 3.4))
        plot_order_spectrum(s, ax[0, 0], max_order=top, excitations=sp.excitations)
        parts.append(
            figure(
                fig,
                f"Order spectrum of {name} ({s.window} window, "
                f"{s.n_periods} period(s) of {fmt(s.period_revs)} rev)",
            )
        )
        rows = []
        lin = getattr(sp, "linear", {}).get(name)
        for e in sp.excitations:
            try:
                a = s.amplitude_at(e.order)
            except Exception:  # an order off the bins of this record or beyond Nyquist
                continue
            row = (e.label, e.order, e.source, a)
            if lin is not None:
                b = lin.get(e.order, 0.0)
                row += (b, 100.0 * (a / b - 1.0) if b > 0 else "")
            rows.append(row)
        head = ["excitation", "order", "source", f"amplitude ({s.unit})"]
        if lin is not None:
            head += [f"linear model ({s.unit})", "simulated / linear - 1 (%)"]
        parts.append(table(head, rows))
    intro = (
        '<p class="muted">Single-sided peak amplitudes against pinion orders (cycles per '
        "pinion revolution), from the pinion angle (order tracking) over whole common "
        "periods of the excitation orders when the record holds one (rectangular "
        "window), else over whole pinion revolutions with a flat-top window. Beside the "
        "simulated amplitudes, where the run has them, the steady response of the model "
        "about the operating point to each order alone (engine and propeller orders on "
        "the linear model, mesh orders by harmonic balance with the time-varying mesh "
        "stiffness): where the two part, the drive runs out of the linear range (contact "
        "loss, impacts) or orders mix.</p>"
    )
    warnings = []
    short = [s for s in sp.spectra.values() if s.window != "rectangular"]
    if short:
        from ..spectrum import common_period_revs

        try:
            revs = common_period_revs([e.order for e in sp.excitations])
            z1 = min((e.order for e in sp.excitations if e.source == "mesh"), default=None)
            cycles = f" ({fmt(revs * z1)} mesh cycles)" if z1 else ""
            need = f"{fmt(revs)} pinion revolutions{cycles}"
        except InputError:  # no common period of these orders
            need = "a common period of the excitation orders"
        warnings.append(
            ReportWarning(
                "spectra",
                f"the settled record ({fmt(short[0].revs)} pinion revolutions) holds less than "
                f"one common period of the excitation orders, {need}: the spectra are over "
                "whole revolutions with a flat-top window, and orders that are not whole "
                "numbers fall between bins (simulation.settled_mesh_cycles sets the record)",
            )
        )
    return Section("Order spectra", intro + "".join(parts), tuple(warnings), anchor="spectra")


def _bins_up_to(wf, top: float) -> int:
    """How many leading bins of ``wf`` reach ``top`` on its own axis (one bin past
    it, at least 2)."""
    n = int(np.searchsorted(np.asarray(wf.bins), top, side="right")) + 1
    return max(2, min(n, len(wf.bins)))


def _span_text(metrics) -> str:
    lo, hi = law_span(metrics)
    if not (math.isfinite(lo) and math.isfinite(hi)):
        return ""
    return f"{100 * lo:+.1f} / {100 * hi:+.1f}"


def _law_text(p) -> str:
    """The mesh law of a sweep point's run; with ``mesh_law = "auto"`` the tangent law's
    reach that sent it to the loaded law."""
    law = p.mesh_law
    reach = p.metrics.get("tangent_law_reach")
    if law == "loaded" and reach is not None and math.isfinite(reach):
        return f"loaded (tangent: {100 * reach:.0f} %)"
    return law


def _mesh_order(p):
    """A sweep point's mesh-order amplitude of the mesh force (N) from its order
    spectrum (against the pinion angle, as the waterfall); the time DFT at the nominal
    mesh frequency where the point has no spectrum."""
    m = p.metrics
    return m.get("mesh_order_amplitude_spectrum_N", m.get("mesh_force_mesh_order_amplitude_N"))


def render_waterfall(sw, run) -> Section:
    """Waterfall map of the mesh force and a table per speed."""
    from ..spectrum.plotting import plot_waterfall

    warnings = []
    rows = []
    friction = any("mesh_efficiency" in p.metrics for p in sw.points)
    spans = any(law_reach(p.metrics) > 0 for p in sw.points)
    # the law of each run, when they are not all the tangent law's (mesh_law 'loaded' or
    # 'auto'); the report warns where the tangent law's runs reach beyond LAW_SPAN
    laws = any(p.mesh_law != "tangent" for p in sw.points)
    for p in sw.points:
        m = p.metrics
        ok = p.status == "success"
        eff = (100 * m["mesh_efficiency"],) if "mesh_efficiency" in m else ("",)
        rows.append(
            (
                p.speed_rpm,
                p.torque_Nm,
                (p.status, "" if ok else "bad"),
                m.get("mesh_force_dynamic_rms_N"),
                _mesh_order(p),
                m.get("linear_mesh_order_amplitude_N", ""),
                m.get("dynamic_factor", ""),
                *(eff if friction else ()),
                *((_span_text(m),) if spans else ()),
                *((_law_text(p),) if laws else ()),
                100 * m.get("contact_loss_fraction", 0.0),
                p.nfev,
                p.wall_time,
            )
        )
        if not ok:
            warnings.append(
                ReportWarning("waterfall", f"{p.speed_rpm:.0f} rpm: simulation status {p.status}")
            )
        warnings += _contact_warnings("waterfall", m, f"at {p.speed_rpm:.0f} rpm")
    wide = [p for p in sw.points if p.mesh_law == "tangent" and law_reach(p.metrics) > LAW_SPAN]
    if wide:
        worst = max(wide, key=lambda p: law_reach(p.metrics))
        lo, hi = law_span(worst.metrics)
        warnings.append(
            ReportWarning(
                "waterfall",
                f"tangent mesh law at {len(wide)} of {len(sw.points)} speeds ("
                + ", ".join(f"{p.speed_rpm:.0f}" for p in wide)
                + f" rpm): the mesh force's range takes the loaded TCA's tangent "
                f"stiffness beyond {100 * LAW_SPAN:.0f} % of the law's constant one "
                f"({100 * lo:+.0f} to {100 * hi:+.0f} % at {worst.speed_rpm:.0f} rpm); "
                "drivetrain.mesh_law = 'loaded' follows it, 'auto' at those speeds",
            )
        )
    parts = [
        '<p class="muted">Speed sweep on the propeller law: mean torque T(n) = T_op '
        "(n / n_op)^2; one settled simulation per speed, run in parallel. The table "
        "puts the mesh order's amplitude from the model about each speed's operating "
        "point (harmonic balance with the time-varying mesh stiffness) beside the "
        "simulated one, and the dynamic factor: the largest mesh force over the mean.</p>"
    ]
    excitations = sw.excitations
    top = 1.1 * max((e.order for e in excitations), default=100.0)
    for name, wf in sw.waterfalls.items():
        fig, ax = new_figure(1, 2, size=(12, 4.4))
        # only the bins on the plot (up to one past the top order): drawing every cell
        # up to the Nyquist order took most of this section's time
        keep = _bins_up_to(wf, top)
        amps = np.array(wf.amplitudes[:, :keep], dtype=float)
        amps[:, 0] = 0.0  # the mean (order 0) would set the scale
        shown = dataclasses.replace(wf, bins=wf.bins[:keep], amplitudes=amps)
        a = plot_waterfall(shown, ax[0, 0], db=True, max_bin=top, excitations=excitations)
        for mesh in a.collections:  # 80 dB of range: the lines, not the numerical floor
            if hasattr(mesh, "set_clim"):
                mesh.set_clim(-80.0, 0.0)
        plot_waterfall(shown, ax[0, 1], kind="lines", max_bin=top)
        ax[0, 1].set_title(f"{name}: spectra offset by speed (linear)", fontsize=9)
        parts.append(
            figure(
                fig,
                f"Waterfall of {name}: order spectra against speed; left in dB re the largest "
                "line, the largest in each cell (peak hold), excitation orders marked along "
                "the top; right linear (the mean left out in both)",
            )
        )
    parts.append(
        table(
            [
                "speed (rpm)",
                "torque (N m)",
                "status",
                "dynamic mesh force RMS (N)",
                "mesh-order amplitude, order spectrum (N)",
                "mesh order, linear model (N)",
                "dynamic factor (max / mean force)",
                *(("mesh efficiency (%, friction)",) if friction else ()),
                *(("loaded TCA stiffness at least / largest force (%)",) if spans else ()),
                *(("mesh law of the run",) if laws else ()),
                "contact loss (% of record)",
                "RHS evaluations",
                "wall time (s)",
            ],
            rows,
        )
    )
    return Section("Speed sweep and waterfall", "".join(parts), tuple(warnings), anchor="waterfall")


def _response_text(c) -> str:
    """'; steady response, peak (% of the mean load): mesh force 1544 N (51.3 %), ...'
    of a crossing with a response, else ''; a mesh force swing that reaches the mean
    mesh force is said to be beyond the linear response (the flanks would part)."""
    r = c.response
    if not r:
        return ""
    parts = [
        f"{label} {r[key]:.4g} {unit} ({100 * r[key.rsplit('_', 1)[0] + '_fraction']:.3g} %)"
        for label, key, unit in _RESPONSE_COLUMNS
    ]
    text = "; steady response, peak (% of the mean load): " + ", ".join(parts)
    if r.get("mesh_force_fraction", 0.0) >= 1.0:
        text += (
            " - a mesh force swing that reaches the mean: the flanks would part, which the "
            "linear response leaves out (the simulated sweep's contact warnings show it)"
        )
    return text


#: The response entries of a crossing shown in the report: label, key, unit.
_RESPONSE_COLUMNS = (
    ("mesh force", "mesh_force_N", "N"),
    ("input shaft", "input_shaft_torque_Nm", "N m"),
    ("output shaft", "output_shaft_torque_Nm", "N m"),
)


#: ISO 6336-1's main resonance range of the resonance ratio N = n / n_E1: from N_S
#: (0.85 at line loads F_t K_A / b of 100 N/mm and more, lower below:
#: :func:`main_resonance_lower_bound`) to 1.15.
MAIN_RESONANCE = (0.85, 1.15)


def main_resonance_lower_bound(line_load_N_per_mm):
    """ISO 6336-1's lower bound N_S of the main resonance range at the line load
    F_t K_A / b (N/mm): 0.5 + 0.35 sqrt(F_t K_A / (100 b)) below 100 N/mm, else 0.85.
    Array in, array out."""
    w = np.asarray(line_load_N_per_mm, dtype=float)
    return np.where(w < 100.0, 0.5 + 0.35 * np.sqrt(np.clip(w, 0.0, None) / 100.0), 0.85)


def line_load(cd, scene) -> np.ndarray | None:
    """The nominal line load F_t / b (N/mm) at the diagram's speeds: the mean pinion
    torque of the order cuts (the propeller law) over the pinion's reference radius
    z_1 m_n / (2 cos beta) and the face width (the narrower gear's), K_A = 1 (the
    engine's torque ripple is in the model); None without order cuts."""
    cuts = cd.order_cuts
    if cuts is None or "input_shaft_torque_Nm" not in cuts.means:
        return None
    pn = scene["pinion"]
    r1 = pn["teeth"] * scene["pair"]["normal_module_mm"] / 2.0
    r1 /= np.cos(np.radians(pn["helix_angle_deg"]))  # mm
    b = min(pn["face_width_mm"], scene["gear"]["face_width_mm"])  # mm
    # T / n^2 is constant on the propeller law: interpolated exactly between the cuts
    n = np.asarray(cuts.speeds_rpm, dtype=float)
    law = np.interp(cd.speeds_rpm, n, np.asarray(cuts.means["input_shaft_torque_Nm"]) / n**2)
    return 1e3 * np.abs(law) * np.asarray(cd.speeds_rpm) ** 2 / r1 / b


def resonance_ratio(cd) -> tuple[np.ndarray, np.ndarray] | None:
    """(speeds_rpm, N): ISO 6336-1's resonance ratio along the diagram's speeds, the
    mesh frequency over the drive's mesh mode (the mode curve named '(mesh)'), which
    for the gear pair alone is ISO 6336-1's n_E1 (docs/drivetrain.md); None without
    a mesh mode or mesh order."""
    modes = [j for j, name in enumerate(cd.mode_names) if name.endswith("(mesh)")]
    mesh = [e.order for e in cd.excitations if e.source == "mesh"]
    if not modes or not mesh:
        return None
    f = np.asarray(cd.mode_frequencies_hz[modes[0]], dtype=float)
    return cd.speeds_rpm, min(mesh) * cd.speeds_rpm / 60.0 / f


def _resonance_text(cd, loads=None) -> tuple[str, list[ReportWarning]]:
    """A sentence on the resonance ratio over the operating range, and a warning when
    that range reaches ISO 6336-1's main resonance range. loads: the line load (N/mm)
    at the diagram's speeds (:func:`line_load`), which sets the range's lower bound
    N_S; None: N_S = 0.85, its value from 100 N/mm."""
    rr = resonance_ratio(cd)
    if rr is None:
        return "", []
    n, ratio = rr
    lo, hi = cd.operating_range_rpm or (float(n[0]), float(n[-1]))
    inside = (n >= lo) & (n <= hi)
    if not np.any(inside):
        return "", []
    r_lo, r_hi = float(ratio[inside].min()), float(ratio[inside].max())
    i_top = int(np.flatnonzero(inside)[np.argmax(ratio[inside])])
    if loads is None:
        n_s = np.full(n.shape, MAIN_RESONANCE[0])
        bound = (
            f"its lower bound N_S is {MAIN_RESONANCE[0]:g} at line loads of 100 N/mm and "
            "more, lower below; taken as 0.85 here"
        )
    else:
        n_s = main_resonance_lower_bound(loads)
        w = np.asarray(loads)[inside]
        bound = (
            f"its lower bound N_S = 0.5 + 0.35 sqrt(F_t K_A / (100 b)) below 100 N/mm, else "
            f"0.85, is {n_s[inside].min():.3g} to {n_s[inside].max():.3g} here, at line loads "
            f"F_t / b of {w.min():.3g} to {w.max():.3g} N/mm on the propeller law (K_A = 1: "
            "the engine's torque ripple is in the model)"
        )
    text = (
        f" Resonance ratio N = mesh frequency / mesh mode (ISO 6336-1's n / n_E1 with the "
        f"drive's mesh mode): {r_lo:.3g} to {r_hi:.3g} over the operating range, the "
        f"largest at {n[i_top]:.0f} rpm; ISO 6336-1's main resonance range is "
        f"N_S < N <= {MAIN_RESONANCE[1]:g} ({bound})."
    )
    band = inside & (ratio > n_s) & (ratio <= MAIN_RESONANCE[1])
    warns = []
    if np.any(band):
        warns.append(
            ReportWarning(
                "campbell",
                f"mesh resonance: from {n[band][0]:.0f} to {n[band][-1]:.0f} rpm the resonance "
                f"ratio N = mesh frequency / mesh mode is in ISO 6336-1's main resonance range "
                f"(N_S < N <= {MAIN_RESONANCE[1]:g}, N_S {n_s[band].min():.3g} to "
                f"{n_s[band].max():.3g} there)",
            )
        )
    return text, warns


def _ranges_text(cd) -> str:
    """The diagram's speed range and the operating range its flags take."""
    lo, hi = float(cd.speeds_rpm[0]), float(cd.speeds_rpm[-1])
    rng = cd.operating_range_rpm
    if rng is None:
        return f" Speeds {lo:.0f} to {hi:.0f} rpm."
    if np.allclose(rng, (lo, hi)):
        return (
            f" Speeds {lo:.0f} to {hi:.0f} rpm, the operating range (every crossing in it; "
            "simulation.operating_range_rpm sets a narrower one)."
        )
    return (
        f" Speeds {lo:.0f} to {hi:.0f} rpm (the sweep's); operating range {rng[0]:.0f} to "
        f"{rng[1]:.0f} rpm (simulation.operating_range_rpm), shaded."
    )


def render_campbell(cd, run) -> Section:
    """Campbell diagram (full and low-frequency view) and the crossings, each with the
    steady response its excitation drives there when the diagram has responses."""
    from ..spectrum.plotting import plot_campbell, plot_order_cuts

    risks = cd.risks
    listed = cd.significant
    warnings = []
    for c in listed[:MAX_LISTED]:
        warnings.append(
            ReportWarning(
                "campbell",
                f"resonance risk: {c.mode} at {c.frequency_hz:.4g} Hz meets "
                f"{c.excitation} (order {c.order:.4g}) at {c.speed_rpm:.0f} rpm"
                + _response_text(c),
            )
        )
    if len(listed) > MAX_LISTED:
        warnings.append(
            ReportWarning(
                "campbell",
                f"{len(listed) - MAX_LISTED} more crossings in the operating range "
                "(see the Campbell section)",
            )
        )
    ratio_text, ratio_warnings = _resonance_text(cd, line_load(cd, run.scene))
    warnings += ratio_warnings
    quiet = len(risks) - len(listed)
    if quiet:
        warnings.append(
            ReportWarning(
                "campbell",
                f"{quiet} further crossing(s) in the operating range drive responses below "
                f"{100 * cd.response_threshold:.3g} % of the mean loads "
                "(simulation.resonance_threshold; see the Campbell section)",
            )
        )
    fig, ax = new_figure(1, 2, size=(11, 4.4))
    plot_campbell(cd, ax[0, 0])
    low = [f for f in np.atleast_2d(cd.mode_frequencies_hz).max(axis=1) if f < 500]
    if low:
        plot_campbell(cd, ax[0, 1], max_frequency_hz=1.3 * max(low))
        ax[0, 1].get_legend().remove()  # the left panel's says the same
        ax[0, 1].set_title("shaft modes", fontsize=9)
    with_resp = any(c.response for c in cd.crossings)
    thr = cd.response_threshold
    rows = []
    for c in cd.crossings:
        row = [
            c.mode,
            c.excitation,
            c.order,
            c.source,
            c.speed_rpm,
            c.frequency_hz,
            ("yes", "bad") if c.in_operating_range else "no",
        ]
        if with_resp:
            r = c.response or {}
            row += [r.get(key, "") for _, key, _ in _RESPONSE_COLUMNS]
            sev = c.severity
            text = "" if sev is None else f"{100 * sev:.3g}"
            warned = c.in_operating_range and thr is not None and sev is not None and sev >= thr
            row.append((text, "bad") if warned else text)
        rows.append(tuple(row))
    head = [
        "mode",
        "excitation",
        "order",
        "source",
        "speed (rpm)",
        "frequency (Hz)",
        "in operating range",
    ]
    note = ""
    if with_resp:
        head += [
            "mesh force (N)",
            "input shaft torque (N m)",
            "output shaft torque (N m)",
            "largest / mean load (%)",
        ]
        note = (
            " Responses: the steady vibration that the crossing's excitation alone drives "
            "at the crossing speed, peak amplitudes of the dynamic mesh force and of the "
            "shaft torques, from the model about that speed's operating point on the "
            "propeller law (engine and propeller orders on the linear model; mesh orders by "
            "harmonic balance with the time-varying mesh stiffness); the last column is "
            "the largest of them over its mean load."
        )
        if thr is not None:
            note += (
                f" Crossings in the operating range from {100 * thr:.3g} % "
                "(simulation.resonance_threshold) are warned of, the most severe first."
            )
    cuts = ""
    if cd.order_cuts is not None:
        names = [k for _, k, _ in _RESPONSE_COLUMNS if k in cd.order_cuts.amplitudes]
        cfig, cax = new_figure(1, len(names), size=(4.4 * len(names), 4.0))
        for i, name in enumerate(names):
            plot_order_cuts(cd.order_cuts, name, cax[0, i], crossings=cd.risks)
        cuts = figure(
            cfig,
            "Order cuts: the steady response of each excitation order against speed on the "
            f"propeller law ({cd.order_cuts.speeds_rpm.size} speeds, the crossing speeds "
            "among them; engine and propeller orders on the linear model, mesh orders by "
            "harmonic balance with the time-varying mesh stiffness), peak amplitudes; "
            "circles: the crossings in the operating range",
        )
    body = (
        '<p class="muted">Eigenfrequencies of the linearised drivetrain (mean mesh '
        "stiffness at the propeller-law torque of each speed) against engine speed, with "
        "the excitation orders; crossing speeds solved by root finding."
        + esc(_ranges_text(cd))
        + esc(ratio_text)
        + note
        + "</p>"
        + figure(fig, "Campbell diagram")
        + cuts
        + table(head, rows)
    )
    return Section("Campbell diagram", body, tuple(warnings), anchor="campbell")


def render_fmu(art, run) -> Section:
    """What was built: file, variables, states, platform, compiler command."""
    b = art.build
    rows = [
        ("file (in the output folder)", f"fmu/{art.filename}"),
        ("size (bytes)", len(art.data)),
        ("model identifier", art.identifier),
        ("GUID", b.get("guid", "")),
        ("variables / states", f"{b.get('n_variables')} / {b.get('n_states')}"),
        ("platform", b.get("platform", "")),
        ("compiler command", " ".join(b.get("command", ()))),
        ("compiler output", b.get("compiler_output", "") or "(none: clean build)"),
    ]
    body = (
        '<p class="muted">FMI 2.0 FMU (Model Exchange and Co-Simulation) of the drivetrain at '
        "the operating point, with the run's mesh tables in its resources (docs/fmu.md).</p>"
        + table(["item", "value"], rows)
    )
    return Section("FMU", body, anchor="fmu")


def _approach(pitch) -> str:
    """The approach's peak-to-peak and what it carries."""
    text = fmt(float(np.ptp(pitch.values)) * 1e6, 4)
    carries = getattr(pitch, "carries", ())
    return f"{text} ({', '.join(carries)})" if carries else text

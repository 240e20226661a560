"""Report section of the loaded TCA: per flank and torque the stiffness, LTE, contact
pattern, pressure and root stress (paper Figs. 12-16 style), with edge-contact and
solver warnings."""

from __future__ import annotations

import numpy as np

from .html import ReportWarning, Section, esc, figure, new_figure, table

__all__ = ["render_ltca"]

_MU = 0.05  # coefficient of friction for the report's example efficiency


def _operating_index(res, run) -> int:
    """Torque level nearest to the scene's operating torque."""
    target = run.scene["load"]["operating_torque_Nm"]
    return int(np.argmin(np.abs(np.asarray(res.torque) - target)))


def _listed(items: list[str]) -> str:
    """``a``, ``a and b``, ``a, b and c``."""
    return items[0] if len(items) == 1 else ", ".join(items[:-1]) + " and " + items[-1]


def render_ltca(lt, run) -> Section:
    """Tables per flank and torque; pattern, stiffness, LTE and root-stress figures."""
    from ..ltca.plot import (
        plot_contact_pattern,
        plot_lte,
        plot_mesh_stiffness,
        plot_modification_map,
        plot_root_stress_face,
    )

    warnings = []
    edges: dict[str, list[tuple[float, float]]] = {}  # flank -> (torque, edge load share)
    rows = []
    speed_rpm = run.scene["drivetrain"]["engine_speed_rpm"]  # the pinion's speed
    omega = speed_rpm * np.pi / 30.0
    summary = lt.summary()["flanks"]
    sliding = all("mesh_loss_factor" in r for per_t in summary.values() for r in per_t.values())
    for flank, per_t in summary.items():
        for r in per_t.values():
            row = [
                flank,
                r["torque_Nm"],
                r["mean_mesh_stiffness_N_per_m"] / 1e6,
                r["mesh_stiffness_peak_to_peak_N_per_m"] / 1e6,
                r["lte_mean_m"] * 1e6,
                r["lte_peak_to_peak_m"] * 1e6,
                100 * r["contact_pattern_area_fraction"],
                r["max_contact_pressure_Pa"] / 1e6,
                r["max_root_stress_pinion_Pa"] / 1e6,
                r["max_root_stress_gear_Pa"] / 1e6,
            ]
            if sliding:
                row.append(f"{r['mesh_loss_factor']:.4f}")
                v = r["max_sliding_speed_per_pinion_speed_m"]
                row.append(f"{v * omega:.2f}")
            row += [
                ("yes", "bad") if r["edge_contact"] else "no",
                ("yes", "ok") if r["solver_converged"] else ("no", "bad"),
            ]
            rows.append(tuple(row))
            if r["edge_contact"]:
                edges.setdefault(flank, []).append((r["torque_Nm"], r["max_edge_load_fraction"]))
            if not r["solver_converged"]:
                warnings.append(
                    ReportWarning(
                        "ltca",
                        f"{flank} flank, {r['torque_Nm']:g} N m: contact solver did not converge",
                    )
                )
    # where the pair lies outside the range the fast level was checked on
    warnings += [ReportWarning("ltca", note) for note in getattr(lt, "notes", ())]
    # one warning per flank with edge contact, its torque levels in one line
    for flank, hits in edges.items():
        torques = _listed([f"{tq:g}" for tq, _ in hits])
        shares = _listed([f"{100 * f:.1f}" for _, f in hits])
        order = ", in that order" if len(hits) > 1 else ""
        warnings.append(
            ReportWarning(
                "ltca",
                f"{flank} flank: edge contact at {torques} N m (up to {shares} % of the load "
                f"on an edge{order}; the pressure there is Hertz's with the flank's curvature, "
                "a lower bound: an edge concentrates it further, a relief removes it)",
            )
        )
    # once, where edges were found on the last profile samples (ltca.edge_borders off)
    if edges and getattr(lt, "attrs", {}).get("edge_points") == "last profile sample":
        warnings.append(
            ReportWarning(
                "ltca",
                "the edge points sit on the last profile sample inside the flank border, "
                "which reads the loaded TE high on a coarse profile grid (case 03 drive at "
                "300 N m: 2.09 um at the default ltca.grid_profile = 20 against 1.58 um "
                "converged): ltca.edge_borders = true puts them on the border (docs/ltca.md)",
            )
        )
    head = [
        "flank",
        "torque (N m)",
        "mean stiffness (N/um)",
        "stiffness p-p (N/um)",
        "mean LTE (um)",
        "LTE p-p (um)",
        "pattern (% of flank)",
        "max pressure (MPa)",
        "max root stress pinion (MPa)",
        "max root stress gear (MPa)",
    ]
    if sliding:
        head.append("mesh loss factor H")
        head.append(f"max sliding (m/s at {speed_rpm:g} rpm)")
    head += ["edge contact", "converged"]
    flanks = dict(lt.flanks)
    first = next(iter(flanks.values()))
    t = _operating_index(first, run)
    parts = [
        f'<p class="muted">{lt.attrs.get("method", "")}; fidelity '
        f"{lt.attrs.get('fidelity', '')}. Root stress: "
        f"{esc(lt.attrs.get('root_stress', 'ISO 6336-3 slices'))}. Flank modifications: "
        f"{esc(lt.attrs.get('flank_modifications', 'none'))}. Figures at "
        f"{first.torque[t]:g} N m, the torque level nearest to the operating torque "
        f"(load.operating_torque_Nm = {run.scene['load']['operating_torque_Nm']:g} N m).</p>",
        table(head, rows),
    ]
    if sliding:
        h = {name: float(res.loss_factor[t].mean()) for name, res in flanks.items()}
        parts.append(
            '<p class="muted">Mesh loss factor H: the friction power per unit coefficient '
            "of friction over the transmitted power, the cycle's mean of "
            "sum F_i |v_sliding,i| / (T omega_1) over the loaded contact points (friction "
            "does not act back on the loads; the drivetrain applies it with "
            "drivetrain.mesh_friction_coefficient, see the dynamics section). A mean "
            "coefficient mu loses mu H of the "
            f"power in the mesh: at {first.torque[t]:g} N m and mu = {_MU:g} (an assumed "
            "value; ISO/TR 14179-2 gives one from load, speed, oil and roughness) "
            + ", ".join(f"{n} flank {100 * (1 - _MU * v):.2f} %" for n, v in h.items())
            + f" mesh efficiency; at {speed_rpm:g} rpm the mesh turns "
            + ", ".join(
                f"{_MU * v * first.torque[t] * omega / 1e3:.2f} kW ({n} flank)"
                for n, v in h.items()
            )
            + f" of the {first.torque[t] * omega / 1e3:.1f} kW into heat.</p>"
        )
    fig, ax = new_figure(1, len(flanks), size=(5.5 * len(flanks), 3.6))
    for i, (name, res) in enumerate(flanks.items()):
        plot_contact_pattern(res, t, ax[0, i], title=f"{name} flank,")
    parts.append(figure(fig, "Contact pattern and maximum contact pressure over the mesh cycle"))
    fig, ax = new_figure(1, 3, size=(15, 3.6))
    plot_mesh_stiffness(flanks, t, ax[0, 0])
    plot_lte(flanks, t, ax[0, 1])
    plot_root_stress_face(flanks, t, ax[0, 2])
    parts.append(figure(fig, "Mesh stiffness, loaded transmission error and root stress"))
    maps = getattr(lt, "modification_maps", None) or {}
    if maps:
        # one row per flank, one column per modified gear
        rows = list(dict.fromkeys(k.split(", ")[1] for k in maps))
        cols = list(dict.fromkeys(k.split(", ")[0] for k in maps))
        fig, ax = new_figure(
            len(rows), len(cols), size=(6.0 * len(cols), 3.6 * len(rows)), wgap=1.6, right=1.0
        )
        for name, m in maps.items():
            gear, flank = name.split(", ")
            plot_modification_map(m, ax[rows.index(flank), cols.index(gear)], title=name)
        parts.append(
            figure(
                fig,
                "Flank modifications: material removed normal to the flank (um), from the "
                "form circle to the tip, against the axial position",
            )
        )
    return Section("Loaded tooth contact analysis", "".join(parts), tuple(warnings), anchor="ltca")

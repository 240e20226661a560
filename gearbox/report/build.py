"""Assemble the HTML report of a pipeline run and write it atomically."""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable
from datetime import UTC, datetime
from pathlib import Path

from .. import __version__
from ..commands._common import write_atomic
from ..pipeline.summary import STATUSES
from . import sections
from .html import CSS, ReportWarning, Section, esc, table
from .provenance import package_versions, provenance_rows

#: Scene entries a report section reads besides its stage's result (see
#: :mod:`gearbox.report.sections`).
SECTION_READS = sections.SECTION_READS

__all__ = [
    "RENDERERS",
    "SECTION_READS",
    "assemble",
    "build_report",
    "scene_toml",
    "section_key",
    "write_report",
]


def _renderers() -> dict[str, Callable]:
    from . import contact, design, dynamics, geometry_sweep, loaded, pitch, tables

    return {
        "design": design.render,
        "sweep": geometry_sweep.render,
        "tca": contact.render_tca,
        "ltca": loaded.render_ltca,
        "pitch": pitch.render_pitch,
        "approach": pitch.render_approach,
        "tables": tables.render,
        "dynamics": dynamics.render_dynamics,
        "spectra": dynamics.render_spectra,
        "waterfall": dynamics.render_waterfall,
        "campbell": dynamics.render_campbell,
        "fmu": dynamics.render_fmu,
    }


#: stage name -> ``render(result, run) -> Section | list[Section]``, in report order.
RENDERERS: dict[str, Callable] = {}


def default_renderer(name: str) -> Callable:
    """The renderer :func:`assemble` uses for stage ``name`` by default: its own, else
    the generic one (``_repr_html_``, ``report_figures`` or the result's scalars)."""
    from .generic import render_generic

    return (RENDERERS or _renderers()).get(name) or render_generic(name, name)


def _toml_value(v) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        return "[" + ", ".join(_toml_value(x) for x in v) + "]"
    return repr(v)


def scene_toml(scene) -> str:
    """The validated scene, defaults filled in, as TOML text (unset keys commented)."""
    lines = []
    for sec, values in scene.data.items():
        if sec:
            lines += ["", f"[{sec}]"]
        for k, v in values.items():
            lines.append(f"# {k} = (not set)" if v is None else f"{k} = {_toml_value(v)}")
    return "\n".join(lines).strip() + "\n"


def _status_warnings(run) -> list[ReportWarning]:
    out = []
    requested = set(run.summary.requested)
    for r in run.summary.records:
        if r.status == "failed":
            out.append(ReportWarning(r.name, f"stage failed: {r.detail}"))
        elif r.status in ("unavailable", "skipped") and r.name in requested:
            out.append(ReportWarning(r.name, f"requested but {STATUSES[r.status]}: {r.detail}"))
    return out


def _stage_table(run, drawn: dict[str, str]) -> str:
    rows = []
    for r in run.summary.records:
        klass = {"failed": "bad", "cached": "ok", "computed": ""}.get(r.status, "note")
        saved = f"{r.saved_seconds:.2f}" if r.status == "cached" else "-"
        sec = drawn.get(r.name, "-")
        sec = (sec, "ok") if sec == "cached" else sec
        status = (r.status, klass) if klass else r.status
        rows.append((r.name, status, f"{r.seconds:.2f}", saved, sec, r.key[:12], r.detail))
    return table(
        [
            "stage",
            "status",
            "seconds",
            "compute time saved (s)",
            "report section: cached or drawing time (s)",
            "cache key",
            "detail",
        ],
        rows,
    )


def section_key(run, name: str) -> str:
    """Cache key of stage ``name``'s report section(s) in ``run``
    (:func:`gearbox.report.sections.section_key`)."""
    return sections.section_key(run.scene, name, run.keys[name])


def _render(
    name: str, render: Callable, run, own: bool, prepared=None
) -> tuple[list[Section], str]:
    """The section(s) of one stage and where they came from (``"cached"`` or the
    seconds spent drawing). Default renderers see only their stage
    (:func:`gearbox.report.sections.stage_view`) and their sections are kept in the
    run's cache; a renderer passed in by the caller sees the whole run and is not
    cached."""
    result = run.results[name]
    if not own:
        t0 = time.perf_counter()
        got = render(result, run)
        return (got if isinstance(got, list) else [got]), f"{time.perf_counter() - t0:.2f}"
    if prepared is not None:  # drawn by a worker process beside the stages
        got, drawn = prepared
        return list(got), drawn
    cached_key = getattr(run, "cached_key", None)
    store = run.cache if cached_key is not None and cached_key(name) is not None else None
    got, drawn = sections.draw(name, render, run.scene, result, run.keys.get(name, ""), store)
    return list(got), drawn


def assemble(
    run, *, renderers: dict[str, Callable] | None = None, prepared=None
) -> tuple[str, dict[str, str]]:
    """``(html, drawn)``: the report of ``run`` and, per stage with a section, where
    the section came from (``"cached"``, or the seconds spent drawing it).

    ``prepared``: stage -> ``(sections, drawn)`` already drawn with the default
    renderers (by :class:`gearbox.pipeline.overlap.OutputWorker`); used as they are."""
    own = renderers is None
    prepared = prepared if own and prepared else {}
    if renderers is None:
        renderers = RENDERERS or _renderers()
    from .generic import render_generic

    sections: list[Section] = []
    warnings = _status_warnings(run)
    drawn: dict[str, str] = {}
    order = {**renderers}
    for name in run.results:  # stages without a renderer of their own
        order.setdefault(name, render_generic(name, name))
    for name, render in order.items():
        if name not in run.results:
            continue
        try:
            got, drawn[name] = _render(name, render, run, own, prepared.get(name))
        except Exception as exc:
            print(f"gearbox report: section {name!r} failed: {exc!r}", file=sys.stderr)
            warnings.append(
                ReportWarning(
                    name, f"report section could not be drawn: {type(exc).__name__}: {exc}"
                )
            )
            continue
        for sec in got:
            sections.append(sec)
            warnings += sec.warnings
    name = run.scene.name
    desc = run.scene[""].get("description", "")
    now = datetime.now(UTC).isoformat(timespec="seconds")
    parts = [
        "<!DOCTYPE html>",
        '<html lang="en"><head><meta charset="utf-8">',
        '<meta name="viewport" content="width=device-width, initial-scale=1">',
        f"<title>gearbox report: {esc(name)}</title><style>{CSS}</style></head><body>",
        f"<h1>gearbox report: {esc(name)}</h1>",
        f'<p class="muted">{esc(desc)}</p>' if desc else "",
        f'<p class="muted">gearbox {esc(__version__)}, written {esc(now)} UTC</p>',
    ]
    s = run.summary
    cached = s.names("cached")
    saved = sum(r.saved_seconds for r in s.records if r.status == "cached")
    parts.append(
        f'<p class="muted" id="run-line">This run: {len(s.names("computed"))} stage(s) computed '
        f"({esc(', '.join(s.names('computed')) or '-')}), {len(cached)} from the cache "
        f"({esc(', '.join(cached) or '-')}; {saved:.1f} s of computing saved), "
        f"{s.seconds:.1f} s in all; report sections from the cache: "
        f"{esc(', '.join(n for n, d in drawn.items() if d == 'cached') or '-')}. "
        "Details under Provenance.</p>"
    )
    anchors = [("warnings", "Warnings")]
    for i, sec in enumerate(sections):
        anchors.append((sec.anchor or f"s{i}", sec.title))
    anchors.append(("provenance", "Provenance"))
    parts.append(
        "<nav>" + "".join(f'<a href="#{esc(a)}">{esc(t)}</a>' for a, t in anchors) + "</nav>"
    )
    parts.append('<h2 id="warnings">Warnings</h2>')
    if warnings:
        items = "".join(f"<li><b>{esc(w.source)}</b>: {esc(w.text)}</li>" for w in warnings)
        parts.append(f'<ul class="warnings" id="warning-list">{items}</ul>')
    else:
        parts.append('<p id="warning-list">None.</p>')
    for i, sec in enumerate(sections):
        anchor = esc(sec.anchor or f"s{i}")
        parts.append(f'<section id="{anchor}"><h2>{esc(sec.title)}</h2>{sec.body}</section>')
    versions = package_versions()
    parts += [
        '<section id="provenance"><h2>Provenance</h2>',
        table(["item", "value"], provenance_rows(run)),
        "<h3>Stages</h3>",
        _stage_table(run, drawn),
        '<p class="muted">'
        + "; ".join(f"{esc(k)}: {esc(v)}" for k, v in STATUSES.items())
        + "</p>",
        "<h3>Versions</h3>",
        table(["package", "version"], sorted(versions.items())),
        "<h3>Scene as run (defaults filled in)</h3>",
        f"<pre>{esc(scene_toml(run.scene))}</pre>",
        "</section></body></html>",
    ]
    return "\n".join(p for p in parts if p), drawn


def build_report(run, *, renderers: dict[str, Callable] | None = None) -> str:
    """The whole report of ``run`` (a :class:`gearbox.pipeline.PipelineRun`) as HTML.

    Every stage with a result and a renderer gets its section(s); a renderer that
    raises is named in the warnings instead of stopping the report. With the default
    renderers and a run that has a cache, each stage's sections are kept in the cache
    under the stage's key (:func:`section_key`), so a stage that came from the cache
    is not drawn again.
    """
    return assemble(run, renderers=renderers)[0]


def write_report(run, path: str | Path, **kwargs) -> Path:
    """Build the report and write it atomically: the file is complete or absent."""
    return write_atomic(path, build_report(run, **kwargs))

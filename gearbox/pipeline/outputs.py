"""Files a run leaves in its output folder, each written atomically.

- ``run_summary.json``: :meth:`RunSummary.to_dict` plus the cache keys and what
  writing the files and the report took (written last);
- per requested stage, its result in the file format that suits it:
  ``design.json``; ``sweep/<study>.csv``; ``tca.json`` (summary); ``ltca.json`` (summary); ``tables.nc`` (netCDF, needs the
  ``tables`` extra) and ``tables.csv``; ``dynamics.csv`` (time first) and
  ``dynamics.json`` (metrics, modes); ``spectra.json``; ``waterfall.json``;
  ``campbell.json`` and ``order_cuts.csv``; ``fmu/<identifier>.fmu``; results with their own
  ``write_files(folder)`` write themselves; any other result with ``to_dict()`` as
  ``<stage>.json``;
- ``report.html`` when ``report`` is requested.

With a cache, the bytes of each stage's files are kept there under a key made from
the stage's key; a stage that came from the cache has its files copied from there.
"""

from __future__ import annotations

import dataclasses
import json
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from ..commands._common import write_atomic

__all__ = ["WRITERS", "Written", "jsonable", "stage_files", "write_outputs", "write_run"]


def jsonable(x: Any) -> Any:
    """Plain JSON types from nested dicts, dataclass dicts and numpy values."""
    import numpy as np

    t = type(x)
    if t is float:  # the common case first: spectra hold hundreds of thousands
        return x if math.isfinite(x) else None
    if t is str or t is int or t is bool or x is None:
        return x
    if hasattr(x, "items"):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        if x.dtype.kind in "fiub" and (x.dtype.kind != "f" or np.isfinite(x).all()):
            return x.tolist()  # plain numbers all through: no walk over the elements
        return jsonable(x.tolist())
    if isinstance(x, np.generic):
        return jsonable(x.item())
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, (str, int, float, bool)):
        return x
    if hasattr(x, "to_dict"):
        return jsonable(x.to_dict())
    return str(x)


def _plain(x: Any) -> Any:
    """What the JSON encoder cannot take itself, as :func:`jsonable` makes it."""
    import numpy as np

    if isinstance(x, np.ndarray):
        return x.tolist()
    if isinstance(x, np.generic):
        return x.item()
    if hasattr(x, "items"):
        return dict(x.items())
    if hasattr(x, "to_dict"):
        return x.to_dict()
    return str(x)


def _json(path: Path, obj: Any, *, compact: bool = False) -> list[Path]:
    """``obj`` as JSON; ``compact``: no indentation (files of many numbers: the
    indenting encoder is pure Python, the compact one is C).

    The encoder takes ``obj`` as it is (numpy values and mappings through
    :func:`_plain`); only when it meets a value JSON has no word for (NaN, infinity,
    a key that is no string, number, bool or None) is ``obj`` walked by
    :func:`jsonable` first, which writes those as null and str(key): a spectrum's
    hundreds of thousands of numbers are not visited one by one in Python. (Keys
    True / None read "true" / "null" here, "True" / "None" through :func:`jsonable`;
    the pipeline's results have none.)"""
    indent = None if compact else 1
    try:
        text = json.dumps(obj, indent=indent, allow_nan=False, default=_plain)
    except (ValueError, TypeError):
        text = json.dumps(jsonable(obj), indent=indent, allow_nan=False)
    return [write_atomic(path, text)]


def _sweep(studies, folder: Path) -> list[Path]:
    return [write_atomic(folder / "sweep" / f"{s.name}.csv", s.to_csv()) for s in studies.studies]


def _tables(table, folder: Path) -> list[Path]:
    files = [write_atomic(folder / "tables.csv", table.to_csv())]
    try:
        files.append(table.to_netcdf(folder / "tables.nc"))
    except ImportError:  # netCDF needs the 'tables' extra; the CSV holds the same data
        pass
    return files


def _dynamics(op, folder: Path) -> list[Path]:
    files = [write_atomic(folder / "dynamics.csv", op.series.to_csv())]
    summary = {
        "speed_rpm": op.speed_rpm,
        "torque_Nm": op.torque_Nm,
        "status": op.series.status,
        "metrics": dict(op.metrics),
        "modes": op.modes.to_dict(),
        "attrs": dict(op.series.attrs),
    }
    return files + _json(folder / "dynamics.json", summary)


def _spectra(sp, folder: Path) -> list[Path]:
    data = {"speed_rpm": sp.speed_rpm, "spectra": sp.spectra}
    if getattr(sp, "linear", None):  # JSON keys are strings: orders as their repr
        data["linear_model"] = {k: {repr(o): a for o, a in v.items()} for k, v in sp.linear.items()}
    return _json(folder / "spectra.json", data, compact=True)


def _waterfall(sw, folder: Path) -> list[Path]:
    points = [
        {
            "speed_rpm": p.speed_rpm,
            "torque_Nm": p.torque_Nm,
            "status": p.status,
            "mesh_law": p.mesh_law,
            "metrics": dict(p.metrics),
            "nfev": p.nfev,
            "wall_time_s": p.wall_time,
        }
        for p in sw.points
    ]
    data = {"points": points, "waterfalls": sw.waterfalls}
    return _json(folder / "waterfall.json", data, compact=True)


def _campbell(cd, folder: Path) -> list[Path]:
    """``campbell.json``, and the order cuts as ``order_cuts.csv`` when it has them: a
    row per speed, a column per channel and order (``mesh_force_N @ 2x mesh``)."""
    files = _json(folder / "campbell.json", cd.to_dict())
    cuts = getattr(cd, "order_cuts", None)
    if cuts is None:
        return files
    head = ["speed_rpm"]
    cols = [cuts.speeds_rpm]
    for name, amp in cuts.amplitudes.items():
        for e, row in zip(cuts.excitations, amp, strict=True):
            head.append(f"{name} @ {e.label}")
            cols.append(row)
        head.append(f"{name} mean")
        cols.append(cuts.means[name])
    lines = [",".join(head)] + [
        ",".join(repr(float(v)) for v in r) for r in zip(*cols, strict=True)
    ]
    return files + [write_atomic(folder / "order_cuts.csv", "\n".join(lines) + "\n")]


def _tca(res, folder: Path) -> list[Path]:
    return _json(folder / "tca.json", res.summary())


def _ltca(res, folder: Path) -> list[Path]:
    return _json(folder / "ltca.json", res.summary())


#: stage -> ``writer(result, folder) -> list of paths``; other results: ``<stage>.json``.
WRITERS: dict[str, Callable[[Any, Path], list[Path]]] = {
    "tca": _tca,
    "ltca": _ltca,
    "sweep": _sweep,
    "tables": _tables,
    "dynamics": _dynamics,
    "spectra": _spectra,
    "waterfall": _waterfall,
    "campbell": _campbell,
}


#: Distributions whose versions shape the files (netCDF through xarray).
FILE_PACKAGES = ("numpy", "xarray", "h5netcdf", "h5py", "netCDF4")


def _write_stage(name: str, result: Any, folder: Path) -> list[Path]:
    if name in WRITERS:
        return WRITERS[name](result, folder)
    if hasattr(result, "write_files"):
        return [Path(p) for p in result.write_files(folder)]
    if hasattr(result, "to_dict"):
        return _json(folder / f"{name}.json", result.to_dict())
    return []


def _timed_files(run, name: str, folder: Path) -> tuple[list[Path], bool, float]:
    """:func:`_stage_files` and the seconds it took."""
    t0 = time.perf_counter()
    got, hit = _stage_files(run, name, folder)
    return got, hit, time.perf_counter() - t0


def _stage_files(run, name: str, folder: Path) -> tuple[list[Path], bool]:
    """Write one stage's files; ``(paths, from_cache)`` (:func:`stage_files`)."""
    key = run.cached_key(name) if hasattr(run, "cached_key") else None
    return stage_files(name, run.results[name], folder, key, getattr(run, "cache", None))


def stage_files(
    name: str, result: Any, folder: Path, key: str | None = None, cache=None
) -> tuple[list[Path], bool]:
    """Write the files of stage ``name``'s ``result`` into ``folder``;
    ``(paths, from_cache)``.

    With a cache and the stage's ``key``, the files' bytes are kept in the cache
    under a key made from it (:func:`gearbox.pipeline.cache.derived_key`), so the
    files of a stage that came from the cache are copied, not serialised again.
    """
    from .cache import derived_key, remembered

    if key is None or cache is None:
        return _write_stage(name, result, folder), False
    made: list[Path] = []

    def write() -> dict[str, bytes]:
        made.extend(_write_stage(name, result, folder))
        return {p.relative_to(folder).as_posix(): p.read_bytes() for p in made}

    dkey = derived_key(
        "files", name, key, code=("gearbox.pipeline.outputs",), packages=FILE_PACKAGES
    )
    files, hit = remembered(cache, "files", dkey, write)
    if not hit:
        return made, False
    return [write_atomic(folder / rel, data) for rel, data in files.items()], True


@dataclass(frozen=True)
class Written:
    """What :func:`write_run` wrote: ``files`` in writing order; ``seconds`` per stage
    (and ``"report"``) spent writing (s); ``copied``: stages whose files came from the
    cache; ``sections``: per stage, ``"cached"`` or the seconds its report section
    took to draw; ``worker``: stages whose files or sections the output worker made
    (:mod:`gearbox.pipeline.overlap`), their seconds being the worker's."""

    files: tuple[Path, ...]
    seconds: Mapping[str, float]
    copied: tuple[str, ...] = ()
    sections: Mapping[str, str] = field(default_factory=dict)
    worker: tuple[str, ...] = ()

    def to_dict(self) -> dict[str, Any]:
        return {
            "files": [str(f) for f in self.files],
            "seconds": dict(self.seconds),
            "copied_from_cache": list(self.copied),
            "report_sections": dict(self.sections),
            "made_by_output_worker": list(self.worker),
        }


def write_run(run, folder: str | Path, *, worker=None) -> Written:
    """Write the run's files into ``folder``: each requested stage's results, the
    report (when requested) and, last, ``run_summary.json`` (with these timings).

    ``worker``: an :class:`gearbox.pipeline.overlap.OutputWorker` the run's computed
    stages were handed to; their files and sections are taken from it (what it
    failed to make is made here)."""
    folder = Path(folder)
    files: list[Path] = []
    seconds: dict[str, float] = {}
    copied: list[str] = []
    drawn: dict[str, str] = {}
    prepared = {}
    here: dict[str, tuple[list[Path], bool, float]] = {}
    if worker is not None:
        # the files the worker has not begun are written here, while it draws
        for name in worker.claim_files():
            if run.results.get(name) is not None:
                here[name] = _timed_files(run, name, folder)
        prepared = {n: p for n in run.results if (p := worker.take(n)) is not None}
    for name in run.summary.requested:
        if run.results.get(name) is None:
            continue
        done = prepared[name].files if name in prepared else None
        if name in here:
            got, hit, seconds[name] = here[name]
        elif done is not None:
            got, hit, seconds[name] = done
        else:
            got, hit, seconds[name] = _timed_files(run, name, folder)
        files += got
        if hit:
            copied.append(name)
    if "report" in run.summary.requested:
        from ..report.build import assemble

        t0 = time.perf_counter()
        drawn_there = {n: p.sections for n, p in prepared.items() if p.sections is not None}
        html, drawn = assemble(run, prepared=drawn_there)
        files.append(write_atomic(folder / "report.html", html))
        seconds["report"] = time.perf_counter() - t0
    made_there = tuple(
        n for n, p in prepared.items() if p.files is not None or p.sections is not None
    )
    written = Written(tuple(files), seconds, tuple(copied), drawn, made_there)
    summary = run.summary.to_dict() | {"keys": dict(run.keys), "outputs": written.to_dict()}
    path = write_atomic(folder / "run_summary.json", json.dumps(summary, indent=2))
    return dataclasses.replace(written, files=(path, *files))


def write_outputs(run, folder: str | Path) -> list[Path]:
    """Write the run's files into ``folder``; return their paths (:func:`write_run`)."""
    return list(write_run(run, folder).files)

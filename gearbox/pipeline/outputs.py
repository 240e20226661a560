"""Files a run leaves in its output folder, each written atomically.

- ``run_summary.json``: :meth:`RunSummary.to_dict` plus the cache keys;
- per requested stage, its result in the file format that suits it:
  ``design.json``; ``sweep/<study>.csv``; ``tca.json`` (summary); ``ltca.json`` (summary); ``tables.nc`` (netCDF, needs the
  ``tables`` extra) and ``tables.csv``; ``dynamics.csv`` (time first) and
  ``dynamics.json`` (metrics, modes); ``spectra.json``; ``waterfall.json``;
  ``campbell.json``; ``fmu/<identifier>.fmu``; results with their own
  ``write_files(folder)`` write themselves; any other result with ``to_dict()`` as
  ``<stage>.json``;
- ``report.html`` when ``report`` is requested, written last.
"""

from __future__ import annotations

import json
import math
from collections.abc import Callable
from pathlib import Path
from typing import Any

from ..commands._common import write_atomic

__all__ = ["WRITERS", "jsonable", "write_outputs"]


def jsonable(x: Any) -> Any:
    """Plain JSON types from nested dicts, dataclass dicts and numpy values."""
    import numpy as np

    if hasattr(x, "items"):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, np.generic):
        return jsonable(x.item())
    if isinstance(x, float) and not math.isfinite(x):
        return None
    if isinstance(x, (str, int, float, bool)) or x is None:
        return x
    if hasattr(x, "to_dict"):
        return jsonable(x.to_dict())
    return str(x)


def _json(path: Path, obj: Any) -> list[Path]:
    return [write_atomic(path, json.dumps(jsonable(obj), indent=1, allow_nan=False))]


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
    return _json(folder / "spectra.json", {"speed_rpm": sp.speed_rpm, "spectra": sp.spectra})


def _waterfall(sw, folder: Path) -> list[Path]:
    points = [
        {
            "speed_rpm": p.speed_rpm,
            "torque_Nm": p.torque_Nm,
            "status": p.status,
            "metrics": dict(p.metrics),
            "nfev": p.nfev,
            "wall_time_s": p.wall_time,
        }
        for p in sw.points
    ]
    return _json(folder / "waterfall.json", {"points": points, "waterfalls": sw.waterfalls})


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
}


def write_outputs(run, folder: str | Path) -> list[Path]:
    """Write the run's files into ``folder``; return their paths in writing order."""
    folder = Path(folder)
    files: list[Path] = []
    summary = run.summary.to_dict() | {"keys": dict(run.keys)}
    files.append(write_atomic(folder / "run_summary.json", json.dumps(summary, indent=2)))
    for name in run.summary.requested:
        result = run.results.get(name)
        if result is None:
            continue
        if name in WRITERS:
            files += WRITERS[name](result, folder)
        elif hasattr(result, "write_files"):
            files += [Path(p) for p in result.write_files(folder)]
        elif hasattr(result, "to_dict"):
            files += _json(folder / f"{name}.json", result.to_dict())
    if "report" in run.summary.requested:
        from ..report import write_report

        files.append(write_report(run, folder / "report.html"))
    return files

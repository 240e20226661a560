"""Files a run leaves in its output folder, each written atomically.

- ``run_summary.json``: :meth:`RunSummary.to_dict` plus the cache keys;
- ``<stage>.json`` for each requested stage whose result has ``to_dict()``
  (arrays as lists);
- files a stage's result writes itself (``write_files(folder) -> list[Path]``, e.g.
  mesh tables as netCDF and CSV);
- ``report.html`` when ``report`` is requested.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

from ..commands._common import write_atomic

__all__ = ["jsonable", "write_outputs"]


def jsonable(x: Any) -> Any:
    """Plain JSON types from nested dicts, dataclass dicts and numpy values."""
    import numpy as np

    if isinstance(x, dict):
        return {str(k): jsonable(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [jsonable(v) for v in x]
    if isinstance(x, np.ndarray):
        return jsonable(x.tolist())
    if isinstance(x, np.generic):
        return x.item()
    if isinstance(x, float) and x != x:
        return None
    if isinstance(x, (str, int, float, bool)) or x is None:
        return x
    return str(x)


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
        if hasattr(result, "write_files"):
            files += [Path(p) for p in result.write_files(folder)]
        elif hasattr(result, "to_dict"):
            text = json.dumps(jsonable(result.to_dict()), indent=2, allow_nan=False)
            files.append(write_atomic(folder / f"{name}.json", text))
    if "report" in run.summary.requested:
        from ..report import write_report

        files.append(write_report(run, folder / "report.html"))
    return files

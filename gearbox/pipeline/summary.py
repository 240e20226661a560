"""What a run did: one record per stage (computed, cached, ...) and its time."""

from __future__ import annotations

from dataclasses import asdict, dataclass
from typing import Any

__all__ = ["STATUSES", "RunSummary", "StageRecord"]

#: Stage outcomes, in words for the summary table and the report.
STATUSES = {
    "computed": "computed in this run",
    "cached": "loaded from the cache",
    "unavailable": "not available in this installation",
    "failed": "raised an error",
    "skipped": "not run: an upstream stage did not produce a result",
}


@dataclass(frozen=True)
class StageRecord:
    """One stage of one run.

    ``seconds`` is the wall time spent on the stage in this run (s); for a cached
    stage ``saved_seconds`` is the time its stored result took to compute (s).
    ``bad_input``: a failed stage whose inputs were found wrong while it computed (an
    :class:`~gearbox.errors.InputError`: ``detail`` lists the problems), not a fault.
    """

    name: str
    status: str
    seconds: float = 0.0
    key: str = ""
    detail: str = ""
    saved_seconds: float = 0.0
    bad_input: bool = False

    def __post_init__(self):
        if self.status not in STATUSES:
            raise ValueError(f"status {self.status!r} must be one of {', '.join(STATUSES)}")


@dataclass(frozen=True)
class RunSummary:
    """All stages of one run, in the order they ran, and the run's own facts.

    ``requested`` are the outputs asked for; ``cache_dir`` is ``""`` when caching was
    off; ``seconds`` is the wall time of the whole run (s).
    """

    records: tuple[StageRecord, ...]
    requested: tuple[str, ...]
    seconds: float
    cache_dir: str = ""
    started: str = ""

    def record(self, name: str) -> StageRecord:
        for r in self.records:
            if r.name == name:
                return r
        raise KeyError(name)

    def names(self, status: str) -> tuple[str, ...]:
        """Stages with the given status, in run order."""
        return tuple(r.name for r in self.records if r.status == status)

    @property
    def ok(self) -> bool:
        """True when no stage failed."""
        return not any(r.status == "failed" for r in self.records)

    def table(self) -> str:
        """Plain-text table: stage, status, seconds, detail."""
        rows = [("stage", "status", "seconds", "detail")]
        for r in self.records:
            detail = r.detail
            if r.bad_input:  # its first line; the problems follow the table
                detail = detail.splitlines()[0] if detail else "bad input"
            if r.status == "cached" and r.saved_seconds:
                detail = f"saved {r.saved_seconds:.2f} s" + (f"; {detail}" if detail else "")
            rows.append((r.name, r.status, f"{r.seconds:.2f}", detail))
        rows.append(("total", "", f"{self.seconds:.2f}", f"cache: {self.cache_dir or 'off'}"))
        w = [max(len(row[i]) for row in rows) for i in range(3)]
        lines = [f"{a:<{w[0]}}  {b:<{w[1]}}  {c:>{w[2]}}  {d}".rstrip() for a, b, c, d in rows]
        lines.insert(1, "-" * max(len(x) for x in lines))
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        d = asdict(self)
        d["records"] = [asdict(r) for r in self.records]
        d["requested"] = list(self.requested)
        return d

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> RunSummary:
        return cls(
            records=tuple(StageRecord(**r) for r in d["records"]),
            requested=tuple(d["requested"]),
            seconds=float(d["seconds"]),
            cache_dir=d.get("cache_dir", ""),
            started=d.get("started", ""),
        )

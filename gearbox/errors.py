"""Input validation shared by every stage.

Problems are collected, not raised one at a time: a whole configuration is checked
and one :class:`InputError` lists every problem with its key path, its value and the
valid range (the habit of FMPy's ``validate_fmu``).
"""

from __future__ import annotations

from dataclasses import dataclass, field

__all__ = ["InputError", "Problem", "Problems"]


@dataclass(frozen=True)
class Problem:
    """One invalid input: where it is, what it is, and what would be valid."""

    path: str
    value: object
    expected: str

    def __str__(self) -> str:
        return f"{self.path} = {self.value!r}: {self.expected}"


class InputError(ValueError):
    """Invalid input; ``problems`` lists every problem found."""

    def __init__(self, problems: list[Problem] | Problem, context: str = "invalid input"):
        if isinstance(problems, Problem):
            problems = [problems]
        self.problems = list(problems)
        if not self.problems:  # a problem with no key path (a file that does not read)
            super().__init__(context)
            return
        lines = [
            f"{context} ({len(self.problems)} problem{'s' if len(self.problems) != 1 else ''}):"
        ]
        lines += [f"  - {p}" for p in self.problems]
        super().__init__("\n".join(lines))


@dataclass
class Problems:
    """Collector: ``check`` records a problem when a condition fails; ``raise_if_any``."""

    items: list[Problem] = field(default_factory=list)

    def add(self, path: str, value: object, expected: str) -> None:
        self.items.append(Problem(path, value, expected))

    def check(self, ok: bool, path: str, value: object, expected: str) -> bool:
        if not ok:
            self.add(path, value, expected)
        return ok

    def in_range(
        self,
        path: str,
        value: float,
        lo: float | None = None,
        hi: float | None = None,
        *,
        lo_open: bool = False,
        hi_open: bool = False,
    ) -> bool:
        """Record a problem unless ``lo <= value <= hi`` (open ends on request)."""
        ok = True
        if lo is not None:
            ok &= value > lo if lo_open else value >= lo
        if hi is not None:
            ok &= value < hi if hi_open else value <= hi
        if not ok:
            left = "(" if lo_open else "["
            right = ")" if hi_open else "]"
            lo_s = "-inf" if lo is None else f"{lo:g}"
            hi_s = "inf" if hi is None else f"{hi:g}"
            self.add(path, value, f"must be in {left}{lo_s}, {hi_s}{right}")
        return bool(ok)

    def raise_if_any(self, context: str = "invalid input") -> None:
        if self.items:
            raise InputError(self.items, context)

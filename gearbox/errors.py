"""Input validation shared by every stage.

Problems are collected, not raised one at a time: a whole configuration is checked
and one :class:`InputError` lists every problem with its key path, its value and the
valid range (the habit of FMPy's ``validate_fmu``).
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Mapping
from dataclasses import dataclass, field

import numpy as np

__all__ = ["InputError", "Problem", "Problems", "expect_scene", "expect_type", "is_real"]


@dataclass(frozen=True)
class Problem:
    """One invalid input: where it is, what it is, and what would be valid."""

    path: str
    value: object
    expected: str

    def __str__(self) -> str:
        return f"{self.path} = {_shown(self.value)}: {self.expected}"


def _shown(value) -> str:
    """``repr(value)``; a float to 12 significant digits first, so that a value taken
    from the scene's units and back (mm -> m -> mm) reads as given (1e-06, not
    1.0000000000000002e-06)."""
    if isinstance(value, float) and math.isfinite(value):
        return repr(float(f"{value:.12g}"))
    return repr(value)


class InputError(ValueError):
    """Invalid input; ``problems`` lists every problem found."""

    def __init__(self, problems: list[Problem] | Problem, context: str = "invalid input"):
        if isinstance(problems, Problem):
            problems = [problems]
        self.problems = list(problems)
        self.context = context
        if not self.problems:  # a problem with no key path (a file that does not read)
            super().__init__(context)
            return
        lines = [
            f"{context} ({len(self.problems)} problem{'s' if len(self.problems) != 1 else ''}):"
        ]
        lines += [f"  - {p}" for p in self.problems]
        super().__init__("\n".join(lines))


def is_real(value) -> bool:
    """A real number (Python or numpy, 0-d arrays included), not a bool."""
    if isinstance(value, np.ndarray) and value.ndim == 0:
        value = value[()]
    return isinstance(value, numbers.Real) and not isinstance(value, bool | np.bool_)


def expect_type(value, types, name: str, hint: str = "") -> None:
    """Raise TypeError unless ``isinstance(value, types)``: the message names the
    parameter, what it must be (and ``hint``, how to make one) and what it got."""
    if isinstance(value, types):
        return
    want = " or ".join(t.__name__ for t in (types if isinstance(types, tuple) else (types,)))
    got = f"{type(value).__name__} {value!r}"
    got = got if len(got) <= 80 else got[:77] + "..."
    raise TypeError(f"{name} must be a {want}{f' ({hint})' if hint else ''}; got {got}")


def expect_scene(scene, name: str = "scene") -> None:
    """Raise TypeError unless ``scene`` reads like a scene (a mapping of sections): a
    file path, the usual slip, is named as such."""
    import os

    if isinstance(scene, str | os.PathLike):
        raise TypeError(f"{name} must be a scene (gearbox.load_scene({str(scene)!r})), not a path")
    if not hasattr(scene, "__getitem__"):
        expect_type(scene, Mapping, name, "a scene: gearbox.load_scene(path)")


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
        """Record a problem unless ``lo <= value <= hi`` (open ends on request); a value
        that is not a real number (a string, None, a bool) is a problem too."""
        real = is_real(value)
        ok = real
        if ok and lo is not None:
            ok = value > lo if lo_open else value >= lo
        if ok and hi is not None:
            ok = value < hi if hi_open else value <= hi
        if not ok:
            kind = "" if real else "a number "
            self.add(path, value, f"must be {kind}in {self.range_text(lo, hi, lo_open, hi_open)}")
        return bool(ok)

    def integer(self, path: str, value, lo: int) -> bool:
        """Record a problem unless ``value`` is an integer (Python or numpy, not a bool)
        of at least ``lo``."""
        ok = isinstance(value, int | np.integer) and not isinstance(value, bool) and value >= lo
        return self.check(bool(ok), path, value, f"must be an integer >= {lo}")

    @staticmethod
    def range_text(lo, hi, lo_open: bool = False, hi_open: bool = False) -> str:
        """``[lo, hi]``, open ends as ``( )``; a missing bound is an open infinity."""
        left = "(" if lo_open or lo is None else "["
        right = ")" if hi_open or hi is None else "]"
        lo_s = "-inf" if lo is None else f"{lo:g}"
        hi_s = "inf" if hi is None else f"{hi:g}"
        return f"{left}{lo_s}, {hi_s}{right}"

    def raise_if_any(self, context: str = "invalid input") -> None:
        if self.items:
            raise InputError(self.items, context)

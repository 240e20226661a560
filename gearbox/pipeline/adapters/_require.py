"""Import a stage module or report the stage unavailable."""

from __future__ import annotations

import importlib
from typing import Any

from ..stage import StageUnavailable

__all__ = ["require"]


def require(module: str, *names: str) -> Any:
    """Import ``module`` and check it has ``names``; raise StageUnavailable otherwise."""
    try:
        mod = importlib.import_module(module)
    except ImportError as exc:
        raise StageUnavailable(f"{module} cannot be imported ({exc})") from None
    missing = [n for n in names if not hasattr(mod, n)]
    if missing:
        raise StageUnavailable(f"{module} has no {', '.join(missing)} in this version")
    return mod

"""The stages of ``gearbox run`` (docs/pipeline.md draws the graph).

Each adapter imports its stage's module when it runs, so ``import gearbox`` stays
light and a stage whose module (or optional extra) is missing is reported as
unavailable rather than replaced by anything else.
"""

from __future__ import annotations

import importlib
from types import MappingProxyType
from typing import Any

from .stage import Stage, StageContext, StageUnavailable

__all__ = ["STAGES", "require"]

_PAIR = ("pair", "pinion", "gear", "tool")


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


# -- design ----------------------------------------------------------------------


def _pair_spec(scene):
    geometry = require("gearbox.geometry", "PairSpec", "design_pair")
    return geometry.PairSpec.from_scene(scene)


def _design(ctx: StageContext):
    geometry = require("gearbox.geometry", "PairSpec", "design_pair")
    return geometry.design_pair(_pair_spec(ctx.scene))


STAGES: MappingProxyType[str, Stage] = MappingProxyType(
    {
        "design": Stage(
            "design",
            _design,
            reads=_PAIR,
            code=("gearbox.geometry",),
            validate=_pair_spec,
            doc="Pitch cone design, FPD angles and checks (paper section 2).",
        ),
    }
)

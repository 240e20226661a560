"""Report sections of one stage: what their renderer sees and their cache key.

A renderer of stage ``name`` sees the stage's result and a run view holding only
that result, its key and the scene entries of :data:`SECTION_READS` (reading
anything else raises ``KeyError``, named in the report's warnings). So a section
depends on the stage's key and those entries only, and is kept in the run's cache
under :func:`section_key`: a stage that came from the cache is not drawn again.
(Drawing the sections on a background thread while later stages computed was tried
and measured: no faster on a 16-core machine, the drawing and the stages' Python
parts share the GIL. ``gearbox run`` draws them in a second process instead:
:mod:`gearbox.pipeline.overlap`.)
"""

from __future__ import annotations

import time
from collections.abc import Callable
from types import MappingProxyType
from typing import Any

from .html import Section

__all__ = [
    "SECTION_CODE",
    "SECTION_PACKAGES",
    "SECTION_READS",
    "draw",
    "section_key",
    "stage_view",
]

#: Scene entries a section reads besides its stage's result; they enter its cache key.
SECTION_READS: dict[str, tuple[str, ...]] = {
    "ltca": ("load.operating_torque_Nm", "drivetrain.engine_speed_rpm"),
    "dynamics": ("load.operating_torque_Nm",),  # the drive's torque set beside it
    # the line load of ISO 6336-1's resonance range (report.dynamics.line_load)
    "campbell": (
        "pair.normal_module_mm",
        "pinion.teeth",
        "pinion.helix_angle_deg",
        "pinion.face_width_mm",
        "gear.face_width_mm",
    ),
}

#: Modules that draw the sections; their source enters every section's cache key.
SECTION_CODE = (
    "gearbox.report",
    "gearbox.geometry.plotting",
    "gearbox.tca.plot",
    "gearbox.ltca.plot",
    "gearbox.spectrum.plotting",
)

#: Distributions whose versions enter the section keys (they shape the figures).
SECTION_PACKAGES = ("matplotlib", "numpy")


def stage_view(scene, name: str, result: Any, key: str):
    """What a renderer of stage ``name`` sees: a run with only its result and key, the
    scene entries of :data:`SECTION_READS` and an empty summary (the summary changes
    every run)."""
    from ..pipeline.runner import PipelineRun
    from ..pipeline.stage import restricted_scene
    from ..pipeline.summary import RunSummary

    return PipelineRun(
        restricted_scene(scene, SECTION_READS.get(name, ())),
        MappingProxyType({name: result}),
        MappingProxyType({name: key}),
        RunSummary((), (), 0.0),
    )


def section_key(scene, name: str, key: str) -> str:
    """Cache key of the section(s) of stage ``name`` whose result has ``key``."""
    from ..pipeline.cache import derived_key
    from ..pipeline.stage import read_values

    return derived_key(
        "report",
        name,
        key,
        code=SECTION_CODE,
        values=read_values(scene, SECTION_READS.get(name, ())),
        packages=SECTION_PACKAGES,
    )


def draw(
    name: str, render: Callable, scene, result: Any, key: str, cache=None
) -> tuple[tuple[Section, ...], str]:
    """The section(s) of one stage and where they came from: ``"cached"``, or the
    seconds spent drawing. With a cache, they are taken from it or stored there."""
    from ..pipeline.cache import remembered

    t0 = time.perf_counter()

    def make() -> tuple[Section, ...]:
        got = render(result, stage_view(scene, name, result, key))
        return tuple(got if isinstance(got, list) else [got])

    skey = section_key(scene, name, key) if cache is not None else ""
    sections, hit = remembered(cache, "report", skey, make)
    return tuple(sections), ("cached" if hit else f"{time.perf_counter() - t0:.2f}")

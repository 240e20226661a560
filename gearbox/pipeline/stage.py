"""A stage of the pipeline: a function of some scene sections and of upstream results.

Each stage declares what it reads, so that its cache key can be made from exactly
that: the scene sections (or single ``section.key`` entries) it depends on and the
stages upstream of it. The stage function sees a scene restricted to what it
declared; reading anything else raises ``KeyError``, so an incomplete declaration
shows up at once instead of as a stale cache entry.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any

from ..scene import Scene

__all__ = ["Stage", "StageContext", "StageUnavailable", "restricted_scene"]


class StageUnavailable(RuntimeError):
    """The stage cannot run in this installation (its module or an extra is missing).

    The message says what is missing; the run records the stage as ``unavailable``
    and the report says so. Nothing is put in its place.
    """


@dataclass(frozen=True)
class Stage:
    """One node of the stage graph.

    Attributes
    ----------
    name : str
        Stage name; also the name of the output in ``outputs.requested``.
    compute : callable
        ``compute(ctx: StageContext) -> result``. The result is an immutable object,
        preferably a frozen dataclass with ``to_dict()`` / ``from_dict()``.
    reads : tuple of str
        Scene entries the stage reads: a section name (``"drivetrain"``) or one key
        (``"load.torques_Nm"``). They, and nothing else of the scene, enter its key.
    depends : tuple of str
        Upstream stages whose results ``compute`` receives in ``ctx.inputs``; when
        one of them produced no result, this stage is skipped.
    optional : tuple of str
        Upstream stages used when they produced a result (else absent from
        ``ctx.inputs``); planned and run like ``depends``.
    route : callable, optional
        ``route(scene) -> (depends, optional)`` for a stage whose upstream depends on
        a scene value (e.g. ``outputs.mesh_tables``); overrides the two fields. It
        sees the whole scene, so what it reads must also be in ``reads``.
    reads_also : callable, optional
        ``reads_also(scene) -> entries`` read besides ``reads`` only for some scene
        values (the ``[pitch]`` section when ``drivetrain.pitch_deviations`` is on):
        they enter the key and the restricted scene then, and only then. What it
        reads itself must be in ``reads``.
    code : tuple of str
        Modules or packages whose source enters the cache key, so that a changed
        implementation is recomputed even without a version bump; the module of
        ``compute`` itself is always added.
    validate : callable, optional
        ``validate(scene) -> None``: cheap checks of the stage's inputs, run for every
        planned stage before anything is computed; raises ``InputError``.
    cacheable : bool
        Whether results are stored in the on-disk cache.
    blas_threads : int, optional
        Threads of the BLAS library (OpenBLAS, MKL) while ``compute`` runs, threads it
        starts included (:func:`gearbox.pipeline.sweep.blas_limit`); None leaves the library's own count. The
        drivetrain stages take 1: their linear algebra is many small products, which a
        BLAS thread pool does not speed up while its threads spin between calls on cores
        the sweep's own threads and the output worker need (docs/pipeline.md).
    doc : str
        One line for ``--help`` and the report.
    """

    name: str
    compute: Callable[[StageContext], Any]
    reads: tuple[str, ...] = ()
    depends: tuple[str, ...] = ()
    optional: tuple[str, ...] = ()
    route: Callable[[Scene], tuple[tuple[str, ...], tuple[str, ...]]] | None = None
    reads_also: Callable[[Scene], tuple[str, ...]] | None = None
    code: tuple[str, ...] = ()
    validate: Callable[[Scene], None] | None = None
    cacheable: bool = True
    blas_threads: int | None = None
    doc: str = ""

    def reads_for(self, scene: Scene) -> tuple[str, ...]:
        """The scene entries the stage reads for ``scene``: ``reads`` and
        ``reads_also(scene)``."""
        if self.reads_also is None:
            return tuple(self.reads)
        return (*self.reads, *self.reads_also(scene))

    def upstream(self, scene: Scene | None = None) -> tuple[tuple[str, ...], tuple[str, ...]]:
        """(required, optional) upstream stages, for ``scene`` when the stage routes."""
        if self.route is not None and scene is not None:
            req, opt = self.route(scene)
            return tuple(req), tuple(opt)
        return tuple(self.depends), tuple(self.optional)


@dataclass(frozen=True)
class StageContext:
    """What a stage function receives.

    ``scene`` is restricted to the stage's ``reads``; ``inputs`` maps each upstream
    stage name to its result; ``map`` runs a sweep through the run's executor.
    """

    name: str
    scene: Scene
    inputs: Mapping[str, Any]
    map: Callable[..., list] = field(repr=False)
    progress: bool = False


def _split(entry: str) -> tuple[str, str | None]:
    sec, _, key = entry.partition(".")
    return sec, (key or None)


def restricted_scene(scene: Scene, reads: Iterable[str]) -> Scene:
    """A scene holding only the entries in ``reads`` (plus the top-level name).

    The top-level section (``schema``, ``name``, ``description``) is kept so that
    results may name their scene; it does not enter cache keys.
    """
    keep: dict[str, dict[str, Any] | None] = {}
    for entry in reads:
        sec, key = _split(entry)
        if key is None:
            keep[sec] = None
        elif keep.get(sec, {}) is not None:
            keep.setdefault(sec, {})[key] = scene[sec][key]
    data: dict[str, Mapping[str, Any]] = {"": scene[""]}
    for sec, sub in keep.items():
        data[sec] = scene[sec] if sub is None else MappingProxyType(sub)
    return Scene(MappingProxyType(data), scene.path)


def read_values(scene: Scene, reads: Iterable[str]) -> dict[str, Any]:
    """The scene values named by ``reads``, as a plain dict (for cache keys)."""
    out: dict[str, Any] = {}
    for entry in sorted(set(reads)):
        sec, key = _split(entry)
        out[entry] = dict(scene[sec]) if key is None else scene[sec][key]
    return out

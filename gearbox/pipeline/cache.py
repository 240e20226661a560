"""The on-disk cache of stage results.

An entry is one file ``<root>/<stage>/<key>.gbx`` written atomically (temporary file,
then rename). Its first line is a format tag, its second the SHA-256 of the payload;
an entry whose tag, checksum or payload does not load is treated as absent (and
removed), so a corrupt or truncated entry is recomputed, never used.

The payload is a pickle. Results with ``to_dict()`` / ``from_dict()`` are stored
through them (the stored form does not depend on the class layout); other results
are pickled as they are. Pickles run code when loaded: keep the cache directory
private to its user, as any cache of pickled data.

Keys (:func:`stage_key`) hash the stage name, the package version, a fingerprint of
the stage's source code, the scene entries the stage reads and the keys of the
upstream stages, so a change anywhere upstream changes every key downstream of it.
"""

from __future__ import annotations

import functools
import hashlib
import importlib
import importlib.util
import json
import os
import pickle
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .. import __version__
from .._pickling import dumps
from ..commands._common import write_atomic

__all__ = [
    "Cache",
    "CacheMiss",
    "code_fingerprint",
    "default_cache_dir",
    "derived_key",
    "remembered",
    "stage_key",
]

_MAGIC = b"GEARBOX-CACHE 1\n"


class CacheMiss(LookupError):
    """No usable entry; ``reason`` says whether it was absent or corrupt."""

    def __init__(self, reason: str, corrupt: bool = False):
        super().__init__(reason)
        self.reason = reason
        self.corrupt = corrupt


def default_cache_dir() -> Path:
    """``$GEARBOX_CACHE``, else ``$XDG_CACHE_HOME/gearbox``, else ``~/.cache/gearbox``."""
    if os.environ.get("GEARBOX_CACHE"):
        return Path(os.environ["GEARBOX_CACHE"])
    base = os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache"
    return Path(base) / "gearbox"


_FINGERPRINTS: dict[str, str] = {}


def code_fingerprint(modules: tuple[str, ...]) -> str:
    """SHA-256 over the source files of the named modules or packages.

    A package contributes every ``.py`` file under its directory. A module that
    cannot be found contributes its name only (the stage will report it missing).
    """
    h = hashlib.sha256()
    for name in sorted(modules):
        if name not in _FINGERPRINTS:
            sub = hashlib.sha256(name.encode())
            try:
                spec = importlib.util.find_spec(name)
            except (ImportError, ValueError):
                spec = None
            files: list[Path] = []
            if spec is not None and spec.submodule_search_locations:
                for loc in spec.submodule_search_locations:
                    files += sorted(Path(loc).rglob("*.py"))
            elif spec is not None and spec.origin and spec.origin.endswith(".py"):
                files = [Path(spec.origin)]
            for f in files:
                sub.update(f.name.encode())
                sub.update(f.read_bytes())
            _FINGERPRINTS[name] = sub.hexdigest()
        h.update(_FINGERPRINTS[name].encode())
    return h.hexdigest()


def stage_key(
    name: str,
    values: dict[str, Any],
    upstream: dict[str, str],
    code: tuple[str, ...] = (),
) -> str:
    """Cache key (hex SHA-256) of one stage run.

    ``values`` are the scene entries the stage reads (scene units, as validated),
    ``upstream`` maps each upstream stage to its key.
    """
    doc = {
        "stage": name,
        "gearbox": __version__,
        "code": code_fingerprint(code),
        "scene": values,
        "upstream": upstream,
    }
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


@functools.cache
def _version(dist: str) -> str | None:
    from importlib import metadata

    try:
        return metadata.version(dist)
    except metadata.PackageNotFoundError:
        return None


def derived_key(
    kind: str,
    stage: str,
    key: str,
    *,
    code: tuple[str, ...] = (),
    values: dict[str, Any] | None = None,
    packages: tuple[str, ...] = (),
) -> str:
    """Cache key (hex SHA-256) of something made from one stage result: its report
    section, its output files.

    It hashes ``kind``, the stage and its key (so everything the result depends on),
    the source of the ``code`` that makes the thing from the result, the scene
    ``values`` that code reads besides the result, and the installed versions of the
    distributions in ``packages`` (e.g. matplotlib for figures).
    """
    versions = {dist: _version(dist) for dist in packages}
    doc = {
        "kind": kind,
        "stage": stage,
        "key": key,
        "code": code_fingerprint(code),
        "scene": values or {},
        "packages": versions,
    }
    text = json.dumps(doc, sort_keys=True, separators=(",", ":"), allow_nan=True)
    return hashlib.sha256(text.encode()).hexdigest()


def remembered(
    store: Cache | None, kind: str, key: str, make: Callable[[], Any]
) -> tuple[Any, bool]:
    """``(value, from_cache)``: the entry ``<root>/<kind>/<key>.gbx`` when it loads,
    else ``make()``, stored there (a failure to store is ignored: the value is used
    anyway). Without a store, ``make()``."""
    if store is not None:
        try:
            return store.load(kind, key)[0], True
        except CacheMiss:
            pass
    t0 = time.perf_counter()
    value = make()
    if store is not None:
        try:
            store.store(kind, key, value, time.perf_counter() - t0)
        except Exception:  # a full disk or an unpicklable value: go on uncached
            pass
    return value, False


def _encode(result: Any) -> bytes:
    cls = type(result)
    if hasattr(result, "to_dict") and hasattr(cls, "from_dict"):
        body = {
            "form": "dict",
            "type": f"{cls.__module__}:{cls.__qualname__}",
            "data": result.to_dict(),
        }
    else:
        body = {"form": "object", "data": result}
    return dumps(body)


def _decode(payload: bytes) -> Any:
    body = pickle.loads(payload)  # noqa: S301 - the user's own cache, see module doc
    if body["form"] == "object":
        return body["data"]
    modname, _, qual = body["type"].partition(":")
    obj: Any = importlib.import_module(modname)
    for part in qual.split("."):
        obj = getattr(obj, part)
    return obj.from_dict(body["data"])


@dataclass(frozen=True)
class Cache:
    """Stage results on disk under ``root`` (see the module doc for the format)."""

    root: Path

    def path(self, stage: str, key: str) -> Path:
        return Path(self.root) / stage / f"{key}.gbx"

    def load(self, stage: str, key: str) -> tuple[Any, dict[str, Any]]:
        """The stored result and its metadata; raise :class:`CacheMiss` otherwise.

        A corrupt entry is removed before ``CacheMiss(corrupt=True)`` is raised.
        """
        p = self.path(stage, key)
        try:
            raw = p.read_bytes()
        except FileNotFoundError:
            raise CacheMiss("no entry") from None
        except OSError as exc:
            raise CacheMiss(f"unreadable entry: {exc}", corrupt=True) from None
        try:
            if not raw.startswith(_MAGIC):
                raise ValueError("bad header")
            digest, _, payload = raw[len(_MAGIC) :].partition(b"\n")
            if hashlib.sha256(payload).hexdigest().encode() != digest:
                raise ValueError("checksum mismatch")
            meta, blob = pickle.loads(payload)  # noqa: S301 - see module doc
            return _decode(blob), meta
        except Exception as exc:  # any failure to load means: not usable
            p.unlink(missing_ok=True)
            raise CacheMiss(
                f"corrupt entry removed ({type(exc).__name__}: {exc})", corrupt=True
            ) from None

    def store(self, stage: str, key: str, result: Any, seconds: float) -> Path:
        """Write one entry atomically; ``seconds`` is the time it took to compute."""
        meta = {"stage": stage, "key": key, "seconds": float(seconds), "created": time.time()}
        payload = dumps((meta, _encode(result)))
        digest = hashlib.sha256(payload).hexdigest().encode()
        return write_atomic(self.path(stage, key), _MAGIC + digest + b"\n" + payload)

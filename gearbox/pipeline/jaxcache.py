"""jax's persistent compilation cache in the pipeline's cache folder, ``<cache>/jax``.

A new process (every ``gearbox run``) would otherwise trace and compile the jitted
solver again. With the cache on, XLA's compiled executables are written to
``<cache>/jax`` and read back by later processes with the same program, jax, XLA and
device (jax makes the key; what changes the program, such as another number of
steps, is another entry). The fixed-step solver's executables hold no Python
callbacks, so jax stores them (jax refuses executables that call back into Python).

Every compilation is stored, however short (``JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS``
set to 0 unless the environment sets it): the pipeline's small jitted helpers are
compiled in every process too. A ``JAX_COMPILATION_CACHE_DIR`` set in the
environment (or through ``jax.config``) is left as it is. The setting holds while the
run lasts (worker processes started by the run inherit it) and is undone after it.

Tracing and lowering the solver still cost a new process 0.5-0.9 s before jax's cache
can be asked (its key is made from the lowered program). The solver's executables are
therefore also kept whole, keyed by what decides them, under ``<cache>/executables``
(:class:`ExecutableStore`, hooked into :mod:`gearbox.drivetrain.diffrax_backend`
for the run by :func:`attach`): a later process loads them without tracing.

Like the rest of the cache folder, keep it private: jax runs what it loads from there,
and the executables' files are pickles.
"""

from __future__ import annotations

import hashlib
import logging
import os
import pickle
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

__all__ = ["DIR_ENV", "MIN_TIME_ENV", "ExecutableStore", "attach", "jax_cache"]

_log = logging.getLogger("gearbox.pipeline")

DIR_ENV = "JAX_COMPILATION_CACHE_DIR"
MIN_TIME_ENV = "JAX_PERSISTENT_CACHE_MIN_COMPILE_TIME_SECS"
#: jax's own default of the shortest compilation it stores (s).
JAX_MIN_TIME_DEFAULT = 1.0


def _configure(folder: str | None, min_time: float) -> None:
    """Point an imported jax at ``folder`` (None: no persistent cache)."""
    import jax
    from jax.experimental.compilation_cache import compilation_cache

    jax.config.update("jax_compilation_cache_dir", folder)
    jax.config.update("jax_persistent_cache_min_compile_time_secs", min_time)
    compilation_cache.reset_cache()  # the cache opens its folder once; open it anew


def _configured_elsewhere() -> str | None:
    """The cache folder the user chose: the environment's, else jax's configuration."""
    given = os.environ.get(DIR_ENV)
    if given:
        return given
    if "jax" in sys.modules:
        import jax

        return jax.config.jax_compilation_cache_dir or None
    return None


@contextmanager
def jax_cache(root: str | Path) -> Iterator[Path]:
    """While the block runs, jax stores its compiled executables under ``root / "jax"``
    (``root``: the pipeline's cache folder), in this process and in the worker
    processes started meanwhile; yields the folder in use (the user's, when set)."""
    given = _configured_elsewhere()
    if given:
        with _executables(root):
            yield Path(given)
        return
    folder = str(Path(root) / "jax")
    saved = {k: os.environ.get(k) for k in (DIR_ENV, MIN_TIME_ENV)}
    os.environ[DIR_ENV] = folder
    os.environ.setdefault(MIN_TIME_ENV, "0")
    if "jax" in sys.modules:  # imported already: its configuration read the environment then
        _configure(folder, float(os.environ[MIN_TIME_ENV]))
    try:
        with _executables(root):
            yield Path(folder)
    finally:
        for k, v in saved.items():
            if v is None:
                os.environ.pop(k, None)
            else:
                os.environ[k] = v
        if "jax" in sys.modules:
            min_time = saved[MIN_TIME_ENV]
            _configure(None, float(min_time) if min_time else JAX_MIN_TIME_DEFAULT)


#: The store of the run in progress (:func:`jax_cache`), None outside a run.
_active: ExecutableStore | None = None


@contextmanager
def _executables(root: str | Path) -> Iterator[None]:
    global _active
    previous, _active = _active, ExecutableStore(Path(root) / "executables")
    try:
        yield
    finally:
        _active = previous
        backend = sys.modules.get("gearbox.drivetrain.diffrax_backend")
        if backend is not None:
            backend.executable_store = previous


def attach() -> None:
    """Hand the run's :class:`ExecutableStore` to the jax backend (a stage about to run
    the diffrax solver calls this; importing the backend imports jax, which stages
    that do not simulate should not pay)."""
    if _active is not None:
        from ..drivetrain import diffrax_backend

        diffrax_backend.executable_store = _active


class ExecutableStore:
    """Compiled jax executables in ``folder``, one file per key: the backend's key
    (solver, method, table size, shapes) with jax's and jaxlib's versions, the
    platform and device kind, the float64 flag and a fingerprint of the source of
    :mod:`gearbox.drivetrain` (what else decides the program). A file that does not
    load is removed and the executable compiled again; a failed save is logged and
    the run goes on."""

    def __init__(self, folder: str | Path):
        self.folder = Path(folder)
        self._env: str | None = None

    def _path(self, key) -> Path:
        if self._env is None:
            import jax
            import jaxlib

            from .cache import code_fingerprint

            dev = jax.devices()[0]
            env = (jax.__version__, jaxlib.__version__, dev.platform, dev.device_kind)
            env += (bool(jax.config.jax_enable_x64), code_fingerprint(("gearbox.drivetrain",)))
            self._env = repr(env)
        digest = hashlib.sha256(f"{self._env}|{key!r}".encode()).hexdigest()
        return self.folder / f"{digest}.exe"

    def get(self, key, compile):
        """The executable stored for ``key``; else ``compile()``'s, stored unless jax took
        it from its persistent cache: an executable that jax loaded serialises without
        all of its code (jax 0.10.2 on the CPU: the copy failed with ``Function
        multiply_sine_fusion not found`` when run), so it is not copied here."""
        compiled = self.load(key)
        if compiled is None:
            with _jax_cache_hits() as hits:
                compiled = compile()
            if not hits:
                self.save(key, compiled)
        return compiled

    def load(self, key):
        """The compiled executable stored for ``key``, or None."""
        path = self._path(key)
        try:
            blob = path.read_bytes()
        except OSError:
            return None
        try:
            from jax.experimental.serialize_executable import deserialize_and_load

            return deserialize_and_load(*pickle.loads(blob))
        except Exception as exc:  # an unreadable entry: compile again
            _log.warning("removed jax executable %s that did not load (%s)", path.name, exc)
            path.unlink(missing_ok=True)
            return None

    def save(self, key, compiled) -> None:
        """Store ``compiled`` for ``key`` (written to a temporary file, then renamed).
        An executable that calls back into Python (diffrax's adaptive runs, which a
        run that loses contact takes, check their steps through host callbacks) does
        not serialise: it is compiled in every process, as jax's own cache does with
        it, without a warning (logged at debug level); a file that cannot be written
        is warned of."""
        path = self._path(key)
        try:
            from jax.experimental.serialize_executable import serialize

            blob = pickle.dumps(serialize(compiled), protocol=pickle.HIGHEST_PROTOCOL)
        except Exception as exc:  # host callbacks: local functions do not pickle
            _log.debug("jax executable not stored (%s: %s)", type(exc).__name__, exc)
            return
        try:
            path.parent.mkdir(parents=True, exist_ok=True)
            tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
            tmp.write_bytes(blob)
            os.replace(tmp, path)
        except OSError as exc:  # a full disk, a folder not writable
            _log.warning("jax executable not stored (%s: %s)", type(exc).__name__, exc)


HIT_EVENT = "/jax/compilation_cache/cache_hits"


@contextmanager
def _jax_cache_hits() -> Iterator[list]:
    """A list that gets an entry for every executable jax loads from its persistent cache
    while the block runs (in any thread: a hit elsewhere only keeps one executable out of
    the store). When jax's events cannot be observed and its cache is on, one entry."""
    hits: list = []
    try:
        from jax._src import monitoring
    except ImportError:  # another jax: store nothing that may have come from its cache
        if os.environ.get(DIR_ENV) or _configured_elsewhere():
            hits.append("unknown")
        yield hits
        return

    def listen(event: str, **kwargs) -> None:
        if event == HIT_EVENT:
            hits.append(event)

    monitoring.register_event_listener(listen)
    try:
        yield hits
    finally:
        monitoring.unregister_event_listener(listen)

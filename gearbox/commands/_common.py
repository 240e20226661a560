"""Small helpers shared by the verb modules."""

from __future__ import annotations

import json
import os
import tempfile
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path


def add_scene_argument(parser) -> None:
    parser.add_argument("scene", help="scene file (TOML), e.g. models/case03.toml")


def scene_and_options(path, option_problems):
    """The scene at ``path``, read and validated, after the command's own options were
    checked (``option_problems``, a list of Problem): one InputError lists the options'
    problems and the scene's together, so that a user fixes both at once."""
    from ..errors import InputError
    from ..scene import load_scene

    try:
        scene = load_scene(path)
    except InputError as exc:
        if option_problems and exc.problems:
            problems = [*option_problems, *exc.problems]
            raise InputError(problems, f"invalid options; {exc.context}") from None
        if option_problems:  # the scene did not read at all: say that, and the options
            raise InputError(option_problems, f"{exc}; and invalid options") from None
        raise
    if option_problems:
        raise InputError(option_problems, "invalid options")
    return scene


@contextmanager
def atomic_target(path: str | Path) -> Iterator[Path]:
    """A temporary path beside ``path`` to write to; renamed to ``path`` when the block
    ends without an error, removed when it raises, so ``path`` is written completely or
    not at all. The file gets the permissions a plain ``open()`` would give it
    (``tempfile.mkstemp`` creates it readable by its owner only)."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def output_folder(
    path: str | Path, option: str = "--out", context: str = "cannot write the output"
) -> Path:
    """``path`` as the folder a command writes to, made if missing and checked to take
    a file (one created and removed at once), before the command computes anything;
    InputError naming ``option``, its value and the reason otherwise. Nothing already
    there is touched."""
    from ..errors import InputError, Problem

    folder = Path(path)
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fd, probe = tempfile.mkstemp(dir=folder, prefix=".gearbox-write-check.", suffix=".tmp")
        os.close(fd)
        os.unlink(probe)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        raise InputError(
            Problem(option, str(folder), f"must be a folder this user can write to ({reason})"),
            context,
        ) from None
    return folder


def add_cache_arguments(parser, what: str) -> None:
    """``--cache DIR`` / ``--no-cache`` (read by :func:`cache_of` and :func:`usable_cache`)."""
    group = parser.add_mutually_exclusive_group()
    group.add_argument(
        "--cache",
        metavar="DIR",
        default=None,
        help=f"cache folder for {what} (default $GEARBOX_CACHE, else ~/.cache/gearbox)",
    )
    group.add_argument("--no-cache", action="store_true", help="compute everything, store nothing")


def cache_of(args):
    """The cache setting of ``--cache`` / ``--no-cache``: False, a folder, or True (the
    default folder)."""
    return False if args.no_cache else (args.cache or True)


def usable_cache(cache, verb: str):
    """A cache setting (False, a folder, True for the default folder) checked before
    anything computes: a ``--cache`` folder that cannot be written is an input error
    (exit 2); the default folder (``$GEARBOX_CACHE``, else the user's cache folder)
    that cannot be written is warned of once (``gearbox VERB: ...``), and the command
    goes on without a cache (False)."""
    import sys

    from ..errors import InputError
    from ..pipeline.cache import default_cache_dir

    if cache is False:
        return False
    if cache is not True:
        output_folder(cache, "--cache", "cannot write the cache")
        return cache
    try:
        output_folder(default_cache_dir(), "cache folder")
    except InputError as exc:
        print(f"gearbox {verb}: {exc.problems[0]}; running without the cache", file=sys.stderr)
        return False
    return cache


@contextmanager
def staged_files(folder: str | Path) -> Iterator[Path]:
    """A hidden folder inside ``folder`` to write one command's files to; when the
    block ends without an error, every file in it is moved into ``folder`` (each move
    atomic, Ctrl-C held off while they run, a few milliseconds), and it is removed; when
    the block raises (an error, Ctrl-C), it is removed with whatever it held. So an
    interrupted command leaves ``folder`` as it was: the files of the last complete run,
    not some new ones beside old ones."""
    import shutil
    import signal
    import threading

    folder = Path(folder)
    stage = Path(tempfile.mkdtemp(dir=folder, prefix=".gearbox-partial."))
    try:
        yield stage
        files = sorted(p for p in stage.rglob("*") if p.is_file())
        held = threading.current_thread() is threading.main_thread()
        previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if held else None
        try:
            for f in files:
                target = folder / f.relative_to(stage)
                target.parent.mkdir(parents=True, exist_ok=True)
                os.replace(f, target)
        finally:
            if held:
                signal.signal(signal.SIGINT, previous)
    finally:
        shutil.rmtree(stage, ignore_errors=True)


def write_atomic(path: str | Path, data: str | bytes) -> Path:
    """Write a file completely or not at all: write a temporary file, then rename."""
    path = Path(path)
    with atomic_target(path) as tmp:
        if isinstance(data, bytes):
            tmp.write_bytes(data)
        else:
            tmp.write_text(data, encoding="utf-8")
    return path


def dumps_json(obj) -> str:
    return json.dumps(obj, indent=2, sort_keys=False, allow_nan=False)


def exit_now(code: int) -> None:
    """End this process with ``code`` without the interpreter's teardown: logging's
    handlers and stdout / stderr are flushed first (a closed pipe is ignored); files
    must be written and closed already. The ``gearbox`` command and the output
    worker's process leave this way (docs/pipeline.md)."""
    import logging
    import sys

    logging.shutdown()
    for stream in (sys.stdout, sys.stderr):
        try:
            stream.flush()
        except (OSError, ValueError):  # a closed pipe: nothing more to say
            pass
    os._exit(code)

"""Small helpers shared by the verb modules."""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path


def add_scene_argument(parser) -> None:
    parser.add_argument("scene", help="scene file (TOML), e.g. models/case03.toml")


def write_atomic(path: str | Path, data: str | bytes) -> Path:
    """Write a file completely or not at all: write a temporary file, then rename."""
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    mode = "wb" if isinstance(data, bytes) else "w"
    fd, tmp = tempfile.mkstemp(dir=path.parent, prefix=f".{path.name}.", suffix=".tmp")
    try:
        with os.fdopen(fd, mode, **({} if mode == "wb" else {"encoding": "utf-8"})) as fh:
            fh.write(data)
        # mkstemp creates the file 0600; give it the permissions a plain open() would
        umask = os.umask(0)
        os.umask(umask)
        os.chmod(tmp, 0o666 & ~umask)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def dumps_json(obj) -> str:
    return json.dumps(obj, indent=2, sort_keys=False, allow_nan=False)

"""Test-session checks.

Tests that need an outside tool or an optional extra skip where it is missing, so that
a partial install still runs the rest. CI installs everything and sets
``GEARBOX_REQUIRE_TOOLS=1``: then a missing tool or extra stops the session with an
error naming it, instead of letting its tests skip unseen.
"""

from __future__ import annotations

import importlib.util
import os
import shutil

import pytest

from gearbox.fmu.build import find_c_compiler
from gearbox.report.browser import find_chromium

#: outside programs some tests need (the FMU build, its memory check, the report's
#: browser check)
TOOLS = {
    "C compiler (gcc or $CC)": find_c_compiler,
    "valgrind": lambda: shutil.which("valgrind"),
    "chromium": find_chromium,
}
#: optional extras (pyproject's [all,test]) whose tests use importorskip
MODULES = ("fmpy", "libcosimpy", "diffrax", "exudyn", "xarray", "skfem", "distributed")


def pytest_configure(config):
    """The tests' default cache folder (``$GEARBOX_CACHE``) is a fresh temporary one:
    a test that runs a command without ``--cache`` neither reads nor fills the user's
    cache. Removed when the session ends."""
    import tempfile

    config._gearbox_cache = tempfile.mkdtemp(prefix="gearbox-test-cache-")
    os.environ["GEARBOX_CACHE"] = config._gearbox_cache


def pytest_unconfigure(config):
    folder = getattr(config, "_gearbox_cache", None)
    if folder:
        shutil.rmtree(folder, ignore_errors=True)


def pytest_sessionstart(session):
    if not os.environ.get("GEARBOX_REQUIRE_TOOLS"):
        return
    missing = [name for name, find in TOOLS.items() if not find()]
    missing += [m for m in MODULES if importlib.util.find_spec(m) is None]
    if missing:
        raise pytest.UsageError(
            "GEARBOX_REQUIRE_TOOLS is set but these are missing: " + ", ".join(missing)
        )

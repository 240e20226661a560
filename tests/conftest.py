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


def pytest_sessionstart(session):
    if not os.environ.get("GEARBOX_REQUIRE_TOOLS"):
        return
    missing = [name for name, find in TOOLS.items() if not find()]
    missing += [m for m in MODULES if importlib.util.find_spec(m) is None]
    if missing:
        raise pytest.UsageError(
            "GEARBOX_REQUIRE_TOOLS is set but these are missing: " + ", ".join(missing)
        )

"""Provenance of a run: package versions, platform, scene file, timings, cache use."""

from __future__ import annotations

import hashlib
import platform
import sys
from importlib import metadata

from .. import __version__

__all__ = ["PACKAGES", "package_versions", "provenance_rows"]

#: Distributions whose versions the report lists (absent ones are marked so): the
#: dependencies and extras of pyproject.toml, and netCDF4, which the mesh tables'
#: files take where it is installed (else h5netcdf).
PACKAGES = (
    "numpy",
    "scipy",
    "matplotlib",
    "tqdm",
    "threadpoolctl",
    "xarray",
    "h5netcdf",
    "h5py",
    "netCDF4",
    "jax",
    "jaxlib",
    "ml_dtypes",
    "diffrax",
    "equinox",
    "exudyn",
    "fmpy",
    "libcosimpy",
    "scikit-fem",
)


def package_versions() -> dict[str, str]:
    """Installed version of each of :data:`PACKAGES` (``"not installed"`` otherwise)."""
    out = {"gearbox": __version__, "python": sys.version.split()[0]}
    for name in PACKAGES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = "not installed"
    return out


def provenance_rows(run) -> list[tuple[str, str]]:
    """(item, value) rows describing where the report's numbers come from."""
    s = run.summary
    rows = [
        ("scene", run.scene.name),
        ("scene file", str(run.scene.path) if run.scene.path else "(built in Python)"),
    ]
    if run.scene.path is not None:
        try:
            digest = hashlib.sha256(run.scene.path.read_bytes()).hexdigest()
            rows.append(("scene file SHA-256", digest))
        except OSError:
            rows.append(("scene file SHA-256", "(file no longer readable)"))
    rows += [
        ("run started (UTC)", s.started),
        ("run wall time (s)", f"{s.seconds:.2f}"),
        ("cache", s.cache_dir or "off"),
        ("requested outputs", ", ".join(s.requested)),
        ("platform", platform.platform()),
    ]
    return rows

"""Write, compile and zip an FMU.

For each :class:`~gearbox.fmu.spec.FmuModel` the build writes a source folder in the
shape of the Modelica Reference-FMUs (``config.h``, ``model.c``, ``FMI2.xml``,
``readme.md``, ``resources/``), compiles it with the machine's C compiler with
warnings as errors into ``binaries/linux64/<id>.so`` and zips the FMU::

    <id>.fmu
      modelDescription.xml
      binaries/linux64/<id>.so
      sources/   fmi2_runtime.c model.c config.h gbx_model.h fmi2*.h
      resources/ the model's tables, read at instantiation
      documentation/readme.md

Nothing is left half-written: the FMU is zipped to a temporary file and renamed.
"""

from __future__ import annotations

import os
import platform
import shutil
import subprocess
import tempfile
import zipfile
from dataclasses import asdict, dataclass
from importlib import resources as ilr
from pathlib import Path

from ..commands._common import atomic_target, write_atomic
from ..errors import InputError, Problem
from .codegen import (
    config_h,
    model_c,
    model_description,
    model_description_fmi3,
    variables_markdown,
    with_solver,
)
from .spec import FmuModel

__all__ = [
    "RUNTIME_FILES",
    "RUNTIME_FILES_FMI3",
    "FmuBuild",
    "build_folder",
    "build_fmu",
    "write_sources",
]

#: Files of the generic runtime (package data in gearbox/fmu/c/).
RUNTIME_FILES = (
    "fmi2_runtime.c",
    "gbx_model.h",
    "fmi2Functions.h",
    "fmi2FunctionTypes.h",
    "fmi2TypesPlatform.h",
)

#: Added for FMI 3.0: the FMI 3.0 layer over the FMI 2.0 runtime and its headers.
RUNTIME_FILES_FMI3 = (
    "fmi3_runtime.c",
    "fmi3Functions.h",
    "fmi3FunctionTypes.h",
    "fmi3PlatformTypes.h",
)

#: Compiler flags; warnings are errors.
CFLAGS = (
    "-std=c11",
    "-O3",
    "-fPIC",
    "-shared",
    "-fvisibility=hidden",
    "-Wall",
    "-Wextra",
    "-Werror",
)


def find_c_compiler(cc: str | None = None) -> str | None:
    """The C compiler the FMU build uses: ``cc``, else ``$CC``, else ``gcc``, as found on
    PATH (full path), or ``None`` where it is missing."""
    return shutil.which(cc or os.environ.get("CC") or "gcc")


@dataclass(frozen=True)
class FmuBuild:
    """Result of :func:`build_fmu`.

    ``fmu`` is the zipped FMU, ``source_dir`` the Reference-FMUs-shaped folder,
    ``command`` the compiler command line, ``compiler_output`` what it printed
    (empty on a clean build), ``platform`` the binaries/ subfolder.
    """

    identifier: str
    guid: str
    fmu: str
    source_dir: str
    command: tuple[str, ...]
    compiler_output: str
    platform: str
    n_variables: int
    n_states: int

    def to_dict(self) -> dict:
        d = asdict(self)
        d["command"] = list(self.command)
        return d

    @classmethod
    def from_dict(cls, d: dict) -> FmuBuild:
        return cls(**{**d, "command": tuple(d["command"])})


def _platform(fmi_version: int = 2) -> str:
    """binaries/ subfolder: FMI 2.0 names (linux64) or FMI 3.0 tuples (x86_64-linux)."""
    system = platform.system()
    machine = platform.machine().lower()
    bits = "64" if machine.endswith("64") else "32"
    if system not in ("Linux", "Darwin", "Windows"):
        raise InputError(Problem("platform", system, "FMU build supports Linux, macOS, Windows"))
    if fmi_version == 3:
        arch = {"amd64": "x86_64", "arm64": "aarch64"}.get(machine, machine)
        return f"{arch}-{system.lower()}"
    if system == "Linux":
        return f"linux{bits}"
    if system == "Darwin":
        return "darwin64"
    return f"win{bits}"


def _runtime_text(name: str) -> str:
    return ilr.files("gearbox.fmu").joinpath("c").joinpath(name).read_text(encoding="utf-8")


def write_sources(model: FmuModel, folder: str | Path) -> Path:
    """Write the Reference-FMUs-shaped source folder of one FMU; return it."""
    model = with_solver(model)
    folder = Path(folder)
    folder.mkdir(parents=True, exist_ok=True)
    write_atomic(folder / "config.h", config_h(model))
    write_atomic(folder / "model.c", model_c(model))
    write_atomic(folder / "FMI2.xml", model_description(model, generation_tool=_tool()))
    write_atomic(folder / "FMI3.xml", model_description_fmi3(model, generation_tool=_tool()))
    if model.readme:
        write_atomic(
            folder / "readme.md", model.readme.rstrip() + "\n\n" + variables_markdown(model)
        )
    for name, text in model.resources.items():
        write_atomic(folder / "resources" / name, text)
    return folder


def _tool() -> str:
    from .. import __version__

    return f"gearbox {__version__}"


def build_fmu(
    model: FmuModel,
    out_dir: str | Path,
    *,
    cc: str | None = None,
    source_dir: str | Path | None = None,
    fmi_version: int = 2,
) -> FmuBuild:
    """Generate, compile (warnings as errors) and zip one FMU into ``out_dir``.

    ``cc`` defaults to ``$CC`` or ``gcc``. ``source_dir`` (default
    ``out_dir/<identifier>``) receives the generated source folder. ``fmi_version`` 2
    writes ``<id>.fmu`` (FMI 2.0), 3 writes ``<id>_fmi3.fmu`` (FMI 3.0). Raises
    :class:`~gearbox.errors.InputError` when no compiler is found and
    :class:`RuntimeError` with the compiler's output when compiling fails.
    """
    model = with_solver(model)
    out_dir = Path(out_dir)
    src = write_sources(model, source_dir or out_dir / model.identifier)
    return build_folder(src, out_dir, cc=cc, fmi_version=fmi_version)


def build_folder(
    src: str | Path, out_dir: str | Path, *, cc: str | None = None, fmi_version: int = 2
) -> FmuBuild:
    """Compile and zip an FMU from a source folder written by :func:`write_sources`
    (``config.h``, ``model.c``, ``FMI2.xml``, ``FMI3.xml``, ``readme.md``,
    ``resources/``), such as the folders under ``fmus/``."""
    import xml.etree.ElementTree as ET

    src = Path(src)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    if fmi_version not in (2, 3):
        raise InputError(Problem("fmi_version", fmi_version, "must be 2 or 3"))
    xml = src / f"FMI{fmi_version}.xml"
    root = ET.parse(xml).getroot()
    ident = root.find("CoSimulation").get("modelIdentifier")
    n_vars = len(root.find("ModelVariables"))
    if fmi_version == 3:
        n_states = len(root.find("ModelStructure").findall("ContinuousStateDerivative"))
    else:
        derivatives = root.find("ModelStructure").find("Derivatives")
        n_states = 0 if derivatives is None else len(derivatives)
    resources = sorted((src / "resources").iterdir()) if (src / "resources").is_dir() else []
    found = find_c_compiler(cc)
    if found is None:
        cc = cc or os.environ.get("CC") or "gcc"
        raise InputError(Problem("cc", cc, "a C compiler on PATH (set CC or install gcc)"))
    cc = found
    plat = _platform(fmi_version)
    suffix = {"Linux": ".so", "Darwin": ".dylib", "Windows": ".dll"}[platform.system()]
    files = RUNTIME_FILES + (RUNTIME_FILES_FMI3 if fmi_version == 3 else ())
    with tempfile.TemporaryDirectory(prefix=f"gbx_{ident}_") as tmp:
        tmp = Path(tmp)
        sources = tmp / "sources"
        sources.mkdir()
        for name in files:
            (sources / name).write_text(_runtime_text(name), encoding="utf-8")
        shutil.copy(src / "config.h", sources / "config.h")
        shutil.copy(src / "model.c", sources / "model.c")
        binary = tmp / "binaries" / plat / f"{ident}{suffix}"
        binary.parent.mkdir(parents=True)
        c_files = [str(sources / f) for f in files if f.endswith(".c")] + [str(sources / "model.c")]
        defines = ("-DGBX_FMI3",) if fmi_version == 3 else ()
        cmd = (cc, *CFLAGS, *defines, "-I", str(sources), "-o", str(binary), *c_files, "-lm")
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise RuntimeError(f"compiling {ident} failed ({' '.join(cmd)}):\n{proc.stderr}")
        fmu_path = out_dir / (f"{ident}.fmu" if fmi_version == 2 else f"{ident}_fmi3.fmu")
        with atomic_target(fmu_path) as tmp_zip:
            with zipfile.ZipFile(tmp_zip, "w", zipfile.ZIP_DEFLATED) as z:
                z.writestr("modelDescription.xml", xml.read_text(encoding="utf-8"))
                z.write(binary, f"binaries/{plat}/{binary.name}")
                for f in sorted(sources.iterdir()):
                    z.write(f, f"sources/{f.name}")
                for f in resources:
                    z.write(f, f"resources/{f.name}")
                if (src / "readme.md").exists():
                    z.write(src / "readme.md", "documentation/readme.md")
    return FmuBuild(
        identifier=ident,
        guid=root.get("guid"),
        fmu=str(fmu_path),
        source_dir=str(src),
        command=tuple(cmd),
        compiler_output=proc.stderr,
        platform=plat,
        n_variables=n_vars,
        n_states=n_states,
    )

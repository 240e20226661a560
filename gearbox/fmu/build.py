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

from ..commands._common import write_atomic
from ..errors import InputError, Problem
from .codegen import config_h, model_c, model_description, variables_markdown, with_solver
from .spec import FmuModel

__all__ = ["RUNTIME_FILES", "FmuBuild", "build_folder", "build_fmu", "write_sources"]

#: Files of the generic runtime (package data in gearbox/fmu/c/).
RUNTIME_FILES = (
    "fmi2_runtime.c",
    "gbx_model.h",
    "fmi2Functions.h",
    "fmi2FunctionTypes.h",
    "fmi2TypesPlatform.h",
)

#: Compiler flags; warnings are errors.
CFLAGS = (
    "-std=c11",
    "-O2",
    "-fPIC",
    "-shared",
    "-fvisibility=hidden",
    "-Wall",
    "-Wextra",
    "-Werror",
)


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


def _platform() -> str:
    system = platform.system()
    bits = "64" if platform.machine().endswith("64") else "32"
    if system == "Linux":
        return f"linux{bits}"
    if system == "Darwin":
        return "darwin64"
    if system == "Windows":
        return f"win{bits}"
    raise InputError(Problem("platform", system, "FMU build supports Linux, macOS, Windows"))


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
) -> FmuBuild:
    """Generate, compile (warnings as errors) and zip one FMU into ``out_dir``.

    ``cc`` defaults to ``$CC`` or ``gcc``. ``source_dir`` (default
    ``out_dir/<identifier>``) receives the generated source folder. Raises
    :class:`~gearbox.errors.InputError` when no compiler is found and
    :class:`RuntimeError` with the compiler's output when compiling fails.
    """
    model = with_solver(model)
    out_dir = Path(out_dir)
    src = write_sources(model, source_dir or out_dir / model.identifier)
    return build_folder(src, out_dir, cc=cc)


def build_folder(src: str | Path, out_dir: str | Path, *, cc: str | None = None) -> FmuBuild:
    """Compile and zip an FMU from a source folder written by :func:`write_sources`
    (``config.h``, ``model.c``, ``FMI2.xml``, ``readme.md``, ``resources/``), such as
    the folders under ``fmus/``."""
    import xml.etree.ElementTree as ET

    src = Path(src)
    out_dir = Path(out_dir)
    out_dir.mkdir(parents=True, exist_ok=True)
    root = ET.parse(src / "FMI2.xml").getroot()
    ident = root.find("CoSimulation").get("modelIdentifier")
    n_vars = len(root.find("ModelVariables"))
    derivatives = root.find("ModelStructure").find("Derivatives")
    n_states = 0 if derivatives is None else len(derivatives)
    resources = sorted((src / "resources").iterdir()) if (src / "resources").is_dir() else []
    cc = cc or os.environ.get("CC") or "gcc"
    if shutil.which(cc) is None:
        raise InputError(Problem("cc", cc, "a C compiler on PATH (set CC or install gcc)"))
    plat = _platform()
    suffix = {"linux": ".so", "darwi": ".dylib", "win32": ".dll", "win64": ".dll"}[plat[:5]]
    with tempfile.TemporaryDirectory(prefix=f"gbx_{ident}_") as tmp:
        tmp = Path(tmp)
        sources = tmp / "sources"
        sources.mkdir()
        for name in RUNTIME_FILES:
            (sources / name).write_text(_runtime_text(name), encoding="utf-8")
        shutil.copy(src / "config.h", sources / "config.h")
        shutil.copy(src / "model.c", sources / "model.c")
        binary = tmp / "binaries" / plat / f"{ident}{suffix}"
        binary.parent.mkdir(parents=True)
        cmd = (
            cc, *CFLAGS, "-I", str(sources), "-o", str(binary),
            str(sources / "fmi2_runtime.c"), str(sources / "model.c"), "-lm",
        )  # fmt: skip
        proc = subprocess.run(cmd, capture_output=True, text=True, check=False)
        if proc.returncode != 0:
            raise RuntimeError(f"compiling {ident} failed ({' '.join(cmd)}):\n{proc.stderr}")
        fmu_path = out_dir / f"{ident}.fmu"
        fd, tmp_zip = tempfile.mkstemp(dir=out_dir, prefix=f".{ident}.", suffix=".fmu.tmp")
        os.close(fd)
        try:
            with zipfile.ZipFile(tmp_zip, "w", zipfile.ZIP_DEFLATED) as z:
                z.writestr("modelDescription.xml", (src / "FMI2.xml").read_text(encoding="utf-8"))
                z.write(binary, f"binaries/{plat}/{binary.name}")
                for f in sorted(sources.iterdir()):
                    z.write(f, f"sources/{f.name}")
                for f in resources:
                    z.write(f, f"resources/{f.name}")
                if (src / "readme.md").exists():
                    z.write(src / "readme.md", "documentation/readme.md")
            os.replace(tmp_zip, fmu_path)
        except BaseException:
            Path(tmp_zip).unlink(missing_ok=True)
            raise
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

"""gearbox: crossed beveloid gear pairs from geometry to drivetrain vibration.

Public API (stage by stage, see docs/pipeline.md):

- scene files: :func:`load_scene`, :class:`Scene`
- geometry design (paper section 2): see :mod:`gearbox.geometry`
- loaded TCA (paper section 3.2): :func:`scene_ltca`, :class:`ParallelPair`;
  see :mod:`gearbox.ltca` and docs/ltca.md; its finite-element level
  :class:`FECompliance` (:mod:`gearbox.fe`, docs/fe.md)
- spectra: :func:`order_spectrum`, :func:`campbell`, :func:`excitation_orders`;
  see :mod:`gearbox.spectrum`

``import gearbox`` imports none of them: each name is imported from its module when
first used (so the ``gearbox`` command starts without loading every stage's code);
exudyn, jax and FMU building are imported only by the stages that use them.
"""

__version__ = "0.1.0"

import importlib
from typing import TYPE_CHECKING

#: public name -> the module (relative to this package) it is imported from.
_EXPORTS = {
    "DrivetrainModel": ".drivetrain",
    "InputError": ".errors",
    "FECompliance": ".fe",
    "GearSpec": ".geometry",
    "PairDesign": ".geometry",
    "PairSpec": ".geometry",
    "ToolSpec": ".geometry",
    "design_pair": ".geometry",
    "ParallelPair": ".ltca",
    "scene_ltca": ".ltca.table",
    "MeshTable": ".meshtable",
    "Scene": ".scene",
    "load_scene": ".scene",
    "campbell": ".spectrum",
    "excitation_orders": ".spectrum",
    "order_spectrum": ".spectrum",
    "ToothBlank": ".surface",
    "blanks_from_design": ".surface",
    "flank_points": ".surface",
    "Assembly": ".tca",
    "AssemblyErrors": ".tca",
    "TCASettings": ".tca",
    "run_tca": ".tca",
}

__all__ = ["__version__", *_EXPORTS]

if TYPE_CHECKING:  # for type checkers and editors: the names as plain imports
    from .drivetrain import DrivetrainModel as DrivetrainModel
    from .errors import InputError as InputError
    from .fe import FECompliance as FECompliance
    from .geometry import GearSpec as GearSpec
    from .geometry import PairDesign as PairDesign
    from .geometry import PairSpec as PairSpec
    from .geometry import ToolSpec as ToolSpec
    from .geometry import design_pair as design_pair
    from .ltca import ParallelPair as ParallelPair
    from .ltca.table import scene_ltca as scene_ltca
    from .meshtable import MeshTable as MeshTable
    from .scene import Scene as Scene
    from .scene import load_scene as load_scene
    from .spectrum import campbell as campbell
    from .spectrum import excitation_orders as excitation_orders
    from .spectrum import order_spectrum as order_spectrum
    from .surface import ToothBlank as ToothBlank
    from .surface import blanks_from_design as blanks_from_design
    from .surface import flank_points as flank_points
    from .tca import Assembly as Assembly
    from .tca import AssemblyErrors as AssemblyErrors
    from .tca import TCASettings as TCASettings
    from .tca import run_tca as run_tca


def __getattr__(name: str):
    """Import a public name, or a subpackage (``gearbox.ltca``), on first use."""
    module = _EXPORTS.get(name)
    if module is not None:
        value = getattr(importlib.import_module(module, __name__), name)
        globals()[name] = value
        return value
    try:
        return importlib.import_module(f"{__name__}.{name}")
    except ModuleNotFoundError as exc:
        if exc.name != f"{__name__}.{name}":
            raise
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted(set(globals()) | set(_EXPORTS))

"""gearbox: crossed beveloid gear pairs from geometry to drivetrain vibration.

Public API (stage by stage, see docs/pipeline.md):

- scene files: :func:`load_scene`, :class:`Scene`
- geometry design (paper section 2): see :mod:`gearbox.geometry`
- loaded TCA (paper section 3.2): :func:`scene_ltca`, :class:`ParallelPair`;
  see :mod:`gearbox.ltca` and docs/ltca.md; its finite-element level
  :class:`FECompliance` (:mod:`gearbox.fe`, docs/fe.md)
- spectra: :func:`order_spectrum`, :func:`campbell`, :func:`excitation_orders`;
  see :mod:`gearbox.spectrum`

exudyn, jax and FMU building are not imported by ``import gearbox``.
"""

__version__ = "0.1.0"

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

"""Geometry design of crossed beveloid gear pairs (paper section 2).

Public API::

    spec = PairSpec.from_scene(load_scene("models/case03.toml"))
    design = design_pair(spec)          # frozen PairDesign, SI units
"""

from .design import Check as Check
from .design import GearDesign as GearDesign
from .design import PairDesign as PairDesign
from .design import design_pair as design_pair
from .design import solve_pair_arrays as solve_pair_arrays
from .involute import inv as inv
from .involute import inv_inverse as inv_inverse
from .spec import GearSpec as GearSpec
from .spec import PairSpec as PairSpec
from .spec import ToolSpec as ToolSpec

__all__ = [
    "Check",
    "GearDesign",
    "GearSpec",
    "PairDesign",
    "PairSpec",
    "ToolSpec",
    "design_pair",
    "inv",
    "inv_inverse",
    "solve_pair_arrays",
]

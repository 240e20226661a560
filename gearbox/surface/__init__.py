"""Tooth flanks by simulated generation with a tilted rack cutter (pipeline stage 2).

Public API::

    pinion, gear = blanks_from_design(design)        # ToothBlank each (SI)
    fp = flank_points(pinion, "R", z, u)             # points, normals, curvatures
    grid = tooth_grid(pinion)                         # both flanks on a grid
    text = tooth_csv(grid)                            # point cloud (CSV)

Flank names: "R" (right, the drive side) and "L" (left, the coast side); see
docs/surface.md for the frames and the method.
"""

from .blank import SIDES as SIDES
from .blank import ToothBlank as ToothBlank
from .blank import blanks_from_design as blanks_from_design
from .generation import FlankPoints as FlankPoints
from .generation import flank_jets as flank_jets
from .generation import flank_points as flank_points
from .generation import fold_parameter as fold_parameter
from .generation import form_point as form_point
from .generation import involute_start as involute_start
from .generation import principal_curvatures as principal_curvatures
from .generation import profile_range as profile_range
from .generation import undercut_margin as undercut_margin
from .sample import SolveFailure as SolveFailure
from .sample import flank_grid as flank_grid
from .sample import parameter_at_radius as parameter_at_radius
from .sample import tip_parameter as tip_parameter
from .sample import tooth_csv as tooth_csv
from .sample import tooth_grid as tooth_grid

__all__ = [
    "SIDES",
    "FlankPoints",
    "SolveFailure",
    "ToothBlank",
    "blanks_from_design",
    "flank_grid",
    "flank_jets",
    "flank_points",
    "parameter_at_radius",
    "principal_curvatures",
    "profile_range",
    "tip_parameter",
    "tooth_csv",
    "tooth_grid",
    "fold_parameter",
    "form_point",
    "involute_start",
    "undercut_margin",
]

"""Loaded tooth contact analysis (paper section 3.2): contact solver, compliance
levels, mesh-cycle tables.

- :class:`ContactGrid`: the flanks at one position, as the mechanics needs them;
- :class:`Compliance` (interface), :class:`FastCompliance` (thin slices: the tooth as
  a plane-strain FE body on Sainsot's foundation, the body's far field shared by the
  gear, shear-layer coupling along the face, Weber contact flattening);
- :func:`solve_contact` / :class:`ContactSolver`: the complementarity problem;
- :func:`ltca_cycle`: a mesh cycle x torque levels -> :class:`CycleResult`;
- :class:`ParallelPair`, :func:`parallel_grid`: spur/helical reference pairs;
- :func:`iso_mesh_stiffness`: ISO 6336-1 method B c' and c_gamma;
- :func:`iso_root_section`: ISO 6336-3 method B critical root section;
- :class:`FlankModification`: tip and root relief, profile and lead crowning, end
  relief and helix slope of one gear.
"""

from .analysis import CycleResult as CycleResult
from .analysis import LTCAOptions as LTCAOptions
from .analysis import cycle_summary as cycle_summary
from .analysis import ltca_cycle as ltca_cycle
from .compliance import BODY_COMPLIANCE as BODY_COMPLIANCE
from .compliance import Compliance as Compliance
from .compliance import FastCompliance as FastCompliance
from .compliance import compliance_for as compliance_for
from .grid import ContactGrid as ContactGrid
from .grid import ToothSections as ToothSections
from .iso6336 import IsoStiffness as IsoStiffness
from .iso6336 import iso_mesh_stiffness as iso_mesh_stiffness
from .modification import FlankModification as FlankModification
from .modification import TipRelief as TipRelief
from .parallel import ParallelPair as ParallelPair
from .parallel import parallel_grid as parallel_grid
from .solver import ContactSolution as ContactSolution
from .solver import ContactSolver as ContactSolver
from .solver import solve_contact as solve_contact
from .stress import RootSection as RootSection
from .stress import iso_root_section as iso_root_section

__all__ = [
    "Compliance",
    "ContactGrid",
    "ContactSolution",
    "ContactSolver",
    "CycleResult",
    "BODY_COMPLIANCE",
    "FastCompliance",
    "FlankModification",
    "IsoStiffness",
    "LTCAOptions",
    "ParallelPair",
    "TipRelief",
    "RootSection",
    "ToothSections",
    "compliance_for",
    "cycle_summary",
    "iso_mesh_stiffness",
    "iso_root_section",
    "ltca_cycle",
    "parallel_grid",
    "solve_contact",
]

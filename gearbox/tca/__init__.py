"""Assembly on crossed axes and unloaded tooth contact analysis (pipeline stage 3).

Public API::

    result = run_tca(design, scene)            # TCAResult: drive and coast sides
    result.summary()                            # JSON-ready numbers
    Assembly.from_design(design, AssemblyErrors(offset=5e-5))

Frames (Sf, S1, S2) are written down in :mod:`gearbox.tca.assembly` and docs/tca.md.
"""

from .analysis import SIDE_NAMES as SIDE_NAMES
from .analysis import FlankContact as FlankContact
from .analysis import TCAResult as TCAResult
from .analysis import TCASettings as TCASettings
from .analysis import run_tca as run_tca
from .analysis import tca_of_blanks as tca_of_blanks
from .assembly import Assembly as Assembly
from .assembly import AssemblyErrors as AssemblyErrors
from .contact import ContactSolution as ContactSolution
from .contact import solve_contact as solve_contact

__all__ = [
    "SIDE_NAMES",
    "Assembly",
    "AssemblyErrors",
    "ContactSolution",
    "FlankContact",
    "TCAResult",
    "TCASettings",
    "run_tca",
    "solve_contact",
    "tca_of_blanks",
]

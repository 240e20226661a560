"""Finite-element reference level of the loaded TCA (``ltca.fidelity = "fe"``).

- :func:`build_tooth_mesh` / :class:`MeshOptions`: mapped 27-node hexahedral mesh of a
  few teeth and the rim from the generated flanks (root fillet included);
- :func:`build_model` / :class:`ToothModel`: assembly, clamping, one factorisation;
- :class:`FECompliance` / :class:`FEOptions`: influence coefficients joined to the
  Boussinesq half-space at a matching depth (Vijayakar 1991), behind the loaded TCA's
  :class:`~gearbox.ltca.compliance.Compliance` interface;
- :func:`fillet_stress`: root stress along the fillet from the same solutions;
- :func:`surface_deflection`, :func:`depth_deflection`: half-space solutions.

numpy and scipy are the only requirements; scikit-fem (extra ``fe``) is the
independent check of the element in the tests.
"""

from .boussinesq import depth_deflection as depth_deflection
from .boussinesq import surface_deflection as surface_deflection
from .compliance import FECompliance as FECompliance
from .compliance import FEOptions as FEOptions
from .mesh import FEBuildError as FEBuildError
from .mesh import MeshOptions as MeshOptions
from .mesh import ToothMesh as ToothMesh
from .mesh import build_tooth_mesh as build_tooth_mesh
from .model import ToothModel as ToothModel
from .model import build_model as build_model
from .stress import FilletStress as FilletStress
from .stress import fillet_stress as fillet_stress

__all__ = [
    "FEBuildError",
    "FECompliance",
    "FEOptions",
    "FilletStress",
    "MeshOptions",
    "ToothMesh",
    "ToothModel",
    "build_model",
    "build_tooth_mesh",
    "depth_deflection",
    "fillet_stress",
    "surface_deflection",
]

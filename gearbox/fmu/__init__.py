"""FMU export (FMI 2.0, Model Exchange and Co-Simulation) and co-simulation.

- :func:`build_fmu` generates C from an :class:`FmuModel`, compiles it with the
  machine's C compiler (warnings as errors) and zips the FMU.
- :func:`drivetrain_fmu`, :func:`gearbox_fmu`, :func:`engine_fmu`,
  :func:`propeller_fmu` make the FMU models from a ``DrivetrainModel``.
- :mod:`gearbox.fmu.cosim` couples engine, gearbox and propeller FMUs on libcosim.

Nothing here is imported by ``import gearbox``; fmpy and libcosimpy are imported
only inside the functions that run FMUs.
"""

from .build import FmuBuild as FmuBuild
from .build import build_fmu as build_fmu
from .models import drivetrain_fmu as drivetrain_fmu
from .models import engine_fmu as engine_fmu
from .models import gearbox_fmu as gearbox_fmu
from .models import propeller_fmu as propeller_fmu
from .spec import FmuModel as FmuModel
from .spec import Variable as Variable

__all__ = [
    "FmuBuild",
    "FmuModel",
    "Variable",
    "build_fmu",
    "drivetrain_fmu",
    "engine_fmu",
    "gearbox_fmu",
    "propeller_fmu",
]

"""Drivetrain vibration: one model (docs/drivetrain.md), several solvers.

- :class:`DrivetrainModel` (``model.py``): parameters in SI, the numpy/jax right-hand side.
- :mod:`.scipy_backend` (reference), :mod:`.diffrax_backend` (jit, vmap, grad),
  exudyn backend (``exudyn_backend.py``).
- :mod:`.linear`: eigenfrequencies and mode shapes about the mean mesh stiffness.
- :class:`TimeSeries` (``timeseries.py``): named channels, SI, time first.

jax and exudyn are imported only by their backends.
"""

from .model import DrivetrainModel as DrivetrainModel
from .model import rhs as rhs

__all__ = ["DrivetrainModel", "rhs"]

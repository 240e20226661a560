"""Spectra of drivetrain signals: order spectra, waterfalls, Campbell diagrams.

Units: signals in SI (N, m, N m), time in s, angles in rad; speeds in rpm and
frequencies in Hz (the edge units of a Campbell diagram), named so in every
argument (``speed_rpm``, ``frequency_hz``). Orders are cycles per revolution of the
reference shaft (the pinion, which turns at engine speed). Amplitudes are
single-sided peak amplitudes in the signal's unit.

- :func:`order_spectrum` / :class:`OrderSpectrum`: over settled whole periods,
  rectangular window; order tracking by angle resampling where the speed varies.
- :func:`waterfall`, :func:`runup_waterfall` / :class:`Waterfall`.
- :func:`campbell` / :class:`CampbellDiagram` (with :class:`OrderCuts`),
  :func:`excitation_orders`.
- :func:`settling` / :class:`Settling`: how much the order amplitudes still
  change between the last two windows of whole periods.
- Adapters: :func:`timeseries_spectra` (drivetrain TimeSeries channels),
  :func:`mode_table` (eigenfrequencies per speed), :func:`period_revs_of`.
- Figures: :mod:`gearbox.spectrum.plotting` (imports matplotlib).

See docs/spectrum.md.
"""

from .adapters import mode_table as mode_table
from .adapters import period_revs_of as period_revs_of
from .adapters import timeseries_spectra as timeseries_spectra
from .campbell import CampbellDiagram as CampbellDiagram
from .campbell import Crossing as Crossing
from .campbell import ExcitationOrder as ExcitationOrder
from .campbell import OrderCuts as OrderCuts
from .campbell import campbell as campbell
from .campbell import excitation_orders as excitation_orders
from .campbell import excitation_orders_from_scene as excitation_orders_from_scene
from .orders import OrderSpectrum as OrderSpectrum
from .orders import common_period_revs as common_period_revs
from .orders import order_spectra as order_spectra
from .orders import order_spectrum as order_spectrum
from .orders import revolutions as revolutions
from .settling import Settling as Settling
from .settling import settling as settling
from .waterfall import Waterfall as Waterfall
from .waterfall import runup_waterfall as runup_waterfall
from .waterfall import waterfall as waterfall

__all__ = [
    "CampbellDiagram",
    "Crossing",
    "ExcitationOrder",
    "OrderCuts",
    "OrderSpectrum",
    "Settling",
    "Waterfall",
    "campbell",
    "common_period_revs",
    "excitation_orders",
    "excitation_orders_from_scene",
    "mode_table",
    "order_spectra",
    "order_spectrum",
    "period_revs_of",
    "revolutions",
    "runup_waterfall",
    "settling",
    "timeseries_spectra",
    "waterfall",
]

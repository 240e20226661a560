"""The HTML report of a run: one self-contained file, figures embedded as PNG.

``write_report(run, "out/report.html")`` builds the report of a
:class:`gearbox.pipeline.PipelineRun` and writes it atomically (temporary file, then
rename), so an interrupted run leaves the previous report or none, never half of one.
"""

from .build import build_report as build_report
from .build import write_report as write_report

__all__ = ["build_report", "write_report"]

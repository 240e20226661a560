"""FMU stage: the drivetrain at the operating point as an FMI 2.0 FMU (gearbox.fmu),
built from the pipeline's mesh tables, kept as bytes so that it caches and is
written into the run's output folder."""

from __future__ import annotations

import tempfile
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ...commands._common import write_atomic
from ..stage import StageContext
from ._require import require
from .dynamics import loaded_twin, model_at

__all__ = ["FmuArtifact", "compute_fmu"]


@dataclass(frozen=True)
class FmuArtifact:
    """A built FMU: ``data`` is the zipped FMU (bytes), ``build`` the
    :class:`gearbox.fmu.FmuBuild` fields (compiler command, variables, states)."""

    identifier: str
    filename: str
    data: bytes
    build: dict[str, Any]

    def write_files(self, folder: str | Path) -> list[Path]:
        """Write ``<folder>/fmu/<filename>`` atomically."""
        return [write_atomic(Path(folder) / "fmu" / self.filename, self.data)]


def compute_fmu(ctx: StageContext) -> FmuArtifact:
    """Generate, compile (gcc, warnings as errors) and zip the drivetrain FMU. With
    ``drivetrain.mesh_law = "auto"`` on the loaded law (the FMU's load is the importer's
    to change), where the tables can take it."""
    fmu = require("gearbox.fmu", "build_fmu", "drivetrain_fmu")
    table = ctx.inputs["tables"]
    approach = ctx.inputs.get("approach")
    model = loaded_twin(ctx.scene, table, approach=approach) or model_at(
        ctx.scene, table, approach=approach
    )
    with tempfile.TemporaryDirectory(prefix="gearbox-fmu-") as tmp:
        b = fmu.build_fmu(fmu.drivetrain_fmu(model, table), tmp)
        data = Path(b.fmu).read_bytes()
    return FmuArtifact(b.identifier, Path(b.fmu).name, data, b.to_dict())

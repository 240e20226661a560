"""``gearbox run``: the stage graph, its on-disk cache, sweeps and the run summary.

::

    from gearbox import load_scene
    from gearbox.pipeline import run_pipeline

    run = run_pipeline(load_scene("models/marine_drive.toml"), cache="~/.cache/gearbox")
    print(run.summary.table())
    design = run["design"]

See docs/pipeline.md for the graph, the cache keys and sweeps on a Dask cluster.
"""

from .cache import Cache as Cache
from .cache import default_cache_dir as default_cache_dir
from .cache import stage_key as stage_key
from .runner import PipelineRun as PipelineRun
from .runner import plan as plan
from .runner import preview as preview
from .runner import run_pipeline as run_pipeline
from .stage import Stage as Stage
from .stage import StageContext as StageContext
from .stage import StageUnavailable as StageUnavailable
from .stages import STAGES as STAGES
from .summary import RunSummary as RunSummary
from .summary import StageRecord as StageRecord
from .sweep import map_items as map_items

__all__ = [
    "STAGES",
    "Cache",
    "PipelineRun",
    "RunSummary",
    "Stage",
    "StageContext",
    "StageRecord",
    "StageUnavailable",
    "default_cache_dir",
    "map_items",
    "plan",
    "preview",
    "run_pipeline",
    "stage_key",
]

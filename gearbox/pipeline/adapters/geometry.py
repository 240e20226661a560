"""Design and parameter-study stages (gearbox.geometry, paper section 2 and 3.1)."""

from __future__ import annotations

from dataclasses import dataclass

from ..stage import StageContext
from ._require import require

__all__ = ["Studies", "compute_design", "compute_sweep", "pair_spec"]

#: Points along each curve of the paper's parameter studies (Figs. 6-9).
SWEEP_POINTS = 101


def pair_spec(scene):
    """The scene's :class:`gearbox.geometry.PairSpec` (validates; raises InputError)."""
    geometry = require("gearbox.geometry", "PairSpec", "design_pair")
    return geometry.PairSpec.from_scene(scene)


def compute_design(ctx: StageContext):
    """:func:`gearbox.geometry.design_pair` of the scene's pair, with its checks."""
    geometry = require("gearbox.geometry", "PairSpec", "design_pair")
    return geometry.design_pair(pair_spec(ctx.scene))


@dataclass(frozen=True)
class Studies:
    """The parameter studies of paper Figs. 6-9 around the scene's design."""

    studies: tuple


def compute_sweep(ctx: StageContext) -> Studies:
    """:func:`gearbox.geometry.sweep.PAPER_STUDIES` (vectorised: no executor needed)."""
    sweep = require("gearbox.geometry.sweep", "PAPER_STUDIES")
    return Studies(tuple(sweep.PAPER_STUDIES(pair_spec(ctx.scene), SWEEP_POINTS)))

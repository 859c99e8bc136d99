"""Parameter studies: many solves of one problem file with some
keys varied, each point a task on Dask distributed (:mod:`.sweep`), the
bodies condensed once per group of points that share them and kept on disk
(:mod:`.cache`)."""

from .cache import BodyCache
from .sweep import INSTALL, SweepOptions, SweepResult, run_sweep

__all__ = ["BodyCache", "INSTALL", "SweepOptions", "SweepResult", "run_sweep"]

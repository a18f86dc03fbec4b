"""Cycle time: how long the path takes at a placement when it runs as fast as the robot allows."""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective


class CycleTime(Objective):
    """The duration (s) of the path under the optimal timing law (:mod:`placement.timing`): the time per pass.

    It ranks placements only when each is timed on its own, so it needs the optimal timing law;
    a placement that no timing can run (a limit broken even at rest) takes forever.
    """

    title = "cycle time"
    unit = "s"
    timing: ClassVar[str | None] = "optimal"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        assert batch.time_law is not None  # the Evaluator refuses this objective under another timing law
        return batch.time_law.duration_s


OBJECTIVES.add("cycle_time", CycleTime())

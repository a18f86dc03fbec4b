"""The optimal timing law's own limit: a placement must have a timing (:mod:`placement.timing`).

Where no timing keeps every limit (a motor too weak to hold the tool even at rest), the placement
holds still at every sample and the other limits show by how much; this limit adds that no path
motion exists there at all. Other timing laws have nothing to report here.
"""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField


class OptimalTiming(Limit):
    """Margin 1 where the optimal timing law found a timing, −1 where none exists."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        if batch.time_law is None:
            return []
        timed = np.broadcast_to(batch.time_law.timed[:, None, None], batch.reachable.shape + (1,)).astype(float)
        return [MarginField("optimal timing", 2 * timed - 1, timed, np.ones_like(timed), ("path",), ("",))]


LIMITS.add("optimal_timing", OptimalTiming())

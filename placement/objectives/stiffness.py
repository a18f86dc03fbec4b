"""Stiffness objectives: how far the tool yields under the process forces along the path (:mod:`placement.stiffness`).

- ``deflection``: the largest translation of the tool point along the path (µm). The default index: a machining
  tolerance bounds the worst point of the part, and an RMS would let one spot of the path go far past it.
- ``deflection_rms``: the root mean square of that translation over the samples (µm): the typical error, for
  comparing placements whose worst spots are alike.

Both need every actuator's stiffness in the sidecar; a path without process forces gives 0.
"""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective

MICROMETRES_PER_METRE = 1e6


class LargestDeflection(Objective):
    """The largest deflection of the tool point under the process forces along the path (µm)."""

    title = "largest tool deflection"
    unit = "µm"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return batch.deflection.largest_m * MICROMETRES_PER_METRE


class RmsDeflection(Objective):
    """The RMS over the samples of the tool point's deflection under the process forces (µm)."""

    title = "RMS tool deflection"
    unit = "µm"

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        return batch.deflection.rms_m * MICROMETRES_PER_METRE


OBJECTIVES.add("deflection", LargestDeflection())
OBJECTIVES.add("deflection_rms", RmsDeflection())

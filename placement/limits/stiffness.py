"""The tool's deflection under the process forces within the path's bound (``max_deflection_um``).

Where the path file gives ``max_deflection_um`` (or the command line ``--max-deflection-um``), the translation of the
tool point under the process force (:mod:`placement.stiffness`) must stay within it at every sample; the scale is the
bound itself, so the margin is (bound − |δ|)/bound. The robot needs every actuator's stiffness for it: on a robot
without, a bound is refused (its sidecar field is named) rather than ignored.
"""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField


class MaxDeflection(Limit):
    """The tool's deflection under the process forces at most the path's ``max_deflection_um``."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        bound = batch.max_deflection_m
        if bound is None:
            return []
        value = batch.deflection.magnitude_m[..., None]
        return [MarginField("tool deflection", (bound - value) / bound, value, np.full_like(value, bound), ("tool",), ("m",))]


LIMITS.add("max_deflection", MaxDeflection())

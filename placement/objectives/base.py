"""Objectives, a plug-in family: what a placement is ranked by.

An objective maps a batch of evaluated placements to one number each and says which direction is
better. The optimiser searches the best placement (and the worst, for the gain), the sweep maps
it, and the command line takes it by name (``--objective NAME``). A package adds an objective (an
instance of an :class:`Objective` subclass) under the entry-point group ``placement.objectives``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import ClassVar, Literal

import numpy as np

from placement.batch import EvaluatedBatch
from placement.registry import Registry


class Objective(ABC):
    """A number per placement, and the better direction.

    Attributes:
        title: What it is, in a few words ("electric energy").
        unit: Its unit ("J").
        better: "lower" or "higher".
    """

    title: ClassVar[str]
    unit: ClassVar[str]
    better: ClassVar[Literal["lower", "higher"]] = "lower"

    @abstractmethod
    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        """(K,) values of the K placements of ``batch`` (finite where every sample is reachable)."""

    @property
    def sign(self) -> float:
        """+1 when lower is better, -1 when higher is: ``sign * value`` is to be minimised."""
        return 1.0 if self.better == "lower" else -1.0


OBJECTIVES: Registry[Objective] = Registry("objective", "placement.objectives")

"""Objectives, a plug-in family: what a placement is ranked by.

An objective maps a batch of evaluated placements to one number each and says which direction is
better. The optimiser searches the best placement (and the worst, for the gain), the sweep maps
it, and the command line takes it by name (``--objective NAME``). A package adds an objective (an
instance of an :class:`Objective` subclass) under the entry-point group ``placement.objectives``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import ClassVar, Literal

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.registry import Registry


class Objective(ABC):
    """A number per placement, and the better direction.

    Attributes:
        title: What it is, in a few words ("electric energy").
        unit: Its unit ("J").
        better: "lower" or "higher".
        timing: The timing law it needs ("optimal" for one that each placement's own timing
            decides), or None: any.
    """

    title: ClassVar[str]
    unit: ClassVar[str]
    better: ClassVar[Literal["lower", "higher"]] = "lower"
    timing: ClassVar[str | None] = None

    def __init_subclass__(cls, **kwargs: object) -> None:
        super().__init_subclass__(**kwargs)
        if cls.better not in ("lower", "higher"):
            raise TypeError(f"{cls.__name__}.better must be 'lower' or 'higher', got {cls.better!r}")

    @abstractmethod
    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        """(K,) values of the K placements of ``batch`` (finite where every sample is reachable)."""

    @property
    def sign(self) -> float:
        """+1 when lower is better, -1 when higher is: ``sign * value`` is to be minimised."""
        return 1.0 if self.better == "lower" else -1.0


OBJECTIVES: Registry[Objective] = Registry("objective", "placement.objectives", Objective,
                                              builtins="placement.objectives")


@dataclass(frozen=True)
class Wording:
    """How reports speak of an objective.

    Attributes:
        subject: Its name in a sentence: "energy" for the paper's, else its title.
        unit: Its unit.
        best, worst: The adjectives of the best and worst placements ("least", "most").
        gain_verb: What the best placement does to it against the worst ("saves", "raises").
    """

    subject: str
    unit: str
    best: str
    worst: str
    gain_verb: str


def quantity(value: float, unit: str) -> str:
    """A value with its unit, as reports print it ("4.7683 J"; a dimensionless one alone)."""
    return f"{value:.4f} {unit}" if unit else f"{value:.4f}"


def wording(name: str) -> Wording:
    """The wording of the objective called ``name``."""
    objective = OBJECTIVES.get(name)
    lower = objective.better == "lower"
    return Wording(subject="energy" if name == "energy" else objective.title, unit=objective.unit,
                   best="least" if lower else "most", worst="most" if lower else "least",
                   gain_verb="saves" if lower else "raises")

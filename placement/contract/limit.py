"""Limits, a plug-in family: how close a placement comes to each limit, where and when.

A limit turns a batch of evaluated placements into margins, normalised so that 0 is the limit and
1 is comfortably far: (limit − value)/scale, with the joint range, the speed limit, the torque
limit or the workspace side as the scale. A placement is feasible when every margin is ≥ 0 at
every sample. A package adds a limit (an instance of a :class:`Limit` subclass) under the
entry-point group ``placement.limits``; every limit that applies to the robot is checked.

A limit on how fast the path may be run (a speed, an acceleration, a torque, a voltage) also
states it as bounds on the motion along the path (:meth:`Limit.path_bounds`): the optimal timing
law (:mod:`placement.timing.optimal`) keeps every bound of every limit that applies, installed
ones included, so that its timing never breaks them.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.dynamics.path_dynamics import PathDynamics, PathForm
from placement.registry import Registry
from placement.robot.model import Robot


@dataclass(frozen=True)
class MarginField:
    """Margins of one kind of limit at every sample, one column per actuator or axis.

    Attributes:
        kind: What is limited ("joint speed", "motor torque", ...).
        margin: (K, N, m) normalised margins; negative means violated.
        value: (K, N, m) the limited quantity (SI).
        limit: (K, N, m) the limit it is compared with.
        where: The m column names (actuator joint or axis).
        units: The m units of value and limit.
        samples: (N,) the batch's samples that the N rows are, in order, when a limit checks only some
            of them (each standing for the samples up to the next); None: every sample.
    """

    kind: str
    margin: np.ndarray
    value: np.ndarray
    limit: np.ndarray
    where: tuple[str, ...]
    units: tuple[str, ...]
    samples: np.ndarray | None = None


@dataclass(frozen=True)
class Margin:
    """The tightest point of one kind of limit along the path of one placement.

    Attributes:
        kind: What is limited.
        where: The actuator's joint name, or the axis.
        margin: (limit − value)/scale at the tightest sample; negative means violated.
        value: The value there (SI).
        limit: The limit it is compared with.
        sample: Index of the tightest sample.
        unit: Unit of value and limit.
    """

    kind: str
    where: str
    margin: float
    value: float
    limit: float
    sample: int
    unit: str


@dataclass(frozen=True)
class PathBound:
    """A bound on the motion along a path: |form| ≤ top at every sample, column by column.

    Attributes:
        kind: What is bounded, as in the limit's margins ("joint speed", ...).
        form: (K, N, m) the bounded quantity, affine in s̈, ṡ² and ṡ.
        top: (m,) its bound (> 0).
    """

    kind: str
    form: PathForm
    top: np.ndarray


class Limit(ABC):
    """One kind (or a few kinds) of limit."""

    def applies_to(self, robot: Robot) -> bool:
        """Whether the robot declares what this limit needs (default: always)."""
        return True

    @abstractmethod
    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        """Per-sample margins of the batch's placements."""

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        """Bounds that this limit puts on the motion along the path of K placements, for the optimal timing law
        (default: none, a limit on where the path lies rather than how fast it is run)."""
        return []


LIMITS: Registry[Limit] = Registry("limit", "placement.limits", Limit, builtins="placement.limits")


def margin_fields(batch: EvaluatedBatch) -> list[MarginField]:
    """The margins of every limit that applies to the batch's robot."""
    return [field for limit in map(LIMITS.get, LIMITS.names()) if limit.applies_to(batch.robot)
            for field in limit.fields(batch)]


def path_bounds(robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
    """The bounds on the motion along the path of every limit that applies to the robot."""
    return [bound for name in LIMITS.names() if LIMITS.get(name).applies_to(robot)
            for bound in LIMITS.get(name).path_bounds(robot, dynamics)]


def worst_margins(fields: list[MarginField]) -> tuple[np.ndarray, tuple[str, ...]]:
    """Tightest margin over the samples of every limit (each kind, each actuator or axis).

    Returns:
        (K, n_limits) margins and the n_limits labels "kind: where". Keeping the limits apart
        (rather than their minimum) keeps each one smooth for the local search.
    """
    margins = np.concatenate([_least_over_samples(field.margin) for field in fields], axis=-1)
    labels = tuple(f"{field.kind}: {name}" for field in fields for name in field.where)
    return margins, labels


def _least_over_samples(margin: np.ndarray) -> np.ndarray:
    """(K, m) the least of (K, N, m) margins over the samples, column by column: numpy's reduction over the middle
    axis of a C-contiguous array runs about ten times slower (its inner loops then span the m columns alone)."""
    columns = [margin[..., column].min(axis=1) for column in range(margin.shape[2])]
    return np.stack(columns, axis=-1) if columns else np.empty((len(margin), 0))


def tightest(fields: list[MarginField], placement: int = 0) -> list[Margin]:
    """The tightest sample of each kind for one placement of the batch."""
    out = []
    for field in fields:
        margin = field.margin[placement]
        sample, column = np.unravel_index(np.argmin(margin), margin.shape)
        out.append(Margin(kind=field.kind, where=field.where[column], margin=float(margin[sample, column]),
                          value=float(field.value[placement, sample, column]),
                          limit=float(field.limit[placement, sample, column]),
                          sample=int(sample if field.samples is None else field.samples[sample]),
                          unit=field.units[column]))
    return out

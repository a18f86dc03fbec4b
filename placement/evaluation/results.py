"""What an evaluation returns: objectives and margins of many placements, or every detail of one."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.contract.limit import Margin
from placement.energy.integration import Energy
from placement.energy.trace import MotorTrace
from placement.path.samples import PathSamples
from placement.stiffness import DeflectionSummary


@dataclass(frozen=True)
class Evaluation:
    """K placements evaluated with the exact model.

    Attributes:
        placements: (K, 6) placement vectors (m, rad).
        objectives: The objectives' names, the ranking one first.
        values: (K, n_objectives) the objectives (inf, or -inf when higher is better, where a sample
            is unreachable).
        margins: (K, n_limits) tightest normalised margin of each limit (kind and actuator or axis).
        limits: Labels of the margin columns.
        reachable: (K,) whether every sample has a configuration.
        required_margin: The margin a feasible placement keeps from every limit (a share, see
            :class:`placement.evaluation.evaluator.EvaluatorSettings`).
    """

    placements: np.ndarray
    objectives: tuple[str, ...]
    values: np.ndarray
    margins: np.ndarray
    limits: tuple[str, ...]
    reachable: np.ndarray
    required_margin: float = 0.0

    @property
    def objective(self) -> str:
        """The ranking objective's name."""
        return self.objectives[0]

    def __repr__(self) -> str:
        """A short summary: how many placements, how many feasible, the range of their objective."""
        feasible = self.value[self.feasible]
        spread = f", {self.objective} {feasible.min():.6g} to {feasible.max():.6g}" if len(feasible) else ""
        return f"Evaluation({len(self.placements)} placements, {len(feasible)} feasible{spread})"

    @property
    def value(self) -> np.ndarray:
        """(K,) the ranking objective."""
        return self.values[:, 0]

    @property
    def feasible(self) -> np.ndarray:
        """(K,) every sample reachable and every margin at least the required one."""
        return self.reachable & (self.margins >= self.required_margin).all(axis=1)

    @staticmethod
    def concatenate(parts: list[Evaluation]) -> Evaluation:
        """The placements of several evaluations, one after the other."""
        return Evaluation(placements=np.concatenate([p.placements for p in parts]), objectives=parts[0].objectives,
                          values=np.concatenate([p.values for p in parts]),
                          margins=np.concatenate([p.margins for p in parts]), limits=parts[0].limits,
                          reachable=np.concatenate([p.reachable for p in parts]),
                          required_margin=parts[0].required_margin)


@dataclass(frozen=True)
class PlacementDetail:
    """Everything about one placement: objective, energy, margins and the per-sample trace (SI).

    Attributes:
        placement: (6,) placement vector.
        objective: The objective's name.
        value: Its value.
        reachable: Whether every sample has a configuration.
        unreachable_samples: Indices of samples without one.
        energy: Energies (scalars, per-actuator arrays).
        margins: Tightest point of each limit kind.
        samples: The path samples in the path frame.
        tool_position_m: (N, 3) tool point in the base frame.
        position, velocity, acceleration, effort: (N, n_act) actuator motion and effort.
        configuration: (N, nq) every joint of the spanning tree (m, rad).
        motor: Motor speed, torque and current, (N, n_act).
        power_W: (N, n_act) signed electric power of each drive at each sample (the mean of the
            adjacent intervals' power, by the drive's motor model).
        timing: The timing law's name (under "optimal", ``samples`` are timed for this placement).
        duration_s: The time the path takes (inf under the optimal law when no timing keeps every
            limit: ``samples`` then hold still at the feed's times).
        hold_effort: (n_act,) actuator efforts holding the path's end pose still, the tool out of the
            cut: gravity alone (N or N·m), for a rest between passes (:mod:`placement.energy.duty`).
        required_margin: The margin a feasible placement keeps from every limit (a share).
        deflection: The tool's deflection under the process forces along the path, where the robot gives every
            actuator's stiffness and reaches every sample; else None.
    """

    placement: np.ndarray
    objective: str
    value: float
    reachable: bool
    unreachable_samples: np.ndarray
    energy: Energy
    margins: list[Margin]
    samples: PathSamples
    tool_position_m: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    configuration: np.ndarray
    motor: MotorTrace
    power_W: np.ndarray
    timing: str
    duration_s: float
    hold_effort: np.ndarray
    required_margin: float = 0.0
    deflection: DeflectionSummary | None = None

    def __repr__(self) -> str:
        """A short summary: the placement (mm, deg), the objective and whether every limit holds."""
        where = ", ".join(f"{value * 1e3:.2f}" for value in self.placement[:3])
        angles = ", ".join(f"{np.degrees(value):.2f}" for value in self.placement[3:])
        state = "feasible" if self.feasible else "INFEASIBLE" if self.reachable else "unreachable"
        return (f"PlacementDetail(at ({where}) mm, ({angles}) deg: {self.objective} {self.value:.6g}, {state}, "
                f"{len(self.samples)} samples, {self.timing} timing)")

    @property
    def feasible(self) -> bool:
        """Reachable and within every limit, keeping the required margin."""
        return self.reachable and all(m.margin >= self.required_margin for m in self.margins)



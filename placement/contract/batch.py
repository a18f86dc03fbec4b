"""What the exact chain computes for a batch of placements, handed to objectives and limits."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from placement.dynamics.path_dynamics import sample_rows
from placement.energy.integration import DrivePower, Energy, drive_power, electric_energy, interval_widths
from placement.energy.trace import MotorTrace
from placement.kinematics.base import KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory
from placement.path.samples import PathSamples
from placement.path.time_law import TimeLaw
from placement.placing.transform import placed_task, placement_pose
from placement.robot.model import Robot
from placement.stiffness import Deflection, joint_springs, path_deflection


@dataclass(frozen=True)
class EvaluatedBatch:
    """K placements of one sampled path, through kinematics, dynamics and drives (SI units).

    Arrays are shaped (K, N, ...): K placements, N samples; the actuator axis is last.

    Attributes:
        robot: The robot.
        samples: The path sampled in its own frame.
        placements: (K, 6) placement vectors [x, y, z, phi, theta, psi] (m, rad).
        reachable: (K, N) whether each sample has a configuration (unreachable samples hold
            the reference configuration at rest, so every value stays finite).
        tool_position_m: (K, N, 3) tool point in the base frame.
        position, velocity, acceleration: (K, N, n_act) actuator motion (m or rad, per s, per s²).
        effort: (K, N, n_act) actuator forces (N) or torques (N·m).
        motor: Motor speed, torque and current, (K, N, n_act).
        regeneration: The regeneration policy energies are computed under.
        joints: Motion of every joint of the spanning tree, K·N rows (placement-major).
        exact: Every limit is to be computed exactly at every sample (for a report or a re-check);
            else a limit may spare work that cannot change feasibility (a search's batch).
        required_margin: The share of every limit a feasible placement keeps free
            (:attr:`placement.evaluation.evaluator.EvaluatorSettings.margin`).
        feasibility_only: Only whether each margin reaches ``required_margin`` is read, not how far
            beyond: a limit may return, for a margin beyond it, a lower bound still beyond it.
        time_law: Each placement's own timing at ``samples`` under the optimal timing law
            (``samples`` then hold the path at unit speed), else None: every placement shares
            ``samples.t_s``.
        path_law: The same timing at the samples of the path geometry it was found on
            (:class:`placement.path.samples.PathGeometry`), or None.
        distinct_samples: The samples that do not repeat the one before (under the optimal timing law, a sample
            inside a run is evaluated twice, zero time apart, at the same position and velocity), or None: every
            sample. A limit on position or velocity checks these alone (:meth:`distinct`).
        max_deflection_m: The largest deflection of the tool under the process load a feasible placement may have
            (m; the path file's ``max_deflection_um`` or ``--max-deflection-um``), or None: no such limit.
        loaded_solver: With the loaded correction (the path file's ``loaded_stiffness`` or ``--loaded-stiffness``),
            the kinematics solver that finds the loaded equilibrium (:mod:`placement.stiffness.loaded`); else None.
    """

    robot: Robot
    samples: PathSamples
    placements: np.ndarray
    reachable: np.ndarray
    tool_position_m: np.ndarray
    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    motor: MotorTrace
    regeneration: str
    joints: JointTrajectory
    exact: bool = False
    required_margin: float = 0.0
    feasibility_only: bool = False
    time_law: TimeLaw | None = None
    path_law: TimeLaw | None = None
    distinct_samples: np.ndarray | None = None
    max_deflection_m: float | None = None
    loaded_solver: KinematicsSolver | None = None

    def __len__(self) -> int:
        return len(self.placements)

    def distinct(self, values: np.ndarray) -> np.ndarray:
        """(K, N', m) ``values`` (K, N, m), a function of the samples' position and velocity, at the distinct samples
        (laid out column by column, :func:`placement.dynamics.path_dynamics.sample_rows`), or the values themselves."""
        return values if self.distinct_samples is None else sample_rows(values, self.distinct_samples)

    @cached_property
    def energy(self) -> Energy:
        """Electric energy of each placement under the regeneration policy (computed once)."""
        return electric_energy(self.robot, self.motor, self.t_s, self.samples.piece, self.regeneration,
                               self.drive_power)

    @cached_property
    def deflection(self) -> Deflection:
        """The tool's deflection under the process force at every sample (:mod:`placement.stiffness`; computed once).

        Raises:
            RobotFileError: An actuator gives no stiffness.
            SettingsError: The loaded correction does not cover the robot or finds no equilibrium.
        """
        rotation = placement_pose(self.placements, self.robot.plane)[0]  # path frame in the base frame, (K, 3, 3)
        force = np.matmul(self.samples.force_on_tool_N, rotation.transpose(0, 2, 1))
        loaded = None
        if self.loaded_solver is not None:
            loaded = (self.loaded_solver, placed_task(self.robot, self.samples, self.placements)[0])
        return path_deflection(joint_springs(self.robot), self.joints, force, loaded)

    @cached_property
    def drive_power(self) -> DrivePower:
        """The drives' power on the intervals between samples and its integrals, under any regeneration policy
        (computed once)."""
        return drive_power(self.robot, self.motor, self.t_s, self.samples.piece)

    @cached_property
    def interval_power_W(self) -> np.ndarray:
        """(K, N-1, n_act) signed electric power of each drive on each interval between samples."""
        return self.drive_power.parts.total_W

    def under(self, regeneration: str) -> EvaluatedBatch:
        """The same batch with its energies under another regeneration policy (the drives' power, the same under
        every policy, computed once for both)."""
        other = dataclasses.replace(self, regeneration=regeneration)
        other.__dict__["drive_power"] = self.drive_power  # a cached property's slot: nothing else carries over
        return other

    @property
    def t_s(self) -> np.ndarray:
        """(N,) time of each sample, shared by the placements, or (K, N), each placement's own."""
        return self.samples.t_s if self.time_law is None else self.time_law.t_s

    @property
    def interval_widths_s(self) -> np.ndarray:
        """(N-1,) or (K, N-1) (as ``t_s``) durations between samples, 0 where a new independently integrated
        piece starts."""
        return interval_widths(self.t_s, self.samples.piece)

    @property
    def widths_by_placement_s(self) -> np.ndarray:
        """(K, N-1) durations between samples, placement by placement (``interval_widths_s``, broadcast)."""
        return np.broadcast_to(self.interval_widths_s, (len(self), len(self.samples) - 1))

"""Kinematics solvers, a plug-in family: from a task trajectory to every joint's motion.

A solver turns an end-effector trajectory into the motion of every joint of the spanning tree,
marking the samples it cannot reach instead of raising, so that a batch of placements is never
stopped by one bad sample. The built-ins are ``closed_form`` (a robot's own closed-form plug-in,
batched over samples), ``numeric`` (Newton for any closed-loop or serial robot of revolute and
prismatic joints, batched over samples) and ``sequential`` (Gauss–Newton sample after sample, for
any joint). A package adds a solver class under the entry-point group
``placement.kinematics``; a sidecar may name one in ``kinematics``.
"""

from __future__ import annotations

import os
from abc import ABC, abstractmethod
from typing import ClassVar

import numpy as np
import pinocchio as pin

from placement.exceptions import SettingsError
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.registry import Registry
from placement.robot.closures import LWA
from placement.robot.model import Robot

SINGULAR_CONDITION = 1e8  # condition number of the task map beyond which a sample is singular


class KinematicsSolver(ABC):
    """Solves the kinematics of one robot.

    Attributes:
        vectorized: Whether one call on many placements' samples runs at compiled speed; the
            evaluator otherwise spreads placements over worker processes.
        threads: Most threads a vectorized solver may use (default: every core; 1 in worker processes).
    """

    vectorized: ClassVar[bool] = False

    def __init__(self, robot: Robot, threads: int | None = None) -> None:
        reason = self.unsuitable(robot)
        if reason:
            raise SettingsError(f"kinematics solver '{type(self).__name__}' cannot serve robot '{robot.name}': {reason}")
        self.robot = robot
        self.threads = threads or os.cpu_count() or 1

    @classmethod
    def unsuitable(cls, robot: Robot) -> str | None:
        """Why this solver cannot serve ``robot``, or None when it can."""
        return None

    @abstractmethod
    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        """Joint motion along ``task``.

        Args:
            task: End-effector trajectory in the base frame, made of ``placements`` independent
                trajectories of equal length one after the other.
            placements: How many.

        Returns:
            The joint motion (unreachable samples hold the reference configuration at rest, so every
            value is finite), the (N,) mask of reachable samples, and why the first unreachable
            one failed.
        """


SOLVERS: Registry[type[KinematicsSolver]] = Registry("kinematics solver", "placement.kinematics", KinematicsSolver,
                                                     instances=False)


def solver_name(robot: Robot, name: str = "auto") -> str:
    """The solver's name: ``name``, or for "auto" the sidecar's, else ``closed_form`` where it serves the robot
    (a plug-in, and the path followed by the frame it solves for), else
    ``numeric`` where it serves the robot, else ``sequential``."""
    if name != "auto":
        return name
    if robot.kinematics_name:
        return robot.kinematics_name
    if SOLVERS.get("closed_form").unsuitable(robot) is None:
        return "closed_form"
    return "numeric" if SOLVERS.get("numeric").unsuitable(robot) is None else "sequential"


def solver_for(robot: Robot, name: str = "auto", threads: int | None = None) -> KinematicsSolver:
    """The solver called ``name`` (see :func:`solver_name`) for ``robot``, on at most ``threads`` threads."""
    return SOLVERS.get(solver_name(robot, name))(robot, threads)


def task_error(robot: Robot, data: pin.Data, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
    """End-effector error against a target (frames already placed in ``data``)."""
    frame = data.oMf[robot.end_effector_frame_id]
    error = frame.translation - position
    if rotation is None:
        return error
    return np.concatenate([error, pin.log3(frame.rotation @ rotation.T)])


def task_jacobian(robot: Robot, data: pin.Data, dimension: int) -> np.ndarray:
    """End-effector Jacobian rows of the task (joint Jacobians already computed in ``data``)."""
    return pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[:dimension]


def task_step(task: TaskTrajectory, k: int) -> np.ndarray:
    """Task displacement from sample k-1 to k: position, then rotation (world frame) for a pose."""
    move = task.position_m[k] - task.position_m[k - 1]
    if task.rotation is None:
        return move
    return np.concatenate([move, pin.log3(task.rotation[k] @ task.rotation[k - 1].T)])


def condition_1(matrices: np.ndarray, inverses: np.ndarray) -> np.ndarray:
    """1-norm condition numbers of a stack of matrices given their inverses (inf if singular)."""
    norm = np.abs(matrices).sum(axis=1).max(axis=1)
    inverse_norm = np.abs(inverses).sum(axis=1).max(axis=1)
    return np.where(np.isfinite(inverse_norm), norm * inverse_norm, np.inf)

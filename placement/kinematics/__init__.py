"""Kinematics: every joint's motion along an end-effector trajectory, by a solver of the family."""

from __future__ import annotations

import numpy as np

from placement.exceptions import SettingsError
from placement.kinematics.base import SOLVERS, KinematicsSolver, solver_for
from placement.kinematics.batched import BatchedSolver
from placement.kinematics.closed_form import ClosedFormSolver
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.generic import SequentialSolver, solve_configuration
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot

__all__ = ["SOLVERS", "BatchedSolver", "ClosedFormSolver", "JointTrajectory", "KinematicsSolver", "SequentialSolver",
           "TaskTrajectory",
           "joint_trajectory", "solve_configuration", "solver_for"]


def joint_trajectory(robot: Robot, task: TaskTrajectory, method: str = "auto") -> JointTrajectory:
    """Motion of every joint along a task-space trajectory.

    Args:
        robot: The robot.
        task: End-effector trajectory in the base frame (a pose for a pose task).
        method: A kinematics solver's name ("closed_form", "numeric", "sequential", or an installed one), or
            "auto" (the sidecar's choice, else the robot's plug-in, else "numeric").

    Returns:
        Joint positions, velocities, accelerations, null-space basis and task map per sample.

    Raises:
        UnreachableError: Some samples have no configuration or are singular (all are listed).
        SettingsError: The task does not match the robot, or the solver cannot serve it.
    """
    joints, reachable, reason = _solve(robot, task, method)
    if not reachable.all():
        indices = np.flatnonzero(~reachable).tolist()
        where = f" (first at {np.round(task.position_m[indices[0]], 6).tolist()} m)" if "target" not in reason else ""
        raise UnreachableError(indices, len(indices), reason + where)
    return joints


def _solve(robot: Robot, task: TaskTrajectory, method: str) -> tuple[JointTrajectory, np.ndarray, str]:
    if task.is_pose != (robot.task == "pose"):
        raise SettingsError(f"robot '{robot.name}' has a {robot.task} task; the trajectory gives "
                            f"{'a pose' if task.is_pose else 'positions only'}")
    return solver_for(robot, method).solve(task)

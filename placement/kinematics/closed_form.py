"""The ``closed_form`` kinematics solver: a robot's own closed-form plug-in, batched over samples.

The plug-in (``kinematics_plugin`` in the sidecar) gives every joint as a function of the platform
position, written with second-order Taylor arithmetic (:mod:`placement.kinematics.taylor`), so that one numpy
pass yields positions, exact rates and accelerations, and ``∂q/∂p`` for all samples at once.
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np

from placement.kinematics.base import SINGULAR_CONDITION, SOLVERS, KinematicsSolver, condition_1
from placement.kinematics.taylor import Taylor2
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot


def _closed_form(robot: Robot, task: TaskTrajectory,
                 columns: dict[str, tuple[int, int]]) -> tuple[JointTrajectory, np.ndarray, str]:
    """Batched plug-in path: Taylor arithmetic gives rates, accelerations and ∂q/∂p at once (``columns``: each
    joint's q and v index, by name)."""
    model, n = robot.model, len(task)
    # Row 0 carries the trajectory's derivatives; rows 1-3 the unit directions e_x, e_y, e_z (coordinate c's axis).
    value, rate, acceleration = np.empty((3, 4, n)), np.zeros((3, 4, n)), np.zeros((3, 4, n))
    value[:] = task.position_m.T[:, None, :]
    rate[:, 0], acceleration[:, 0] = task.velocity_m_s.T, task.acceleration_m_s2.T
    rate[:, 1:][np.eye(3, dtype=bool)] = 1.0
    coordinates = tuple(Taylor2(value[c], rate[c], acceleration[c]) for c in range(3))
    solve = robot.closed_form
    assert solve is not None  # ClosedFormSolver.unsuitable
    with np.errstate(invalid="ignore", divide="ignore"):
        joints = solve(coordinates)
    q, v, a = np.zeros((n, model.nq)), np.zeros((n, model.nv)), np.zeros((n, model.nv))
    jacobian = np.zeros((n, model.nv, 3))
    for name, value in joints.items():
        i_q, i_v = columns[name]
        q[:, i_q], v[:, i_v], a[:, i_v] = value.v[0], value.d1[0], value.d2[0]
        jacobian[:, i_v, :] = value.d1[1:].T
    finite = (np.isfinite(q).all(axis=1) & np.isfinite(v).all(axis=1) & np.isfinite(a).all(axis=1)
              & np.isfinite(jacobian).all(axis=(1, 2)))
    bad = np.asarray(~finite)
    actuated = np.where(bad[:, None, None], np.eye(3), jacobian[:, robot.actuated_v_indices, :])  # ∂rho/∂p
    with np.errstate(invalid="ignore", divide="ignore"):
        task_map = np.linalg.inv(actuated)  # ∂p/∂rho
    bad |= ~(condition_1(actuated, task_map) < SINGULAR_CONDITION)
    if bad.any():  # finite placeholders: the reference configuration at rest
        q[bad], v[bad], a[bad], jacobian[bad] = robot.reference_q, 0.0, 0.0, 0.0
        actuated[bad], task_map[bad] = np.eye(3), np.eye(3)
    reason = "outside the reach of the closed-form kinematics or singular"
    return JointTrajectory(q, v, a, jacobian @ task_map, task_map), ~bad, reason


class ClosedFormSolver(KinematicsSolver):
    """The robot's closed-form plug-in: position tasks of three-actuator robots."""

    vectorized: ClassVar[bool] = True

    @classmethod
    def unsuitable(cls, robot: Robot) -> str | None:
        if robot.closed_form is None:
            return "the robot has no kinematics_plugin"
        if robot.model.frames[robot.end_effector_frame_id].name != robot.mount_frame:
            return "a tool tip moves the path point off the frame the plug-in solves for"
        return None

    def __init__(self, robot: Robot, threads: int | None = None) -> None:
        super().__init__(robot, threads)
        model = robot.model
        self._columns = {model.names[j]: (joint.idx_q, joint.idx_v) for j, joint in enumerate(model.joints)}

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        return _closed_form(self.robot, task, self._columns)


SOLVERS.add("closed_form", ClosedFormSolver)

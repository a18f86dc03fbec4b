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
    joint's q and v index, by name). Samples run along the arrays' last axis until the end."""
    model, n = robot.model, len(task)
    # Row 0 carries the trajectory's derivatives; rows 1-3 the unit directions e_x, e_y, e_z (coordinate c's axis),
    # first derivatives only. The value is the same in every row: one row, broadcast.
    rate, acceleration = np.zeros((3, 4, n)), np.ascontiguousarray(task.acceleration_m_s2.T)[:, None]
    rate[:, 0] = task.velocity_m_s.T
    rate[:, 1:][np.eye(3, dtype=bool)] = 1.0
    value = np.ascontiguousarray(task.position_m.T)
    coordinates = tuple(Taylor2(value[c][None], rate[c], acceleration[c]) for c in range(3))
    solve = robot.closed_form
    assert solve is not None  # ClosedFormSolver.unsuitable
    with np.errstate(invalid="ignore", divide="ignore"):
        joints = solve(coordinates)
    q, v, a = np.zeros((model.nq, n)), np.zeros((model.nv, n)), np.zeros((model.nv, n))
    jacobian = np.zeros((model.nv, 3, n))  # [joint, coordinate, sample]
    for name, value in joints.items():
        i_q, i_v = columns[name]
        q[i_q], v[i_v], a[i_v], jacobian[i_v] = value.v[0], value.d1[0], value.d2[0], value.d1[1:]
    finite = (np.isfinite(q).all(axis=0) & np.isfinite(v).all(axis=0) & np.isfinite(a).all(axis=0)
              & np.isfinite(jacobian).all(axis=(0, 1)))
    actuated = jacobian[robot.actuated_v_indices]  # ∂rho/∂p
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        task_map = _inverses(actuated)  # ∂p/∂rho
    bad = ~(finite & (condition_1(np.moveaxis(actuated, -1, 0), np.moveaxis(task_map, -1, 0)) < SINGULAR_CONDITION))
    if bad.any():  # finite placeholders: the reference configuration at rest
        q[:, bad], v[:, bad], a[:, bad], jacobian[..., bad] = robot.reference_q[:, None], 0.0, 0.0, 0.0
        task_map[..., bad] = np.eye(3)[..., None]
    basis = np.einsum("icn,ckn->ikn", jacobian, task_map)  # ∂q/∂rho: [joint, actuator, sample]
    reason = "outside the reach of the closed-form kinematics or singular"
    trajectory = JointTrajectory(*(np.ascontiguousarray(np.moveaxis(x, -1, 0)) for x in (q, v, a, basis, task_map)))
    return trajectory, ~bad, reason


def _inverses(matrices: np.ndarray) -> np.ndarray:
    """(3, 3, N) the inverses of the 3 × 3 matrices ``matrices[:, :, k]``, by their adjugates (inf or nan where one is
    singular)."""
    (a, b, c), (d, e, f), (g, h, i) = matrices
    adjugate = np.array([[e * i - f * h, c * h - b * i, b * f - c * e],
                         [f * g - d * i, a * i - c * g, c * d - a * f],
                         [d * h - e * g, b * g - a * h, a * e - b * d]])
    return adjugate / (a * adjugate[0, 0] + b * adjugate[1, 0] + c * adjugate[2, 0])


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

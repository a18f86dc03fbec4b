"""Kinetostatic objectives: how well the actuators transmit motion and force to the tool along the path.

Both read the task map J = J_task·G of each sample (task velocity per unit actuator velocity, see
:class:`placement.kinematics.trajectories.JointTrajectory`), made dimensionless first: linear task rows and
prismatic actuator columns are divided by a characteristic length L, so that a slider moving at
L per second and a joint turning at 1 rad/s weigh the same. L is the mean distance, at the
reference configuration, from the actuated joints to the end-effector frame; it only matters for
robots that mix units (a pose task, or prismatic and revolute actuators together): a
translational machine with sliders (the Orthoglide) has a dimensionless J already.

- ``dexterity``: the worst condition number σ_max/σ_min of J along the path (1 is isotropic; it
  grows without bound near a singularity).
- ``transmission``: the worst velocity transmission factor, max over the path of max(σ_max,
  1/σ_min): how much faster (or slower) than its actuators the tool can move in the least
  favourable direction. Suited to parallel machines: the Orthoglide was designed to keep its
  factors within [1/2, 2] over its whole cubic workspace (Chablat and Wenger, 2003), so the
  index is 1 at its isotropic point and 2 at the cube's corners Q⁺ and Q⁻.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.contract.batch import EvaluatedBatch
from placement.contract.objective import OBJECTIVES, Objective
from placement.robot.model import Robot

SINGULAR_FLOOR = 1e-12  # smallest singular value divided by: a singular sample gives a huge but finite index


def characteristic_length_m(robot: Robot) -> float:
    """Mean distance (m) from the actuated joints to the end-effector frame at the reference configuration."""
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    tool = data.oMf[robot.end_effector_frame_id].translation
    joints = [robot.model.getJointId(a.joint) for a in robot.actuators]
    length = float(np.mean([np.linalg.norm(tool - data.oMi[j].translation) for j in joints]))
    return length if length > 0 else 1.0


def dimensionless_task_map(robot: Robot, task_map: np.ndarray) -> np.ndarray:
    """The task map (M, task_dim, n_act) with linear rows and prismatic columns divided by L (module docstring)."""
    length = characteristic_length_m(robot)
    rows = np.ones(task_map.shape[1])
    rows[:3] /= length
    columns = np.array([length if a.prismatic else 1.0 for a in robot.actuators])
    return task_map * rows[:, None] * columns[None, :]


def singular_values(batch: EvaluatedBatch) -> np.ndarray:
    """(K, N, r) singular values of the dimensionless task map at every sample, largest first."""
    k, n = batch.reachable.shape
    values = np.linalg.svd(dimensionless_task_map(batch.robot, batch.joints.task_map), compute_uv=False)
    return np.maximum(values, SINGULAR_FLOOR).reshape(k, n, -1)


class Dexterity(Objective):
    """Worst condition number σ_max/σ_min of the dimensionless task map along the path."""

    title = "Jacobian condition number"
    unit = ""

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        values = singular_values(batch)
        return (values[..., 0] / values[..., -1]).max(axis=1)


class Transmission(Objective):
    """Worst velocity transmission factor max(σ_max, 1/σ_min) along the path (1 at an isotropic point)."""

    title = "velocity transmission factor"
    unit = ""

    def __call__(self, batch: EvaluatedBatch) -> np.ndarray:
        values = singular_values(batch)
        return np.maximum(values[..., 0], 1.0 / values[..., -1]).max(axis=1)


OBJECTIVES.add("dexterity", Dexterity())
OBJECTIVES.add("transmission", Transmission())

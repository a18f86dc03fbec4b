"""Actuator efforts by Pinocchio's RNEA, sample by sample: the reference the batched dynamics is checked against."""

from __future__ import annotations

import numpy as np
import pinocchio as pin


def rnea_actuator_efforts(robot, joints, force: np.ndarray) -> np.ndarray:
    """The actuators' efforts (N m or N), (N, n_actuators), on a serial robot's joint trajectory with a load on its tool.

    Args:
        robot: A serial robot (a tree: every joint's effort from RNEA).
        joints: Its trajectory: ``q``, ``v``, ``a`` (N, nq) / (N, nv).
        force: (N, 6) the wrench on the tool from the workpiece (N, N m; base frame, at the tool point), balanced by the
            joints.
    """
    model = robot.model
    data = model.createData()
    efforts = np.empty((len(joints.q), model.nv))
    for k in range(len(joints.q)):
        torque = pin.rnea(model, data, joints.q[k], joints.v[k], joints.a[k])
        jacobian = pin.computeFrameJacobian(model, data, joints.q[k], robot.end_effector_frame_id,
                                            pin.LOCAL_WORLD_ALIGNED)
        efforts[k] = torque - jacobian.T @ force[k]
    return efforts[:, robot.actuated_v_indices]

"""Loop-closure equations of a robot's spanning tree: residuals, Jacobian and drift.

Each closure ties two frames: a point closure makes their origins coincide (3 equations), a weld
also aligns their orientations (6 equations). Rows are expressed in the world-aligned frame at
each frame's origin (Pinocchio's LOCAL_WORLD_ALIGNED).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.robot.model import Robot

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED


def closure_residuals(robot: Robot, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Stacked closure errors at ``q``: position gaps (m) and, for welds, rotation gaps (rad)."""
    pin.framesForwardKinematics(robot.model, data, q)
    parts = []
    for closure in robot.closures:
        m1, m2 = (data.oMf[i] for i in closure.frame_ids)
        parts.append(m1.translation - m2.translation)
        if closure.kind == "weld":
            parts.append(pin.log3(m1.rotation @ m2.rotation.T))
    return np.concatenate(parts) if parts else np.zeros(0)


def closure_jacobian(robot: Robot, data: pin.Data, q: np.ndarray) -> np.ndarray:
    """Closure Jacobian (rows, nv) at ``q``; also leaves joint Jacobians and frames in ``data``."""
    pin.computeJointJacobians(robot.model, data, q)
    pin.updateFramePlacements(robot.model, data)
    rows = []
    for closure in robot.closures:
        j1, j2 = (pin.getFrameJacobian(robot.model, data, i, LWA) for i in closure.frame_ids)
        rows.append((j1 - j2)[: closure.dimension])
    return np.vstack(rows) if rows else np.zeros((0, robot.model.nv))


def closure_drift(robot: Robot, data: pin.Data) -> np.ndarray:
    """J̇·v of the closures, after ``forwardKinematics(q, v, 0)``."""
    parts = []
    for closure in robot.closures:
        a1, a2 = (pin.getFrameClassicalAcceleration(robot.model, data, i, LWA) for i in closure.frame_ids)
        parts.append((a1.vector - a2.vector)[: closure.dimension])
    return np.concatenate(parts) if parts else np.zeros(0)

"""An independent static solver for the tests: the full nonlinear equilibrium of a robot's springs under a load.

The robot's springs (k at some joints, every other joint free) hold the end effector against a constant load w
(force at its origin, world-aligned; then a moment, for a pose task). Its equilibrium configuration q solves

    K·(q − q₀) = J_e(q)ᵀ·w + J_c(q)ᵀ·λ,   c(q) = 0,

the stationarity of ½·(q − q₀)ᵀ·K·(q − q₀) − (work of w) with the closures c(q) = 0 enforced by multipliers λ. It
is solved by Newton steps on the whole nonlinear system (kinematics, Jacobians and closures from Pinocchio at the
current q, nothing linearised once), each step by least squares (redundant closures make the system singular in λ
alone). The tool's displacement is read from Pinocchio's frame placements: translation (m) and rotation vector
log(R·R₀ᵀ) (rad), world frame. Nothing of placement's kinematics solvers, null-space basis or task map is used.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.robot.closures import LWA, closure_jacobian, closure_residuals
from placement.robot.model import Robot

STEPS = 30
TOLERANCE = 1e-15  # of the largest step of q (m, rad): Newton's steps shrink quadratically to rounding


def tool_pose(robot: Robot, data: pin.Data, q: np.ndarray) -> pin.SE3:
    pin.framesForwardKinematics(robot.model, data, q)
    return data.oMf[robot.end_effector_frame_id].copy()


def settle(robot: Robot, q0: np.ndarray, stiffness_by_v: dict[int, float], load: np.ndarray) -> np.ndarray:
    """The tool's displacement (d,) at the equilibrium under ``load`` (d,), from the unloaded configuration q₀
    (closures closed), springs ``stiffness_by_v`` {velocity index: N/m or N·m/rad}."""
    data = robot.model.createData()
    q = equilibrium(robot, q0, stiffness_by_v, load)
    start, end = tool_pose(robot, data, q0), tool_pose(robot, data, q)
    moved = end.translation - start.translation
    return moved if len(load) == 3 else np.concatenate([moved, pin.log3(end.rotation @ start.rotation.T)])


def equilibrium(robot: Robot, q0: np.ndarray, stiffness_by_v: dict[int, float], load: np.ndarray) -> np.ndarray:
    """The equilibrium configuration under ``load`` (see :func:`settle`)."""
    model, data = robot.model, robot.model.createData()
    stiffness = np.zeros((model.nv, model.nv))
    for v, k in stiffness_by_v.items():
        stiffness[v, v] = k
    dimension = len(load)
    q = q0.copy()
    for _ in range(STEPS):
        constraint = closure_jacobian(robot, data, q)  # also the joint Jacobians of q, in data
        tool = pin.getFrameJacobian(model, data, robot.end_effector_frame_id, LWA)[:dimension]
        residual = np.concatenate([stiffness @ pin.difference(model, q0, q) - tool.T @ load,
                                   closure_residuals(robot, data, q)])
        # the Jacobian of the residual: K plus the load's and the closures' curvature, by central differences
        jacobian = np.column_stack([_residual_rate(robot, q, load, stiffness, q0, e) for e in np.eye(model.nv)])
        rows, scale = len(constraint), max(stiffness_by_v.values())  # equilibrium rows in units of the stiffest spring,
        residual[: model.nv] /= scale  # so that the least squares are well conditioned (λ then in those units too)
        kkt = np.block([[jacobian[: model.nv] / scale, -constraint.T], [jacobian[model.nv:], np.zeros((rows, rows))]])
        step = np.linalg.lstsq(kkt, -residual, rcond=None)[0][: model.nv]
        q = pin.integrate(model, q, step)
        if np.abs(step).max() < TOLERANCE:
            break
    return q


def _residual_rate(robot: Robot, q: np.ndarray, load: np.ndarray, stiffness: np.ndarray, q0: np.ndarray,
                   direction: np.ndarray, h: float = 1e-6) -> np.ndarray:
    """d/dε of [K·(q − q₀) − J_eᵀ·w; c(q)] along ``direction`` (the λ terms are handled by the KKT block)."""
    def residual(offset: float) -> np.ndarray:
        moved = pin.integrate(robot.model, q, offset * direction)
        data = robot.model.createData()
        closure_jacobian(robot, data, moved)
        tool = pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[: len(load)]
        return np.concatenate([stiffness @ pin.difference(robot.model, q0, moved) - tool.T @ load,
                               closure_residuals(robot, data, moved)])

    return (residual(h) - residual(-h)) / (2 * h)

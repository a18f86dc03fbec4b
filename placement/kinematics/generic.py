"""The sequential kinematics solver (``sequential``): any closed-loop or serial robot, sample by sample.

The batched ``numeric`` solver is the generic route; this one serves joints it does not handle
(spherical, floating, in Pinocchio models built by hand) and is its independent reference in the tests.

Closed loops: damped Gauss–Newton on the stacked closure residuals and end-effector error,
warm-started from a first-order prediction of the previous sample, with a homotopy from the
reference configuration to the first sample; joint rates and accelerations follow from the
closure Jacobian and its drift: ``v = G·ρ̇`` with ``G[act] = I``, ``G[passive] = −J_p⁺·J_a``, and
``a = G·ρ̈ − J_p⁺·γ`` on the passive joints. Serial arms (every joint actuated): Gauss–Newton on
the end-effector error alone, so the configuration stays on one continuous branch.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import pinocchio as pin

from placement.kinematics.base import (
    SINGULAR_CONDITION,
    SOLVERS,
    KinematicsSolver,
    condition_1,
    task_error,
    task_jacobian,
    task_step,
)
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory, task_rows
from placement.robot.closures import LWA, closure_drift, closure_jacobian, closure_residuals
from placement.robot.model import Robot

SOLVE_TOLERANCE = 1e-12  # residual norm (m and rad) at which Gauss–Newton stops
MAX_ITERATIONS = 60
MAX_STEP = 0.2  # largest joint step of one Gauss–Newton iteration (m or rad)
CONTINUATION_STEP_M = 0.02  # first-sample homotopy step from the reference configuration

# Reaches one target: (robot, position, rotation or None, start configuration, data) -> configuration.
Solve = Callable[[Robot, np.ndarray, "np.ndarray | None", np.ndarray, pin.Data], np.ndarray]


def solve_configuration(robot: Robot, position_m: np.ndarray, rotation: np.ndarray | None = None,
                        q_start: np.ndarray | None = None, data: pin.Data | None = None) -> np.ndarray:
    """Full configuration (actuated and passive joints) placing the end effector at a target.

    Damped Gauss–Newton on the stacked closure residuals and end-effector error, from
    ``q_start`` (default: the robot's reference configuration).

    Args:
        position_m: Target position of the end-effector frame origin in the base frame (m).
        rotation: Target orientation (3x3) for a pose task, else None.
        q_start: Initial guess.
        data: Pinocchio data to work in (created if None).

    Returns:
        The configuration (nq,).

    Raises:
        UnreachableError: Gauss–Newton did not reach the target.
    """
    data = data or robot.model.createData()
    q = (robot.reference_q if q_start is None else q_start).copy()
    dimension = 3 if rotation is None else 6
    residual = np.inf
    for _ in range(MAX_ITERATIONS):
        jacobian = closure_jacobian(robot, data, q)
        residual_vector = np.concatenate([closure_residuals(robot, data, q),
                                          task_error(robot, data, position_m, rotation)])
        residual = float(np.linalg.norm(residual_vector))
        if residual < SOLVE_TOLERANCE:
            return q
        full = np.vstack([jacobian, task_jacobian(robot, data, dimension)])
        step = -np.linalg.lstsq(full, residual_vector, rcond=None)[0]
        largest = np.abs(step).max()
        if largest > MAX_STEP:
            step *= MAX_STEP / largest
        q = pin.integrate(robot.model, q, step)
    raise UnreachableError([0], 1, f"no configuration reaches the target {np.round(position_m, 6).tolist()} m "
                                   f"(residual {residual:.2e} after {MAX_ITERATIONS} iterations)")


def first_configuration(robot: Robot, data: pin.Data, task: TaskTrajectory, solve: Solve | None = None) -> np.ndarray:
    """Walk from the reference configuration to the first sample in small steps.

    ``solve(robot, position, rotation, q, data)`` reaches one target (default: the generic solver).
    """
    solve = solve or solve_configuration
    q = robot.reference_q.copy()
    pin.framesForwardKinematics(robot.model, data, q)
    frame = data.oMf[robot.end_effector_frame_id]
    start_p, start_r = frame.translation.copy(), frame.rotation.copy()
    turn = pin.log3(start_r.T @ task.rotation[0]) if task.rotation is not None else np.zeros(3)
    steps = max(1, int(np.ceil(max(np.linalg.norm(task.position_m[0] - start_p), np.linalg.norm(turn) * 0.1)
                               / CONTINUATION_STEP_M)))
    for s in np.linspace(0.0, 1.0, steps + 1)[1:]:
        rotation = start_r @ pin.exp3(s * turn) if task.rotation is not None else None
        q = solve(robot, start_p + s * (task.position_m[0] - start_p), rotation, q, data)
    return q


def null_space_basis(robot: Robot, jacobian: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """G with G[actuated] = I, G[passive] = -J_p⁺·J_a; also J_p⁺ and the passive indices."""
    nv = robot.model.nv
    act = robot.actuated_v_indices
    passive = np.setdiff1d(np.arange(nv), act)
    basis = np.zeros((nv, len(act)))
    basis[act, np.arange(len(act))] = 1.0
    pinv = np.linalg.pinv(jacobian[:, passive]) if len(passive) else np.zeros((0, jacobian.shape[0]))
    basis[passive] = -pinv @ jacobian[:, act]
    return basis, pinv, passive


def _solve_task_map(task_map: np.ndarray, rhs: np.ndarray, index: int) -> np.ndarray:
    if np.linalg.cond(task_map) > SINGULAR_CONDITION:
        raise UnreachableError([index], 1, "singular configuration: the actuators cannot produce the task motion")
    return np.linalg.lstsq(task_map, rhs, rcond=None)[0]


def _numeric(robot: Robot, task: TaskTrajectory) -> tuple[JointTrajectory, np.ndarray, str]:
    model, data = robot.model, robot.model.createData()
    n, dim, n_act = len(task), robot.task_dimension, len(robot.actuators)
    q_all, v_all, a_all = np.zeros((n, model.nq)), np.zeros((n, model.nv)), np.zeros((n, model.nv))
    basis_all, map_all = np.zeros((n, model.nv, n_act)), np.zeros((n, dim, n_act))
    twist, acceleration = task.twist(), task.acceleration()
    reachable = np.ones(n, dtype=bool)
    reason = ""
    q: np.ndarray | None = None
    basis, task_map = np.zeros((model.nv, n_act)), np.zeros((dim, n_act))  # set by each solved sample
    for k in range(n):
        try:
            rotation = task.rotation[k] if task.rotation is not None else None
            if q is None:
                q = first_configuration(robot, data, task)
            elif reachable[k - 1]:  # first-order prediction from the previous sample
                q = pin.integrate(model, q, basis @ np.linalg.lstsq(task_map, task_step(task, k))[0])
            q = solve_configuration(robot, task.position_m[k], rotation, q, data)
            jacobian = closure_jacobian(robot, data, q)
            end_effector = task_jacobian(robot, data, dim)
            basis, pinv, passive = null_space_basis(robot, jacobian)
            task_map = end_effector @ basis
            v = basis @ _solve_task_map(task_map, twist[k], k)
            pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
            a0 = np.zeros(model.nv)
            a0[passive] = -pinv @ closure_drift(robot, data)
            task_drift = pin.getFrameClassicalAcceleration(model, data, robot.end_effector_frame_id, LWA).vector
            rhodd = _solve_task_map(task_map, acceleration[k] - task_drift[:dim] - end_effector @ a0, k)
        except UnreachableError as error:
            reachable[k] = False
            reason = reason or error.reason
            q_all[k] = robot.reference_q
            continue
        q_all[k], v_all[k], a_all[k] = q, v, basis @ rhodd + a0
        basis_all[k], map_all[k] = basis, task_map
    return JointTrajectory(q_all, v_all, a_all, basis_all, map_all), reachable, reason


def _solve_serial(robot: Robot, position_m: np.ndarray, rotation: np.ndarray | None, q: np.ndarray,
                  data: pin.Data) -> np.ndarray:
    """Gauss–Newton on the end-effector error alone (a serial robot has no closure)."""
    model, frame, dim = robot.model, robot.end_effector_frame_id, 3 if rotation is None else 6
    for _ in range(MAX_ITERATIONS):
        jacobian = pin.computeFrameJacobian(model, data, q, frame, LWA)[:dim]
        error = task_error(robot, data, position_m, rotation)
        if np.linalg.norm(error) < SOLVE_TOLERANCE:
            return q
        try:
            step = -(np.linalg.solve(jacobian, error) if dim == model.nv else np.linalg.lstsq(jacobian, error)[0])
        except np.linalg.LinAlgError:
            raise UnreachableError([0], 1, "singular configuration on the way to the target") from None
        q = pin.integrate(model, q, step * min(1.0, MAX_STEP / np.abs(step).max()))
    raise UnreachableError([0], 1, f"no configuration reaches the target {np.round(position_m, 6).tolist()} m")


def _serial(robot: Robot, task: TaskTrajectory) -> tuple[JointTrajectory, np.ndarray, str]:
    """Serial robots (no closure, every joint actuated): Gauss–Newton on the task alone."""
    model, data, frame = robot.model, robot.model.createData(), robot.end_effector_frame_id
    n, dim, nv = len(task), robot.task_dimension, robot.model.nv
    q_all, v_all, a_all = np.zeros((n, model.nq)), np.zeros((n, nv)), np.zeros((n, nv))
    map_all = np.zeros((n, dim, nv))
    twist, acceleration = task.twist(), task.acceleration()
    reachable = np.ones(n, dtype=bool)
    reason, q = "", None
    inverse = np.zeros((nv, dim))  # set by each solved sample
    for k in range(n):
        rotation = task.rotation[k] if task.rotation is not None else None
        try:
            if q is None:
                q = first_configuration(robot, data, task, _solve_serial)
            elif reachable[k - 1]:  # first-order prediction from the previous sample
                q = pin.integrate(model, q, inverse @ task_step(task, k))
            q = _solve_serial(robot, task.position_m[k], rotation, q, data)
            jacobian = pin.computeFrameJacobian(model, data, q, frame, LWA)[:dim]
            inverse = np.linalg.pinv(jacobian) if dim != nv else np.linalg.inv(jacobian)
            if not condition_1(jacobian[None], inverse[None])[0] < SINGULAR_CONDITION:
                raise UnreachableError([k], 1, "singular configuration: the actuators cannot produce the task motion")
            v = inverse @ twist[k]
            pin.forwardKinematics(model, data, q, v, np.zeros(nv))
            drift = pin.getFrameClassicalAcceleration(model, data, frame, LWA).vector[:dim]
            a = inverse @ (acceleration[k] - drift)
        except UnreachableError as error:
            reachable[k], reason = False, reason or error.reason
            q_all[k] = robot.reference_q
            q = None if k == 0 else q
            continue
        q_all[k], v_all[k], a_all[k], map_all[k] = q, v, a, jacobian
    act = robot.actuated_v_indices
    selection = np.zeros((nv, nv))
    selection[act, np.arange(nv)] = 1.0  # v = G·rhodot with rhodot in actuator order
    basis = np.broadcast_to(selection, (n, nv, nv))
    return JointTrajectory(q_all, v_all, a_all, basis, map_all @ selection), reachable, reason


class SequentialSolver(KinematicsSolver):
    """Gauss–Newton for any robot, sample after sample; each placement walks from the reference configuration."""

    @classmethod
    def unsuitable(cls, robot: Robot) -> str | None:
        if robot.redundant_joints:
            return f"it does not profile redundant joints ({', '.join(robot.redundant_joints)}); use 'numeric'"
        return None

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        solve_one = _serial if self.robot.is_serial else _numeric
        n = len(task) // placements
        pieces = [solve_one(self.robot, task_rows(task, i * n, (i + 1) * n)) for i in range(placements)]
        reason = next((p[2] for p in pieces if p[2]), "")
        return JointTrajectory.concatenate([p[0] for p in pieces]), np.concatenate([p[1] for p in pieces]), reason


SOLVERS.add("sequential", SequentialSolver)

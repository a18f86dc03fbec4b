"""Closed-loop kinematics: configurations, joint rates and accelerations along a trajectory.

Conventions (base frame, SI): a task trajectory gives the end-effector frame origin's position,
velocity and classical acceleration, and for a pose task also its rotation, angular velocity and
angular acceleration, all in the base frame. Joint motion is returned for every joint of the
spanning tree, actuated and passive, together with the null-space basis ``G`` (``v = G·rhodot``)
and the task map ``J_task·G`` (task velocity = ``J_task·G·rhodot``) that dynamics needs.

Two solvers give the same answer: a generic one (damped Gauss–Newton on closure residuals and
end-effector error, warm-started sample to sample, then the closed-loop Jacobian and drift for
rates and accelerations), and a robot's closed-form plug-in, whose positions are differentiated
exactly by second-order Taylor arithmetic (:mod:`placement.taylor`) and which is batched over
samples.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from placement.exceptions import PlacementError, UnreachableError
from placement.robot import Robot
from placement.taylor import Taylor2

LWA = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
SOLVE_TOLERANCE = 1e-12  # residual norm (m and rad) at which Gauss–Newton stops
MAX_ITERATIONS = 60
MAX_STEP = 0.2  # largest joint step of one Gauss–Newton iteration (m or rad)
CONTINUATION_STEP_M = 0.02  # first-sample homotopy step from the reference configuration
SINGULAR_CONDITION = 1e8  # condition number of the task map beyond which a sample is singular


@dataclass(frozen=True)
class TaskTrajectory:
    """End-effector motion in the base frame, one row per sample.

    Attributes:
        position_m: (N, 3) frame origin positions.
        velocity_m_s: (N, 3) their velocities.
        acceleration_m_s2: (N, 3) their classical accelerations.
        rotation: (N, 3, 3) frame orientations (pose tasks only).
        angular_velocity_rad_s: (N, 3) in the base frame (pose tasks only).
        angular_acceleration_rad_s2: (N, 3) in the base frame (pose tasks only).
    """

    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    rotation: np.ndarray | None = None
    angular_velocity_rad_s: np.ndarray | None = None
    angular_acceleration_rad_s2: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.position_m)

    @property
    def is_pose(self) -> bool:
        """Whether orientation is prescribed too."""
        return self.rotation is not None

    def twist(self) -> np.ndarray:
        """(N, 3 or 6) task velocity: linear, then angular for a pose task."""
        if not self.is_pose:
            return self.velocity_m_s
        return np.hstack([self.velocity_m_s, self.angular_velocity_rad_s])

    def acceleration(self) -> np.ndarray:
        """(N, 3 or 6) task acceleration: classical linear, then angular for a pose task."""
        if not self.is_pose:
            return self.acceleration_m_s2
        return np.hstack([self.acceleration_m_s2, self.angular_acceleration_rad_s2])


@dataclass(frozen=True)
class JointTrajectory:
    """Motion of every joint of the spanning tree, one row per sample.

    Attributes:
        q: (N, nq) configurations.
        v: (N, nv) joint velocities.
        a: (N, nv) joint accelerations.
        basis: (N, nv, n_act) null-space basis G of the closure constraints: v = G·rhodot.
        task_map: (N, task_dim, n_act) J_task·G: task velocity per unit actuator velocity.
    """

    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    basis: np.ndarray
    task_map: np.ndarray


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


def _closure_drift(robot: Robot, data: pin.Data) -> np.ndarray:
    """J̇·v of the closures, after ``forwardKinematics(q, v, 0)``."""
    parts = []
    for closure in robot.closures:
        a1, a2 = (pin.getFrameClassicalAcceleration(robot.model, data, i, LWA) for i in closure.frame_ids)
        parts.append((a1.vector - a2.vector)[: closure.dimension])
    return np.concatenate(parts) if parts else np.zeros(0)


def _task_error(robot: Robot, data: pin.Data, position: np.ndarray, rotation: np.ndarray | None) -> np.ndarray:
    frame = data.oMf[robot.end_effector_frame_id]
    error = frame.translation - position
    if rotation is None:
        return error
    return np.concatenate([error, pin.log3(frame.rotation @ rotation.T)])


def _task_jacobian(robot: Robot, data: pin.Data, dimension: int) -> np.ndarray:
    return pin.getFrameJacobian(robot.model, data, robot.end_effector_frame_id, LWA)[:dimension]


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
                                          _task_error(robot, data, position_m, rotation)])
        residual = float(np.linalg.norm(residual_vector))
        if residual < SOLVE_TOLERANCE:
            return q
        full = np.vstack([jacobian, _task_jacobian(robot, data, dimension)])
        step = -np.linalg.lstsq(full, residual_vector, rcond=None)[0]
        largest = np.abs(step).max()
        if largest > MAX_STEP:
            step *= MAX_STEP / largest
        q = pin.integrate(robot.model, q, step)
    raise UnreachableError([0], 1, f"no configuration reaches the target {np.round(position_m, 6).tolist()} m "
                                   f"(residual {residual:.2e} after {MAX_ITERATIONS} iterations)")


def _first_configuration(robot: Robot, data: pin.Data, task: TaskTrajectory, solve=None) -> np.ndarray:
    """Walk from the reference configuration to the first sample in small steps.

    ``solve(robot, position, rotation, q, data)`` reaches one target (default: the generic solver).
    """
    solve = solve or solve_configuration
    q = robot.reference_q.copy()
    pin.framesForwardKinematics(robot.model, data, q)
    frame = data.oMf[robot.end_effector_frame_id]
    start_p, start_r = frame.translation.copy(), frame.rotation.copy()
    target_r = task.rotation[0] if task.is_pose else None
    turn = pin.log3(start_r.T @ target_r) if task.is_pose else np.zeros(3)
    steps = max(1, int(np.ceil(max(np.linalg.norm(task.position_m[0] - start_p), np.linalg.norm(turn) * 0.1)
                               / CONTINUATION_STEP_M)))
    for s in np.linspace(0.0, 1.0, steps + 1)[1:]:
        rotation = start_r @ pin.exp3(s * turn) if task.is_pose else None
        q = solve(robot, start_p + s * (task.position_m[0] - start_p), rotation, q, data)
    return q


def _task_step(task: TaskTrajectory, k: int) -> np.ndarray:
    """Task displacement from sample k-1 to k: position, then rotation (world frame) for a pose."""
    move = task.position_m[k] - task.position_m[k - 1]
    if not task.is_pose:
        return move
    return np.concatenate([move, pin.log3(task.rotation[k] @ task.rotation[k - 1].T)])


def _null_space_basis(robot: Robot, jacobian: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
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
    q = None
    for k in range(n):
        try:
            rotation = task.rotation[k] if task.is_pose else None
            if q is None:
                q = _first_configuration(robot, data, task)
            elif reachable[k - 1]:  # first-order prediction from the previous sample
                q = pin.integrate(model, q, basis @ np.linalg.lstsq(task_map, _task_step(task, k))[0])
            q = solve_configuration(robot, task.position_m[k], rotation, q, data)
            jacobian = closure_jacobian(robot, data, q)
            task_jacobian = _task_jacobian(robot, data, dim)
            basis, pinv, passive = _null_space_basis(robot, jacobian)
            task_map = task_jacobian @ basis
            v = basis @ _solve_task_map(task_map, twist[k], k)
            pin.forwardKinematics(model, data, q, v, np.zeros(model.nv))
            a0 = np.zeros(model.nv)
            a0[passive] = -pinv @ _closure_drift(robot, data)
            task_drift = pin.getFrameClassicalAcceleration(model, data, robot.end_effector_frame_id, LWA).vector
            rhodd = _solve_task_map(task_map, acceleration[k] - task_drift[:dim] - task_jacobian @ a0, k)
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
        error = _task_error(robot, data, position_m, rotation)
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
    for k in range(n):
        rotation = task.rotation[k] if task.is_pose else None
        try:
            if q is None:
                q = _first_configuration(robot, data, task, _solve_serial)
            elif reachable[k - 1]:  # first-order prediction from the previous sample
                q = pin.integrate(model, q, inverse @ _task_step(task, k))
            q = _solve_serial(robot, task.position_m[k], rotation, q, data)
            jacobian = pin.computeFrameJacobian(model, data, q, frame, LWA)[:dim]
            inverse = np.linalg.pinv(jacobian) if dim != nv else np.linalg.inv(jacobian)
            if not _condition_1(jacobian[None], inverse[None])[0] < SINGULAR_CONDITION:
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


def _closed_form(robot: Robot, task: TaskTrajectory) -> tuple[JointTrajectory, np.ndarray, str]:
    """Batched plug-in path: Taylor arithmetic gives rates, accelerations and ∂q/∂p at once."""
    model, n = robot.model, len(task)
    # Row 0 carries the trajectory's derivatives; rows 1-3 the unit directions e_x, e_y, e_z.
    coordinates = tuple(
        Taylor2(np.tile(task.position_m[:, c], (4, 1)),
                np.vstack([task.velocity_m_s[:, c], np.outer(np.eye(3)[c], np.ones(n))]),
                np.vstack([task.acceleration_m_s2[:, c], np.zeros((3, n))]))
        for c in range(3))
    with np.errstate(invalid="ignore", divide="ignore"):
        joints = robot.closed_form(coordinates)
    q, v, a = np.zeros((n, model.nq)), np.zeros((n, model.nv)), np.zeros((n, model.nv))
    jacobian = np.zeros((n, model.nv, 3))
    for name, value in joints.items():
        j = model.joints[model.getJointId(name)]
        q[:, j.idx_q], v[:, j.idx_v], a[:, j.idx_v] = value.v[0], value.d1[0], value.d2[0]
        jacobian[:, j.idx_v, :] = value.d1[1:].T
    bad = ~(np.isfinite(q).all(axis=1) & np.isfinite(v).all(axis=1) & np.isfinite(a).all(axis=1)
            & np.isfinite(jacobian).all(axis=(1, 2)))
    actuated = np.where(bad[:, None, None], np.eye(3), jacobian[:, robot.actuated_v_indices, :])  # ∂rho/∂p
    with np.errstate(invalid="ignore", divide="ignore"):
        task_map = np.linalg.inv(actuated)  # ∂p/∂rho
    bad |= ~(_condition_1(actuated, task_map) < SINGULAR_CONDITION)
    if bad.any():  # finite placeholders: the reference configuration at rest
        q[bad], v[bad], a[bad], jacobian[bad] = robot.reference_q, 0.0, 0.0, 0.0
        actuated[bad], task_map[bad] = np.eye(3), np.eye(3)
    reason = "outside the reach of the closed-form kinematics or singular"
    return JointTrajectory(q, v, a, jacobian @ task_map, task_map), ~bad, reason


def _condition_1(matrices: np.ndarray, inverses: np.ndarray) -> np.ndarray:
    """1-norm condition numbers of a stack of matrices given their inverses (inf if singular)."""
    norm = np.abs(matrices).sum(axis=1).max(axis=1)
    inverse_norm = np.abs(inverses).sum(axis=1).max(axis=1)
    return np.where(np.isfinite(inverse_norm), norm * inverse_norm, np.inf)


def joint_trajectory(robot: Robot, task: TaskTrajectory, method: str = "auto") -> JointTrajectory:
    """Motion of every joint along a task-space trajectory.

    Args:
        robot: The robot.
        task: End-effector trajectory in the base frame (a pose for a pose task).
        method: "closed_form" (the robot's plug-in), "numeric" (generic solver), or "auto"
            (the plug-in when the robot has one).

    Returns:
        Joint positions, velocities, accelerations, null-space basis and task map per sample.

    Raises:
        UnreachableError: Some samples have no configuration or are singular (all are listed).
        PlacementError: The task does not match the robot, or no plug-in exists.
    """
    joints, reachable, reason = _solve(robot, task, method)
    if not reachable.all():
        indices = np.flatnonzero(~reachable).tolist()
        where = f" (first at {np.round(task.position_m[indices[0]], 6).tolist()} m)" if "target" not in reason else ""
        raise UnreachableError(indices, len(indices), reason + where)
    return joints


def try_joint_trajectory(robot: Robot, task: TaskTrajectory, method: str = "auto") -> tuple[JointTrajectory, np.ndarray]:
    """Like :func:`joint_trajectory`, but marks unreachable samples instead of raising.

    Returns:
        The joint motion (unreachable samples hold the reference configuration at rest, so every
        value is finite) and the (N,) boolean mask of reachable samples.
    """
    joints, reachable, _ = _solve(robot, task, method)
    return joints, reachable


def _solve(robot: Robot, task: TaskTrajectory, method: str) -> tuple[JointTrajectory, np.ndarray, str]:
    if task.is_pose != (robot.task == "pose"):
        raise PlacementError(f"robot '{robot.name}' has a {robot.task} task; the trajectory gives "
                             f"{'a pose' if task.is_pose else 'positions only'}")
    if method == "auto":
        method = "closed_form" if robot.closed_form is not None else "numeric"
    if method == "numeric":
        serial = not robot.closures and len(robot.actuators) == robot.model.nv
        return _serial(robot, task) if serial else _numeric(robot, task)
    if method != "closed_form" or robot.closed_form is None:
        raise PlacementError(f"kinematics method '{method}' is not available for robot '{robot.name}'")
    return _closed_form(robot, task)

"""The ``closed_form`` kinematics solver: a robot's own closed-form plug-in, batched over samples.

The plug-in (``kinematics_plugin`` in the sidecar) gives every joint as a function of the platform
position, written with second-order Taylor arithmetic (:mod:`placement.kinematics.taylor`), so that one numpy
pass yields positions, exact rates and accelerations, and ``∂q/∂p`` for all samples at once; a plug-in that
also has a compiled solver (:mod:`placement.robot.plugins`) gives the same faster. A compiled kernel here makes
every joint's motion from them: the actuators' task map by the adjugate, the singular samples, the null-space basis.
"""

from __future__ import annotations

import functools
from typing import ClassVar

import numpy as np
from numba import njit

from placement.exceptions import PluginError
from placement.kinematics.base import SINGULAR_CONDITION, SOLVERS, KinematicsSolver
from placement.kinematics.taylor import Taylor2
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot
from placement.robot.plugins import CompiledClosedForm, make_compiled_closed_form


def _by_taylor_arithmetic(robot: Robot, position_m: np.ndarray, velocity_m_s: np.ndarray,
                          acceleration_m_s2: np.ndarray) -> tuple[tuple[str, ...], np.ndarray, np.ndarray, np.ndarray,
                                                                  np.ndarray]:
    """The plug-in's joints along (N, 3) platform positions, velocities and accelerations, by its Taylor arithmetic,
    as a compiled plug-in gives them (:mod:`placement.robot.plugins`): their names (J,), values, rates and
    accelerations (N, J), gradients by the platform position (N, J, 3)."""
    n = len(position_m)
    # Row 0 carries the trajectory's derivatives; rows 1-3 the unit directions e_x, e_y, e_z (coordinate c's axis),
    # first derivatives only. The value is the same in every row: one row, broadcast.
    rates, accelerations = np.zeros((3, 4, n)), np.ascontiguousarray(acceleration_m_s2.T)[:, None]
    rates[:, 0] = velocity_m_s.T
    rates[:, 1:][np.eye(3, dtype=bool)] = 1.0
    values = np.ascontiguousarray(position_m.T)
    coordinates = tuple(Taylor2(values[c][None], rates[c], accelerations[c]) for c in range(3))
    solve = robot.closed_form
    assert solve is not None  # ClosedFormSolver.unsuitable
    with np.errstate(invalid="ignore", divide="ignore"):
        joints = solve(coordinates)
    value, rate, acceleration = np.empty((n, len(joints))), np.empty((n, len(joints))), np.empty((n, len(joints)))
    gradient = np.empty((n, len(joints), 3))
    for j, joint in enumerate(joints.values()):
        value[:, j], rate[:, j], acceleration[:, j], gradient[:, j] = joint.v[0], joint.d1[0], joint.d2[0], joint.d1[1:].T
    return tuple(joints), value, rate, acceleration, gradient


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
        self._compiled = make_compiled_closed_form(robot.plugin, model, robot.sidecar_path)
        self._joints: CompiledClosedForm = self._compiled or functools.partial(_by_taylor_arithmetic, robot)

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        return _closed_form(self.robot, task, self._joints, self._columns)


def _closed_form(robot: Robot, task: TaskTrajectory, joints: CompiledClosedForm,
                 columns: dict[str, tuple[int, int]]) -> tuple[JointTrajectory, np.ndarray, str]:
    """Every joint's motion along ``task`` from the plug-in's ``joints`` (its compiled solver or its Taylor
    arithmetic, :func:`_by_taylor_arithmetic`), and which samples are regular (``columns``: each joint's q and v
    index, by name)."""
    names, value, rate, acceleration, gradient = joints(task.position_m, task.velocity_m_s, task.acceleration_m_s2)
    unknown = sorted(set(names) - set(columns))
    if unknown:
        raise PluginError(f"robot '{robot.name}': the kinematics plug-in returns joints the model does not have: "
                          f"{unknown}")
    index = np.array([columns[name] for name in names], dtype=np.int64).reshape(-1, 2)
    q, v, a, basis, task_map, regular = _joint_motion(
        value, rate, acceleration, gradient, index[:, 0], index[:, 1], robot.actuated_v_indices.astype(np.int64),
        robot.reference_q.astype(float), robot.model.nq, robot.model.nv, SINGULAR_CONDITION)
    return JointTrajectory(q, v, a, basis, task_map), regular, "outside the reach of the closed-form kinematics or singular"


def touch_joint_motion_kernel() -> None:
    """Compile the kernel that makes every joint's motion from a plug-in's joints (about 5 s of CPU on a machine's
    first run), or load it from numba's disk cache, by running it on one sample of one joint: its numba types do not
    depend on the robot."""
    one, index = np.zeros((1, 1)), np.zeros(1, dtype=np.int64)
    _joint_motion(one, one, one, np.zeros((1, 1, 3)), index, index, np.zeros(3, dtype=np.int64), np.zeros(1), 1, 1,
                  SINGULAR_CONDITION)


@njit(cache=True, error_model="numpy")
def _joint_motion(value, rate, second, gradient, q_index, v_index, actuated, reference_q, nq, nv, singular):
    """Every joint's motion from the plug-in's joints (value, rate, acceleration (N, J), gradient (N, J, 3)): q, v, a
    (N, nq or nv), basis G = ∂q/∂rho (N, nv, 3), task map ∂p/∂rho (N, 3, 3) by the adjugate, and whether each sample
    is regular (finite, with a 1-norm condition number of ∂rho/∂p below ``singular``); an irregular one holds
    finite placeholders: the reference configuration at rest."""
    n = len(value)
    q, v, a = np.empty((n, nq)), np.empty((n, nv)), np.empty((n, nv))
    basis, task_map, regular = np.empty((n, nv, 3)), np.empty((n, 3, 3)), np.empty(n, dtype=np.bool_)
    jacobian, matrix, inverse = np.zeros((nv, 3)), np.zeros((3, 3)), np.zeros((3, 3))  # ∂q/∂p, ∂rho/∂p, ∂p/∂rho
    q_free, v_free = np.ones(nq, dtype=np.bool_), np.ones(nv, dtype=np.bool_)
    q_free[q_index], v_free[v_index] = False, False
    q_zero, v_zero = np.flatnonzero(q_free), np.flatnonzero(v_free)  # the joints the plug-in leaves out: at 0
    for k in range(n):
        for left_out in q_zero:
            q[k, left_out] = 0.0
        for left_out in v_zero:
            v[k, left_out], a[k, left_out] = 0.0, 0.0
        for j in range(len(q_index)):
            q[k, q_index[j]], v[k, v_index[j]], a[k, v_index[j]] = value[k, j], rate[k, j], second[k, j]
            for c in range(3):
                jacobian[v_index[j], c] = gradient[k, j, c]
        for i in range(3):
            for c in range(3):
                matrix[i, c] = jacobian[actuated[i], c]
        _invert(matrix, inverse)
        regular[k] = _finite(q[k]) and _finite(v[k]) and _finite(a[k]) and _finite(jacobian) \
            and _condition_1(matrix, inverse) < singular
        if not regular[k]:  # finite placeholders: the reference configuration at rest
            q[k], v[k], a[k], jacobian[:], inverse[:] = reference_q, 0.0, 0.0, 0.0, 0.0
            for c in range(3):
                inverse[c, c] = 1.0
        task_map[k] = inverse
        for i in range(nv):
            for c in range(3):
                basis[k, i, c] = jacobian[i, 0] * inverse[0, c] + jacobian[i, 1] * inverse[1, c] \
                    + jacobian[i, 2] * inverse[2, c]
    return q, v, a, basis, task_map, regular


@njit(error_model="numpy")
def _finite(values):
    """Whether every value of the array is finite."""
    finite = True
    for value in values.flat:  # no early exit: a loop the compiler turns into vector instructions
        finite &= np.isfinite(value)
    return finite


@njit(error_model="numpy")
def _invert(m, inverse):
    """The inverse of the 3 × 3 matrix ``m`` by its adjugate, into ``inverse`` (inf or nan where it is singular)."""
    a, b, c, d, e, f, g, h, i = m[0, 0], m[0, 1], m[0, 2], m[1, 0], m[1, 1], m[1, 2], m[2, 0], m[2, 1], m[2, 2]
    inverse[0, 0], inverse[0, 1], inverse[0, 2] = e * i - f * h, c * h - b * i, b * f - c * e
    inverse[1, 0], inverse[1, 1], inverse[1, 2] = f * g - d * i, a * i - c * g, c * d - a * f
    inverse[2, 0], inverse[2, 1], inverse[2, 2] = d * h - e * g, b * g - a * h, a * e - b * d
    determinant = a * inverse[0, 0] + b * inverse[1, 0] + c * inverse[2, 0]
    for row in range(3):
        for column in range(3):
            inverse[row, column] = inverse[row, column] / determinant


@njit(error_model="numpy")
def _condition_1(matrix, inverse):
    """:func:`placement.kinematics.base.condition_1` of one matrix (inf where the inverse is not finite)."""
    if not _finite(inverse):
        return np.inf
    norm = inverse_norm = 0.0
    for c in range(3):
        norm = max(norm, np.abs(matrix[0, c]) + np.abs(matrix[1, c]) + np.abs(matrix[2, c]))
        inverse_norm = max(inverse_norm, np.abs(inverse[0, c]) + np.abs(inverse[1, c]) + np.abs(inverse[2, c]))
    return norm * inverse_norm


SOLVERS.add("closed_form", ClosedFormSolver)

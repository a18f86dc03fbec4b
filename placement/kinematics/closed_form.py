"""The ``closed_form`` kinematics solver: a robot's own closed-form plug-in, batched over samples.

The plug-in (``kinematics_plugin`` in the sidecar) gives every joint as a function of the platform
position, written with second-order Taylor arithmetic (:mod:`placement.kinematics.taylor`), so that one numpy
pass yields positions, exact rates and accelerations, and ``∂q/∂p`` for all samples at once. A plug-in that
also has a compiled solver (:mod:`placement.robot.plugins`) runs that instead, and a compiled kernel here makes its
joints' motion from it (the same operations in the same order as the numpy path: the same numbers).
"""

from __future__ import annotations

from typing import ClassVar

import numpy as np
from numba import njit

from placement.exceptions import PlacementError
from placement.kinematics.base import SINGULAR_CONDITION, SOLVERS, KinematicsSolver, condition_1
from placement.kinematics.taylor import Taylor2
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot
from placement.robot.plugins import CompiledClosedForm, make_compiled_closed_form


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
        self._compiled = make_compiled_closed_form(robot.plugin, model, robot.sidecar_path)

    def solve(self, task: TaskTrajectory, placements: int = 1) -> tuple[JointTrajectory, np.ndarray, str]:
        if self._compiled is None:
            return _closed_form(self.robot, task, self._columns)
        return _compiled_closed_form(self.robot, task, self._compiled, self._columns)


def _compiled_closed_form(robot: Robot, task: TaskTrajectory, solve: CompiledClosedForm,
                          columns: dict[str, tuple[int, int]]) -> tuple[JointTrajectory, np.ndarray, str]:
    """:func:`_closed_form` by the plug-in's compiled solver and :func:`_joint_motion` (the same numbers)."""
    names, value, rate, acceleration, gradient = solve(task.position_m, task.velocity_m_s, task.acceleration_m_s2)
    unknown = sorted(set(names) - set(columns))
    if unknown:
        raise PlacementError(f"robot '{robot.name}': the compiled kinematics plug-in returns joints the model does not "
                             f"have: {unknown}")
    index = np.array([columns[name] for name in names], dtype=np.int64).reshape(-1, 2)
    q, v, a, basis, task_map, regular = _joint_motion(
        value, rate, acceleration, gradient, index[:, 0], index[:, 1], robot.actuated_v_indices.astype(np.int64),
        robot.reference_q.astype(float), robot.model.nq, robot.model.nv, SINGULAR_CONDITION)
    return JointTrajectory(q, v, a, basis, task_map), regular, "outside the reach of the closed-form kinematics or singular"


def touch_joint_motion_kernel() -> None:
    """Compile the kernel that makes every joint's motion from a compiled plug-in (about 5 s of CPU on a machine's
    first run), or load it from numba's disk cache, by running it on one sample of one joint: its numba types do not
    depend on the robot."""
    one, index = np.zeros((1, 1)), np.zeros(1, dtype=np.int64)
    _joint_motion(one, one, one, np.zeros((1, 1, 3)), index, index, np.zeros(3, dtype=np.int64), np.zeros(1), 1, 1,
                  SINGULAR_CONDITION)


@njit(cache=True, error_model="numpy")
def _joint_motion(value, rate, second, gradient, q_index, v_index, actuated, reference_q, nq, nv, singular):
    """Every joint's motion from the plug-in's joints (value, rate, acceleration (N, J), gradient (N, J, 3)) as
    :func:`_closed_form` makes it: q, v, a (N, nq or nv), basis (N, nv, 3), task map (N, 3, 3), regular (N,)."""
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
    finite = True
    for value in values.flat:  # no early exit: a loop the compiler turns into vector instructions
        finite &= np.isfinite(value)
    return finite


@njit(error_model="numpy")
def _invert(m, inverse):
    """:func:`_inverses` of one matrix, into ``inverse``."""
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

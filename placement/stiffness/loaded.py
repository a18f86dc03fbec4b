"""The loaded (complementary) correction: the tool's tangent compliance under a finite load.

The linear compliance C = T·K_ρ⁻¹·Tᵀ (:mod:`placement.stiffness.compliance`) holds the task map T fixed. Under a
finite load w the springs balance T(ρ)ᵀ·w at the displaced posture, and the posture's change turns the load: the
equilibrium K_ρ·Δρ = T(ρ)ᵀ·w has the tangent (K_ρ − K_C)·dρ = Tᵀ·dw with the complementary stiffness

    K_C = ∂(T(ρ)ᵀ·w)/∂ρ   (w held constant in the base frame),

so the loaded tangent compliance is C_w = T·(K_ρ − K_C)⁻¹·Tᵀ, evaluated at the loaded posture. K_C is the
derivative of the actuator-space load along the closed-loop motion, closures included, and is found by central
differences along the task: ∂(Tᵀ·w)/∂ρ = Σ_j ∂(Tᵀ·w)/∂x_j · T_j (row j of T), the task moved by ±h along each of its
directions (a translation, or a rotation about a base axis for a pose task) and solved by the robot's kinematics
solver. Its size relative to K_ρ is about |w|·(a lever arm)/k. Springs on passive joints are not covered (their
preload adds terms of G's derivative), nor robots with more actuators than task freedoms (their springs also move
the tool's posture along the redundancy, which the task does not describe).

The deflection under a finite load (:func:`loaded_deflection`) is the equilibrium itself: the tool moved to x where
K_ρ·(ρ(x) − ρ₀) = T(x)ᵀ·w, ρ(x) from the robot's kinematics solver, found by Newton steps in the task whose matrix
is the loaded tangent: Δx = −T·(K_ρ − K_C)⁻¹·r, r the equilibrium's residual in actuator space. The first step is
C_w·w; at process loads (K_C about 1e-5 of K_ρ) the second brings the residual to rounding.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.exceptions import SettingsError
from placement.kinematics.base import KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.kinematics.tree import log3
from placement.robot.model import Robot
from placement.stiffness.compliance import JointSprings

STEP = 1e-6  # of the task's central differences: m along a translation, rad about an axis
MAX_STEPS = 4  # Newton steps of the loaded equilibrium: two suffice at process loads, each adds digits quadratically
CONVERGED = 1e-9  # the last step's largest move relative to the largest deflection, at which the equilibrium is found
SOLVER_FLOOR = 1e-10  # m or rad: a move below it is the kinematics solvers' own residual (1e-11 to 1e-12), not a step


def complementary_stiffness(solver: KinematicsSolver, task: TaskTrajectory, joints: JointTrajectory,
                            load: np.ndarray) -> np.ndarray:
    """(M, m, m) K_C = ∂(Tᵀ·w)/∂ρ at M samples (module docstring).

    Args:
        solver: The robot's kinematics solver.
        task: The task at the samples (the loaded posture).
        joints: Its joint motion (the task map T of each sample).
        load: (M, d) the load on the end effector, base frame (N, then N·m for a pose task).

    Raises:
        SettingsError: A moved task leaves the robot's reach.
    """
    _square(solver.robot)
    dimension = load.shape[1]
    moved = [_moved(task, axis, sign * STEP) for axis in range(dimension) for sign in (1.0, -1.0)]
    maps, reachable, reason = solver.solve(_stacked(moved), len(moved))
    if not reachable.all():
        raise SettingsError(f"the loaded correction moves the task {STEP:g} m or rad off a sample out of reach: {reason}")
    samples = len(task)
    loads = np.einsum("nta,nt->na", maps.task_map, np.tile(load, (len(moved), 1))).reshape(dimension, 2, samples, -1)
    rates = (loads[:, 0] - loads[:, 1]) / (2 * STEP)  # (d, M, m): ∂(Tᵀ·w)/∂x_j
    return np.einsum("jma,mjb->mab", rates, joints.task_map)


def loaded_compliance(springs: JointSprings, joints: JointTrajectory, stiffness_c: np.ndarray) -> np.ndarray:
    """(M, d, d) C_w = T·(K_ρ − K_C)⁻¹·Tᵀ, the tangent compliance under the load that ``stiffness_c`` (M, m, m, from
    :func:`complementary_stiffness`) was computed for."""
    _actuators_only(springs)
    tangent = np.eye(len(springs.actuator_stiffness)) * springs.actuator_stiffness - stiffness_c
    return np.matmul(joints.task_map, np.linalg.solve(tangent, np.swapaxes(joints.task_map, 1, 2)))


def loaded_deflection(springs: JointSprings, solver: KinematicsSolver, task: TaskTrajectory, joints: JointTrajectory,
                      load: np.ndarray) -> np.ndarray:
    """(M, d) the tool's displacement at the nonlinear equilibrium of the springs under the finite loads (module
    docstring): translation (m), then the rotation vector log(R·R₀ᵀ) (rad, base frame) for a pose task.

    Args:
        springs: The robot's springs (actuated joints only).
        solver: The robot's kinematics solver.
        task: The task at the samples, unloaded (its rates are ignored).
        joints: Its joint motion.
        load: (M, d) the load on the end effector, base frame (N, then N·m for a pose task).

    Raises:
        SettingsError: Passive springs or a redundant robot (not covered), a moved task out of reach, or no
            equilibrium within MAX_STEPS (a load near the robot's buckling).
    """
    _actuators_only(springs)
    actuated = solver.robot.actuated_q_indices
    tangent = np.eye(len(springs.actuator_stiffness)) * springs.actuator_stiffness - \
        complementary_stiffness(solver, task, joints, load)
    start, current, moved = joints.q[:, actuated], joints, _still(task)
    for _ in range(MAX_STEPS):
        residual = springs.actuator_stiffness * (current.q[:, actuated] - start) - \
            np.einsum("nta,nt->na", current.task_map, load)  # K_ρ·Δρ − Tᵀ·w (N or N·m)
        move = -np.einsum("nta,na->nt", current.task_map, np.linalg.solve(tangent, residual[..., None])[..., 0])
        moved = _displaced(moved, move)
        displacement = _displacement(task, moved)
        if np.abs(move).max() <= CONVERGED * np.abs(displacement).max() + SOLVER_FLOOR:
            return displacement
        current, reachable, reason = solver.solve(moved)
        if not reachable.all():
            raise SettingsError(f"the loaded equilibrium moves the tool out of reach: {reason}")
    raise SettingsError(f"the loaded equilibrium was not found in {MAX_STEPS} Newton steps (the last moved the tool "
                        f"{np.abs(move).max():.3g} against a deflection of {np.abs(displacement).max():.3g}): a load "
                        "this large is near the robot's buckling, beyond a static stiffness model")


def _actuators_only(springs: JointSprings) -> None:
    """The loaded correction covers springs on actuated joints alone."""
    if len(springs.passive_stiffness) or springs.links is not None:
        raise SettingsError("the loaded correction covers springs on actuated joints only (joint_springs or "
                            "link_springs are declared)")


def _square(robot: Robot) -> None:
    """The loaded correction needs as many actuators as task freedoms (module docstring)."""
    if len(robot.actuators) != robot.task_dimension:
        raise SettingsError(f"the loaded correction needs as many actuators as task freedoms: robot '{robot.name}' "
                            f"has {len(robot.actuators)} for {robot.task_dimension} (its springs move it along its "
                            "redundancy too)")


def _still(task: TaskTrajectory) -> TaskTrajectory:
    """The task's poses at rest."""
    still = np.zeros_like(task.position_m)
    pose = task.rotation is not None
    return TaskTrajectory(task.position_m.copy(), still, still, task.rotation, still if pose else None,
                          still if pose else None)


def _displaced(task: TaskTrajectory, move: np.ndarray) -> TaskTrajectory:
    """The task at rest moved by ``move`` (M, d): a translation, then a rotation vector (base frame)."""
    still = np.zeros_like(task.position_m)
    if task.rotation is None:
        return TaskTrajectory(task.position_m + move, still, still)
    return TaskTrajectory(task.position_m + move[:, :3], still, still, _exp3(move[:, 3:]) @ task.rotation, still, still)


def _displacement(task: TaskTrajectory, moved: TaskTrajectory) -> np.ndarray:
    """(M, d) from ``task`` to ``moved``: translation, then log(R·R₀ᵀ) for a pose task."""
    translation = moved.position_m - task.position_m
    if task.rotation is None or moved.rotation is None:
        return translation
    return np.hstack([translation, log3(moved.rotation @ np.swapaxes(task.rotation, 1, 2))])


def _exp3(vector: np.ndarray) -> np.ndarray:
    """(M, 3, 3) the rotations of (M, 3) rotation vectors (rad), by Rodrigues' formula."""
    angle = np.linalg.norm(vector, axis=1)[:, None, None]
    skew = np.zeros((len(vector), 3, 3))
    skew[:, [2, 0, 1], [1, 2, 0]] = vector
    skew = skew - np.swapaxes(skew, 1, 2)
    small = angle < 1e-8
    sine = np.where(small, 1.0 - angle**2 / 6, np.sin(angle) / np.where(small, 1.0, angle))
    versine = np.where(small, 0.5 - angle**2 / 24, (1 - np.cos(angle)) / np.where(small, 1.0, angle) ** 2)
    return np.eye(3) + sine * skew + versine * (skew @ skew)


def _moved(task: TaskTrajectory, axis: int, step: float) -> TaskTrajectory:
    """The task at rest, moved by ``step`` along its direction ``axis``: x, y, z, then rotations about them."""
    still = np.zeros_like(task.position_m)
    if axis < 3:
        position = task.position_m.copy()
        position[:, axis] += step
        return TaskTrajectory(position, still, still, task.rotation, None if task.rotation is None else still,
                              None if task.rotation is None else still)
    assert task.rotation is not None  # a pose task's load has six components
    turn = pin.exp3(np.eye(3)[axis - 3] * step)
    return TaskTrajectory(task.position_m, still, still, turn @ task.rotation, still, still)


def _stacked(tasks: list[TaskTrajectory]) -> TaskTrajectory:
    """Several tasks of equal length at rest, one after the other (the solver's placements)."""
    position = np.concatenate([t.position_m for t in tasks])
    still = np.zeros_like(position)
    if tasks[0].rotation is None:
        return TaskTrajectory(position, still, still)
    rotation = np.concatenate([t.rotation for t in tasks if t.rotation is not None])
    return TaskTrajectory(position, still, still, rotation, still, still)

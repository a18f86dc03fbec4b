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
preload adds terms of G's derivative).
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin

from placement.exceptions import SettingsError
from placement.kinematics.base import KinematicsSolver
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.stiffness.compliance import JointSprings

STEP = 1e-6  # of the task's central differences: m along a translation, rad about an axis


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
    if len(springs.passive_stiffness):
        raise SettingsError("the loaded correction covers springs on actuated joints only (joint_springs are declared)")
    tangent = np.eye(len(springs.actuator_stiffness)) * springs.actuator_stiffness - stiffness_c
    return np.matmul(joints.task_map, np.linalg.solve(tangent, np.swapaxes(joints.task_map, 1, 2)))


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

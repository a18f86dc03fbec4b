"""Exact inverse dynamics of closed-loop and serial robots, batched over samples.

The recursive Newton–Euler algorithm (RNEA) gives the joint torques ``tau`` of the spanning tree moving with the
closed-loop motion (q, v, a): compiled passes over blocks of samples for a large tree of revolute and prismatic
joints (:mod:`placement.dynamics.tree_rnea`, equal to Pinocchio's to rounding), Pinocchio's ``rneaInParallel``
for another tree (:class:`TreeDynamics` says which). Projecting them on the closure null space removes the
unknown constraint forces (``Gᵀ·Jᵀ·lambda = 0``), so the actuator efforts are

    F = Gᵀ·tau - (J_task·G)ᵀ·w_ext,

with ``w_ext`` the load the environment applies on the end effector (a force at the frame
origin, world-aligned; for a pose task followed by the moment). Gravity comes from the model, and
the drives' rotor and screw inertia are in ``model.armature``, so ``F`` is the effort the
transmission must deliver at each actuated joint (N for a slider, N·m for a revolute joint).
"""

from __future__ import annotations

import os
from dataclasses import dataclass

import numpy as np
import pinocchio as pin

from placement.dynamics.tree_rnea import joint_torques, path_torques, tree_inertias
from placement.exceptions import SettingsError
from placement.kinematics import joint_trajectory
from placement.kinematics.trajectories import JointTrajectory, TaskTrajectory
from placement.robot.model import Robot

SAMPLES_PER_THREAD = 1000  # threads pay off on large batches only
COMPILED_FROM_JOINTS = 12  # joints of the smallest tree whose efforts take the compiled pass (TreeDynamics)
_openmp_started = False  # whether this process has run RNEA on several OpenMP threads (see openmp_started)


@dataclass(frozen=True)
class ActuatorTrajectory:
    """Actuator motion and effort, one row per sample and one column per actuator.

    Attributes:
        position: (N, n_act) joint positions (m or rad).
        velocity: (N, n_act) joint velocities (m/s or rad/s).
        acceleration: (N, n_act) joint accelerations (m/s² or rad/s²).
        effort: (N, n_act) forces (N) or torques (N·m) at the actuated joints.
        joints: Motion of every joint of the spanning tree.
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    effort: np.ndarray
    joints: JointTrajectory


def rnea_batch(model: pin.Model, q: np.ndarray, v: np.ndarray, a: np.ndarray, threads: int | None = None) -> np.ndarray:
    """Tree inverse dynamics for many samples in one call (rows are samples), (N, nv).

    Args:
        threads: Most threads of Pinocchio's parallel RNEA (default: every core; fewer on small batches).
    """
    global _openmp_started
    threads = thread_count(threads, len(q))
    _openmp_started = _openmp_started or threads > 1
    pool = pin.ModelPool(model, threads)
    tau = pin.rneaInParallel(threads, pool, np.asfortranarray(q.T), np.asfortranarray(v.T), np.asfortranarray(a.T))
    return np.reshape(tau, (model.nv, len(q))).T


def thread_count(threads: int | None, samples: int) -> int:
    """The threads to run a batch of ``samples`` samples on: at most ``threads`` (default: every core), fewer on a
    small batch."""
    return max(1, min(threads or os.cpu_count() or 1, samples // SAMPLES_PER_THREAD))


class TreeDynamics:
    """The joint torques of a spanning tree at many samples, by the compiled passes of
    :mod:`placement.dynamics.tree_rnea` where every joint is revolute or prismatic, else by Pinocchio's RNEA.

    The efforts of a timed motion (:meth:`efforts`) take the compiled pass on a tree of COMPILED_FROM_JOINTS joints
    or more (a closed-loop robot's legs); on a smaller one (a serial arm), Pinocchio's RNEA costs about a
    microsecond a sample beside several of kinematics, and spares a machine's first run the pass's compile (about 4 s
    of CPU). The path dynamics of the optimal timing law (:meth:`path_efforts`) take it on every such tree.

    Attributes:
        compiled_efforts: Whether :meth:`efforts` takes the compiled pass.

    Args:
        model: The tree (read once, here: build another after changing it).
    """

    def __init__(self, model: pin.Model) -> None:
        self.model, self.tree = model, tree_inertias(model)
        self.compiled_efforts = self.tree is not None and model.nv >= COMPILED_FROM_JOINTS

    def efforts(self, q: np.ndarray, v: np.ndarray, a: np.ndarray, basis: np.ndarray,
                threads: int | None = None) -> np.ndarray:
        """(N, m) Gᵀ·rnea(q, v, a) at N samples (rows), gravity and armature included, G = ``basis`` (N, nv, m).

        Args:
            threads: Most threads (default: every core; fewer on small batches).
        """
        if self.tree is None or not self.compiled_efforts:
            return np.matmul(rnea_batch(self.model, q, v, a, threads)[:, None, :], basis)[:, 0]
        return joint_torques(self.tree, q, v, a, basis, thread_count(threads, len(q)))

    def path_efforts(self, q: np.ndarray, rate: np.ndarray, curvature: np.ndarray, basis: np.ndarray,
                     threads: int | None = None) -> np.ndarray:
        """(N, 3, m) Gᵀ times the torques C = rnea(q, 0, 0), A = rnea(q, 0, q') − C and B = rnea(q, q', q'') − C at N
        samples: in one pass (:func:`placement.dynamics.tree_rnea.path_torques`), or from three of Pinocchio's."""
        if self.tree is not None:
            return path_torques(self.tree, q, rate, curvature, basis, thread_count(threads, len(q)))
        rest = np.zeros_like(rate)
        static = rnea_batch(self.model, q, rest, rest, threads)
        torques = np.stack([static, rnea_batch(self.model, q, rest, rate, threads) - static,
                            rnea_batch(self.model, q, rate, curvature, threads) - static], axis=1)
        return np.matmul(torques, basis)


def openmp_started() -> bool:
    """Whether this process has run Pinocchio's RNEA on several OpenMP threads: a process forked from it then
    hangs in its own first parallel RNEA (GNU OpenMP's thread pool does not survive a fork)."""
    return _openmp_started


def actuator_efforts(robot: Robot, joints: JointTrajectory, external_load: np.ndarray | None = None,
                     threads: int | None = None, dynamics: TreeDynamics | None = None) -> np.ndarray:
    """Actuator efforts (N, n_act) for a known closed-loop joint motion.

    Args:
        robot: The robot.
        joints: Motion of every joint (from :func:`placement.kinematics.joint_trajectory`).
        external_load: (N, task_dim) load on the end effector from the environment, in the base
            frame at the end-effector origin: force (N), then moment (N·m) for a pose task.
        threads: Most threads of the batched RNEA (default: every core).
        dynamics: The robot's tree dynamics, where the caller keeps them (default: built from ``robot.model``).

    Returns:
        Forces (N) or torques (N·m) at the actuated joints.
    """
    effort = (dynamics or TreeDynamics(robot.model)).efforts(joints.q, joints.v, joints.a, joints.basis, threads)
    if external_load is not None:
        effort -= load_efforts(joints, external_load)
    return effort


def load_efforts(joints: JointTrajectory, external_load: np.ndarray) -> np.ndarray:
    """(N, n_act) the actuator efforts that balance the load (N, task_dim) on the end effector: (J_task·G)ᵀ·w_ext
    (see :func:`actuator_efforts`)."""
    load = np.asarray(external_load, dtype=float)
    if load.shape != (len(joints.q), joints.task_map.shape[1]):
        raise SettingsError(f"external load must have shape {(len(joints.q), joints.task_map.shape[1])}, "
                            f"got {load.shape}")
    return np.einsum("nta,nt->na", joints.task_map, load)


def inverse_dynamics(robot: Robot, task: TaskTrajectory, external_load: np.ndarray | None = None,
                     method: str = "auto") -> ActuatorTrajectory:
    """Actuator motion and efforts along an end-effector trajectory.

    Args:
        robot: The robot.
        task: End-effector trajectory in the base frame.
        external_load: See :func:`actuator_efforts`.
        method: Kinematics solver, see :func:`placement.kinematics.joint_trajectory`.

    Returns:
        Actuator positions, velocities, accelerations and efforts, and every joint's motion.

    Raises:
        UnreachableError: Some samples are out of reach or singular.
    """
    joints = joint_trajectory(robot, task, method)
    act = robot.actuated_v_indices
    return ActuatorTrajectory(position=joints.q[:, robot.actuated_q_indices], velocity=joints.v[:, act],
                              acceleration=joints.a[:, act],
                              effort=actuator_efforts(robot, joints, external_load), joints=joints)

"""Motion in task space (the end effector) and in joint space (every joint of the tree).

Conventions (base frame, SI): a task trajectory gives the end-effector frame origin's position,
velocity and classical acceleration, and for a pose task also its rotation, angular velocity and
angular acceleration, all in the base frame. Joint motion covers every joint of the spanning
tree, actuated and passive, with the null-space basis ``G`` (``v = G·rhodot``) and the task map
``J_task·G`` (task velocity = ``J_task·G·rhodot``) that dynamics needs.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np


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
        joint_position: (N, R) the redundant joints' values the task prescribes (m or rad; a robot with
            redundant joints, see ``Robot.redundant_joints``), or None: they stay at the reference configuration.
        joint_velocity, joint_acceleration: (N, R) their rates.
    """

    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    rotation: np.ndarray | None = None
    angular_velocity_rad_s: np.ndarray | None = None
    angular_acceleration_rad_s2: np.ndarray | None = None
    joint_position: np.ndarray | None = None
    joint_velocity: np.ndarray | None = None
    joint_acceleration: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.position_m)

    @property
    def is_pose(self) -> bool:
        """Whether orientation is prescribed too."""
        return self.rotation is not None

    def twist(self) -> np.ndarray:
        """(N, 3 or 6) task velocity: linear, then angular for a pose task."""
        if self.angular_velocity_rad_s is None:
            return self.velocity_m_s
        return np.hstack([self.velocity_m_s, self.angular_velocity_rad_s])

    def acceleration(self) -> np.ndarray:
        """(N, 3 or 6) task acceleration: classical linear, then angular for a pose task."""
        if self.angular_acceleration_rad_s2 is None:
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

    def __len__(self) -> int:
        return len(self.q)

    @staticmethod
    def concatenate(parts: list[JointTrajectory]) -> JointTrajectory:
        """The samples of several joint trajectories, one after the other."""
        return JointTrajectory(*(np.concatenate([getattr(p, f.name) for p in parts]) for f in fields(JointTrajectory)))


def task_rows(task: TaskTrajectory, start: int, stop: int) -> TaskTrajectory:
    """Samples ``start:stop`` of a task trajectory."""
    def rows(value: np.ndarray | None) -> np.ndarray | None:
        return None if value is None else value[start:stop]

    return TaskTrajectory(task.position_m[start:stop], task.velocity_m_s[start:stop], task.acceleration_m_s2[start:stop],
                          rows(task.rotation), rows(task.angular_velocity_rad_s), rows(task.angular_acceleration_rad_s2),
                          rows(task.joint_position), rows(task.joint_velocity), rows(task.joint_acceleration))

"""Placement of the path frame F_p in the robot's base frame F_b, and the space searched.

A placement is x = [x, y, z, phi, theta, psi] (m, rad): the origin of F_p in F_b and the
orientation R = Rz(phi)·Ry(theta)·Rx(psi), the paper's matrix bTp. Any subset of the six may be
free (searched within bounds) while the others stay fixed.

A planar mechanism declares its plane in the sidecar (``placement.plane``: a normal and a point).
The placement is then read in the plane's own frame F_pl (:func:`plane_frame`): its origin is the
plane's point, its z axis the normal, its x axis the base x axis projected on the plane (the base
y axis if the normal is within 8° of x) and its y axis completes a right-handed frame. So x and y
are the path origin's coordinates in the plane, phi turns the path about the normal, and z, theta
and psi stay 0, keeping the path in the plane: bTp = bT_pl·(the placement's transform).
"""

from __future__ import annotations

import dataclasses
import warnings

import numpy as np
import pinocchio as pin

from placement.exceptions import PlacementWarning, SettingsError
from placement.kinematics.trajectories import TaskTrajectory
from placement.kinematics.tree import frame_kinematics
from placement.path.samples import PathSamples
from placement.placing.profiles import joint_profiles, knots_of, spin_of
from placement.robot.model import Robot
from placement.robot.sidecar import Plane

VARIABLES = ("x", "y", "z", "phi", "theta", "psi")
ANGLES = ("phi", "theta", "psi")
NORMAL_ALONG_X = np.cos(np.radians(8.0))  # |n·X_b| above this: the plane's x axis is taken from Y_b


def rotation_zyx(phi: np.ndarray, theta: np.ndarray, psi: np.ndarray) -> np.ndarray:
    """Rz(phi)·Ry(theta)·Rx(psi) for arrays of angles (rad), shape (..., 3, 3)."""
    cf, sf, ct, st, cp, sp = np.cos(phi), np.sin(phi), np.cos(theta), np.sin(theta), np.cos(psi), np.sin(psi)
    return np.stack([
        np.stack([cf * ct, cf * st * sp - sf * cp, cf * st * cp + sf * sp], axis=-1),
        np.stack([sf * ct, sf * st * sp + cf * cp, sf * st * cp - cf * sp], axis=-1),
        np.stack([-st, ct * sp, ct * cp], axis=-1),
    ], axis=-2)


def plane_frame(plane: Plane) -> tuple[np.ndarray, np.ndarray]:
    """The plane's own frame F_pl in the base frame (module docstring).

    Args:
        plane: The sidecar's ``placement.plane``.

    Returns:
        The rotation [u, v, n] (columns: the plane's x and y axes, its unit normal) and the origin (m).
    """
    normal = np.asarray(plane.normal, dtype=float) / np.linalg.norm(plane.normal)
    axis = np.eye(3)[1 if abs(normal[0]) > NORMAL_ALONG_X else 0]
    u = axis - (axis @ normal) * normal
    u /= np.linalg.norm(u)
    return np.column_stack([u, np.cross(normal, u), normal]), np.asarray(plane.point_m, dtype=float)


def describe_plane(plane: Plane) -> dict[str, list[float]]:
    """The plane and the axes its placement coordinates x, y run along (base frame, JSON-ready)."""
    rotation, origin = plane_frame(plane)
    return {"normal": rotation[:, 2].tolist(), "point_m": origin.tolist(), "x_axis": rotation[:, 0].tolist(),
            "y_axis": rotation[:, 1].tolist()}


def placement_pose(placements: np.ndarray, plane: Plane | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The path frame's rotation (K, 3, 3) and origin (K, 3) (m) in the base frame, for (K, 6) placements.

    Args:
        placements: Placement vectors (m, rad), in the plane's frame when ``plane`` is given.
        plane: The robot's plane (module docstring), or None: placements are in the base frame.
    """
    x = np.atleast_2d(placements)
    rotation = rotation_zyx(x[:, 3], x[:, 4], x[:, 5])
    if plane is None:
        return rotation, x[:, :3]
    turn, origin = plane_frame(plane)
    return turn @ rotation, origin + x[:, :3] @ turn.T


def placed_task(robot: Robot, samples: PathSamples, placements: np.ndarray) -> tuple[TaskTrajectory, np.ndarray]:
    """The end-effector task and its external load for placed paths, as the robot's task needs.

    A position task follows the tool point (a pose list's orientations are ignored, with a warning
    once). A pose task also holds the end-effector frame at R_place·R_tool·R_ee, where R_place is
    the placement's rotation, R_tool the tool frame in the path frame (a pose list's orientation;
    the identity otherwise) and R_ee the robot's ``tool_rpy_in_path_rad``, which maps the tool
    frame to the end-effector frame. The angular velocity and acceleration in the base frame are
    R_place times the path frame's. The load is the process force on the tool from the workpiece,
    with a zero moment for a pose task. A robot's redundant joints follow the profiles whose knots end the
    placement vectors (:mod:`placement.placing.profiles`). On a robot whose workpiece rides on a chain (a
    positioner's table, ``Robot.workpiece_frame``), the placement is in the workpiece's frame, which the profiled
    joints move: the task is the tool's motion relative to it, seen in the base frame (:func:`on_workpiece`).

    Args:
        robot: The robot.
        samples: The path sampled in its own frame (N samples).
        placements: (K, 6) placement vectors, or (K, 6 + R·knots) with the redundant joints' knots.

    Returns:
        The task (K·N samples, placement-major) and the load, (K·N, 3 or 6).

    Raises:
        SettingsError: A path with process forces on a robot whose workpiece rides on a chain.
    """
    task, force = _placed_tool(robot, samples, placements)
    knots = knots_of(robot, np.atleast_2d(placements))
    if knots is not None:
        position, velocity, acceleration = joint_profiles(knots, samples)
        task = dataclasses.replace(task, joint_position=position, joint_velocity=velocity,
                                   joint_acceleration=acceleration)
    if robot.workpiece_frame is None:
        return task, force
    if np.any(samples.force_on_tool_N):
        raise SettingsError(f"robot '{robot.name}' carries the workpiece on a positioner ({robot.workpiece_frame}): a "
                            "path with process forces is not covered (their reaction on the positioner is not modelled)")
    return on_workpiece(robot, task), force


def workpiece_motion(robot: Robot, task: TaskTrajectory) -> tuple[np.ndarray, ...]:
    """The workpiece frame's motion in the base frame at each sample, as the profiled joints that carry it move.

    The compiled tree kinematics runs on the chain that carries the frame alone (the model with every other joint
    held at the reference configuration: they do not move it), batched over the samples.

    Returns:
        Its rotation (B, 3, 3), origin (B, 3) (m), twist (B, 6) (m/s, rad/s: its origin's velocity, then its angular
        velocity) and classical acceleration (B, 6) (m/s², rad/s²), world-aligned axes.
    """
    rows, name = len(task.position_m), robot.workpiece_frame
    model = robot.model
    support = list(model.supports[model.frames[model.getFrameId(name)].parentJoint])[1:]
    if not support or task.joint_position is None:  # the frame stands still where the reference configuration holds it
        data = model.createData()
        pin.framesForwardKinematics(model, data, robot.reference_q)
        placement = data.oMf[model.getFrameId(name)]
        still = np.zeros((rows, 6))
        return (np.repeat(placement.rotation[None], rows, axis=0), np.repeat(placement.translation[None], rows, axis=0),
                still, still.copy())
    chain = pin.buildReducedModel(model, [j for j in range(1, model.njoints) if j not in support], robot.reference_q)
    columns = [robot.redundant_joints.index(model.names[j]) for j in support]  # every one profiled (checked at load)
    q, v = task.joint_position[:, columns], np.zeros((rows, len(columns)))
    a = np.zeros_like(v)
    if task.joint_velocity is not None and task.joint_acceleration is not None:
        v, a = task.joint_velocity[:, columns], task.joint_acceleration[:, columns]
    rotation, origin, jacobian, drift = (each[:, 0] for each in frame_kinematics(chain, [chain.getFrameId(name)], q, v))
    return rotation, origin, (jacobian @ v[:, :, None])[:, :, 0], (jacobian @ a[:, :, None])[:, :, 0] + drift


def on_workpiece(robot: Robot, task: TaskTrajectory) -> TaskTrajectory:
    """The tool's task in the base frame, from its task relative to the workpiece frame (``task``: positions,
    velocities, accelerations and rotations in that frame's axes), as the workpiece frame moves with the profiled
    joints (:func:`workpiece_motion`).

    With the table's rotation R_w, origin o_w, velocity v_w, angular velocity ω_w and classical accelerations a_w,
    α_w, and the tool's relative position p, velocity u and acceleration b: r = R_w·p, position o_w + r, velocity
    v_w + ω_w × r + R_w·u, acceleration a_w + α_w × r + ω_w × (ω_w × r) + 2 ω_w × R_w·u + R_w·b; rotation
    R_w·R, angular velocity ω_w + R_w·ω, angular acceleration α_w + ω_w × R_w·ω + R_w·α̇. The profiled joints stay
    rows of the task: the tool's rows do not depend on them, so the inverse kinematics solves the tool relative to
    the workpiece exactly.
    """
    rotation, origin, twist, acceleration = workpiece_motion(robot, task)
    omega, alpha = twist[:, 3:], acceleration[:, 3:]

    def turn(vectors: np.ndarray) -> np.ndarray:
        return (rotation @ vectors[:, :, None])[:, :, 0]

    arm, relative = turn(task.position_m), turn(task.velocity_m_s)
    velocity = twist[:, :3] + np.cross(omega, arm) + relative
    accel = (acceleration[:, :3] + np.cross(alpha, arm) + np.cross(omega, np.cross(omega, arm))
             + 2.0 * np.cross(omega, relative) + turn(task.acceleration_m_s2))
    placed = dataclasses.replace(task, position_m=origin + arm, velocity_m_s=velocity, acceleration_m_s2=accel)
    if task.rotation is None:
        return placed
    assert task.angular_velocity_rad_s is not None and task.angular_acceleration_rad_s2 is not None
    spin = turn(task.angular_velocity_rad_s)
    return dataclasses.replace(placed, rotation=rotation @ task.rotation, angular_velocity_rad_s=omega + spin,
                               angular_acceleration_rad_s2=alpha + np.cross(omega, spin)
                               + turn(task.angular_acceleration_rad_s2))


def _placed_tool(robot: Robot, samples: PathSamples, placements: np.ndarray) -> tuple[TaskTrajectory, np.ndarray]:
    """:func:`placed_task` without the redundant joints."""
    plane = robot.plane
    task, force = transform_path_to_base(samples, placements, plane)
    if robot.task == "position":
        if samples.rotation is not None:
            warnings.warn_explicit(f"robot '{robot.name}' has a position task: the pose list's orientations are "
                                   "ignored", OrientationIgnoredWarning, "placement.placing", 0, registry=_WARNED)
        return task, force
    rpy = robot.tool_rpy_in_path_rad
    end_effector = rotation_zyx(np.array(rpy[2]), np.array(rpy[1]), np.array(rpy[0]))
    spin = spin_of(robot, np.atleast_2d(placements))
    if spin is not None:  # the tool turned about its own axis (z of the tool frame), then the end effector in it
        still = np.zeros_like(spin)
        end_effector = rotation_zyx(spin, still, still) @ end_effector  # (K, 3, 3)
    path_rotation = placement_pose(placements, plane)[0]  # (K, 3, 3)
    if samples.rotation is None:
        rotation = np.repeat(path_rotation @ end_effector, len(samples), axis=0)
        still = np.zeros_like(task.position_m)
        angular_velocity, angular_acceleration = still, still
    else:
        assert samples.angular_velocity_rad_s is not None and samples.angular_acceleration_rad_s2 is not None
        turn = end_effector[:, None] if end_effector.ndim == 3 else end_effector
        rotation = (path_rotation[:, None] @ samples.rotation[None] @ turn).reshape(-1, 3, 3)
        angular_velocity = _turned(path_rotation, samples.angular_velocity_rad_s)
        angular_acceleration = _turned(path_rotation, samples.angular_acceleration_rad_s2)
    pose = TaskTrajectory(task.position_m, task.velocity_m_s, task.acceleration_m_s2, rotation, angular_velocity,
                          angular_acceleration)
    return pose, np.hstack([force, np.zeros_like(force)])


class OrientationIgnoredWarning(PlacementWarning):
    """A path's tool orientations meet a robot whose task is a position."""


_WARNED: dict = {}  # the warnings shown: once per message and process


def _turned(rotation: np.ndarray, vectors: np.ndarray) -> np.ndarray:
    """(K·N, 3) path-frame vectors (N, 3) turned by each placement's rotation (K, 3, 3), placement-major."""
    return np.matmul(vectors, rotation.transpose(0, 2, 1)).reshape(-1, 3)


def transform_path_to_base(samples: PathSamples, placements: np.ndarray,
                           plane: Plane | None = None) -> tuple[TaskTrajectory, np.ndarray]:
    """The sampled path seen in the base frame for each placement, stacked placement by placement.

    Args:
        samples: The path sampled in its own frame (N samples).
        placements: (K, 6) or (6,) placement vectors [x, y, z, phi, theta, psi] (m, rad).
        plane: A planar robot's plane, in whose frame the placements are read (module docstring).

    Returns:
        The task trajectory of the tool point (K·N samples, placement-major) and the process
        force on the tool in the base frame, (K·N, 3) N.
    """
    rotation, origin = placement_pose(placements, plane)  # (K, 3, 3), (K, 3)
    position = _turned(rotation, samples.position_m) + np.repeat(origin, len(samples), axis=0)
    task = TaskTrajectory(position, _turned(rotation, samples.velocity_m_s), _turned(rotation, samples.acceleration_m_s2))
    return task, _turned(rotation, samples.force_on_tool_N)













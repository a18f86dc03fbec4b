"""A serial arm through the same closed-loop machinery: must equal Pinocchio's RNEA."""

import numpy as np
import pinocchio as pin

from placement import load_robot
from placement.dynamics.inverse import inverse_dynamics
from placement.kinematics import joint_trajectory
from placement.kinematics.trajectories import TaskTrajectory
from placement.robot.closures import LWA


def joint_motion(robot, t):
    """Smooth joint trajectory around the reference posture, with exact derivatives."""
    amplitude = np.array([0.3, 0.2, 0.25, 0.4, 0.3, 0.5])
    w = 2 * np.pi * np.array([0.5, 0.7, 0.6, 0.9, 1.1, 0.8])
    angle = w * t[:, None]
    return (robot.reference_q + amplitude * np.sin(angle), amplitude * w * np.cos(angle),
            -amplitude * w**2 * np.sin(angle))


def task_of(robot, q, v, a):
    model, data, frame = robot.model, robot.model.createData(), robot.end_effector_frame_id
    rows = []
    for qk, vk, ak in zip(q, v, a):
        pin.forwardKinematics(model, data, qk, vk, ak)
        pin.updateFramePlacements(model, data)
        placement = data.oMf[frame]
        twist = pin.getFrameVelocity(model, data, frame, LWA)
        acceleration = pin.getFrameClassicalAcceleration(model, data, frame, LWA)
        rows.append((placement.translation.copy(), placement.rotation.copy(), twist.linear.copy(),
                     twist.angular.copy(), acceleration.linear.copy(), acceleration.angular.copy()))
    p, rotation, velocity, omega, acc, alpha = (np.array(column) for column in zip(*rows))
    return TaskTrajectory(p, velocity, acc, rotation, omega, alpha)


def test_ur5_inverse_kinematics_and_dynamics_equal_rnea():
    robot = load_robot("ur5")
    q, v, a = joint_motion(robot, np.linspace(0.0, 2.0, 80))
    task = task_of(robot, q, v, a)
    joints = joint_trajectory(robot, task)
    np.testing.assert_allclose(joints.q, q, atol=1e-10)
    np.testing.assert_allclose(joints.v, v, atol=1e-9)
    np.testing.assert_allclose(joints.a, a, atol=1e-8)
    wrench = np.tile([5.0, -12.0, 30.0, 0.5, -1.0, 0.2], (len(q), 1))
    result = inverse_dynamics(robot, task, wrench)
    model, data = robot.model, robot.model.createData()
    for k in range(len(q)):
        fext = pin.StdVec_Force()
        for _ in range(model.njoints):
            fext.append(pin.Force.Zero())
        pin.framesForwardKinematics(model, data, q[k])
        frame = model.frames[robot.end_effector_frame_id]
        # The wrench acts at the tool origin, world-aligned; express it in the parent joint frame.
        at_tool = pin.Force(wrench[k, :3], wrench[k, 3:])
        tool_origin = data.oMf[robot.end_effector_frame_id].translation
        world_aligned_to_joint = data.oMi[frame.parentJoint].inverse() * pin.SE3(np.eye(3), tool_origin)
        fext[frame.parentJoint] = world_aligned_to_joint.act(at_tool)
        expected = pin.rnea(model, data, q[k], v[k], a[k], fext)
        np.testing.assert_allclose(result.effort[k], expected, atol=1e-8)

"""A closed-loop machine with a single leg is a serial chain: its constrained compliance (passive joints free,
closure enforced) equals the serial formula J·K⁻¹·Jᵀ of the leg alone.

The machine: the two-link planar arm (tests/support/robot_copies.py) as its one leg, and a platform on two passive
slides (x, then z) that a point closure ties to the arm's tip; the platform follows the path. Its tree has four
joints and a closure, so its compliance comes through the closure null-space basis; the arm's is the serial formula.
"""

import copy

import numpy as np
import pinocchio as pin
import yaml

from placement import TaskTrajectory, load_robot
from placement.kinematics import joint_trajectory
from placement.stiffness import joint_springs, tool_compliance
from tests.support.robot_copies import ARM_ELBOW, ARM_LINKS, ARM_SIDECAR, planar_arm

PLATFORM = """\
  <link name="carriage"><inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/>
    </inertial></link>
  <link name="platform"><inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0" iyz="0"/>
    </inertial></link>
  <joint name="slide_x" type="prismatic"><parent link="base"/><child link="carriage"/><axis xyz="1 0 0"/>
    <limit lower="-1" upper="1" effort="100" velocity="10"/></joint>
  <joint name="slide_z" type="prismatic"><parent link="carriage"/><child link="platform"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="100" velocity="10"/></joint>
"""
STIFFNESS = {"shoulder": 3.0e4, "elbow": 1.2e4}  # N·m/rad


def _stiff(document: dict) -> None:
    for actuator in document["actuators"]:
        actuator["stiffness"] = STIFFNESS[actuator["joint"]]
    document["sources"]["actuators.stiffness"] = "EST: test springs"


def closed_arm(folder, tip_m):
    """The arm as the single leg of a platform on two slides, closed at the reference posture (tip at ``tip_m``)."""
    (folder / "closed.urdf").write_text('<?xml version="1.0"?>\n<robot name="closed_arm">\n  <link name="base"/>\n'
                                        + ARM_LINKS + PLATFORM + """\
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 -1 0"/>
    <limit lower="-3.1416" upper="3.1416" effort="20" velocity="10"/></joint>
""" + ARM_ELBOW)
    document = copy.deepcopy(ARM_SIDECAR)
    document.update(name="closed_arm", urdf="closed.urdf", end_effector={"frame": "platform", "task": "position"},
                    closures=[{"name": "leg", "type": "point", "frames": ["tip", "platform"]}])
    document["reference_configuration"].update(slide_x=float(tip_m[0]), slide_z=float(tip_m[2]))
    _stiff(document)
    sidecar = folder / "closed.yaml"
    sidecar.write_text(yaml.safe_dump(document))
    return load_robot(sidecar)


def test_a_closed_loop_machine_with_one_leg_has_the_serial_compliance(tmp_path):
    arm = load_robot(planar_arm(tmp_path, _stiff))
    data = arm.model.createData()
    pin.framesForwardKinematics(arm.model, data, arm.reference_q)
    tip = data.oMf[arm.end_effector_frame_id].translation.copy()
    machine = closed_arm(tmp_path, tip)
    points = tip + np.array([[0.0, 0.0, 0.0], [0.04, 0.0, -0.03], [-0.05, 0.0, 0.02]])
    still = np.zeros_like(points)
    serial, closed = (tool_compliance(joint_springs(robot), joint_trajectory(robot, TaskTrajectory(points, still, still)))
                      for robot in (arm, machine))
    np.testing.assert_allclose(closed, serial, rtol=1e-9, atol=1e-12 * np.abs(serial).max())
    arm_joints = joint_trajectory(arm, TaskTrajectory(points, still, still))
    for q, compliance in zip(arm_joints.q, serial):  # the serial formula itself, from Pinocchio's Jacobian
        jacobian = pin.computeFrameJacobian(arm.model, data, q, arm.end_effector_frame_id, pin.LOCAL_WORLD_ALIGNED)[:3]
        np.testing.assert_allclose(compliance, jacobian @ np.diag(1 / np.array([3.0e4, 1.2e4])) @ jacobian.T,
                                   rtol=1e-9, atol=1e-12 * np.abs(compliance).max())

"""A robot's kinematics, checked as it loads: the solver its sidecar names, and its closed-form plug-in.

Both checks name the sidecar's field at fault (:class:`placement.robot.exceptions.RobotFileError`).
:func:`placement.workshop.load.robot_from_sidecar` runs them after :func:`placement.robot.build.build_robot`.
"""

from __future__ import annotations

import pinocchio as pin

from placement.kinematics.base import SOLVERS
from placement.kinematics.taylor import Taylor2
from placement.robot.exceptions import KinematicsPluginError, RobotFileError
from placement.robot.model import Robot


def check_kinematics(robot: Robot, *, plugin: bool = True) -> None:
    """Check the solver the sidecar names and, with ``plugin``, the closed-form plug-in (loops closed).

    Raises:
        RobotFileError: The solver is unknown or cannot serve the robot, or the plug-in disagrees with the URDF.
    """
    if plugin:
        _check_plugin(robot)
    _check_solver(robot)


def _check_solver(robot: Robot) -> None:
    """A solver named in the sidecar must exist and serve this robot."""
    name = robot.kinematics_name
    if name is None:
        return
    if name not in SOLVERS:
        raise RobotFileError(robot.sidecar_path, "kinematics", f"unknown kinematics solver '{name[:40]}', expected one "
                             f"of {', '.join(SOLVERS.names())}")
    reason = SOLVERS.get(name).unsuitable(robot)
    if reason:
        raise RobotFileError(robot.sidecar_path, "kinematics", f"the {name} solver cannot serve this robot: {reason}")


def _check_plugin(robot: Robot) -> None:
    """A closed-form plug-in must cover every joint and agree with the reference configuration."""
    if robot.closed_form is None:
        return
    field = "kinematics_plugin"
    if robot.task != "position" or len(robot.actuators) != 3:
        raise RobotFileError(robot.sidecar_path, field, "closed-form plug-ins serve position tasks of "
                             "three-actuator robots; remove the plug-in to use the generic solver")
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    position = data.oMf[robot.end_effector_frame_id].translation
    joints = robot.closed_form(tuple(Taylor2.constant([c]) for c in position))
    movable = set(robot.model.names[1:])
    if set(joints) != movable:
        raise KinematicsPluginError(robot.sidecar_path, field, f"the plug-in must return exactly the joints "
                                    f"{sorted(movable)}, got {sorted(joints)}")
    for name, value in joints.items():
        joint = robot.model.joints[robot.model.getJointId(name)]
        if joint.nq != 1 or abs(float(value.v[0]) - robot.reference_q[joint.idx_q]) > 1e-9:
            raise RobotFileError(robot.sidecar_path, field, f"the plug-in disagrees with reference_configuration "
                                 f"at joint '{name}'")

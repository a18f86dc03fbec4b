"""Mobility: the degrees-of-freedom error names the joints left free and proposes the locked_joints that fix
it; a planar serial arm that declares its plane follows position paths in it with 2 joints."""

import re

import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.kinematics import joint_trajectory
from placement.kinematics.trajectories import TaskTrajectory
from placement.robot.exceptions import RobotFileError
from tests.support.paths import CIRCLE
from tests.support.robot_copies import planar_arm, spinning_rods_fivebar


def test_the_error_names_the_spinning_joints_and_the_proposal_makes_it_load(tmp_path):
    sidecar = spinning_rods_fivebar(tmp_path)
    with pytest.raises(RobotFileError) as caught:
        load_robot(sidecar)
    error = caught.value
    assert error.field == "actuators" and "\n" not in str(error)
    assert "the closures leave 4 degree(s) of freedom at reference_configuration for the 2 actuated joint(s)" in str(error)
    assert "joint(s) spin1, spin2 still move" in str(error)
    proposal = re.search(r"locked_joints: (\{[^}]*\})", str(error)).group(1)
    assert yaml.safe_load(proposal) == {"spin1": 0.0, "spin2": 0.0}

    document = yaml.safe_load(sidecar.read_text())
    document["locked_joints"] = yaml.safe_load(proposal)
    sidecar.write_text(yaml.safe_dump(document))
    robot = load_robot(sidecar)
    np.testing.assert_allclose(robot.reference_q, load_robot("fivebar").reference_q, atol=1e-12)


def test_a_two_link_arm_with_a_plane_loads_checks_and_is_placed(tmp_path, capsys):
    sidecar = planar_arm(tmp_path)
    robot = load_robot(sidecar)
    t = np.linspace(0.0, 1.0, 40)[:, None]
    turn = np.hstack([np.cos(2 * np.pi * t), 0 * t, np.sin(2 * np.pi * t)])
    dturn = 2 * np.pi * np.hstack([-turn[:, 2:], 0 * t, turn[:, :1]])
    position = np.array([0.36, 0.0, 0.11]) + 0.03 * turn  # a circle in the plane: 3 task rows, 2 actuators
    joints = joint_trajectory(robot, TaskTrajectory(position, 0.03 * dturn, -0.03 * (2 * np.pi) ** 2 * turn))
    data = robot.model.createData()
    for q, v, target, velocity in zip(joints.q, joints.v, position, 0.03 * dturn):
        jacobian = pin.computeFrameJacobian(robot.model, data, q, robot.end_effector_frame_id, pin.LOCAL_WORLD_ALIGNED)
        np.testing.assert_allclose(data.oMf[robot.end_effector_frame_id].translation, target, atol=1e-9)
        np.testing.assert_allclose(jacobian[:3] @ v, velocity, atol=1e-9)

    assert main(["check", str(sidecar)]) == 0
    assert "result: exact to round-off" in capsys.readouterr().out
    assert main(["--robot", str(sidecar), "--path", str(CIRCLE), "--generations", "2", "--population", "6"]) == 0
    out = capsys.readouterr().out
    assert "plane (sidecar placement.plane): normal [0, -1, 0]" in out and "best placement (least energy)" in out


@pytest.mark.parametrize(("edit", "field", "problem"), [
    (lambda d: d.pop("placement"), "end_effector.task", "a serial robot with 2 actuated joints cannot follow a position "
     "task of 3: unlock joints, or declare the plane of a planar arm (placement.plane)"),
    (lambda d: d.update(task_pose(d)), "end_effector.task", "cannot follow a pose task of 6: use a position task or "
     "unlock joints"),
    (lambda d: d.update(locked_joints={"elbow": -1.6}, actuators=d["actuators"][:1],
                        reference_configuration={"shoulder": 1.0}),
     "end_effector.task", "a serial robot with 1 actuated joints cannot follow a planar position task of 2: unlock joints"),
    (lambda d: d["placement"]["plane"].update(normal=[0, 0, 1]), "placement.plane",
     "the end effector of this planar arm must move in the plane of normal [0, 0, 1]"),
])
def test_a_planar_arm_short_of_joints_or_off_its_plane_is_refused(tmp_path, edit, field, problem):
    with pytest.raises(RobotFileError) as caught:
        load_robot(planar_arm(tmp_path, edit))
    assert caught.value.field == field and problem in caught.value.problem


def task_pose(document: dict) -> dict:
    """The sidecar's fields for a pose task (no plane: a plane takes a position task)."""
    document.pop("placement")
    return {"end_effector": {"frame": "tip", "task": "pose", "tool_rpy_in_path_rad": [0.0, 0.0, 0.0]}}

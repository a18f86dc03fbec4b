"""Every registered robot: loads, is exact, and runs the command line end to end."""

import json
import shutil

import numpy as np
import pytest
import yaml

from placement import Evaluator, EvaluatorSettings, load_path, load_robot, robot_names
from placement.__main__ import main
from placement.robot.exceptions import RobotFileError
from placement.search import optimize
from placement.workshop.catalog import builtin_robots_dir
from tests.support.paths import EXAMPLE

CIRCLE = EXAMPLE.with_name("circle.yaml")


def test_the_registry_lists_serial_and_parallel_robots(capsys):
    assert {"orthoglide", "fivebar", "ur5", "panda"} <= set(robot_names())
    assert main(["robots"]) == 0
    listing = capsys.readouterr().out
    assert all(name in listing for name in robot_names())


@pytest.mark.parametrize("name", ["orthoglide", "fivebar", "ur5", "panda"])
def test_every_robot_places_a_path_end_to_end(name, tmp_path, capsys, monkeypatch):
    # A plumbing test: a small search budget (two generations of six, a coarse sampling, one local
    # polish instead of three) runs every stage of the search and the report for each robot.
    monkeypatch.setattr(optimize, "POLISH_STARTS", 1)
    out = tmp_path / "result.json"
    code = main(["--robot", name, "--path", str(CIRCLE), "--time-step", "0.05", "--generations", "2",
                 "--population", "6", "--quiet", "--json", str(out)])
    assert code == 0, capsys.readouterr().err
    document = json.loads(out.read_text())
    assert document["best"]["feasible"] and document["worst"]["feasible"]
    # The JSON's placements, evaluated again through the Python API, give the JSON's energies.
    placements = [list(document[key]["placement"].values()) for key in ("best", "worst")]  # the knots too
    again = Evaluator(load_robot(name), load_path(CIRCLE), EvaluatorSettings(time_step_s=0.05, workers=1)).evaluate(placements)
    assert again.feasible.all()
    np.testing.assert_allclose(again.value, [document["best"]["energy_J"], document["worst"]["energy_J"]], rtol=1e-9)


def test_serial_arm_tool_axis_points_into_the_workpiece():
    import pinocchio as pin

    from placement.evaluation.evaluator import Evaluator
    from placement.kinematics import joint_trajectory
    from placement.path import load_path
    from placement.placing.transform import placed_task

    robot = load_robot("ur5")
    samples = load_path(CIRCLE).sample(0.01)
    placement = np.array([0.4, 0.1, 0.2, 0.3, 0.1, -0.1])
    task, _ = placed_task(robot, samples, placement[None])
    joints = joint_trajectory(robot, task)
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, joints.q[5])
    tool_z = data.oMf[robot.end_effector_frame_id].rotation[:, 2]
    from placement.placing.transform import rotation_zyx

    path_z = rotation_zyx(*placement[3:])[:, 2]
    assert tool_z @ path_z == pytest.approx(-1.0)
    evaluator = Evaluator(robot, load_path(CIRCLE), EvaluatorSettings(time_step_s=0.01, workers=1))
    assert evaluator.evaluate(placement[None]).reachable[0]


@pytest.fixture
def ur5_copy(tmp_path):
    folder = tmp_path / "ur5"
    shutil.copytree(builtin_robots_dir() / "ur5", folder)
    sidecar = folder / "ur5.yaml"
    return sidecar, yaml.safe_load(sidecar.read_text())


def test_a_sidecar_with_a_unit_in_the_wrong_name_is_answered_with_the_expected_field(ur5_copy):
    sidecar, data = ur5_copy
    del data["drives"]["size3"]["transmission"]["ratio"]
    data["drives"]["size3"]["transmission"]["ratio_percent"] = 101
    sidecar.write_text(yaml.safe_dump(data))
    with pytest.raises(RobotFileError) as error:
        load_robot(sidecar)
    assert error.value.field == "drives.size3.transmission.ratio_percent" and "ratio" in str(error.value)


def test_a_missing_drive_is_answered_with_the_file_and_field(ur5_copy, capsys):
    sidecar, data = ur5_copy
    del data["actuators"][4]["drive"]
    sidecar.write_text(yaml.safe_dump(data))
    assert load_robot(sidecar).actuators[4].drive is None  # kinematics and dynamics need no drive
    code = main(["--robot", str(sidecar), "--path", str(CIRCLE), "--at", "x=400,y=100,z=200", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and "ur5.yaml, field 'actuators.4.drive'" in err


def test_a_redundant_arm_must_lock_joints(tmp_path):
    folder = tmp_path / "panda"
    shutil.copytree(builtin_robots_dir() / "panda", folder)
    sidecar = folder / "panda.yaml"
    data = yaml.safe_load(sidecar.read_text())
    del data["redundancy"], data["sources"]["redundancy"]  # seven axes, none profiled
    sidecar.write_text(yaml.safe_dump(data))
    with pytest.raises(RobotFileError) as error:
        load_robot(sidecar)
    assert error.value.field == "locked_joints" and "7 degrees of freedom" in str(error.value)
    assert "redundancy.joints" in str(error.value)


def test_a_locked_joint_cannot_also_be_an_actuator(ur5_copy):
    sidecar, data = ur5_copy
    data["locked_joints"] = {"wrist_3_joint": 0.0}
    sidecar.write_text(yaml.safe_dump(data))
    with pytest.raises(RobotFileError) as error:
        load_robot(sidecar)
    assert "is locked" in str(error.value)
    data["locked_joints"] = {"wrist_3_joint": 10.0}
    del data["actuators"][5]
    del data["reference_configuration"]["wrist_3_joint"]
    sidecar.write_text(yaml.safe_dump(data))
    with pytest.raises(RobotFileError) as error:
        load_robot(sidecar)
    assert error.value.field == "locked_joints.wrist_3_joint" and "outside the joint's limits" in str(error.value)

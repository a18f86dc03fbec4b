"""example-robot-data arms by name (erd:NAME --tool FRAME): estimated drives, same kinematics, clear errors."""

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.__main__ import main
from placement.robot.urdf import erd_urdf_path
from placement.workshop.catalog import builtin_robots_dir
from placement.workshop.estimates import GEAR_RATIO, load_erd_robot
from tests.support.paths import CIRCLE


@pytest.fixture(scope="module")
def erd_ur5():
    return load_erd_robot("ur5", "tool0")


def test_estimated_drives_reach_exactly_the_urdf_limits(erd_ur5):
    model = erd_ur5.model
    assert len(erd_ur5.actuators) == 6 and erd_ur5.task == "pose"
    for actuator in erd_ur5.actuators:
        drive = actuator.drive
        assert drive.transmission.ratio == GEAR_RATIO
        assert drive.motor.max_torque_Nm * GEAR_RATIO == pytest.approx(model.effortLimit[actuator.v_index], rel=1e-15)
        assert drive.motor.max_speed_rad_s / GEAR_RATIO == pytest.approx(model.velocityLimit[actuator.v_index],
                                                                         rel=1e-15)
        assert drive.motor.back_emf_constant_V_s_per_rad == pytest.approx(drive.motor.torque_constant_Nm_per_A / 3)
    sources = erd_ur5.sources
    for a in erd_ur5.actuators:
        assert sources[f"drives.{a.joint}.motor"].startswith("EST")
        assert sources[f"drives.{a.joint}.transmission"].startswith("EST")
    assert sources["workspace"].startswith("EST")


def test_kinematics_equal_the_builtin_ur5_at_the_same_configuration(erd_ur5):
    builtin = load_robot("ur5")
    assert builtin.model.names.tolist() == erd_ur5.model.names.tolist()
    rng = np.random.default_rng(1)
    for q in rng.uniform(-np.pi, np.pi, (5, 6)):
        poses = []
        for robot in (builtin, erd_ur5):
            data = robot.model.createData()
            pin.framesForwardKinematics(robot.model, data, q)
            poses.append(data.oMf[robot.end_effector_frame_id].homogeneous)
        np.testing.assert_allclose(poses[0], poses[1], atol=1e-14)


def test_reference_posture_points_the_tool_down_away_from_singularities(erd_ur5):
    data = erd_ur5.model.createData()
    q = erd_ur5.reference_q
    pin.framesForwardKinematics(erd_ur5.model, data, q)
    np.testing.assert_allclose(data.oMf[erd_ur5.end_effector_frame_id].rotation[:, 2], [0, 0, -1], atol=1e-9)
    jacobian = pin.computeFrameJacobian(erd_ur5.model, data, q, erd_ur5.end_effector_frame_id, pin.LOCAL_WORLD_ALIGNED)
    assert np.linalg.cond(jacobian) < 1e3
    low, high = erd_ur5.workspace.min_m, erd_ur5.workspace.max_m
    assert np.all(np.array(low) <= data.oMf[erd_ur5.end_effector_frame_id].translation)
    assert np.all(data.oMf[erd_ur5.end_effector_frame_id].translation <= np.array(high))


def test_panda_locks_its_fingers_and_profiles_its_third_joint():
    panda = load_erd_robot("panda", "panda_hand_tcp")
    assert set(panda.locked_joints) == {"panda_finger_joint1", "panda_finger_joint2"}
    assert len(panda.actuators) == 7 and panda.redundant_joints == ("panda_joint3",)


def test_check_passes_on_erd_ur10(capsys):
    assert main(["check", "erd:ur10", "--tool", "tool0", "--samples", "30"]) == 0
    captured = capsys.readouterr()
    assert "exact to round-off" in captured.out
    assert captured.err.count("warning:") == 1 and "estimates" in captured.err


@pytest.mark.parametrize(("argv", "said"), [
    (["check", "erd:ur11", "--tool", "tool0"], ["'ur11'", "ur10"]),
    (["check", "erd:ur10", "--tool", "tool9"], ["'tool9'", "tool0"]),
    (["check", "erd:ur10"], ["--tool", "tool0"]),
    (["check", "ur5", "--tool", "tool0"], ["--tool", "erd:NAME"]),
    (["check", "erd:double_pendulum", "--tool", "link2"], ["2 joint(s)", "locks the joints"]),
])
def test_mistakes_exit_2_naming_what_is_wrong(argv, said, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "Traceback" not in err
    assert all(word in err for word in said)


def test_short_search_on_erd_ur10(capsys):
    argv = ["--robot", "erd:ur10", "--tool", "tool0", "--path", str(CIRCLE), "--minimize", "--free", "x,y,z",
            "--generations", "1", "--population", "2", "--time-step", "0.01", "--quiet"]
    assert main(argv) == 0
    assert "best placement" in capsys.readouterr().out


@pytest.mark.parametrize("argv", [["calibrate", "erd:ur10", "--log", "x.csv", "--fit", "resistance_ohm"],
                                  ["assemble", "erd:ur10", "--write"]])
def test_commands_that_need_a_sidecar_file_say_how_to_write_one(capsys, argv):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {argv[0]} needs a robot folder or sidecar file, not erd:ur10")
    assert str(builtin_robots_dir() / "ur5" / "ur5.yaml") in err and "'urdf: example-robot-data:ur10'" in err
    assert "unknown robot" not in err and err.count("\n") == 1


@pytest.mark.parametrize("name", ["ur5", "panda", "ur10", "z1"])
def test_the_urdf_is_found_where_the_loader_finds_it_without_building_the_robot(name):
    from example_robot_data.robots_loader import ROBOTS

    assert erd_urdf_path(ROBOTS[name]) == Path(ROBOTS[name]().df_path).resolve()

"""`placement check`: the motion amplitude scaled to the robot, and plausibility warnings."""

import re

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.__main__ import main
from placement.robot.exceptions import RobotFileError
from placement.workshop.checks import check_robot, default_amplitude
from tests.support.robot_copies import edited_copy

SAMPLES = 20


def fivebar_with_urdf(tmp_path, edit_urdf, edit_sidecar=lambda document: None):
    """A fivebar copy whose URDF text goes through ``edit_urdf``; returns the sidecar."""
    sidecar = edited_copy("fivebar", tmp_path, edit_sidecar)
    urdf = sidecar.parent / "fivebar.urdf"
    urdf.write_text(edit_urdf(urdf.read_text()))
    return sidecar


def link_mass(link, kg):
    """A URDF edit: link ``link`` weighs ``kg``."""
    return lambda text: re.sub(rf'(<link name="{link}">\s*<inertial>.*?<mass value=")[^"]*', rf"\g<1>{kg}", text,
                               count=1, flags=re.S)


def joint_limits_dropped(joint):
    """A URDF edit: joint ``joint``'s <limit> keeps effort and velocity, loses lower and upper."""
    return lambda text: re.sub(rf'(<joint name="{joint}".*?<limit) lower="[^"]*" upper="[^"]*"', r"\1", text,
                               count=1, flags=re.S)


def drive_torque(max_torque_Nm):
    """A sidecar edit: the fivebar's motors give at most ``max_torque_Nm``."""

    def edit(document):
        document["drives"]["geared_servo"]["motor"]["max_torque_Nm"] = max_torque_Nm

    return edit


@pytest.fixture(scope="module")
def fivebar_report():
    return check_robot(load_robot("fivebar"), SAMPLES)


@pytest.fixture(scope="module")
def peak_motor_Nm(fivebar_report):
    """The largest motor torque of the fivebar's default check motion: gear 20:1, efficiency 1 and no
    friction make it the joint effort / 20 (rotor inertia included)."""
    return float(fivebar_report.peak_effort.max()) / 20


def test_the_built_in_robots_raise_no_warning(fivebar_report):
    assert fivebar_report.warnings == ()
    assert check_robot(load_robot("ur5"), SAMPLES).warnings == ()


def test_a_heavy_link_is_named_with_both_masses(tmp_path):
    report = check_robot(load_robot(fivebar_with_urdf(tmp_path, link_mass("dist2", 100))), SAMPLES)
    heavy = [w for w in report.warnings if w.startswith("link ")]
    assert len(heavy) == 1  # median of 0.5, 0.5, 0.4, 100 and 1 kg: 0.5 kg
    assert "'dist2'" in heavy[0] and "100 kg" in heavy[0] and "0.5 kg" in heavy[0]
    assert report.passed  # a plausibility warning is not a physics failure


def test_a_link_below_100_medians_is_not_warned_about(tmp_path):
    report = check_robot(load_robot(fivebar_with_urdf(tmp_path, link_mass("payload", 45))), SAMPLES)
    assert not [w for w in report.warnings if w.startswith("link ")]  # 45 kg < 100 x 0.5 kg


@pytest.mark.parametrize("fraction", [0.5, 0.98])
def test_a_drive_too_weak_for_the_check_motion_is_named(tmp_path, peak_motor_Nm, fraction):
    report = check_robot(load_robot(edited_copy("fivebar", tmp_path, drive_torque(fraction * peak_motor_Nm))), SAMPLES)
    weak = [w for w in report.warnings if w.startswith("actuator ")]
    worst = int(np.argmax(report.peak_effort))
    joint = ("a1", "a2")[worst]
    line = next(w for w in weak if f"'{joint}'" in w)
    peak, effort, limit = (float(x) for x in re.findall(r"([0-9.]+(?:e[-+]?\d+)?) N m", line))
    assert peak == pytest.approx(peak_motor_Nm, rel=1e-3)
    assert effort == pytest.approx(report.peak_effort[worst], rel=1e-3)
    assert limit == pytest.approx(fraction * peak_motor_Nm, rel=1e-3)


def test_a_drive_just_strong_enough_raises_no_warning(tmp_path, peak_motor_Nm):
    report = check_robot(load_robot(edited_copy("fivebar", tmp_path, drive_torque(1.02 * peak_motor_Nm))), SAMPLES)
    assert not [w for w in report.warnings if w.startswith("actuator ")]


def test_a_peak_torque_raised_without_its_torque_constant_is_named_with_the_current(tmp_path):
    """1000 times the peak torque at the same torque constant takes 1000 times the current: beyond 500 A."""
    motor = load_robot("fivebar").actuators[0].drive.motor
    current_A = 1000 * motor.max_torque_Nm / motor.torque_constant_Nm_per_A
    assert current_A > 500 > current_A / 1000
    report = check_robot(load_robot(edited_copy("fivebar", tmp_path, drive_torque(1000 * motor.max_torque_Nm))),
                         SAMPLES)
    lines = [w for w in report.warnings if w.startswith("motor of actuator ")]
    assert [re.search(r"'(\w+)'", w).group(1) for w in lines] == ["a1", "a2"]
    assert all(f"{current_A:.4g} A" in w for w in lines)


def test_the_effort_warning_is_printed_and_the_check_still_passes(tmp_path, capsys, peak_motor_Nm):
    sidecar = edited_copy("fivebar", tmp_path, drive_torque(0.1 * peak_motor_Nm))
    assert main(["check", str(sidecar), "--samples", str(SAMPLES)]) == 0
    out = capsys.readouterr().out
    assert "plausibility: 2 warning(s)" in out and "warning: actuator 'a1'" in out and "warning: actuator 'a2'" in out


def test_an_actuated_joint_without_urdf_limits_names_the_sidecar_fields(tmp_path):
    with pytest.raises(RobotFileError) as error:
        load_robot(fivebar_with_urdf(tmp_path, joint_limits_dropped("a2")))
    message = str(error.value)
    assert "joint 'a2' has no limits in the URDF" in message
    assert "actuators.1.position_min and actuators.1.position_max" in message and "0.0 >= 0.0" not in message


def test_joints_without_urdf_limits_are_warned_about(tmp_path):
    def limits(document):
        document["actuators"][1].update(position_min=-3.0, position_max=3.0)

    sidecar = fivebar_with_urdf(tmp_path, lambda text: joint_limits_dropped("b2")(joint_limits_dropped("a2")(text)),
                                limits)
    robot = load_robot(sidecar)
    assert (robot.actuators[1].position_min, robot.actuators[1].position_max) == (-3.0, 3.0)
    warnings = [w for w in check_robot(robot, SAMPLES).warnings if "has no limits in the URDF" in w]
    assert len(warnings) == 2
    assert any(w.startswith("joint 'a2'") and "[-3, 3]" in w for w in warnings)
    assert any(w.startswith("joint 'b2'") and "passive" in w for w in warnings)


def without_workspace(document):
    document.pop("workspace")
    document["sources"].pop("workspace", None)


def reference_reach_m(robot):
    data = robot.model.createData()
    pin.framesForwardKinematics(robot.model, data, robot.reference_q)
    return float(np.linalg.norm(data.oMf[robot.end_effector_frame_id].translation))


def test_the_default_amplitude_is_5_percent_of_the_workspace_box():
    # fivebar: the 0.24 x 0.20 m box of its plane (its 2 mm thickness across the plane is not a motion axis);
    # orthoglide: a 0.2 m cube; ur5: 0.35 x 0.60 x 0.40 m
    expected = {"fivebar": 0.05 * 0.20, "orthoglide": 0.05 * 0.20, "ur5": 0.05 * 0.35}
    for name, amplitude in expected.items():
        assert default_amplitude(load_robot(name))[0] == pytest.approx(amplitude, rel=1e-9), name


def test_the_default_amplitude_scales_with_the_workspace_box(tmp_path):
    def doubled(document):
        box = document["workspace"]
        center = (np.array(box["min_m"]) + np.array(box["max_m"])) / 2
        box["min_m"], box["max_m"] = ((center + 2 * (np.array(box[k]) - center)).tolist() for k in ("min_m", "max_m"))

    big = default_amplitude(load_robot(edited_copy("ur5", tmp_path, doubled)))[0]
    assert big == pytest.approx(2 * default_amplitude(load_robot("ur5"))[0], rel=1e-9)


def test_without_a_workspace_the_amplitude_is_5_percent_of_the_reach(tmp_path):
    amplitudes = {}
    for name in ("fivebar", "orthoglide", "ur5"):
        robot = load_robot(edited_copy(name, tmp_path / name, without_workspace))
        amplitudes[name], basis = default_amplitude(robot)
        assert amplitudes[name] == pytest.approx(0.05 * reference_reach_m(robot), rel=1e-9)
        assert "base to end-effector distance" in basis
    assert amplitudes["fivebar"] == pytest.approx(0.05 * 0.30)  # the tip at (0, 0.30, 0) m
    assert len({round(a, 6) for a in amplitudes.values()}) == 3


def test_the_amplitude_option_is_honoured(capsys):
    assert main(["check", "fivebar", "--samples", str(SAMPLES), "--amplitude", "0.03"]) == 0
    out = capsys.readouterr().out
    assert "amplitude 0.03 m: given" in out and "exact to round-off" in out
    robot = load_robot("fivebar")
    small, large = (check_robot(robot, SAMPLES, amplitude) for amplitude in (0.01, 0.03))
    # three times the motion at the same frequencies: about three times the speed, and more power
    assert (small.amplitude_m, large.amplitude_m) == (0.01, 0.03)
    assert large.peak_power_W > 2 * small.peak_power_W


@pytest.mark.parametrize("value", ["-1", "0", "inf", "nan", "one"])
def test_a_bad_amplitude_exits_2_with_one_line(capsys, value):
    with pytest.raises(SystemExit) as exit_:
        main(["check", "fivebar", "--amplitude", value])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    errors = [line for line in err.splitlines() if "error" in line]
    assert len(errors) == 1 and "--amplitude" in errors[0] and f"'{value}'" in errors[0] and "Traceback" not in err


def test_an_unreachable_amplitude_exits_2_with_one_line(capsys):
    assert main(["check", "fivebar", "--samples", str(SAMPLES), "--amplitude", "0.5"]) == 2
    err = capsys.readouterr().err
    assert len(err.splitlines()) == 1 and err.startswith("error: ") and "smaller --amplitude" in err

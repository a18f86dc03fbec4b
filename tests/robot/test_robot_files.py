"""Robot files: built-ins load, generated files are in sync, and mistakes get clear errors."""

import shutil

import numpy as np
import pytest
import yaml

from placement import load_robot, robot_names
from placement.robot.exceptions import RobotFileError, UnknownRobotError
from placement.workshop.catalog import builtin_robots_dir
from tests.support.generators import urdf_generator

ORTHOGLIDE_DIR = builtin_robots_dir() / "orthoglide"


def test_builtin_orthoglide_loads_with_its_drives(orthoglide):
    assert "orthoglide" in robot_names()
    assert orthoglide.model.nq == 18 and len(orthoglide.closures) == 5
    # Rotor and screw inertia reflected through a 20 mm lead: (2.5e-5 + 2e-5)·(2π/0.02)² kg.
    assert orthoglide.actuators[0].reflected_inertia == pytest.approx(4.5e-5 * (2 * 3.141592653589793 / 0.02) ** 2)


def test_rotor_and_screw_inertia_act_at_the_sliders(orthoglide):
    """The drives' inertia adds exactly reflected_inertia · slider acceleration to each slider's force."""
    import dataclasses

    from placement.dynamics.inverse import inverse_dynamics
    from tests.support.trajectories import orthoglide_path

    bare_model = orthoglide.model.copy()
    bare_model.armature[:] = 0.0
    bare = dataclasses.replace(orthoglide, model=bare_model)
    task = orthoglide_path(np.linspace(0.0, 1.0, 80))
    loaded, unloaded = inverse_dynamics(orthoglide, task), inverse_dynamics(bare, task)
    inertia = np.array([a.reflected_inertia for a in orthoglide.actuators])
    np.testing.assert_allclose(loaded.effort - unloaded.effort, inertia * loaded.acceleration, rtol=1e-9, atol=1e-9)
    assert np.abs(inertia * loaded.acceleration).max() > 1.0  # the test moves the sliders hard enough to tell


def test_committed_urdf_is_what_the_generator_writes():
    module = urdf_generator(ORTHOGLIDE_DIR)
    assert (ORTHOGLIDE_DIR / "orthoglide.urdf").read_text() == module.urdf_text()


@pytest.fixture
def robot_copy(tmp_path):
    """A writable copy of the Orthoglide folder: (sidecar path, sidecar dict, writer)."""
    folder = tmp_path / "orthoglide"
    shutil.copytree(ORTHOGLIDE_DIR, folder)
    sidecar = folder / "orthoglide.yaml"
    data = yaml.safe_load(sidecar.read_text())

    def write(new_data):
        sidecar.write_text(yaml.safe_dump(new_data))
        return sidecar

    return sidecar, data, write


def expect_error(path, field_prefix, words):
    with pytest.raises(RobotFileError) as error:
        load_robot(path)
    assert error.value.field.startswith(field_prefix), error.value
    for word in words:
        assert word in str(error.value), error.value
    assert str(path.name) in str(error.value)
    return error.value


def test_copy_of_the_builtin_loads(robot_copy):
    sidecar, data, write = robot_copy
    assert load_robot(write(data)).name == "orthoglide"


def test_unknown_field_lists_the_allowed_ones(robot_copy):
    sidecar, data, write = robot_copy
    data["gravity"] = [0, 0, -9.81]
    expect_error(write(data), "gravity", ["unknown field", "gravity_m_s2"])


def test_unknown_nested_field(robot_copy):
    sidecar, data, write = robot_copy
    data["drives"]["sanyo_p30b06040d_ball_screw"]["motor"]["resistance"] = 1.0
    expect_error(write(data), "drives.sanyo_p30b06040d_ball_screw.motor.resistance", ["resistance_ohm"])


def test_missing_joint(robot_copy):
    sidecar, data, write = robot_copy
    data["actuators"][1]["joint"] = "slider_w"
    expect_error(write(data), "actuators.1.joint", ["slider_w", "slider_y"])


def test_missing_frame_in_a_closure(robot_copy):
    sidecar, data, write = robot_copy
    data["closures"][0]["frames"][1] = "nowhere"
    expect_error(write(data), "closures.0.frames.1", ["nowhere"])


def test_closure_that_does_not_close(robot_copy):
    sidecar, data, write = robot_copy
    data["reference_configuration"]["slider_x"] = 0.30
    expect_error(write(data), "closures.3", ["does not close", "platform_y"])


def test_negative_mass_in_the_urdf(robot_copy):
    sidecar, data, write = robot_copy
    urdf = sidecar.with_name("orthoglide.urdf")
    urdf.write_text(urdf.read_text().replace('<mass value="6.0"/>', '<mass value="-6.0"/>'))
    with pytest.raises(RobotFileError) as error:
        load_robot(sidecar)
    assert error.value.path == urdf and "platform" in error.value.field and ">= 0" in str(error.value)


def test_negative_lead_is_rejected_with_its_unit(robot_copy):
    sidecar, data, write = robot_copy
    data["drives"]["sanyo_p30b06040d_ball_screw"]["transmission"]["lead_m"] = -0.02
    expect_error(write(data), "drives.sanyo_p30b06040d_ball_screw.transmission.lead_m", ["greater than 0"])


def test_motor_constants_must_conserve_energy(robot_copy):
    sidecar, data, write = robot_copy
    data["drives"]["sanyo_p30b06040d_ball_screw"]["motor"]["back_emf_constant_V_s_per_rad"] = 0.2
    expect_error(write(data), "drives.sanyo_p30b06040d_ball_screw.motor", ["torque_constant_Nm_per_A / phases"])


def test_unknown_drive(robot_copy):
    sidecar, data, write = robot_copy
    data["actuators"][2]["drive"] = "maxon"
    expect_error(write(data), "actuators.2.drive", ["maxon", "sanyo_p30b06040d_ball_screw"])


def test_missing_required_field(robot_copy):
    sidecar, data, write = robot_copy
    del data["end_effector"]
    expect_error(write(data), "end_effector", ["required"])


def test_too_few_actuators_for_the_mechanism(robot_copy):
    sidecar, data, write = robot_copy
    data["actuators"] = data["actuators"][:2]
    expect_error(write(data), "actuators", ["3 degree(s) of freedom", "2 actuated"])


def test_source_with_an_unknown_status_or_field(robot_copy):
    sidecar, data, write = robot_copy
    data["sources"]["gravity_m_s2"] = "GUESS: who knows"
    expect_error(write(data), "sources.gravity_m_s2", ["PAPER", "EST"])
    data["sources"]["gravity_m_s2"] = "EST: fine"
    data["sources"]["drives.nothing.lead_m"] = "EST: wrong path"
    expect_error(write(data), "sources.drives.nothing.lead_m", ["names no field"])


def test_yaml_syntax_error(robot_copy):
    sidecar, data, write = robot_copy
    sidecar.write_text("name: [unclosed\n")
    expect_error(sidecar, "", ["not valid YAML"])


def test_unknown_robot_lists_the_known_ones():
    with pytest.raises(UnknownRobotError) as error:
        load_robot("orthoglyde")
    assert "orthoglide" in str(error.value)


def test_a_kinematics_solver_named_in_the_sidecar_is_checked_at_load(tmp_path):
    from tests.support.robot_copies import edited_copy

    with pytest.raises(RobotFileError, match="unknown kinematics solver 'bogus', expected one of") as error:
        load_robot(edited_copy("fivebar", tmp_path / "a", lambda d: d.update(kinematics="bogus")))
    assert error.value.field == "kinematics"
    with pytest.raises(RobotFileError, match="the closed_form solver cannot serve this robot: the robot has no"):
        load_robot(edited_copy("fivebar", tmp_path / "b", lambda d: d.update(kinematics="closed_form")))

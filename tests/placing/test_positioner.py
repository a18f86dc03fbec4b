"""The UR5 beside a tilt-rotate positioner: the workpiece's frame rides on a chain whose joints are profiled.

Physics, not snapshots: the tool's task in the base frame is the derivative of its own pose (finite differences) and
relative to the moving table is the path as placed on it (Pinocchio's forward kinematics); the positioner held still
is the plain UR5 with the path in a fixed frame, to the last digits; the resolved motion's efforts and energy are
those Pinocchio's RNEA gives on the same joint trajectory, the positioner's drives included.
"""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.energy.integration import electric_energy
from placement.energy.trace import motor_trace
from placement.evaluation.evaluator import Evaluator
from placement.exceptions import SettingsError
from placement.path import load_path
from placement.placing.profiles import redundant_variables
from placement.placing.transform import on_workpiece, placed_task, placement_pose
from placement.robot.exceptions import RobotFileError
from placement.workshop.catalog import builtin_robots_dir
from placement.workshop.load import edit_redundancy, robot_from_sidecar
from tests.support.generators import urdf_generator
from tests.support.paths import CIRCLE, EXAMPLES
from tests.support.positioner import TURNING
from tests.support.rnea_reference import rnea_actuator_efforts
from tests.support.robot_copies import edited_copy

WELD = EXAMPLES / "positioner_weld.yaml"
POSITIONER_DIR = builtin_robots_dir() / "ur5_positioner"


@pytest.fixture(scope="module")
def positioner():
    return load_robot("ur5_positioner")


@pytest.fixture(scope="module")
def small_arc(tmp_path_factory):
    """A 60 mm arc without process force, fast: the UR5 reaches it from the table's near side."""
    path = tmp_path_factory.mktemp("arc") / "arc.yaml"
    path.write_text(yaml.safe_dump({"units": "mm", "shape": {"type": "arc", "radius": 30, "sweep_deg": 270},
                                    "feed_m_s": 0.05, "time_step_s": 0.01,
                                    "timing": {"mode": "realistic", "max_acceleration_m_s2": 1, "max_jerk_m_s3": 20}}))
    return load_path(path)


def test_committed_urdf_is_what_the_generator_writes():
    module = urdf_generator(POSITIONER_DIR)
    assert (POSITIONER_DIR / "ur5_positioner.urdf").read_text(encoding="utf-8") == module.positioner_urdf()


def test_the_ur5s_drives_and_torch_are_the_ur5s_and_the_tracks():
    own = yaml.safe_load((POSITIONER_DIR / "ur5_positioner.yaml").read_text(encoding="utf-8"))
    ur5 = yaml.safe_load((builtin_robots_dir() / "ur5" / "ur5.yaml").read_text(encoding="utf-8"))
    track = yaml.safe_load((builtin_robots_dir() / "ur5_track" / "ur5_track.yaml").read_text(encoding="utf-8"))
    assert {name: own["drives"][name] for name in ur5["drives"]} == ur5["drives"]
    assert own["actuators"][2:] == ur5["actuators"] and own["tool"] == track["tool"]
    assert own["end_effector"] == ur5["end_effector"]


def test_both_positioner_axes_are_profiled(positioner):
    assert positioner.redundant_joints == ("tilt", "rotate") and positioner.workpiece_frame == "workpiece"
    assert redundant_variables(positioner)[:1] == ("tilt@0",) and len(redundant_variables(positioner)) == 6


def test_the_relative_task_is_the_derivative_of_its_pose_and_the_path_on_the_table(positioner):
    """The tool's task in the base frame: its velocity and acceleration (linear and angular) are the finite
    differences of its position, rotation and velocity; seen from the table (Pinocchio's forward kinematics at the
    profiled joints), it is the path as placed in the table's frame."""
    samples = load_path(WELD).sample(0.025)
    task, _ = placed_task(positioner, samples, TURNING[None])
    t, inner = samples.t_s, slice(40, -40)  # a second from either end, clear of the start and stop ramps
    spacing = np.diff(t)
    assert np.ptp(spacing) < 1e-9  # a uniform grid: the central differences below are second order
    dt = float(spacing[0])

    def central(values):
        return ((values[2:] - values[:-2]) / (2 * dt))[inner]

    def near(finite, exact, relative):
        exact = exact[1:-1][inner]
        assert np.abs(finite - exact).max() <= relative * np.abs(exact).max()

    near(central(task.position_m), task.velocity_m_s, 1e-5)
    near(central(task.velocity_m_s), task.acceleration_m_s2, 1e-4)
    turns = np.array([pin.log3(after @ before.T) for before, after in zip(task.rotation[:-2], task.rotation[2:])])
    near(turns[inner] / (2 * dt), task.angular_velocity_rad_s, 1e-5)
    near(central(task.angular_velocity_rad_s), task.angular_acceleration_rad_s2, 1e-4)
    alone, _ = placed_task(load_robot("ur5"), samples, TURNING[None, :6])  # the same path in a fixed frame
    model, data = positioner.model, positioner.model.createData()
    frame, q = model.getFrameId("workpiece"), np.repeat(positioner.reference_q[None], len(samples), axis=0)
    q[:, positioner.redundant_q_indices] = task.joint_position
    for k in range(0, len(samples), 37):
        pin.framesForwardKinematics(model, data, q[k])
        table = data.oMf[frame]
        np.testing.assert_allclose(table.rotation.T @ (task.position_m[k] - table.translation), alone.position_m[k],
                                   atol=1e-12)
        np.testing.assert_allclose(table.rotation.T @ task.rotation[k], alone.rotation[k], atol=1e-12)
    np.testing.assert_allclose(task.joint_position[[0, -1]], TURNING[[6, 9, 8, 11]].reshape(2, 2), atol=1e-12)


def test_a_tool_turning_on_the_moving_table_is_composed_to_second_order(positioner):
    """A tool turning and moving relative to the table (analytic: a helix, turning about the table's z and tilted),
    the table tilting and turning as the profiles say: the base frame's velocities and accelerations, linear and
    angular, are the finite differences of the composed pose (the cross terms ω_table × R·ω, 2 ω_table × R·u
    included)."""
    samples = load_path(WELD).sample(0.025)
    profiled, _ = placed_task(positioner, samples, TURNING[None])
    t = samples.t_s
    c, s = np.cos(0.2 * t), np.sin(0.2 * t)
    position = np.stack([0.1 * c, 0.1 * s, 0.002 * t ** 2], axis=1)
    velocity = np.stack([-0.02 * s, 0.02 * c, 0.004 * t], axis=1)
    acceleration = np.stack([-0.004 * c, -0.004 * s, np.full_like(t, 0.004)], axis=1)
    turning = np.array([pin.exp3(np.array([0.0, 0.0, 0.2 * time])) @ pin.exp3(np.array([0.3, 0.0, 0.0])) for time in t])
    spin, still = np.tile([0.0, 0.0, 0.2], (len(t), 1)), np.zeros((len(t), 3))
    relative = dataclasses.replace(profiled, position_m=position, velocity_m_s=velocity, acceleration_m_s2=acceleration,
                                   rotation=turning, angular_velocity_rad_s=spin, angular_acceleration_rad_s2=still)
    task = on_workpiece(positioner, relative)
    dt, inner = float(t[1] - t[0]), slice(40, -40)

    def central(values):
        return ((values[2:] - values[:-2]) / (2 * dt))[inner]

    def near(finite, exact):
        exact = exact[1:-1][inner]
        assert np.abs(finite - exact).max() <= 1e-4 * np.abs(exact).max()

    near(central(task.position_m), task.velocity_m_s)
    near(central(task.velocity_m_s), task.acceleration_m_s2)
    turns = np.array([pin.log3(after @ before.T) for before, after in zip(task.rotation[:-2], task.rotation[2:])])
    near(turns[inner] / (2 * dt), task.angular_velocity_rad_s)
    near(central(task.angular_velocity_rad_s), task.angular_acceleration_rad_s2)


def test_the_held_positioner_is_the_plain_ur5_with_the_path_in_a_fixed_frame(positioner, small_arc):
    """--lock tilt=0.2 --lock rotate=0.7 leaves the UR5 of robots/ur5 (with the same torch) and the path in the
    table's frame where the locked axes hold it: the same efforts and energies, to 1e-12."""
    tilt, rotate = 0.2, 0.7
    locked = edit_redundancy(positioner, {"tilt": tilt, "rotate": rotate})
    plain = load_robot("ur5")
    ur5 = robot_from_sidecar(plain.sidecar_path, plain.edited_sidecar(tool=positioner.sidecar.tool))
    in_base = np.array([0.62, 0.02, 0.22, 0.3, 0.05, -0.05])  # on the table's side nearest the UR5
    model, data = positioner.model, positioner.model.createData()
    q = positioner.reference_q.copy()
    q[positioner.redundant_q_indices] = tilt, rotate
    pin.framesForwardKinematics(model, data, q)
    table = data.oMf[model.getFrameId("workpiece")]
    rotation, origin = placement_pose(in_base)
    yaw_pitch_roll = pin.rpy.matrixToRpy(table.rotation.T @ rotation[0])[::-1]
    on_table = np.concatenate([table.rotation.T @ (origin[0] - table.translation), yaw_pitch_roll])
    held, alone = Evaluator(locked, small_arc).batch(on_table[None]), Evaluator(ur5, small_arc).batch(in_base[None])
    assert held.reachable.all() and alone.reachable.all()
    assert [a.joint for a in locked.actuators] == [a.joint for a in ur5.actuators]
    np.testing.assert_allclose(held.effort[0], alone.effort[0], rtol=1e-12, atol=1e-10)
    np.testing.assert_allclose(held.energy.per_actuator_J[0], alone.energy.per_actuator_J[0], rtol=1e-11)


def test_energy_of_the_resolved_motion_is_rnea_on_its_joint_trajectory(positioner):
    """Efforts by Pinocchio's RNEA, sample by sample, on the same joint trajectory (the table tilting and turning):
    the same efforts and the same electric energy, the positioner's friction and efficiency included, to 1e-9."""
    evaluator = Evaluator(positioner, load_path(WELD))
    batch = evaluator.batch(TURNING[None])
    assert batch.reachable.all()
    joints = batch.joints
    _, force = placed_task(positioner, evaluator.samples, TURNING[None])
    efforts = rnea_actuator_efforts(positioner, joints, force)
    np.testing.assert_allclose(batch.effort[0], efforts, rtol=1e-9, atol=1e-9 * np.abs(efforts).max())
    rotate = joints.q[:, positioner.redundant_q_indices[1]]
    assert rotate[0] == pytest.approx(TURNING[9], abs=1e-12) and rotate[-1] == pytest.approx(TURNING[11], abs=1e-12)
    v, a = joints.v[:, positioner.actuated_v_indices], joints.a[:, positioner.actuated_v_indices]
    energy = electric_energy(positioner, motor_trace(positioner, efforts, v, a), evaluator.samples.t_s,
                             evaluator.samples.piece)
    assert energy.total_J == pytest.approx(float(batch.energy.total_J[0]), rel=1e-9)
    np.testing.assert_allclose(energy.per_actuator_J, batch.energy.per_actuator_J[0], rtol=1e-9, atol=1e-12)
    assert (batch.energy.per_actuator_J[0][:2] > 1.0).all()  # both positioner drives work: the tilted load, friction


def test_turning_the_path_on_the_part_and_the_table_back_changes_no_energy(positioner):
    """phi and the table's rotation are one freedom (why the sidecar leaves phi fixed): the path turned by 40° on the
    round part and the table's rotation profile turned back by 40° draw the same energy, drive by drive (1e-9)."""
    evaluator = Evaluator(positioner, load_path(WELD))
    turned = TURNING.copy()
    turned[3] += np.radians(40.0)
    turned[9:] -= np.radians(40.0)
    batch = evaluator.batch(np.vstack([TURNING, turned]))
    assert batch.reachable.all()
    np.testing.assert_allclose(batch.energy.per_actuator_J[1], batch.energy.per_actuator_J[0], rtol=1e-9, atol=1e-9)


def test_the_locked_positioner_searches_phi_when_asked(capsys):
    """Both axes locked, no knot is left and the sidecar frees no placement variable: the command says to free one."""
    assert main(["--robot", "ur5_positioner", "--path", str(WELD), "--lock", "tilt=0", "--lock", "rotate=0"]) == 2
    assert "leaves no placement variable free" in capsys.readouterr().err


def test_a_workpiece_frame_must_ride_on_profiled_joints_only(positioner):
    sidecar = positioner.edited_sidecar(workpiece_frame="no_such_frame")
    with pytest.raises(RobotFileError, match="workpiece_frame"):
        robot_from_sidecar(positioner.sidecar_path, sidecar)
    redundancy = positioner.sidecar.redundancy.model_copy(update={"joints": ["tilt", "shoulder_pan_joint"]})
    with pytest.raises(RobotFileError, match="moved by rotate, which redundancy.joints does not profile"):
        robot_from_sidecar(positioner.sidecar_path, positioner.edited_sidecar(redundancy=redundancy))


def test_an_empty_free_set_needs_redundant_joints(tmp_path):
    def held(document):
        document["locked_joints"] = {"tilt": 0.0, "rotate": 0.0}
        document["actuators"] = document["actuators"][2:]
        for key in ("redundancy", "workpiece_frame"):
            document.pop(key)
        for joint in ("tilt", "rotate"):
            document["reference_configuration"].pop(joint)
        document["sources"] = {key: text for key, text in document["sources"].items()
                               if key.split(".")[0] not in ("redundancy", "workpiece_frame")}

    with pytest.raises(RobotFileError, match="placement.free.*at least one free placement variable"):
        load_robot(edited_copy("ur5_positioner", tmp_path, held))


def test_process_forces_on_a_positioner_are_refused(positioner):
    samples = load_path(CIRCLE).sample(0.01)
    with pytest.raises(SettingsError, match="process forces is not covered"):
        placed_task(positioner, samples, TURNING[None])


def test_the_positioner_axes_are_rows_of_the_energy_table(tmp_path, capsys):
    out = tmp_path / "at.json"
    at = "phi=-120,tilt@0=-10,tilt@1=-25,tilt@2=-20,rotate@0=290,rotate@1=140,rotate@2=-20"
    assert main(["--robot", "ur5_positioner", "--path", str(WELD), "--at", at, "--json", str(out)]) == 0
    text = capsys.readouterr().out
    rows = {line.split()[0] for line in text.splitlines() if len(line.split()) == 6}
    assert {"tilt", "rotate"} <= rows
    assert json.loads(out.read_text())["workpiece_frame"] == "workpiece"
    assert main(["export", str(out), "--which", "at", "--to", "ur"]) == 2  # the work frame moves: not a fixed one
    assert "work object carried by the positioner" in capsys.readouterr().err
    document = json.loads(out.read_text())["at"]
    assert document["feasible"]
    assert document["energy_per_actuator_J"]["rotate"] > 0.0 and document["energy_per_actuator_J"]["tilt"] > 0.0
    assert document["profiles"]["rotate"]["position_rad"][-1] == pytest.approx(TURNING[11], abs=1e-12)


def test_the_profiles_figure_draws_the_resolved_joints_and_the_knots_where_they_stand(positioner, tmp_path, capsys):
    """--png without --objectives plots each redundant joint along the path: the curves are the resolved joint
    values, and the knot markers, placed at the times their shares of arc length are reached, sit on the knots'
    values (the natural spline passes through its knots); a robot without redundant joints is told --png has
    nothing to plot."""
    pytest.importorskip("matplotlib")
    from placement.output.plots import profiles_figure

    evaluator = Evaluator(positioner, load_path(WELD))
    detail = evaluator.detail(TURNING)
    figure = profiles_figure(positioner, detail, "test")
    for ax, q, knots in zip(figure.axes, positioner.redundant_q_indices, (TURNING[6:9], TURNING[9:]), strict=True):
        curve, markers = ax.lines
        np.testing.assert_allclose(curve.get_ydata(), np.degrees(detail.configuration[:, q]), rtol=1e-12)
        np.testing.assert_allclose(markers.get_ydata(), np.degrees(knots), atol=0.05)  # between samples 0.25 s apart
    png = tmp_path / "profiles.png"
    at = "phi=-120,tilt@0=-10,tilt@1=-25,tilt@2=-20,rotate@0=290,rotate@1=140,rotate@2=-20"
    assert main(["--robot", "ur5_positioner", "--path", str(WELD), "--at", at, "--png", str(png)]) == 0
    assert png.stat().st_size > 0 and png.with_suffix(".svg").stat().st_size > 0
    capsys.readouterr()
    assert main(["--robot", "ur5", "--path", str(CIRCLE), "--at", "x=400", "--png", str(tmp_path / "no.png")]) == 2
    assert "robot 'ur5' has none" in capsys.readouterr().err

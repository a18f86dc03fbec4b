"""Pose lists as tool paths: orientation conventions, exact angular motion, the UR5 following them, errors."""

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.evaluation.evaluator import Evaluator
from placement.kinematics import joint_trajectory
from placement.path import load_path
from placement.path.exceptions import PoseFileError
from placement.placing.transform import OrientationIgnoredWarning, placed_task
from placement.robot.closures import LWA

AT = np.array([0.45, 0.1, 0.2, 0.3, 0.1, -0.05])  # inside the UR5's workspace, the workpiece tilted


def poses(tmp_path, table, settings="units: mm\nfeed_m_s: 0.05\n", orientation="none", name="poses.csv"):
    (tmp_path / name).write_text(table)
    file = tmp_path / "path.yaml"
    file.write_text(f"shape: {{type: poses, file: {name}, orientation: {orientation}}}\n" + settings)
    return load_path(file)


def rx(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def ry(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])


def rz(a):
    c, s = np.cos(a), np.sin(a)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def vee(skew):
    return np.array([skew[2, 1], skew[0, 2], skew[1, 0]])


TURNING = """x,y,z,roll_deg,pitch_deg,yaw_deg
0,0,0,0,0,0
30,0,0,10,0,0
30,20,-5,10,-12,20
0,20,0,-5,8,-15
"""


def test_orientation_conventions(tmp_path):
    rpy = poses(tmp_path, "x,y,z,roll_deg,pitch_deg,yaw_deg\n0,0,0,10,20,30\n10,0,0,10,20,30\n", orientation="rpy_deg")
    expected = rz(np.radians(30)) @ ry(np.radians(20)) @ rx(np.radians(10))
    np.testing.assert_allclose(rpy.sample().rotation[0], expected, atol=1e-15)
    half = np.radians(40) / 2  # qx, qy, qz, qw of 40° about z
    quaternion = poses(tmp_path, f"x,y,z,qx,qy,qz,qw\n0,0,0,0,0,{float(np.sin(half))!r},{float(np.cos(half))!r}\n1,0,0,0,0,0,1\n",
                       orientation="quaternion_xyzw")
    np.testing.assert_allclose(quaternion.sample().rotation[0], rz(np.radians(40)), atol=1e-15)


@pytest.mark.parametrize("timing", ["paper", "realistic"])
def test_the_orientation_turns_uniformly_with_exact_rates(tmp_path, timing):
    settings = (f"units: mm\nfeed_m_s: 0.05\ntiming: {{mode: {timing}, max_acceleration_m_s2: 2, max_jerk_m_s3: 50}}\n"
                "time_step_s: 0.0002\n")
    samples = poses(tmp_path, TURNING, settings, "rpy_deg").sample()
    r, t = samples.rotation, samples.t_s
    inside = np.flatnonzero((samples.piece[:-2] == samples.piece[2:]) & (t[2:] > t[:-2])) + 1
    derivative = (r[inside + 1] - r[inside - 1]) / (t[inside + 1] - t[inside - 1])[:, None, None]
    omega = np.array([vee(d @ rk.T) for d, rk in zip(derivative, r[inside])])
    # Central differences err by about h²/6 times the rate's second derivative: up to ~5e-6 rad/s where the
    # realistic law's jerk (50 m/s³) drives a turning rate of ~6 rad/m.
    np.testing.assert_allclose(samples.angular_velocity_rad_s[inside], omega, atol=1e-5 if timing == "realistic"
                               else 1e-8)
    rate = (samples.angular_velocity_rad_s[inside + 1] - samples.angular_velocity_rad_s[inside - 1])
    alpha = rate / (t[inside + 1] - t[inside - 1])[:, None]
    # Where the double-S profile switches its jerk the acceleration has a kink: central differences hold elsewhere.
    acc = samples.acceleration_m_s2
    smooth = np.linalg.norm(acc[inside + 1] - 2 * acc[inside] + acc[inside - 1], axis=1) < 1e-9
    assert smooth.mean() > 0.95
    np.testing.assert_allclose(samples.angular_acceleration_rad_s2[inside[smooth]], alpha[smooth], atol=1e-9)
    # Every pose is reached at the end of its segment.
    ends = [np.radians(row) for row in ([10, 0, 0], [10, -12, 20], [-5, 8, -15])]
    for end in ends:
        target = rz(end[2]) @ ry(end[1]) @ rx(end[0])
        assert np.min(np.abs(r - target).max(axis=(1, 2))) < 1e-12


def test_the_ur5_follows_a_turning_pose_list_exactly(tmp_path):
    robot = load_robot("ur5")
    samples = poses(tmp_path, TURNING, "units: mm\nfeed_m_s: 0.05\ntime_step_s: 0.005\n", "rpy_deg").sample()
    task, _ = placed_task(robot, samples, AT[None])
    joints = joint_trajectory(robot, task)
    model, data, frame = robot.model, robot.model.createData(), robot.end_effector_frame_id
    for k in range(len(samples)):
        pin.framesForwardKinematics(model, data, joints.q[k])
        np.testing.assert_allclose(data.oMf[frame].rotation, task.rotation[k], atol=1e-9)
        np.testing.assert_allclose(data.oMf[frame].translation, task.position_m[k], atol=1e-9)
        jacobian = pin.computeFrameJacobian(model, data, joints.q[k], frame, LWA)
        np.testing.assert_allclose(jacobian @ joints.v[k], task.twist()[k], atol=1e-9)
    # The base-frame angular velocity is the placement's rotation times the path frame's.
    rotation = pin.rpy.rpyToMatrix(AT[5], AT[4], AT[3])
    np.testing.assert_allclose(task.angular_velocity_rad_s, samples.angular_velocity_rad_s @ rotation.T, atol=1e-15)


def test_a_constant_orientation_list_is_the_polyline(tmp_path):
    robot = load_robot("ur5")
    table = "x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n30,0,0,0,0,0,1\n30,20,-5,0,0,0,1\n0,20,0,0,0,0,1\n"
    listed = poses(tmp_path, table, orientation="quaternion_xyzw")
    line = tmp_path / "line.yaml"
    line.write_text("units: mm\nshape: {type: polyline, points: [[0, 0, 0], [30, 0, 0], [30, 20, -5], [0, 20, 0]]}\n"
                    "feed_m_s: 0.05\n")
    polyline = load_path(line)
    a, b = listed.sample(), polyline.sample()
    for field in ("t_s", "position_m", "velocity_m_s", "acceleration_m_s2", "force_on_tool_N", "piece"):
        np.testing.assert_allclose(getattr(a, field), getattr(b, field), atol=1e-9, rtol=0)
    np.testing.assert_allclose(a.rotation, np.broadcast_to(np.eye(3), a.rotation.shape), atol=0)
    energies = [Evaluator(robot, path).detail(AT).energy.total_J for path in (listed, polyline)]
    assert energies[0] == pytest.approx(energies[1], rel=1e-9)


def test_timed_poses_pass_through_every_pose_at_its_time(tmp_path):
    table = ("t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n0.4,20,5,0,0.0871557,0,0,0.9961947\n"
             "0.9,35,25,-3,0.0616284,0.0616284,0.0616284,0.9943667\n1.5,10,40,0,0,0,0.1305262,0.9914449\n")
    path = poses(tmp_path, table, "units: mm\ntime_step_s: 0.0001\n", "quaternion_xyzw")
    samples = path.sample()
    times = [0.0, 0.4, 0.9, 1.5]
    points = np.array([[0, 0, 0], [20, 5, 0], [35, 25, -3], [10, 40, 0]]) * 1e-3
    for time, point in zip(times, points):
        k = int(np.argmin(np.abs(samples.t_s - time)))
        assert samples.t_s[k] == pytest.approx(time, abs=1e-12)
        np.testing.assert_allclose(samples.position_m[k], point, atol=1e-12)
    np.testing.assert_allclose(samples.rotation[-1], rz(np.radians(15)), atol=1e-6)  # the quaternion's 7 digits
    # Velocity, acceleration and angular velocity are the derivatives of position and orientation.
    t, p, r = samples.t_s, samples.position_m, samples.rotation
    mid = np.arange(1, len(t) - 1)
    dt = (t[2:] - t[:-2])[:, None]
    np.testing.assert_allclose(samples.velocity_m_s[mid], (p[2:] - p[:-2]) / dt, atol=1e-8)
    np.testing.assert_allclose(samples.acceleration_m_s2[mid], (samples.velocity_m_s[2:] - samples.velocity_m_s[:-2]) / dt,
                               atol=1e-5)
    omega = np.array([vee((r[k + 1] - r[k - 1]) @ r[k].T) for k in mid]) / dt
    np.testing.assert_allclose(samples.angular_velocity_rad_s[mid], omega, atol=1e-6)
    alpha = (samples.angular_velocity_rad_s[2:] - samples.angular_velocity_rad_s[:-2]) / dt
    # scipy's RotationSpline makes the angular acceleration continuous at the poses to its solver's tolerance:
    # it jumps there by a few 1e-4 rad/s² (of ~2 rad/s²).
    np.testing.assert_allclose(samples.angular_acceleration_rad_s2[mid], alpha, atol=1e-3)
    # The feed command's scale runs the list faster: half the time at twice the feed.
    import dataclasses

    faster = dataclasses.replace(path, feed_m_s=2 * path.feed_m_s).sample()
    assert faster.t_s[-1] == pytest.approx(0.75, rel=1e-12)


def test_a_json_list_is_the_csv_list(tmp_path):
    csv = poses(tmp_path, "x,y,z\n0,0,0\n10,0,0\n10,10,0\n")
    json = poses(tmp_path, '[{"x": 0, "y": 0, "z": 0}, {"x": 10, "y": 0, "z": 0}, {"x": 10, "y": 10, "z": 0}]',
                 name="poses.json")
    np.testing.assert_array_equal(csv.sample().position_m, json.sample().position_m)


def test_a_position_robot_warns_once_that_orientations_are_ignored(tmp_path):
    robot = load_robot("orthoglide")
    samples = poses(tmp_path, TURNING, orientation="rpy_deg").sample()
    with pytest.warns(OrientationIgnoredWarning, match="ignored"):
        task, _ = placed_task(robot, samples, np.zeros((1, 6)))
    assert task.rotation is None


@pytest.mark.parametrize("table, orientation, settings, row, column, words", [
    ("x,y\n0,0\n1,1\n", "none", None, 0, "z", ["missing column"]),
    ("x,y,z,roll\n0,0,0,0\n1,1,1,0\n", "none", None, 0, "roll", ["unknown column"]),
    ("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n1,0,0,0,0,0.5,1\n", "quaternion_xyzw", None, 2, "qw", ["norm 1.118"]),
    ("t,x,y,z\n0,0,0,0\n1,1,0,0\n1,2,0,0\n", "none", "units: mm\n", 3, "t", ["must increase"]),
    ("x,y,z\n0,0,0\n1,nan,0\n", "none", None, 2, "y", ["finite number"]),
    ("x,y,z\n0,0,0\n1,abc,0\n", "none", None, 2, "y", ["expected a number"]),
    ("x,y,z\n0,0,0\n1,0\n", "none", None, 2, "", ["2 values for the 3 columns"]),
    ("x,y,z,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,0,0\n0,0,0,0,0,10\n", "rpy_deg", None, 2, "", ["turns on the spot"]),
])
def test_bad_pose_lists_name_file_row_and_column(tmp_path, table, orientation, settings, row, column, words):
    with pytest.raises(PoseFileError) as error:
        poses(tmp_path, table, settings or "units: mm\nfeed_m_s: 0.05\n", orientation)
    assert (error.value.row, error.value.column) == (row, column)
    message = str(error.value)
    assert message.startswith(str(tmp_path / "poses.csv"))
    assert (f"row {row}" in message) == bool(row) and (f"column '{column}'" in message) == bool(column)
    for word in words:
        assert word in message


def test_a_timed_list_may_turn_on_the_spot(tmp_path):
    table = "t,x,y,z,roll_deg,pitch_deg,yaw_deg\n0,0,0,0,0,0,0\n0.5,0,0,0,0,0,30\n1,10,0,0,0,0,30\n"
    samples = poses(tmp_path, table, "units: mm\n", "rpy_deg").sample()
    k = int(np.argmin(np.abs(samples.t_s - 0.5)))
    np.testing.assert_allclose(samples.rotation[k], rz(np.radians(30)), atol=1e-12)
    np.testing.assert_allclose(samples.position_m[k], 0.0, atol=1e-15)


@pytest.mark.parametrize("settings, field", [("units: mm\nfeed_m_s: 0.1\n", "feed_m_s"),
                                             ("units: mm\ntiming: {mode: paper}\n", "timing"),
                                             ("feed_m_s: 0.1\n", "units")])
def test_fields_a_timed_list_refuses_or_needs(tmp_path, settings, field):
    from placement.path.exceptions import PathFileError

    with pytest.raises(PathFileError) as error:
        poses(tmp_path, "t,x,y,z\n0,0,0,0\n1,1,0,0\n", settings)
    assert error.value.field == field


def test_the_schema_offers_every_orientation_kind():
    from typing import get_args

    from placement.path.path_file import Poses
    from placement.path.poses import ORIENTATION_COLUMNS

    assert set(get_args(Poses.model_fields["orientation"].annotation)) == set(ORIENTATION_COLUMNS)

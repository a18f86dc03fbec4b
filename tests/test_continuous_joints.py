"""URDF ``continuous`` joints: one angle each, with the kinematics and dynamics of Pinocchio's two-coordinate joint."""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from placement.cli import main
from placement.evaluation.evaluator import Evaluator
from placement.path import load_path
from placement.robot import load_robot
from placement.robot.erd import load_erd_robot
from placement.robot.exceptions import RobotFileError
from placement.robot.load import one_angle_urdf, pinocchio_model, urdf_limits_missing
from placement.search.space import default_space

CONTINUOUS = ("shoulder_pan_joint", "wrist_3_joint")


def continuous_ur5_urdf(keep_limit: bool = True) -> str:
    """The built-in UR5's URDF with its first and last joints made continuous: their ``<limit>`` keeps effort and
    velocity only, or is removed."""
    text = load_robot("ur5").urdf_path.read_text()
    for name in CONTINUOUS:
        element = re.search(rf'<joint name="{name}" type="revolute">.*?</joint>', text, re.DOTALL)
        assert element is not None
        limit = re.search(r"<limit\b[^>]*/>", element.group(0))
        assert limit is not None
        effort_velocity = re.sub(r'\s(lower|upper)="[^"]*"', "", limit.group(0)) if keep_limit else ""
        changed = element.group(0).replace('type="revolute"', 'type="continuous"').replace(limit.group(0), effort_velocity)
        text = text.replace(element.group(0), changed)
    return text


def test_a_continuous_joint_is_one_angle_with_pinocchios_kinematics_and_dynamics(tmp_path):
    """Frame placements and RNEA efforts at random angles equal those of Pinocchio's (cos, sin) joint to 1e-12."""
    text = continuous_ur5_urdf()
    two = pin.buildModelFromXML(text)
    assert [two.joints[two.getJointId(n)].nq for n in CONTINUOUS] == [2, 2]
    urdf = tmp_path / "ur5.urdf"
    urdf.write_text(text)
    one = pinocchio_model(urdf)
    assert one.nq == one.nv == two.nv == 6
    assert all(urdf_limits_missing(one, one.getJointId(n)) for n in CONTINUOUS)
    rng = np.random.default_rng(0)
    data_one, data_two = one.createData(), two.createData()
    for _ in range(5):
        angles, v, a = rng.uniform(-4.0, 4.0, 6), rng.normal(size=6), rng.normal(size=6)
        q_two = np.concatenate([[np.cos(x), np.sin(x)] if two.joints[j + 1].nq == 2 else [x] for j, x in enumerate(angles)])
        pin.framesForwardKinematics(one, data_one, angles)
        pin.framesForwardKinematics(two, data_two, q_two)
        for frame in range(one.nframes):
            np.testing.assert_allclose(data_one.oMf[frame].homogeneous, data_two.oMf[frame].homogeneous, atol=1e-12)
        np.testing.assert_allclose(pin.rnea(one, data_one, angles, v, a), pin.rnea(two, data_two, q_two, v, a),
                                   atol=1e-12)


def test_only_continuous_joint_elements_change():
    """A joint named in a transmission (empty or not) or in a comment is left alone, the continuous joints after
    them are found, and their position bounds go (the URDF ignores them for a continuous joint)."""
    text = ('<robot name="r"><transmission><joint name="a"/></transmission><!-- <joint name="c" type="fixed"> -->'
            '<joint name="a" type="continuous"><parent link="p"/><child link="c"/><!-- <limit effort="1"/> --></joint>'
            "<joint name='b' type='continuous'><limit lower='-1' effort='2' upper = '1' velocity='3'/></joint >"
            '<transmission><joint name="b"><hardwareInterface>x</hardwareInterface></joint></transmission></robot>')
    assert one_angle_urdf(text) == (
        '<robot name="r"><transmission><joint name="a"/></transmission>'
        '<joint name="a" type="revolute"><parent link="p"/><child link="c"/><limit effort="0" velocity="0"/></joint>'
        "<joint name='b' type='revolute'><limit effort='2' velocity='3'/></joint >"
        '<transmission><joint name="b"><hardwareInterface>x</hardwareInterface></joint></transmission></robot>')


def test_a_continuous_joint_without_limit_reads_as_giving_no_effort_or_speed(tmp_path):
    urdf = tmp_path / "ur5.urdf"
    urdf.write_text(continuous_ur5_urdf(keep_limit=False))
    model = pinocchio_model(urdf)
    joint = model.getJointId("shoulder_pan_joint")
    assert model.nq == 6 and urdf_limits_missing(model, joint)
    assert model.effortLimit[model.joints[joint].idx_v] == 0 and model.velocityLimit[model.joints[joint].idx_v] == 0


def test_a_sidecar_on_continuous_joints_needs_their_range_and_then_solves(tmp_path):
    from robot_copies import edited_copy

    def continuous(document: dict) -> None:
        document["urdf"] = "ur5.urdf"

    sidecar = edited_copy("ur5", tmp_path, continuous)
    (sidecar.parent / "ur5.urdf").write_text(continuous_ur5_urdf())
    with pytest.raises(RobotFileError, match="joint 'shoulder_pan_joint' has no limits in the URDF") as error:
        load_robot(sidecar)
    assert error.value.field == "actuators.0.position_min"

    def with_ranges(document: dict) -> None:
        continuous(document)
        for actuator in document["actuators"]:
            if actuator["joint"] in CONTINUOUS:
                actuator.update(position_min=-np.pi, position_max=np.pi)

    ranged = edited_copy("ur5", tmp_path / "ranged", with_ranges)
    (ranged.parent / "ur5.urdf").write_text(continuous_ur5_urdf())
    robot = load_robot(ranged)
    builtin = load_robot("ur5")
    assert robot.model.nq == builtin.model.nq == 6
    path = load_path("examples/rect.yaml")
    placement = default_space(builtin).full(np.zeros((1, len(default_space(builtin).free))))[0]
    energy = [Evaluator(r, path).detail(placement).energy.total_J for r in (robot, builtin)]
    assert energy[0] == pytest.approx(energy[1], rel=1e-9) and energy[1] > 0


def test_kinova_with_continuous_joints_loads_and_passes_check(capsys):
    kinova = load_erd_robot("kinova", "j2s6s200_end_effector")
    assert kinova.model.nq == kinova.model.nv == 6 and len(kinova.actuators) == 6
    assert main(["check", "erd:kinova", "--tool", "j2s6s200_end_effector", "--samples", "30"]) == 0
    assert "exact to round-off" in capsys.readouterr().out


def test_an_erd_arm_with_unlimited_continuous_joints_gets_a_full_turn_about_its_reference(tmp_path, monkeypatch):
    """example-robot-data's UR5 with two continuous joints without position limits: each gets the range of a full
    turn about the reference posture, labelled as an estimate, and the arm moves as the revolute one."""
    import placement.robot.erd as erd
    import placement.robot.load as load

    urdf = tmp_path / "ur5.urdf"
    urdf.write_text(continuous_ur5_urdf())
    monkeypatch.setattr(erd, "erd_urdf_path", lambda loader: urdf)
    monkeypatch.setattr(load, "erd_urdf_path", lambda loader: urdf)
    robot = load_erd_robot("ur5", "tool0")
    for name in CONTINUOUS:
        actuator = next(a for a in robot.actuators if a.joint == name)
        reference = robot.reference_q[actuator.q_index]
        assert (actuator.position_min, actuator.position_max) == pytest.approx((reference - np.pi, reference + np.pi))
        index = [a.joint for a in robot.actuators].index(name)
        assert "continuous" in robot.sidecar.sources[f"actuators.{index}.position_min"]
    monkeypatch.undo()
    revolute = load_erd_robot("ur5", "tool0")
    data, data_revolute = robot.model.createData(), revolute.model.createData()
    q = robot.reference_q + 0.3
    pin.framesForwardKinematics(robot.model, data, q)
    pin.framesForwardKinematics(revolute.model, data_revolute, q)
    frame = robot.end_effector_frame_id
    np.testing.assert_allclose(data.oMf[frame].homogeneous, data_revolute.oMf[revolute.end_effector_frame_id].homogeneous,
                               atol=1e-12)


def test_a_continuous_joint_locks_at_any_angle(tmp_path):
    """Without position limits, a locked continuous joint may be held anywhere (here the UR5's wrist, at 0.5 rad,
    the arm then following a position task with its first three joints)."""
    from robot_copies import edited_copy

    wrist = {"wrist_1_joint": -1.67, "wrist_2_joint": -1.5707963267948966, "wrist_3_joint": 0.5}

    def wrist_locked(document: dict) -> None:
        document["urdf"] = "ur5.urdf"
        document["end_effector"] = {"frame": "tool0", "task": "position"}
        document["locked_joints"] = wrist
        document["reference_configuration"] = {k: v for k, v in document["reference_configuration"].items()
                                               if k not in wrist}
        document["actuators"] = [a for a in document["actuators"] if a["joint"] not in wrist]
        document["actuators"][0].update(position_min=-np.pi, position_max=np.pi)
        document["placement"] = {"free": ["x", "y", "z", "phi"]}

    sidecar = edited_copy("ur5", tmp_path, wrist_locked)
    (sidecar.parent / "ur5.urdf").write_text(continuous_ur5_urdf())
    robot = load_robot(sidecar)
    assert robot.model.nq == 3
    builtin = load_robot("ur5")
    data, data_builtin = robot.model.createData(), builtin.model.createData()
    q = np.array([0.2, -1.9, 2.0])
    pin.framesForwardKinematics(robot.model, data, q)
    pin.framesForwardKinematics(builtin.model, data_builtin, np.concatenate([q, list(wrist.values())]))
    np.testing.assert_allclose(data.oMf[robot.end_effector_frame_id].translation,
                               data_builtin.oMf[builtin.end_effector_frame_id].translation, atol=1e-12)


def test_a_gepetto_export_with_continuous_motors_assembles_with_a_full_turn_each(tmp_path, capsys):
    """The Gepetto-format five-bar with its motor joints continuous (with bounds, which a continuous joint ignores):
    each motor gets the estimated range of a full turn, and the robot assembles and moves as the revolute one."""
    import shutil
    import warnings

    data = Path(__file__).parent / "data" / "gepetto_fivebar"
    folders = {}
    for kind in ("revolute", "continuous"):
        folder = folders[kind] = tmp_path / kind
        shutil.copytree(data, folder)
        urdf = folder / "robot.urdf"
        text = urdf.read_text()
        if kind == "continuous":
            for motor in ("mot1", "mot2"):
                text = text.replace(f'<joint name="{motor}" type="revolute">', f'<joint name="{motor}" type="continuous">')
            mot1_limit = '<child link="part_2"/><axis xyz="0 0 1"/><limit '
            text = text.replace(mot1_limit, mot1_limit + 'lower="-0.1" upper="0.1" ')
        urdf.write_text(text)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            assert main(["assemble", str(folder), "--write"]) == 0
    capsys.readouterr()
    continuous, revolute = load_robot(folders["continuous"]), load_robot(folders["revolute"])
    assert [(a.position_min, a.position_max) for a in continuous.actuators] == [(-np.pi, np.pi)] * 2
    np.testing.assert_allclose(continuous.reference_q, revolute.reference_q, atol=1e-12)
    path = load_path("examples/circle.yaml")
    placement = default_space(revolute).full(np.zeros((1, len(default_space(revolute).free))))[0]
    energy = [Evaluator(r, path).detail(placement).energy.total_J for r in (continuous, revolute)]
    assert energy[0] == pytest.approx(energy[1], rel=1e-9) and energy[1] > 0

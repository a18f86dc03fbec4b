"""URDF ``continuous`` joints: one angle each, with the kinematics and dynamics of Pinocchio's two-coordinate joint."""

from __future__ import annotations

import re
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import pytest

from placement import load_robot
from placement.cli import main
from placement.evaluation.evaluator import Evaluator
from placement.path import load_path
from placement.robot.exceptions import RobotFileError
from placement.robot.urdf import one_angle_urdf, pinocchio_model, read_urdf, urdf_limits_missing
from placement.search.space import default_space
from placement.workshop.estimates import load_erd_robot
from tests.support.paths import DATA
from tests.support.robot_copies import CONTINUOUS, continuous_ur5, continuous_ur5_urdf, edited_copy


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
    assert ElementTree.canonicalize(one_angle_urdf(text), with_comments=True) == ElementTree.canonicalize(
        '<robot name="r"><transmission><joint name="a"/></transmission>'
        '<joint name="a" type="revolute"><parent link="p"/><child link="c"/><limit effort="0" velocity="0"/></joint>'
        "<joint name='b' type='revolute'><limit effort='2' velocity='3'/></joint >"
        '<transmission><joint name="b"><hardwareInterface>x</hardwareInterface></joint></transmission></robot>')


INERTIAL = '<inertial><mass value="1"/><inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial>'
BOUNDED = '<limit lower="-1" upper="1" effort="5" velocity="2"/>'


def robot_text(joints: int, body: str, head: str = "") -> str:
    """A URDF of links ``l0`` to ``l{joints}`` (1 kg each) and ``body`` (its joints, transmissions...), after
    ``head``."""
    links = "".join(f'<link name="l{i}">{INERTIAL}</link>' for i in range(joints + 1))
    return f'{head}<robot name="r">{links}{body}</robot>'


def joint(name: str, kind: str, child: int, limit: str = "") -> str:
    """A joint element about z from link ``l{child - 1}`` to link ``l{child}``."""
    return (f'<joint name="{name}" type="{kind}"><parent link="l{child - 1}"/><child link="l{child}"/>'
            f'<axis xyz="0 0 1"/>{limit}</joint>')


def robot_joints(text: str) -> dict[str, tuple[str, dict[str, str] | None]]:
    """The ``<robot>``'s joints after :func:`one_angle_urdf`, by name: type and ``<limit>`` attributes (None if none)."""
    joints = ElementTree.fromstring(one_angle_urdf(text)).findall("joint")
    return {str(j.get("name")): (str(j.get("type")), None if (limit := j.find("limit")) is None else dict(limit.attrib))
            for j in joints}


def built(tmp_path: Path, text: str | bytes) -> pin.Model:
    """Pinocchio's model of the URDF ``text`` (:func:`pinocchio_model`, from a file)."""
    urdf = tmp_path / "robot.urdf"
    urdf.write_bytes(text.encode() if isinstance(text, str) else text)
    return pinocchio_model(urdf)


def bounds(model: pin.Model, name: str) -> tuple[float, float]:
    """A one-coordinate joint's position limits in ``model`` (rad or m)."""
    index = model.joints[model.getJointId(name)].idx_q
    return float(model.lowerPositionLimit[index]), float(model.upperPositionLimit[index])


def test_a_commented_out_continuous_joint_is_ignored(tmp_path):
    """A continuous joint in a comment, whole or its opening tag alone, is no joint: the revolute joint after it
    keeps its bounds; a ``<limit>`` in a comment is no limit either."""
    text = robot_text(2, '<!-- <joint name="c" type="continuous"> -->' + joint("a", "revolute", 1, BOUNDED)
                      + "<!-- " + joint("d", "continuous", 2) + " -->" + joint("b", "continuous", 2, f"<!-- {BOUNDED} -->"))
    assert robot_joints(text) == {"a": ("revolute", {"lower": "-1", "upper": "1", "effort": "5", "velocity": "2"}),
                                  "b": ("revolute", {"effort": "0", "velocity": "0"})}
    model = built(tmp_path, text)
    assert list(model.names[1:]) == ["a", "b"] and bounds(model, "a") == (-1.0, 1.0)
    assert urdf_limits_missing(model, model.getJointId("b"))


def test_a_joint_end_tag_with_a_space_ends_its_joint(tmp_path):
    """``</joint >`` closes a continuous joint without ``<limit>``: it gets one, and the next joint keeps its bounds."""
    text = robot_text(2, joint("a", "continuous", 1).replace("</joint>", "</joint >") + joint("b", "revolute", 2, BOUNDED))
    assert robot_joints(text) == {"a": ("revolute", {"effort": "0", "velocity": "0"}),
                                  "b": ("revolute", {"lower": "-1", "upper": "1", "effort": "5", "velocity": "2"})}
    model = built(tmp_path, text)
    assert model.nq == 2 and urdf_limits_missing(model, model.getJointId("a")) and bounds(model, "b") == (-1.0, 1.0)


def test_an_empty_joint_in_a_transmission_leaves_the_next_robot_joint_to_its_type(tmp_path):
    """A transmission names robot joints by ``<joint name="x"/>``: that element is left as it is, and the continuous
    joint after it is made revolute; the transmission after the joint keeps its own joint element too."""
    transmission = '<transmission name="t{}"><joint name="{}"/><actuator name="m{}"/></transmission>'
    text = robot_text(2, transmission.format(1, "a", 1) + joint("a", "continuous", 1, BOUNDED)
                      + transmission.format(2, "b", 2) + joint("b", "revolute", 2, BOUNDED))
    assert robot_joints(text) == {"a": ("revolute", {"effort": "5", "velocity": "2"}),
                                  "b": ("revolute", {"lower": "-1", "upper": "1", "effort": "5", "velocity": "2"})}
    kept = ElementTree.fromstring(one_angle_urdf(text)).findall("transmission/joint")
    assert [(j.attrib, len(j)) for j in kept] == [({"name": "a"}, 0), ({"name": "b"}, 0)]
    model = built(tmp_path, text)
    assert model.nq == 2 and urdf_limits_missing(model, model.getJointId("a")) and bounds(model, "b") == (-1.0, 1.0)


@pytest.mark.parametrize("limit, kept", [
    (BOUNDED, {"effort": "5", "velocity": "2"}),
    ("", {"effort": "0", "velocity": "0"}),
], ids=["bounds", "none"])
def test_a_continuous_joint_loses_its_bounds_and_keeps_effort_and_velocity(tmp_path, limit, kept):
    """Its ``<limit>`` without ``lower`` and ``upper`` (position limits read as missing), or a ``<limit>`` giving
    effort and velocity 0 where it had none."""
    assert robot_joints(robot_text(1, joint("a", "continuous", 1, limit))) == {"a": ("revolute", kept)}
    model = built(tmp_path, robot_text(1, joint("a", "continuous", 1, limit)))
    v = model.joints[1].idx_v
    assert model.nq == 1 and urdf_limits_missing(model, 1)
    assert (model.effortLimit[v], model.velocityLimit[v]) == (float(kept["effort"]), float(kept["velocity"]))


def test_single_quoted_attributes_are_read(tmp_path):
    text = robot_text(2, joint("a", "continuous", 1, BOUNDED).replace('"', "'") + joint("b", "continuous", 2))
    assert robot_joints(text) == {"a": ("revolute", {"effort": "5", "velocity": "2"}),
                                  "b": ("revolute", {"effort": "0", "velocity": "0"})}
    model = built(tmp_path, text)
    a = model.getJointId("a")
    assert model.nq == 2 and urdf_limits_missing(model, a) and model.velocityLimit[model.joints[a].idx_v] == 2


@pytest.mark.parametrize("encoding", ["UTF-8", "ISO-8859-1"])
def test_an_xml_declaration_and_processing_instruction_are_read(tmp_path, encoding):
    """A URDF file opening with an XML declaration (its encoding honoured) and an ``<?xml-model?>`` instruction."""
    head = f'<?xml version="1.0" encoding="{encoding}"?>\n<?xml-model href="urdf.xsd" type="application/xml"?>\n'
    text = robot_text(1, joint("coude_é", "continuous", 1, BOUNDED), head)
    assert robot_joints(text) == {"coude_é": ("revolute", {"effort": "5", "velocity": "2"})}
    model = built(tmp_path, text.encode(encoding))
    assert list(model.names[1:]) == ["coude_é"] and model.nq == 1 and urdf_limits_missing(model, 1)


def test_namespaced_elements_and_attributes_are_kept(tmp_path):
    """Elements of other namespaces (xacro's, left in a generated URDF) keep their names, attributes and text."""
    xacro = "http://www.ros.org/wiki/xacro"
    gazebo = '<gazebo reference="l1"><xacro:property name="p" value="1"/><sensor xacro:kind="camera">on</sensor></gazebo>'
    text = robot_text(1, joint("a", "continuous", 1) + gazebo).replace("<robot ", f'<robot xmlns:xacro="{xacro}" ')
    kept = ElementTree.fromstring(one_angle_urdf(text)).find("gazebo")
    assert kept is not None and kept.attrib == {"reference": "l1"}
    assert [(e.tag, e.attrib, e.text) for e in kept] == [
        (f"{{{xacro}}}property", {"name": "p", "value": "1"}, None), ("sensor", {f"{{{xacro}}}kind": "camera"}, "on")]
    assert built(tmp_path, text).nq == 1


def test_a_urdf_that_is_not_xml_is_an_error_naming_the_file(tmp_path):
    urdf = tmp_path / "robot.urdf"
    urdf.write_text(robot_text(1, joint("a", "continuous", 1))[:-20])
    for read in (pinocchio_model, read_urdf):
        with pytest.raises(RobotFileError, match=r"robot\.urdf: not an XML file: .*line 1, column") as error:
            read(urdf)
        assert error.value.path == urdf and error.value.field == ""


def test_a_continuous_joint_without_limit_reads_as_giving_no_effort_or_speed(tmp_path):
    urdf = tmp_path / "ur5.urdf"
    urdf.write_text(continuous_ur5_urdf(keep_limit=False))
    model = pinocchio_model(urdf)
    joint = model.getJointId("shoulder_pan_joint")
    assert model.nq == 6 and urdf_limits_missing(model, joint)
    assert model.effortLimit[model.joints[joint].idx_v] == 0 and model.velocityLimit[model.joints[joint].idx_v] == 0


def test_a_sidecar_on_continuous_joints_needs_their_range_and_then_solves(tmp_path):
    def continuous(document: dict) -> None:
        document["urdf"] = "ur5.urdf"

    sidecar = edited_copy("ur5", tmp_path, continuous)
    (sidecar.parent / "ur5.urdf").write_text(continuous_ur5_urdf())
    with pytest.raises(RobotFileError, match="joint 'shoulder_pan_joint' has no limits in the URDF") as error:
        load_robot(sidecar)
    assert error.value.field == "actuators.0.position_min"

    robot = load_robot(continuous_ur5(tmp_path / "ranged"))  # the same, the continuous actuators given a range
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
    import placement.robot.urdf as urdf_module
    from placement.workshop import estimates

    urdf = tmp_path / "ur5.urdf"
    urdf.write_text(continuous_ur5_urdf())
    monkeypatch.setattr(estimates, "erd_urdf_path", lambda loader: urdf)
    monkeypatch.setattr(urdf_module, "erd_urdf_path", lambda loader: urdf)
    robot = load_erd_robot("ur5", "tool0")
    for name in CONTINUOUS:
        actuator = next(a for a in robot.actuators if a.joint == name)
        reference = robot.reference_q[actuator.q_index]
        assert (actuator.position_min, actuator.position_max) == pytest.approx((reference - np.pi, reference + np.pi))
        index = [a.joint for a in robot.actuators].index(name)
        assert "continuous" in robot.sources[f"actuators.{index}.position_min"]
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

    data = DATA / "gepetto_fivebar"
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


def test_a_continuous_redundant_joint_is_profiled_over_its_actuators_turn_not_the_urdfs_empty_range(tmp_path):
    """A seven-axis arm whose redundant third joint is continuous (Kinova's Gen3): the URDF gives it no range, so its
    knots take the actuator's full turn about the reference posture, which holds the reference (they were held at
    0 by the model's empty range, away from the posture the estimates chose)."""
    from example_robot_data.robots_loader import ROBOTS

    from placement.placing.profiles import redundant_bounds
    from placement.robot.urdf import erd_urdf_path
    from placement.workshop.estimates import load_description_robot

    text = Path(erd_urdf_path(ROBOTS["panda"])).read_text()
    element = re.search(r'<joint name="panda_joint3" type="revolute">.*?</joint>', text, re.DOTALL)
    assert element is not None
    changed = re.sub(r'\s(lower|upper)="[^"]*"', "", element.group(0).replace('type="revolute"', 'type="continuous"'))
    urdf = tmp_path / "panda.urdf"
    urdf.write_text(text.replace(element.group(0), changed))
    robot = load_description_robot(urdf, "panda_hand")
    actuator = next(a for a in robot.actuators if a.joint == "panda_joint3")
    reference = robot.reference_q[actuator.q_index]
    bounds = redundant_bounds(robot)
    assert set(bounds) == {f"panda_joint3@{i}" for i in range(3)}
    for low, high in bounds.values():
        assert (low, high) == pytest.approx((reference - np.pi, reference + np.pi))

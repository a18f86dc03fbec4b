"""MuJoCo's MJCF descriptions: read through Pinocchio as the same arm as its URDF twin and as MuJoCo compiles it (its
dynamics, its actuators' effort bounds), placed by the direct route (--robot FILE.xml --tool SITE) with the same
energy as the URDF twin carrying the same drives, and refused when a moving body has no inertia."""

import json

import mujoco
import numpy as np
import pinocchio as pin
import pytest
import yaml

from placement.cli import main
from placement.robot.build import reduced_model
from placement.robot.exceptions import RobotFileError
from placement.robot.mjcf import mjcf_model, qpos0, read_mjcf
from placement.robot.urdf import pinocchio_model
from placement.workshop.estimates import description_sidecar, load_description_robot
from placement.workshop.loops import JOINT_SPEED_RAD_S
from tests.support.paths import CIRCLE

# A three-joint arm: angles in degrees (MJCF's default), default classes under a body's childclass, three kinds of
# actuator (a position servo with a forcerange, a motor bounded by its ctrlrange, a joint's actuatorfrcrange below
# its actuator's), armature, damping and friction loss.
ARM = """<mujoco model="arm3">
  <compiler angle="degree"/>
  <default>
    <motor ctrlrange="-1 1"/>
    <default class="arm">
      <joint axis="0 1 0" range="-170 170" armature="0.02" damping="0.3" frictionloss="0.1"/>
      <general forcerange="-80 80" gear="2" biastype="affine" gainprm="100" biasprm="0 -100 -10"/>
      <default class="wrist">
        <joint actuatorfrcrange="-30 30"/>
        <general forcerange="-20 20"/>
      </default>
    </default>
  </default>
  <worldbody>
    <body name="base" childclass="arm">
      <body name="link1" pos="0 0 0.1">
        <joint name="joint1" axis="0 0 1"/>
        <inertial pos="0 0 0.05" mass="2" diaginertia="0.02 0.02 0.004"/>
        <body name="link2" pos="0 0 0.1" euler="0 0 90">
          <joint name="joint2"/>
          <inertial pos="0.01 0 0.15" mass="3" fullinertia="0.05 0.05 0.006 0.001 0 0"/>
          <body name="link3" pos="0 0 0.3">
            <joint name="joint3" class="wrist"/>
            <inertial pos="0 0 0.12" mass="1.5" diaginertia="0.01 0.01 0.002"/>
            <site name="tip" pos="0 0 0.25"/>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <general name="a1" joint="joint1" class="arm"/>
    <motor name="a2" joint="joint2" gear="50" ctrlrange="-2 2"/>
    <general name="a3" joint="joint3" class="wrist"/>
  </actuator>
</mujoco>
"""
EFFORTS = {"joint1": 160.0, "joint2": 100.0, "joint3": 30.0}  # 80 x gear 2; ctrlrange 2 x gear 50; actuatorfrcrange 30

# The same arm as a URDF (radians, the inertia tensor's off-diagonal terms as URDF writes them).
TWIN = """<robot name="arm3">
  <link name="base"/>
  <link name="link1"><inertial><origin xyz="0 0 0.05"/><mass value="2"/>
    <inertia ixx="0.02" iyy="0.02" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="link2"><inertial><origin xyz="0.01 0 0.15"/><mass value="3"/>
    <inertia ixx="0.05" iyy="0.05" izz="0.006" ixy="0.001" ixz="0" iyz="0"/></inertial></link>
  <link name="link3"><inertial><origin xyz="0 0 0.12"/><mass value="1.5"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"/>
  <joint name="joint1" type="revolute"><parent link="base"/><child link="link1"/><origin xyz="0 0 0.1"/>
    <axis xyz="0 0 1"/><limit lower="-2.9670597283903604" upper="2.9670597283903604" effort="160" velocity="3"/></joint>
  <joint name="joint2" type="revolute"><parent link="link1"/><child link="link2"/>
    <origin xyz="0 0 0.1" rpy="0 0 1.5707963267948966"/>
    <axis xyz="0 1 0"/><limit lower="-2.9670597283903604" upper="2.9670597283903604" effort="100" velocity="3"/></joint>
  <joint name="joint3" type="revolute"><parent link="link2"/><child link="link3"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 1 0"/><limit lower="-2.9670597283903604" upper="2.9670597283903604" effort="30" velocity="3"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="link3"/><child link="tip"/><origin xyz="0 0 0.25"/></joint>
</robot>
"""


@pytest.fixture
def arm(tmp_path):
    path = tmp_path / "arm3.xml"
    path.write_text(ARM)
    return path


@pytest.fixture
def twin(tmp_path):
    path = tmp_path / "arm3.urdf"
    path.write_text(TWIN)
    return path


def _samples(model, count=5, seed=0):
    rng = np.random.default_rng(seed)
    for _ in range(count):
        yield rng.uniform(-2, 2, model.nq), rng.uniform(-1, 1, model.nv), rng.uniform(-3, 3, model.nv)


def test_pinocchio_reads_the_mjcf_as_the_same_arm_as_its_urdf_twin(arm, twin):
    by_mjcf, by_urdf = mjcf_model(arm), pinocchio_model(twin)
    assert [by_mjcf.names[j] for j in range(1, by_mjcf.njoints)] == ["joint1", "joint2", "joint3"]
    assert np.allclose(by_mjcf.upperPositionLimit, np.radians(170)) and np.allclose(by_mjcf.lowerPositionLimit, -np.radians(170))
    tip_mjcf, tip_urdf = by_mjcf.getFrameId("tip"), by_urdf.getFrameId("tip")
    data_mjcf, data_urdf = by_mjcf.createData(), by_urdf.createData()
    for q, v, a in _samples(by_mjcf):
        assert np.allclose(pin.rnea(by_mjcf, data_mjcf, q, v, a), pin.rnea(by_urdf, data_urdf, q, v, a), atol=1e-12)
        pin.framesForwardKinematics(by_mjcf, data_mjcf, q)
        pin.framesForwardKinematics(by_urdf, data_urdf, q)
        assert np.allclose(data_mjcf.oMf[tip_mjcf].homogeneous, data_urdf.oMf[tip_urdf].homogeneous, atol=1e-12)


def test_mujoco_agrees_on_the_mass_matrix_the_bias_forces_and_where_the_tool_is(arm):
    model, simulated = mjcf_model(arm), mujoco.MjModel.from_xml_path(str(arm))
    data, state = model.createData(), mujoco.MjData(simulated)
    tip = model.getFrameId("tip")
    for q, v, _ in _samples(model):
        state.qpos[:], state.qvel[:] = q, v
        mujoco.mj_forward(simulated, state)
        inertia = _mass_matrix(simulated, state)
        # MuJoCo's mass matrix holds the armature, which placement leaves to the drives
        assert np.allclose(inertia - np.diag(simulated.dof_armature), pin.crba(model, data, q), atol=1e-10)
        assert np.allclose(state.qfrc_bias, pin.nonLinearEffects(model, data, q, v), atol=1e-10)
        pin.framesForwardKinematics(model, data, q)
        assert np.allclose(state.site_xpos[0], data.oMf[tip].translation, atol=1e-12)


def _mass_matrix(simulated, state):
    """MuJoCo's joint-space inertia matrix (newer MuJoCo's mj_fullM takes the data, older ones the sparse matrix)."""
    inertia = np.zeros((simulated.nv, simulated.nv))
    if hasattr(state, "qM"):
        mujoco.mj_fullM(simulated, inertia, state.qM)
    else:
        mujoco.mj_fullM(simulated, state, inertia)
    return inertia


def _mujoco_effort_bounds(simulated):
    """Each joint's effort bound as MuJoCo compiles the actuators (its defaults resolved by MuJoCo itself)."""
    bounds = {}
    for j in range(simulated.njnt):
        total = 0.0
        for k in np.flatnonzero(simulated.actuator_trnid[:, 0] == j):
            if simulated.actuator_forcelimited[k]:
                force = np.abs(simulated.actuator_forcerange[k]).max()
            else:  # a motor: gain times control, no bias
                assert simulated.actuator_biastype[k] == mujoco.mjtBias.mjBIAS_NONE and simulated.actuator_ctrllimited[k]
                force = abs(simulated.actuator_gainprm[k, 0]) * np.abs(simulated.actuator_ctrlrange[k]).max()
            total += abs(simulated.actuator_gear[k, 0]) * force
        if simulated.jnt_actfrclimited[j]:
            total = min(total, np.abs(simulated.jnt_actfrcrange[j]).max())
        bounds[mujoco.mj_id2name(simulated, mujoco.mjtObj.mjOBJ_JOINT, j)] = total
    return bounds


def test_the_effort_bounds_are_those_mujoco_compiles_from_the_actuators(arm):
    model, contents = mjcf_model(arm), read_mjcf(arm)
    simulated = mujoco.MjModel.from_xml_path(str(arm))
    compiled = _mujoco_effort_bounds(simulated)
    assert compiled == pytest.approx(EFFORTS)
    assert {model.names[j]: model.effortLimit[model.joints[j].idx_v] for j in range(1, model.njoints)} == pytest.approx(compiled)
    assert [contents.joints[name].armature for name in EFFORTS] == pytest.approx(simulated.dof_armature)
    assert [contents.joints[name].damping for name in EFFORTS] == pytest.approx(simulated.dof_damping)
    assert [contents.joints[name].frictionloss for name in EFFORTS] == pytest.approx(simulated.dof_frictionloss)
    assert (model.velocityLimit == 0).all() and (model.armature == 0).all()  # none given; the drives carry the armature


def test_an_mjcf_arm_gets_drives_that_reach_its_bounds_and_carry_its_armature_and_friction(arm):
    sidecar = description_sidecar(arm, "tip")
    assert sidecar.end_effector.task == "position" and sidecar.urdf == str(arm.resolve())
    for actuator in sidecar.actuators:
        drive = sidecar.drives[actuator.drive]
        ratio = drive.transmission.speed_ratio
        assert drive.motor.max_torque_Nm * ratio == pytest.approx(EFFORTS[actuator.joint])
        assert drive.reflected_inertia == pytest.approx(0.02)  # the MJCF's armature, at the joint
        assert (drive.friction.coulomb, drive.friction.viscous) == pytest.approx((0.1, 0.3))
        assert actuator.velocity_max == JOINT_SPEED_RAD_S
    i = next(i for i, a in enumerate(sidecar.actuators) if a.joint == "joint3")
    assert sidecar.sources[f"actuators.{i}.velocity_max"].startswith("EST: the MJCF gives no speed limits")
    assert "actuatorfrcrange 30" in sidecar.sources["drives.joint3.motor"]
    assert sidecar.sources["drives.joint1.friction"].startswith("DERIVED: the MJCF's joint frictionloss 0.1")


def test_the_direct_route_places_a_path_with_the_energy_of_the_urdf_twin_carrying_the_same_drives(arm, twin, tmp_path,
                                                                                                 capsys):
    written, direct, by_twin = tmp_path / "arm3.yaml", tmp_path / "direct.json", tmp_path / "twin.json"
    reference = description_sidecar(arm, "tip").workspace.points_m["reference"]
    at = ["--path", str(CIRCLE), "--at", ",".join(f"{axis}={value * 1e3:.3f}" for axis, value in zip("xyz", reference))]
    assert main(["--robot", str(arm), "--tool", "tip", *at, "--json", str(direct), "--write-sidecar", str(written)]) == 0
    assert "MJCF's actuator force ranges" in capsys.readouterr().err
    document = yaml.safe_load(written.read_text())
    assert document["urdf"] == "arm3.xml"  # the sidecar's urdf field names any description, relative to it
    document["urdf"] = "arm3.urdf"
    twin_sidecar = tmp_path / "twin.yaml"
    twin_sidecar.write_text(yaml.safe_dump(document))
    assert main(["--robot", str(twin_sidecar), *at, "--json", str(by_twin)]) == 0
    first, second = (json.loads(file.read_text())["at"] for file in (direct, by_twin))
    assert np.isfinite(first["energy_J"]) and first["energy_J"] > 0
    assert second["energy_J"] == pytest.approx(first["energy_J"], rel=1e-9)


def test_a_moving_body_without_inertia_is_refused_naming_it_and_where_its_inertial_goes(tmp_path):
    light = tmp_path / "light.xml"
    light.write_text(ARM.replace('<inertial pos="0 0 0.12" mass="1.5" diaginertia="0.01 0.01 0.002"/>',
                                 '<inertial pos="0 0 0.12" mass="1e-9" diaginertia="1e-12 1e-12 1e-12"/>'))
    with pytest.raises(RobotFileError, match=r"link3.*<inertial> for each body in light.xml"):
        load_description_robot(light, "tip")


def test_a_sidecar_giving_inertials_to_an_mjcf_is_refused(arm, tmp_path):
    document = description_sidecar(arm, "tip").model_dump(mode="json", exclude_defaults=True)
    document["links"] = {"link3": {"mass_kg": 1.0, "com_m": [0, 0, 0], "inertia_kg_m2": [0.01, 0.01, 0.01, 0, 0, 0]}}
    document["sources"]["links.link3"] = "EST: a test"
    sidecar = tmp_path / "given.yaml"
    sidecar.write_text(yaml.safe_dump(document))
    assert main(["--robot", str(sidecar), "--path", str(CIRCLE), "--at", "x=0"]) == 2


def test_a_scene_including_the_arm_loads_the_same_arm(arm, tmp_path):
    scene = tmp_path / "scene.xml"
    scene.write_text('<mujoco><include file="arm3.xml"/><worldbody><geom name="floor" type="plane" size="1 1 0.1"/>'
                     "</worldbody></mujoco>")
    alone, included = mjcf_model(arm), mjcf_model(scene)
    assert included.nq == alone.nq and np.array_equal(included.effortLimit, alone.effortLimit)
    q = np.array([0.3, -0.5, 0.8])
    assert np.allclose(pin.rnea(included, included.createData(), q, q, q), pin.rnea(alone, alone.createData(), q, q, q))


def test_a_file_that_is_not_an_mjcf_says_so(tmp_path):
    other = tmp_path / "other.xml"
    other.write_text("<robot name='x'/>")
    with pytest.raises(RobotFileError, match="not an MJCF file: the root element is <robot>, expected <mujoco>"):
        mjcf_model(other)


def test_an_mjcf_joint_can_be_held_as_a_seven_joint_arm_holds_its_third(arm):
    """Pinocchio 4 keeps a lower speed bound too, +inf from its MJCF parser: held joints need it consistent."""
    model = mjcf_model(arm)
    held = reduced_model(model, [model.getJointId("joint1")], pin.neutral(model))
    assert held.nq == 2 and np.allclose(held.effortLimit, [100.0, 30.0])


def test_a_joint_reference_shifts_neither_its_range_nor_where_the_tool_is_against_mujoco(tmp_path):
    """A joint's ref (MuJoCo's qpos0) places the bodies; its range stays in qpos units, as MuJoCo reads it."""
    shifted = tmp_path / "ref.xml"
    shifted.write_text(ARM.replace('<joint name="joint2"/>', '<joint name="joint2" ref="30" range="-20 100"/>'))
    model, simulated = mjcf_model(shifted), mujoco.MjModel.from_xml_path(str(shifted))
    assert np.allclose(model.lowerPositionLimit, simulated.jnt_range[:, 0])
    assert np.allclose(model.upperPositionLimit, simulated.jnt_range[:, 1])
    assert np.allclose(qpos0(model, read_mjcf(shifted).joints), simulated.qpos0)
    state, data = mujoco.MjData(simulated), model.createData()
    for q in (simulated.qpos0, np.array([0.2, -0.1, 0.4])):
        state.qpos[:] = q
        mujoco.mj_forward(simulated, state)
        pin.framesForwardKinematics(model, data, q)
        assert np.allclose(state.site_xpos[0], data.oMf[model.getFrameId("tip")].translation, atol=1e-12)


def test_an_mjcf_with_two_default_sections_reads_both_as_mujoco_does(arm, tmp_path):
    """onshape-to-robot appends its joints_properties.xml as a second <default> section (the SO-101's): MuJoCo reads
    both; Pinocchio 4.1 alone read the first and failed on the classes of the second."""
    split = ARM.replace('<motor ctrlrange="-1 1"/>\n', '<motor ctrlrange="-1 1"/>\n  </default>\n  <default>\n', 1)
    assert split.count("<default>") == 2
    path = tmp_path / "split.xml"
    path.write_text(split)
    model, contents, whole = mjcf_model(path), read_mjcf(path), mjcf_model(arm)
    simulated = mujoco.MjModel.from_xml_path(str(path))
    assert _mujoco_effort_bounds(simulated) == pytest.approx(EFFORTS)
    assert {model.names[j]: model.effortLimit[model.joints[j].idx_v] for j in range(1, model.njoints)} == pytest.approx(EFFORTS)
    assert [contents.joints[name].armature for name in EFFORTS] == pytest.approx(simulated.dof_armature)
    assert np.allclose(model.upperPositionLimit, simulated.jnt_range[:, 1])
    data, data_whole = model.createData(), whole.createData()
    for q, v, a in _samples(model):
        assert np.allclose(pin.rnea(model, data, q, v, a), pin.rnea(whole, data_whole, q, v, a), atol=1e-12)


# A five-joint arm whose jaw joint bears its hand body's name, as the SO-101's 'gripper' does.
FIVE = """<mujoco model="arm5">
  <compiler angle="radian"/>
  <worldbody>
    <body name="base">
      <body name="l1" pos="0 0 0.1"><joint name="j1" axis="0 0 1" range="-3 3"/>
        <inertial pos="0 0 0.05" mass="1" diaginertia="0.01 0.01 0.002"/>
        <body name="l2" pos="0 0 0.1"><joint name="j2" axis="0 1 0" range="-2 2"/>
          <inertial pos="0 0 0.1" mass="1" diaginertia="0.01 0.01 0.002"/>
          <body name="l3" pos="0 0 0.2"><joint name="j3" axis="0 1 0" range="-2.5 2.5"/>
            <inertial pos="0 0 0.1" mass="0.8" diaginertia="0.008 0.008 0.001"/>
            <body name="l4" pos="0 0 0.2"><joint name="j4" axis="0 1 0" range="-2 2"/>
              <inertial pos="0 0 0.03" mass="0.4" diaginertia="0.001 0.001 0.0005"/>
              <body name="hand" pos="0 0 0.05"><joint name="roll" axis="0 0 1" range="-3 3"/>
                <inertial pos="0 0 0.03" mass="0.3" diaginertia="0.001 0.001 0.0005"/>
                <site name="tip" pos="0 0 0.08"/>
                <body name="jaw" pos="0.02 0 0.03"><joint name="hand" axis="1 0 0" range="-0.2 1"/>
                  <inertial pos="0 0 0.02" mass="0.05" diaginertia="1e-5 1e-5 2e-6"/>
                </body>
              </body>
            </body>
          </body>
        </body>
      </body>
    </body>
  </worldbody>
  <actuator>
    <motor joint="j1" ctrlrange="-20 20"/><motor joint="j2" ctrlrange="-20 20"/><motor joint="j3" ctrlrange="-10 10"/>
    <motor joint="j4" ctrlrange="-5 5"/><motor joint="roll" ctrlrange="-2 2"/><motor joint="hand" ctrlrange="-1 1"/>
  </actuator>
</mujoco>
"""


def test_a_five_joint_arm_follows_the_tools_position_its_wrist_profiled_and_a_joint_named_as_a_body_held(tmp_path):
    path = tmp_path / "arm5.xml"
    path.write_text(FIVE)
    robot = load_description_robot(path, "tip")
    sidecar = robot.sidecar
    assert sidecar.end_effector.task == "position" and sidecar.redundancy is not None
    assert sidecar.redundancy.joints == ["j4", "roll"] and set(sidecar.locked_joints) == {"hand"}
    assert "4- or 5-axis" in sidecar.sources["redundancy"]
    assert robot.model.existFrame("hand", pin.FrameType.BODY)  # the names Pinocchio needed apart are given back
    full = mjcf_model(path)
    data, data_full = robot.model.createData(), full.createData()
    tip, tip_full = robot.model.getFrameId("tip"), full.getFrameId("tip")
    rng = np.random.default_rng(1)
    for _ in range(3):  # the held model moves the tool and carries the jaw as the whole one does, the jaw held
        q = rng.uniform(-1, 1, robot.model.nq)
        q_full = np.append(q, sidecar.locked_joints["hand"])
        pin.framesForwardKinematics(robot.model, data, q)
        pin.framesForwardKinematics(full, data_full, q_full)
        assert np.allclose(data.oMf[tip].homogeneous, data_full.oMf[tip_full].homogeneous, atol=1e-12)
        gravity = pin.computeGeneralizedGravity(robot.model, data, q)
        assert np.allclose(gravity, pin.computeGeneralizedGravity(full, data_full, q_full)[:5], atol=1e-12)

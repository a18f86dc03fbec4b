"""Closed loops as description files carry them: an MJCF's <equality><connect> and onshape-to-robot's closing_NAME_1/_2
frame pairs become closures without a robot.yaml. Both are the planar five-bar of tests/data/gepetto_fivebar (proximal
rods 0.20 m from (-0.1, 0, 0) and (0.1, 0, 0), distal rods 0.25 m meeting at (0, 0.30, 0) with the actuators at 0):
the MJCF five-bar closes where MuJoCo says its constraint holds, and both give the energy of the Gepetto export (an
independent route to the same physics) at the same placement."""

import json
import shutil
import warnings

import mujoco
import numpy as np
import pytest
import yaml

from placement.__main__ import main
from placement.robot.closures import closure_residuals
from placement.robot.exceptions import RobotFileError
from placement.robot.formats import DescriptionOptions
from placement.workshop.assemble import assemble
from placement.workshop.estimates import description_sidecar, load_description_robot
from placement.workshop.gepetto import EstimatesWarning
from tests.support.paths import CIRCLE, DATA

PROXIMAL_M, DISTAL_M = 0.20, 0.25
BASES = (np.array([-0.1, 0.0]), np.array([0.1, 0.0]))
TIP = np.array([0.0, 0.30])
ROD = ('<inertial pos="{c} 0 0" mass="{m}" diaginertia="{ixx} {iyy} {iyy}"/>')


def _closed_angles(base, elbow):
    """The proximal rod's angle and the distal rod's angle relative to it that put the tip at TIP (rad)."""
    reach = TIP - base
    spread = np.arccos((PROXIMAL_M**2 + reach @ reach - DISTAL_M**2) / (2 * PROXIMAL_M * np.linalg.norm(reach)))
    proximal = float(np.arctan2(reach[1], reach[0]) + elbow * spread)
    elbow_point = base + PROXIMAL_M * np.array([np.cos(proximal), np.sin(proximal)])
    distal = float(np.arctan2(*(TIP - elbow_point)[::-1]))
    return proximal, distal - proximal


def fivebar_mjcf():
    """The five-bar as an MJCF, its loop closed by a connect equality, its actuators motors of 10 N m."""
    (t1, f1), (t2, f2) = _closed_angles(BASES[0], 1), _closed_angles(BASES[1], -1)
    proximal = ROD.format(c=0.1, m=0.5, ixx=2.5e-05, iyy=0.00167917)
    distal = ROD.format(c=0.125, m=0.4, ixx=2e-05, iyy=0.00209333)
    return f"""<mujoco model="fivebar">
  <compiler angle="radian"/>
  <worldbody>
    <body name="part_2" pos="-0.1 0 0" euler="0 0 {t1!r}">
      <joint name="mot1" axis="0 0 1"/>{proximal}
      <body name="part_3" pos="0.2 0 0" euler="0 0 {f1!r}">
        <joint name="free1" axis="0 0 1"/>{distal}
        <site name="effector" pos="0.25 0 0"/>
      </body>
    </body>
    <body name="part_2_2" pos="0.1 0 0" euler="0 0 {t2!r}">
      <joint name="mot2" axis="0 0 1"/>{proximal}
      <body name="part_5" pos="0.2 0 0" euler="0 0 {f2!r}">
        <joint name="free2" axis="0 0 1"/>{distal}
      </body>
    </body>
  </worldbody>
  <equality><connect name="tip" body1="part_3" body2="part_5" anchor="0.25 0 0"/></equality>
  <actuator><motor joint="mot1" ctrlrange="-10 10"/><motor joint="mot2" ctrlrange="-10 10"/></actuator>
</mujoco>
"""


def weld_fivebar_mjcf():
    """The five-bar cut at the second elbow instead of the tip: the second distal rod hangs from the first at the tip
    (joint tip_pin), a stub of 1e-9 kg turns on its far end (joint free2) and is welded to the second proximal rod's
    end (a weld without a name: weld0)."""
    (t1, f1), (t2, _) = _closed_angles(BASES[0], 1), _closed_angles(BASES[1], -1)
    elbow = BASES[1] + PROXIMAL_M * np.array([np.cos(t2), np.sin(t2)])
    back = float(np.arctan2(*(elbow - TIP)[::-1]) - t1 - f1)
    proximal = ROD.format(c=0.1, m=0.5, ixx=2.5e-05, iyy=0.00167917)
    distal = ROD.format(c=0.125, m=0.4, ixx=2e-05, iyy=0.00209333)
    stub = ROD.format(c=0, m=1e-9, ixx=1e-12, iyy=1e-12)
    return f"""<mujoco model="weld_fivebar">
  <compiler angle="radian"/>
  <worldbody>
    <body name="part_2" pos="-0.1 0 0" euler="0 0 {t1!r}">
      <joint name="mot1" axis="0 0 1"/>{proximal}
      <body name="part_3" pos="0.2 0 0" euler="0 0 {f1!r}">
        <joint name="free1" axis="0 0 1"/>{distal}
        <site name="effector" pos="0.25 0 0"/>
        <body name="far_rod" pos="0.25 0 0" euler="0 0 {back!r}">
          <joint name="tip_pin" axis="0 0 1"/>{distal}
          <body name="stub" pos="0.25 0 0">
            <joint name="free2" axis="0 0 1"/>{stub}
          </body>
        </body>
      </body>
    </body>
    <body name="part_2_2" pos="0.1 0 0" euler="0 0 {t2!r}">
      <joint name="mot2" axis="0 0 1"/>{proximal}
    </body>
  </worldbody>
  <equality><weld body1="stub" body2="part_2_2" anchor="0.2 0 0"/></equality>
  <actuator><motor joint="mot1" ctrlrange="-10 10"/><motor joint="mot2" ctrlrange="-10 10"/></actuator>
</mujoco>
"""


@pytest.fixture
def mjcf(tmp_path):
    path = tmp_path / "fivebar.xml"
    path.write_text(fivebar_mjcf())
    return path


@pytest.fixture
def gepetto(tmp_path, capsys):
    """The Gepetto export, assembled (its sidecar written beside it)."""
    folder = tmp_path / "gepetto_fivebar"
    shutil.copytree(DATA / "gepetto_fivebar", folder)
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    capsys.readouterr()
    return folder / "placement.yaml"


def test_the_mjcf_loop_closes_where_mujoco_says_its_connect_constraint_holds(mjcf):
    robot = load_description_robot(mjcf, "effector")
    assert [c.kind for c in robot.closures] == ["point"] and [a.joint for a in robot.actuators] == ["mot1", "mot2"]
    simulated = mujoco.MjModel.from_xml_path(str(mjcf))
    state = mujoco.MjData(simulated)
    names = [robot.model.names[j] for j in range(1, robot.model.njoints)]
    order = [mujoco.mj_name2id(simulated, mujoco.mjtObj.mjOBJ_JOINT, name) for name in names]
    for motors in ({"mot1": 0.0, "mot2": 0.0}, {"mot1": 0.3, "mot2": -0.2}, {"mot1": -0.25, "mot2": 0.15}):
        q = assemble(robot, near=motors).q
        assert np.abs(closure_residuals(robot, robot.model.createData(), q)).max() < 1e-10
        assert [q[robot.model.joints[robot.model.getJointId(n)].idx_q] for n in motors] == list(motors.values())
        state.qpos[[simulated.jnt_qposadr[j] for j in order]] = q
        mujoco.mj_forward(simulated, state)
        assert state.nefc >= 3 and np.abs(state.efc_pos[:3]).max() < 1e-10  # MuJoCo's own violation of 'tip'
        data = robot.model.createData()
        closure_residuals(robot, data, q)  # places the frames
        assert np.allclose(state.site_xpos[0], data.oMf[robot.end_effector_frame_id].translation, atol=1e-12)
    unclosed = q.copy()
    unclosed[robot.model.joints[robot.model.getJointId("free1")].idx_q] += 0.1
    state.qpos[[simulated.jnt_qposadr[j] for j in order]] = unclosed
    mujoco.mj_forward(simulated, state)
    gap = np.abs(closure_residuals(robot, robot.model.createData(), unclosed))
    assert np.allclose(np.sort(np.abs(state.efc_pos[:3])), np.sort(gap), atol=1e-12)  # the same gap, measured twice


def _energy_at(sidecar, at, out):
    assert main(["--robot", str(sidecar), "--path", str(CIRCLE), "--at", at, "--json", str(out)]) == 0
    return json.loads(out.read_text())["at"]["energy_J"]


def _at(sidecar):
    """A placement at the middle of the sidecar's workspace (mm, deg)."""
    workspace = yaml.safe_load(sidecar.read_text())["workspace"]
    x, y, _ = (np.array(workspace["min_m"]) + workspace["max_m"]) / 2
    return f"x={x * 1e3:.3f},y={y * 1e3:.3f},phi=30"


def test_the_mjcf_fivebar_with_the_gepetto_drives_takes_the_gepetto_fivebar_energy(mjcf, gepetto, tmp_path):
    document = yaml.safe_load(gepetto.read_text())
    document.update(urdf=str(mjcf), reference_configuration={})  # closed at its zero posture
    document["closures"] = [{"name": "tip", "type": "point", "frames": ["tip_1", "tip_2"]}]
    document["actuators"] = [{**actuator, "velocity_max": 10.0} for actuator in document["actuators"]]  # the URDF's
    by_mjcf = tmp_path / "mjcf.yaml"
    by_mjcf.write_text(yaml.safe_dump(document))
    at = _at(gepetto)
    expected = _energy_at(gepetto, at, tmp_path / "gepetto.json")
    assert expected > 0
    # the Gepetto export's frame links weigh 1e-9 kg each
    assert _energy_at(by_mjcf, at, tmp_path / "mjcf.json") == pytest.approx(expected, rel=1e-6)


def test_a_weld_cut_closes_where_mujoco_says_and_takes_the_gepetto_fivebar_energy(gepetto, tmp_path):
    weld = tmp_path / "weld.xml"
    weld.write_text(weld_fivebar_mjcf())
    robot = load_description_robot(weld, "effector")
    assert [(c.name, c.kind) for c in robot.closures] == [("weld0", "weld")]
    simulated = mujoco.MjModel.from_xml_path(str(weld))
    state = mujoco.MjData(simulated)
    order = [simulated.jnt_qposadr[mujoco.mj_name2id(simulated, mujoco.mjtObj.mjOBJ_JOINT, robot.model.names[j])]
             for j in range(1, robot.model.njoints)]
    state.qpos[order] = assemble(robot, near={"mot1": 0.3, "mot2": -0.2}).q
    mujoco.mj_forward(simulated, state)
    assert state.nefc >= 6 and np.abs(state.efc_pos[:6]).max() < 1e-10  # MuJoCo's own violation of the weld
    document = yaml.safe_load(gepetto.read_text())
    document.update(urdf=str(weld), reference_configuration={})
    document["closures"] = [{"name": "weld0", "type": "weld", "frames": ["weld0_1", "weld0_2"]}]
    document["actuators"] = [{**actuator, "velocity_max": 10.0} for actuator in document["actuators"]]
    by_weld = tmp_path / "weld.yaml"
    by_weld.write_text(yaml.safe_dump(document))
    expected = _energy_at(gepetto, _at(gepetto), tmp_path / "gepetto.json")
    assert _energy_at(by_weld, _at(gepetto), tmp_path / "weld.json") == pytest.approx(expected, rel=1e-6)


def test_the_direct_route_estimates_a_closed_loop_sidecar_and_places_a_circle(mjcf, tmp_path, capsys):
    written = tmp_path / "fivebar.yaml"
    assert main(["--robot", str(mjcf), "--tool", "effector", "--path", str(CIRCLE), "--generations", "2",
                 "--population", "6", "--write-sidecar", str(written)]) == 0
    captured = capsys.readouterr()
    assert "best placement (least energy)" in captured.out and "3000 rpm motors" in captured.err
    document = yaml.safe_load(written.read_text())
    assert document["closures"] == [{"name": "tip", "type": "point", "frames": ["tip_1", "tip_2"]}]
    assert document["placement"] == {"free": ["x", "y", "phi"]}
    assert document["sources"]["workspace"].startswith("EST: the largest box")
    assert document["sources"]["actuators"] == "DERIVED: the joints the MJCF's actuators drive"


ONSHAPE_NAMES = {"closedloop3D_1A": "closing_tip_1", "closedloop3D_1B": "closing_tip_2", "free1": "passive1",
                 "free2": "passive2"}


@pytest.fixture
def onshape(tmp_path):
    """The Gepetto export's URDF with onshape-to-robot's names: closing_tip_1/_2 on the two distal rods, the loop
    open at q = 0 (the elbows off by 0.08 and -0.05 rad), no robot.yaml."""
    text = (DATA / "gepetto_fivebar" / "robot.urdf").read_text()
    for old, new in ONSHAPE_NAMES.items():
        text = text.replace(f'"{old}', f'"{new}')
    path = tmp_path / "onshape" / "robot.urdf"
    path.parent.mkdir()
    path.write_text(text)
    return path


def test_onshape_closing_frames_become_a_loop_closed_by_the_solver_with_the_gepetto_energy(onshape, gepetto, tmp_path):
    sidecar = description_sidecar(onshape, "effector")
    assert [(c.name, c.type, c.frames) for c in sidecar.closures] == [("tip", "point", ("closing_tip_1", "closing_tip_2"))]
    assert [a.joint for a in sidecar.actuators] == ["mot1", "mot2"]
    assert sidecar.sources["actuators"].startswith("EST: the joints on the base link")
    assert sidecar.sources["reference_configuration"].startswith("DERIVED: the loops closed by placement's solver")
    written = tmp_path / "onshape.yaml"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert main(["--robot", str(onshape), "--tool", "effector", "--path", str(CIRCLE), "--at", _at(gepetto),
                     "--json", str(tmp_path / "direct.json"), "--write-sidecar", str(written)]) == 0
    expected = _energy_at(gepetto, _at(gepetto), tmp_path / "gepetto.json")
    assert json.loads((tmp_path / "direct.json").read_text())["at"]["energy_J"] == pytest.approx(expected, rel=1e-9)
    assert _energy_at(written, _at(gepetto), tmp_path / "reloaded.json") == pytest.approx(expected, rel=1e-9)


def test_a_closing_frame_without_its_pair_is_refused_naming_it(onshape):
    onshape.write_text(onshape.read_text().replace('"closing_tip_2"', '"closing_other_2"'))
    with pytest.raises(RobotFileError, match="'closing_tip_1' has no 'closing_tip_2' to coincide with"):
        description_sidecar(onshape, "effector")


def test_the_urdf_of_a_gepetto_folder_given_alone_says_to_assemble_the_folder(tmp_path, capsys):
    folder = tmp_path / "gepetto_fivebar"
    shutil.copytree(DATA / "gepetto_fivebar", folder)
    assert main(["--robot", str(folder / "robot.urdf"), "--tool", "effector", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert f"'python -m placement assemble {folder} --write' closes them" in err and len(err.strip().splitlines()) == 1


def test_an_end_effector_the_solver_cannot_move_is_refused_naming_it_and_what_to_choose(onshape, monkeypatch, capsys):
    """Orbita (placo-examples), a spherical mechanism whose effector its three actuators only turn: the solver reaches
    no position but the reference one, which made a box of no size (was: 'cannot estimate workspace: Value error,
    min_m ... must be below max_m'). Here the five-bar's rule from the actuators' reach is taken as not applying (as
    for Orbita's three actuators and two directions) and the solver as reaching nothing, as Orbita's does."""
    from placement.workshop import gepetto

    def unreached(robot, center, half, normal):
        return center.copy(), center.copy()

    monkeypatch.setattr(gepetto, "_reachable_box", unreached)
    monkeypatch.setattr(gepetto, "reached_box", lambda *args: "a rule that does not apply")
    assert main(["--robot", str(onshape), "--tool", "effector", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert "field 'end_effector.frame': the numeric solver reaches no position of the end effector 'effector'" in err
    assert "choose another frame (--tool, or end_effector.frame)" in err and len(err.strip().splitlines()) <= 2


def test_an_mjcf_loop_whose_actuators_nothing_bounds_is_refused_naming_every_one(tmp_path, capsys):
    """onshape-to-robot's MJCF exports give their position actuators a kp and no forcerange: both motors named, and
    where the bound goes; with it the five-bar loads."""
    unbounded = fivebar_mjcf().replace('<motor joint="mot1" ctrlrange="-10 10"/><motor joint="mot2" ctrlrange="-10 10"/>',
                                       '<position joint="mot1" kp="50"/><position joint="mot2" kp="50"/>')
    path = tmp_path / "fivebar.xml"
    path.write_text(unbounded)
    assert main(["--robot", str(path), "--tool", "effector", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert "nothing bounds the effort of actuated joint(s) mot1, mot2" in err and "--effort mot1=" in err
    given = description_sidecar(path, "effector", DescriptionOptions(efforts={"mot1": 10.0, "mot2": 10.0}))
    path.write_text(unbounded.replace('kp="50"/>', 'kp="50" forcerange="-10 10"/>'))
    bounded = description_sidecar(path, "effector")
    assert [a.joint for a in bounded.actuators] == ["mot1", "mot2"]
    assert given.drives == bounded.drives  # --effort 10 sizes each drive as the file's forcerange of 10 does
    assert "given by --effort mot1=10 on the command line" in given.sources["drives.mot1.motor"]
    path.write_text(unbounded)
    main(["--robot", str(path), "--tool", "effector", "--effort", "mot1=10", "--effort", "mot2=10", "--at", "x=0,y=0",
          "--path", str(CIRCLE)])  # the robot's estimates are said when it loads, whatever the placement
    assert "sized from the MJCF's actuator force ranges, the --effort bounds and" in capsys.readouterr().err


@pytest.mark.parametrize("effort, expected", [("mot1=-1", "--effort: expected JOINT=VALUE"),
                                              ("mot1=abc", "--effort: expected JOINT=VALUE"),
                                              ("mot1", "--effort: expected JOINT=VALUE"),
                                              ("nope=1", "--effort names nope, not a joint of the description")])
def test_a_bad_effort_on_the_command_line_exits_2_naming_the_option(tmp_path, capsys, effort, expected):
    """--effort takes a joint of the description and a positive bound; anything else is named, not guessed."""
    path = tmp_path / "fivebar.xml"
    path.write_text(fivebar_mjcf())
    assert main(["--robot", str(path), "--tool", "effector", "--effort", effort, "--path", str(CIRCLE)]) == 2
    assert expected in capsys.readouterr().err

"""Robots in Gepetto's example-parallel-robots format: a folder with robot.urdf and robot.yaml.

tests/data/gepetto_fivebar is a planar five-bar written as such an export: loops open at q = 0,
URDF limits without a range, no drives. Closed, its actuators at 0, its tip is at (0, 0.30, 0).
"""

import math
import os
import shutil
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.kinematics.base import SOLVERS
from placement.kinematics.exceptions import UnreachableError
from placement.kinematics.trajectories import TaskTrajectory
from placement.robot.closures import closure_residuals
from placement.robot.exceptions import RobotFileError
from placement.workshop.assemble import _solve
from placement.workshop.catalog import sidecar_path
from placement.workshop.checks import check_robot, default_amplitude
from placement.workshop.gepetto import EstimatesWarning, StaleSidecarWarning, estimated_drive, generate
from placement.workshop.load import _load_robot
from tests.support.fivebar_analytic import reached_on_branch
from tests.support.gepetto_weld import assembled_weld_fivebar
from tests.support.paths import CIRCLE, DATA

DATA = DATA / "gepetto_fivebar"


@pytest.fixture
def folder(tmp_path):
    copy = tmp_path / "gepetto_fivebar"
    shutil.copytree(DATA, copy)
    return copy


def test_loading_lists_the_estimates_in_one_warning_and_says_to_assemble(folder):
    for given in (folder, folder / "robot.yaml"):
        with pytest.warns(EstimatesWarning) as caught, pytest.raises(RobotFileError, match="does not close") as error:
            load_robot(given)
        assert error.value.path == folder / "robot.yaml" and error.value.field == "closed_loop.0"
        assert f"'python -m placement assemble {folder} --write' closes the loops and writes them to " \
               f"{folder / 'placement.yaml'}" in str(error.value)
        assert len(caught) == 1
        message = str(caught[0].message)
        assert "these 6 quantities are estimates" in message
        for estimate in ("gravity_m_s2: [0.0, 0.0, -9.81]", "end_effector: frame 'effector', position task",
                         "actuators.0 (mot1): range [-pi, pi] rad", "actuators.1 (mot2): range [-pi, pi] rad",
                         "drives.mot1: gear 31.42:1, 3-phase motor of 0.3183 N m peak", "drives.mot2: gear 31.42:1"):
            assert f"\n  - {estimate}" in message
        assert f"assemble {folder} --write' closes the loops" in message and str(folder / "placement.yaml") in message


def test_the_drive_rule_as_stated():
    """Rated speed 314.16 rad/s gives the URDF's velocity; copper loss at peak torque = peak power."""
    drive, text = estimated_drive(effort=10.0, velocity=10.0, prismatic=False)
    motor = drive["motor"]
    assert drive["transmission"] == {"type": "gear", "ratio": 31.42, "efficiency": 1.0}
    assert motor["max_torque_Nm"] == pytest.approx(10 / 31.42, rel=1e-3)
    assert motor["torque_constant_Nm_per_A"] == pytest.approx(motor["max_torque_Nm"] / 10, rel=1e-3)
    assert motor["back_emf_constant_V_s_per_rad"] == pytest.approx(motor["torque_constant_Nm_per_A"] / 3, rel=1e-3)
    assert 3 * motor["resistance_ohm"] * 10**2 == pytest.approx(motor["max_torque_Nm"] * 314.16, rel=1e-3)
    assert motor["inductance_H"] == pytest.approx(motor["resistance_ohm"] * 1e-3, rel=1e-3)
    assert "from the URDF's effort 10 N m and velocity 10 rad/s" in text
    screw, _ = estimated_drive(effort=1000.0, velocity=0.5, prismatic=True)
    assert screw["transmission"]["lead_m"] == pytest.approx(2 * math.pi * 0.5 / 314.16, rel=1e-3)
    assert screw["motor"]["max_torque_Nm"] == pytest.approx(1000 * screw["transmission"]["lead_m"] / (2 * math.pi),
                                                            rel=1e-3)


def test_assemble_write_then_check_then_search(folder, capsys):
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    out = capsys.readouterr().out
    written = folder / "placement.yaml"
    assert f"wrote the sidecar {written}" in out and "actuated joints kept their start values" in out
    assert sidecar_path(folder) == written and sidecar_path(folder / "robot.yaml") == written
    with warnings.catch_warnings():
        warnings.simplefilter("error", EstimatesWarning)  # a sidecar now: its estimates are in its sources
        robot = load_robot(folder)
    assert np.abs(closure_residuals(robot, robot.model.createData(), robot.reference_q)).max() < 1e-9
    assert all(robot.reference_q[a.q_index] == 0.0 for a in robot.actuators)  # the actuators held
    document = yaml.safe_load(written.read_text())
    low, high = document["workspace"]["min_m"], document["workspace"]["max_m"]
    assert low[2] == -0.001 and high[2] == 0.001 and document["placement"] == {"free": ["x", "y", "phi"]}
    assert -low[0] == high[0] > 0.15 and high[1] - low[1] > 0.1  # mirror symmetric, as the mechanism is; 30 by 10 cm at least
    assert document["sources"]["workspace"].startswith("EST: the largest box")
    assert sum(text.startswith("EST") for text in document["sources"].values()) == 9

    assert main(["check", str(folder)]) == 0
    assert "result: exact to round-off" in capsys.readouterr().out
    assert main(["--robot", str(folder), "--path", str(CIRCLE), "--generations", "2", "--population", "6"]) == 0
    assert "best placement (least energy)" in capsys.readouterr().out


def edited(folder: Path, text: str) -> Path:
    (folder / "robot.yaml").write_text(text)
    return folder


@pytest.mark.parametrize(("text", "field", "problem"), [
    ("closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d']\n", "name_mot", "required field is missing"),
    ("closed_loop: [['closedloop3D_1A', 'nowhere']]\ntype: ['3d']\nname_mot: ['mot1', 'mot2']\n", "closed_loop.0.1",
     "no frame 'nowhere' in robot.urdf"),
    ("closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d', '6d']\nname_mot: ['mot1', 'mot2']\n", "type",
     "1 pair(s), 2 type(s)"),
    ("closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['2d']\nname_mot: ['mot1', 'mot2']\n", "type.0",
     "'3d', '3D', '6d' or '6D'"),
    ("closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d']\nname_mot: ['mot1', 'effector_frame']\n",
     "name_mot.1", "'effector_frame' is a fixed joint in robot.urdf: expected a revolute or prismatic joint"),
    ("closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d']\nname_mot: ['mot1', 'mot2']\n"
     "joint_name: ['free1']\njoint_type: ['SPHERICAL']\n", "joint_type.0", "one-coordinate joints only"),
])
def test_a_malformed_robot_yaml_is_a_located_error(folder, text, field, problem):
    with pytest.raises(RobotFileError) as caught:
        load_robot(edited(folder, text))
    assert caught.value.path == folder / "robot.yaml" and caught.value.field == field and problem in caught.value.problem


def test_a_malformed_robot_yaml_exits_2_with_one_line(folder, capsys):
    edited(folder, "closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d']\n")
    assert main(["check", str(folder)]) == 2
    err = capsys.readouterr().err
    assert err == f"error: {folder / 'robot.yaml'}, field 'name_mot': required field is missing\n"


def test_fixed_joints_are_locked_and_a_named_end_effector_is_no_estimate(folder):
    document, estimates = generate(edited(folder, "closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\n"
                                          "type: ['3d']\nname_mot: ['mot1', 'mot2']\njoint_name: ['free2']\n"
                                          "joint_type: ['FIXED']\nend_effector: closedloop3D_1B\n") / "robot.yaml")
    assert document["locked_joints"] == {"free2": 0.0}
    assert document["end_effector"] == {"frame": "closedloop3D_1B", "task": "position"}
    assert not any(line.startswith("end_effector") for line in estimates) and "end_effector" not in document["sources"]


def test_a_folder_without_robot_files_is_an_error(tmp_path):
    with pytest.raises(RobotFileError, match=f"needs a sidecar placement.yaml or {tmp_path.name}.yaml, or robot.yaml "
                                             "and robot.urdf"):
        load_robot(tmp_path)


def test_assemble_near_motor_values_writes_them_and_the_sidecar_loads(folder, capsys):
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--near", "mot1=0.3,mot2=-0.2", "--write"]) == 0
    assert "it loads; largest closure residual" in capsys.readouterr().out
    reference = yaml.safe_load((folder / "placement.yaml").read_text())["reference_configuration"]
    assert reference["mot1"] == 0.3 and reference["mot2"] == -0.2 and set(reference) == {"mot1", "mot2", "free1", "free2"}
    robot = load_robot(folder)
    assert np.abs(closure_residuals(robot, robot.model.createData(), robot.reference_q)).max() < 1e-9


MISSING_MOTOR = "closed_loop: [['closedloop3D_1A', 'closedloop3D_1B']]\ntype: ['3d']\nname_mot: ['mot1']\n"


def test_a_failed_write_leaves_no_sidecar_to_hide_the_fix(folder, capsys):
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(edited(folder, MISSING_MOTOR)), "--write"]) == 2
    err = capsys.readouterr().err
    assert f"error: {folder / 'placement.yaml'} not written: it would not load: " in err
    assert "field 'actuators'" in err and "fix robot.yaml (name_mot lists the actuated joints" in err
    assert sorted(p.name for p in folder.iterdir()) == ["robot.urdf", "robot.yaml"]  # no sidecar, no temporary file
    shutil.copy(DATA / "robot.yaml", folder / "robot.yaml")
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    assert "it loads" in capsys.readouterr().out


def test_a_sidecar_older_than_robot_yaml_is_loaded_with_a_warning(folder, capsys, monkeypatch):
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    written = (folder / "placement.yaml").stat().st_mtime
    with warnings.catch_warnings():
        warnings.simplefilter("error", StaleSidecarWarning)
        load_robot(folder)  # written after robot.yaml: no warning
    os.utime(folder / "robot.yaml", (written + 10, written + 10))
    with pytest.warns(StaleSidecarWarning, match="placement.yaml is older than .*robot.yaml, which is ignored"):
        load_robot(folder / "robot.yaml")

    def shown(message, category, filename, lineno, file=None, line=None):  # Python's own showwarning, unrecorded
        sys.stderr.write(warnings.formatwarning(message, category, filename, lineno, line))

    monkeypatch.setattr(warnings, "showwarning", shown)
    capsys.readouterr()
    with warnings.catch_warnings():
        warnings.simplefilter("always")
        assert main(["check", str(folder)]) == 0
    err = capsys.readouterr().err
    assert err.startswith(f"warning: {folder / 'placement.yaml'} is older than {folder / 'robot.yaml'}")
    assert f"delete placement.yaml and run 'python -m placement assemble {folder} --write'" in err
    assert "StaleSidecarWarning" not in err and ":0:" not in err


def test_a_fivebar_exported_in_the_x_z_plane_gets_its_plane(folder, capsys):
    urdf = folder / "robot.urdf"  # the export turned a quarter turn about x: the mechanism's plane is x-z
    text = urdf.read_text()
    first = text.index("<link")
    urdf.write_text(text[:first] + '<link name="ground"/><joint name="tilt" type="fixed"><origin xyz="0 0 0" '
                    'rpy="1.5707963267948966 0 0"/><parent link="ground"/><child link="part_1"/></joint>\n' + text[first:])
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    document = yaml.safe_load((folder / "placement.yaml").read_text())
    assert document["placement"] == {"plane": {"normal": [0.0, -1.0, 0.0], "point_m": [0.0, 0.0, 0.3]}}
    low, high = document["workspace"]["min_m"], document["workspace"]["max_m"]
    assert low[1] == -0.001 and high[1] == 0.001 and -low[0] == high[0] > 0  # across the plane; mirror symmetric
    x, z = np.meshgrid(np.linspace(low[0], high[0], 31), np.linspace(low[2], high[2], 31))
    assert reached_on_branch(x, z, math.pi).all() and document["sources"]["placement"].startswith("DERIVED")
    capsys.readouterr()
    assert main(["--robot", str(folder), "--path", str(CIRCLE), "--generations", "2", "--population", "6"]) == 0
    assert "plane (sidecar placement.plane): normal [0, -1, 0] through [0, 0, 0.3] m" in capsys.readouterr().out


WELD = DATA.parent / "gepetto_fivebar_weld"


def _closed_tool_position(robot, motors: dict[str, float]) -> np.ndarray:
    """The end effector's position (m) with the motors at ``motors`` and the loops closed by the passive joints."""
    data = robot.model.createData()
    q = robot.reference_q.copy()
    for actuator in robot.actuators:
        q[actuator.q_index] += motors[actuator.joint]
    passive = np.setdiff1d(np.arange(robot.model.nv), robot.actuated_v_indices)
    q, _ = _solve(robot, data, q, passive)
    assert np.abs(closure_residuals(robot, data, q)).max() < 1e-10
    return data.oMf[robot.end_effector_frame_id].translation.copy()


def test_assemble_write_locks_the_pins_a_weld_leaves_spinning(tmp_path, capsys):
    """A weld between two coaxial pins leaves them free to turn together: assemble --write locks one, says so,
    marks it EST, and the tool moves exactly as with the pins free (the lock removes no motion of the tool)."""
    folder = tmp_path / "weld"
    shutil.copytree(WELD, folder)
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    out = capsys.readouterr().out
    assert "the closures leave 1 freedom(s) no actuator drives" in out and "locked closedloop1_A" in out
    assert "locked_joints (1 joints)" in out and "condition number" in out  # measured with the pin locked
    document = yaml.safe_load((folder / "placement.yaml").read_text())
    assert set(document["locked_joints"]) == {"closedloop1_A"} and "closedloop1_A" not in document["reference_configuration"]
    assert document["sources"]["locked_joints.closedloop1_A"].startswith("EST: placement assemble")
    assert document["placement"] == {"plane": {"normal": [0.0, -1.0, 0.0], "point_m": [0.0, 0.0, 0.3]}}
    locked = load_robot(folder)
    assert np.abs(closure_residuals(locked, locked.model.createData(), locked.reference_q)).max() < 1e-9
    (folder / "placement.yaml").unlink()  # back to robot.yaml: the pins free
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EstimatesWarning)
        free = _load_robot(folder / "robot.yaml", check_closures=False)
    free.reference_q[:] = 0.0
    for name, value in {**document["reference_configuration"], **document["locked_joints"]}.items():
        free.reference_q[free.model.joints[free.model.getJointId(name)].idx_q] = value
    for motors in ({"mot1": 0.0, "mot2": 0.0}, {"mot1": 0.3, "mot2": -0.2}, {"mot1": -0.25, "mot2": 0.15}):
        np.testing.assert_allclose(_closed_tool_position(locked, motors), _closed_tool_position(free, motors), atol=1e-10)


def test_no_lock_refuses_and_names_the_joint_to_lock(tmp_path, capsys):
    folder = tmp_path / "weld"
    shutil.copytree(WELD, folder)
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write", "--no-lock"]) == 2
    err = capsys.readouterr().err
    assert "joint(s) closedloop1_A, closedloop1_B still move" in err and "locked_joints: {closedloop1_A: " in err
    assert "'placement assemble --write' locks them for you" in err
    assert sorted(p.name for p in folder.iterdir()) == ["robot.urdf", "robot.yaml"]


def test_assemble_write_adds_the_lock_to_a_sidecar_in_place(tmp_path, capsys):
    """On an ordinary sidecar whose pin is free and loop open, the lock goes into locked_joints (appended, the
    field missing) and its source at the end of sources; outside reference_configuration no line changes."""
    folder = tmp_path / "weld"
    shutil.copytree(WELD, folder)
    with pytest.warns(EstimatesWarning):
        assert main(["assemble", str(folder), "--write"]) == 0
    sidecar = folder / "placement.yaml"
    closed = yaml.safe_load(sidecar.read_text())
    lines = sidecar.read_text().splitlines(keepends=True)
    opened = "".join(line for line in lines if not line.startswith(("locked_joints:", "  locked_joints.")))
    free1 = closed["reference_configuration"]["free1"]
    opened = opened.replace(f"free1: {free1!r}", f"free1: {free1 + 0.2!r}")  # the loop open by 0.2 rad
    sidecar.write_text(opened)
    capsys.readouterr()
    assert main(["assemble", str(sidecar), "--write"]) == 0
    assert "and locked_joints (1 joints, EST under sources)" in capsys.readouterr().out
    again = yaml.safe_load(sidecar.read_text())
    assert again["locked_joints"].keys() == closed["locked_joints"].keys()  # at the value its new closure needs
    robot = load_robot(sidecar)
    assert np.abs(closure_residuals(robot, robot.model.createData(), robot.reference_q)).max() < 1e-9
    assert again["sources"] == closed["sources"]
    node = next(value for key, value in yaml.compose(opened).value if key.value == "reference_configuration")
    unchanged = opened[:node.start_mark.index] + opened[opened.index("\n", node.end_mark.index):]
    new = sidecar.read_text()
    node = next(value for key, value in yaml.compose(new).value if key.value == "reference_configuration")
    assert (new[:node.start_mark.index] + new[new.index("\n", node.end_mark.index):]).startswith(unchanged)


REACH_M = math.sqrt(0.45**2 - 0.1**2)  # the weld five-bar's highest tip: both arms straight, tip above the middle


@pytest.fixture(scope="module")
def stretched_weld(tmp_path_factory):
    """The weld five-bar exported with its tip at (0, 0, 0.41) m, 29 mm below the highest it can reach, assembled."""
    tmp = tmp_path_factory.mktemp("stretched")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", EstimatesWarning)
        robot = load_robot(assembled_weld_fivebar(tmp))
        still = np.zeros((1, 3))
        joints, ok, _ = SOLVERS.get("numeric")(robot).solve(TaskTrajectory(np.array([[0.0, 0.0, 0.41]]), still, still))
        assert ok.all()
        near = ",".join(f"{a.joint}={float(joints.q[0, a.q_index])!r}" for a in robot.actuators)
        folder = tmp / "stretched"
        shutil.copytree(WELD, folder)
        assert main(["assemble", str(folder), "--near", near, "--write"]) == 0
    return folder


def test_the_estimated_workspace_is_within_reach_for_a_stretched_export(stretched_weld, capsys):
    """Exported with its tip 29 mm below the highest it can reach, the five-bar gets a box of what its actuators
    reach, not one around the tip: nothing above the highest tip position, mirror symmetric, in the analytic reach."""
    box = yaml.safe_load((stretched_weld / "placement.yaml").read_text())["workspace"]
    assert box["max_m"][2] <= REACH_M and -box["min_m"][0] == box["max_m"][0] > 0.1
    x, z = np.meshgrid(np.linspace(box["min_m"][0], box["max_m"][0], 31), np.linspace(box["min_m"][2], box["max_m"][2], 31))
    assert reached_on_branch(x, z, math.pi).all()
    capsys.readouterr()


def test_check_halves_the_default_amplitude_until_the_motion_is_reachable(stretched_weld, tmp_path):
    """With a workspace box 1 m wide the default amplitude (5 cm) leaves the reach (the tip is 29 mm below it);
    check runs at its half, which stays reachable, and says so."""
    sidecar = tmp_path / "placement.yaml"
    document = yaml.safe_load((stretched_weld / "placement.yaml").read_text())
    document["workspace"].update(min_m=[-0.5, -0.001, 0.0], max_m=[0.5, 0.001, 1.0])
    sidecar.write_text(yaml.safe_dump(document, sort_keys=False))
    shutil.copy(stretched_weld / "robot.urdf", tmp_path / "robot.urdf")
    robot = load_robot(sidecar)
    with pytest.raises(UnreachableError):
        check_robot(robot, amplitude_m=default_amplitude(robot)[0])
    report = check_robot(robot)
    assert "halved 1 time(s)" in report.amplitude_basis and report.amplitude_m == default_amplitude(robot)[0] / 2


def test_a_search_whose_reachable_placements_overload_a_motor_says_so(stretched_weld, tmp_path, capsys):
    """Drives too weak for the arms' weight: every placement breaks a motor's torque; the search names the motor
    torque, not the reach."""
    folder = tmp_path / "weak"
    shutil.copytree(stretched_weld, folder)
    sidecar = folder / "placement.yaml"
    document = yaml.safe_load(sidecar.read_text())
    for drive in document["drives"].values():
        drive["motor"]["max_torque_Nm"] = 1e-4
    sidecar.write_text(yaml.safe_dump(document, sort_keys=False))
    capsys.readouterr()
    assert main(["--robot", str(folder), "--path", str(CIRCLE), "--generations", "3", "--population", "8"]) == 2
    err = capsys.readouterr().err
    said = err.replace(str(CIRCLE), "PATH")  # the path's folder may hold the word
    assert "no feasible placement" in said and "motor torque" in said and "reach" not in said, err

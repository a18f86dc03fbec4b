"""'assemble': closing the loops of a robot whose reference configuration is open."""

import re
import shutil

import numpy as np
import pytest
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.robot.closures import closure_residuals
from placement.robot.exceptions import RobotFileError
from placement.workshop.catalog import builtin_robots_dir
from tests.support.robot_copies import edited_copy


def largest_residual(robot) -> float:
    return float(np.abs(closure_residuals(robot, robot.model.createData(), robot.reference_q)).max())


def perturbed_fivebar(folder, db1: float, db2: float):
    def edit(document):
        document["reference_configuration"]["b1"] += db1
        document["reference_configuration"]["b2"] += db2

    return edited_copy("fivebar", folder, edit)


@pytest.mark.parametrize(("db1", "db2", "gap_m"), [(0.08, -0.05, 0.02), (0.3, -0.2, 0.08)])
def test_write_closes_an_open_fivebar_holding_its_actuators(tmp_path, capsys, db1, db2, gap_m):
    sidecar = perturbed_fivebar(tmp_path, db1, db2)
    with pytest.raises(RobotFileError, match="does not close"):
        load_robot(sidecar)
    before = yaml.safe_load(sidecar.read_text())["reference_configuration"]
    assert main(["assemble", str(sidecar), "--write"]) == 0
    out = capsys.readouterr().out
    gap = float(re.search(r"largest gap before: (\S+) m", out).group(1))
    assert gap_m / 2 < gap < gap_m * 1.5  # the loop was open by centimetres
    assert "actuated joints kept their start values" in out and "condition number" in out
    robot = load_robot(sidecar)
    assert largest_residual(robot) < 1e-9
    after = yaml.safe_load(sidecar.read_text())["reference_configuration"]
    assert after["a1"] == before["a1"] and after["a2"] == before["a2"]
    original = load_robot("fivebar").reference_q  # the same branch as the shipped reference
    np.testing.assert_allclose(robot.reference_q, original, atol=1e-9)


@pytest.mark.parametrize("newline", ["\n", "\r\n"])
def test_write_changes_only_the_reference_block(tmp_path, capsys, newline):
    folder = tmp_path / "fivebar"
    shutil.copytree(builtin_robots_dir() / "fivebar", folder)
    sidecar = folder / "fivebar.yaml"
    text = sidecar.read_text()
    assert "  b1: -1.595798931694258\n" in text
    text = text.replace("  b1: -1.595798931694258\n", "  b1: -1.395798931694258   # off by 0.2 rad\n")
    sidecar.write_bytes(text.replace("\n", newline).encode())
    assert main(["assemble", str(sidecar), "--write"]) == 0
    new = sidecar.read_bytes().decode()
    old_lines, new_lines = text.replace("\n", newline).split(newline), new.split(newline)
    start = old_lines.index("  a1: 2.1603806695735632")
    assert new_lines[:start] == old_lines[:start] and new_lines[start + 4:] == old_lines[start + 4:]
    assert new_lines[start:start + 4] == [f"  {name}: {float(value)!r}" for name, value in
                                          zip(("a1", "b1", "a2", "b2"), load_robot(sidecar).reference_q)]
    assert "\r\n" not in new or new.count("\n") == new.count("\r\n")
    capsys.readouterr()


def test_orthoglide_passive_joints_close_back_to_its_reference(tmp_path, capsys):
    original = load_robot("orthoglide")
    sliders = {a.joint for a in original.actuators}
    passive = [name for name in original.model.names[1:] if name not in sliders]

    def edit(document):
        for i, name in enumerate(passive):
            document["reference_configuration"][name] = 0.2 * (-1) ** i

    sidecar = edited_copy("orthoglide", tmp_path, edit)
    with pytest.raises(RobotFileError, match="does not close"):
        load_robot(sidecar)
    assert main(["assemble", str(sidecar), "--write"]) == 0
    capsys.readouterr()
    robot = load_robot(sidecar)  # the closed-form plug-in agrees again, too
    assert largest_residual(robot) < 1e-9
    np.testing.assert_allclose(robot.reference_q, original.reference_q, atol=1e-9)
    assert all(robot.reference_q[a.q_index] == original.reference_q[a.q_index] for a in robot.actuators)


def test_without_write_prints_the_block_and_leaves_the_file(tmp_path, capsys):
    sidecar = perturbed_fivebar(tmp_path, 0.08, -0.05)
    text = sidecar.read_bytes()
    assert main(["assemble", str(sidecar), "--near", "a1=2.1603806695735632rad"]) == 0
    out = capsys.readouterr().out
    assert sidecar.read_bytes() == text
    block = yaml.safe_load(out[out.index("reference_configuration:"):])["reference_configuration"]
    assert set(block) == {"a1", "b1", "a2", "b2"}
    values = [block[name] for name in ("a1", "b1", "a2", "b2")]  # in the URDF's order
    np.testing.assert_allclose(values, load_robot("fivebar").reference_q, atol=1e-9)


def test_actuators_move_when_the_passive_joints_alone_cannot_close(capsys):
    assert main(["assemble", "fivebar", "--near", "a1=3.1,a2=0"]) == 0  # elbows 0.6 m apart, links reach 0.5 m
    out = capsys.readouterr().out
    assert "the actuated joints moved too" in out and "largest gap after:  " in out


@pytest.mark.parametrize(("argv", "message"), [
    (["--near", "elbow=0.1"], "--near: unknown joint 'elbow'; expected one of a1, b1, a2, b2"),
    (["--near", "a1=0.1m"], "--near: a1 is a revolute joint (rad), got a value in m"),
    (["--near", "a1=x"], "--near: 'x' is not a number"),
    (["--write"], "is a built-in robot shipped with placement"),
])
def test_bad_input_exits_2_with_one_line(capsys, argv, message):
    assert main(["assemble", "fivebar", *argv]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and message in err and err.count("\n") == 1


def test_a_loop_that_cannot_close_exits_2_naming_it(tmp_path, capsys):
    sidecar = perturbed_fivebar(tmp_path, 0.08, -0.05)
    urdf = sidecar.parent / "fivebar.urdf"  # lift one tip 1 cm out of the mechanism's plane
    text = urdf.read_text()
    old = '<joint name="dist2_tip_joint" type="fixed"><parent link="dist2"/><child link="dist2_tip"/><origin xyz="0.25 0.0 0.0"'
    assert old in text
    urdf.write_text(text.replace(old, old.replace('xyz="0.25 0.0 0.0"', 'xyz="0.25 0.0 0.01"')))
    text = sidecar.read_bytes()
    assert main(["assemble", str(sidecar), "--write"]) == 2
    err = capsys.readouterr().err
    assert "closure 'tip' cannot close" in err and "gap of 0.01 m" in err and err.count("\n") == 1
    assert sidecar.read_bytes() == text


def test_a_serial_robot_has_nothing_to_assemble(capsys):
    assert main(["assemble", "ur5"]) == 2
    assert "no loop closures" in capsys.readouterr().err


def one_actuator_too_few(document):
    """The five-bar with its loop open and its second motor left out."""
    document["reference_configuration"]["b1"] += 0.05
    del document["actuators"][1]
    document["sources"] = {key: text for key, text in document["sources"].items() if not key.startswith("actuators.1")}


def test_a_rewrite_that_would_not_load_leaves_the_sidecar_as_it_was(tmp_path, capsys):
    sidecar = edited_copy("fivebar", tmp_path, one_actuator_too_few)
    before = sidecar.read_bytes()
    assert main(["assemble", str(sidecar), "--write"]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"error: {sidecar} not written: it would not load: {sidecar}, field 'actuators': ")
    assert sidecar.read_bytes() == before
    assert sorted(p.name for p in sidecar.parent.iterdir() if p.name.startswith(".")) == []  # no temporary file left


def test_singular_passive_joints_are_reported_as_singular(tmp_path, capsys):
    assert main(["assemble", str(edited_copy("fivebar", tmp_path, one_actuator_too_few))]) == 0
    out = capsys.readouterr().out
    assert "    passive joints: singular (smallest singular value of their closure Jacobian 0): the actuated joints " \
           "do not determine them" in out
    assert "    actuators to end effector: undefined while the passive joints are singular\n" in out
    assert "condition number" not in out


def test_the_joints_outside_their_limits_are_named_with_the_limits_that_apply():
    """An actuator's range is the sidecar's, a passive joint's the URDF's."""
    from placement.workshop.assemble import outside_limits

    robot = load_robot("fivebar")
    assert outside_limits(robot, {"a1": 3.0, "b2": -3.0}) == []
    assert outside_limits(robot, {"a1": 4.0, "b1": 0.0, "b2": 100.0}) == [
        "joint 'a1' is at 4, outside its limits [-3.14159, 3.14159]",
        "joint 'b2' is at 100, outside its limits [-3.14159, 3.14159]"]

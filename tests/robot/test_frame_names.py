"""A URDF that gives one name to a link and a joint (the Unitree Z1's 'gripperStator', the SO-101's 'gripper'): the
link is the frame meant, and its joints are held as any others (Pinocchio, which needs the names apart to hold them,
gets them apart while it does)."""

import json
from pathlib import Path

import pinocchio as pin
import pytest
from example_robot_data.robots_loader import ROBOTS

from placement.__main__ import main
from placement.robot.tool import find_frame
from placement.robot.urdf import erd_urdf_path
from placement.workshop.catalog import builtin_robots_dir
from tests.support.paths import CIRCLE


def test_a_name_shared_by_a_link_and_a_joint_finds_the_link():
    model = pin.buildModelFromUrdf(ROBOTS["z1"]().df_path)
    assert sum(f.name == "gripperStator" for f in model.frames) > 1  # the case this test is about
    assert model.frames[find_frame(model, "gripperStator")].type == pin.FrameType.BODY
    assert find_frame(model, "no such frame") is None


def test_holding_joints_of_a_urdf_with_shared_names_moves_and_costs_as_with_distinct_ones(tmp_path, capsys):
    """The Panda with its third link renamed to the name of a joint ('panda_joint5'), its fingers and third joint
    held: Pinocchio needs the names apart while it holds them (it refused: 'Several frames match'), and the arm is
    the same arm, to the last digit of its energy."""
    urdf = tmp_path / "panda" / "panda.urdf"
    urdf.parent.mkdir()
    text = Path(erd_urdf_path(ROBOTS["panda"])).read_text()
    assert text.count('"panda_link3"') == 3  # the link, and the joints it is child and parent of
    urdf.write_text(text.replace('"panda_link3"', '"panda_joint5"'))
    sidecar = urdf.parent / "panda.yaml"
    sidecar.write_text((builtin_robots_dir() / "panda" / "panda.yaml").read_text()
                       .replace("urdf: example-robot-data:panda", "urdf: panda.urdf"))
    energies = []
    for robot in ("panda", str(sidecar)):
        out = tmp_path / f"{len(energies)}.json"
        assert main(["--robot", robot, "--path", str(CIRCLE), "--at", "x=400,y=0,z=300", "--lock", "panda_joint3=0",
                     "--json", str(out)]) == 0
        energies.append(json.loads(out.read_text())["at"]["energy_J"])
    capsys.readouterr()
    assert energies[1] == pytest.approx(energies[0], rel=1e-12) and energies[0] > 0

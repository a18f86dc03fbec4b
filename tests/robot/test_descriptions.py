"""Robots as users bring them: a URDF or xacro file with --tool (the rest estimated), its package:// meshes found
where a cloned repository or ROS keeps them, and the estimated sidecar written for the user to refine."""

import json
import shutil
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pinocchio as pin
import pytest
from example_robot_data.robots_loader import ROBOTS

from placement.cli import main
from placement.robot.exceptions import RobotFileError
from placement.robot.formats import DescriptionOptions
from placement.robot.packages import description_geometry, find_package, resolve_uri, search_folders
from placement.robot.urdf import erd_urdf_path
from placement.robot.xacro import expand_xacro
from placement.workshop.checks import check_robot
from placement.workshop.estimates import description_sidecar, erd_sidecar, load_description_robot
from tests.support.paths import CIRCLE

PACKAGE = "placement_demo_description"  # a name no machine has installed
STL = """solid box
facet normal 0 0 1
 outer loop
  vertex 0 0 0
  vertex 0.01 0 0
  vertex 0 0.01 0
 endloop
endfacet
facet normal 0 0 -1
 outer loop
  vertex 0 0 0
  vertex 0 0.01 0
  vertex 0 0 0.01
 endloop
endfacet
endsolid box
"""
ARM_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://www.ros.org/wiki/xacro" name="three_link">
  <xacro:property name="l" value="$(arg reach)"/>
  <xacro:macro name="segment" params="i parent axis z">
    <link name="link${i}">
      <inertial><origin xyz="0 0 ${l/4}"/><mass value="2"/>
        <inertia ixx="0.02" iyy="0.02" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial>
      <visual><geometry><mesh filename="package://PACKAGE/meshes/box.stl"/></geometry></visual>
    </link>
    <joint name="joint${i}" type="revolute"><parent link="${parent}"/><child link="link${i}"/>
      <origin xyz="0 0 ${z}"/><axis xyz="${axis}"/><limit lower="-3" upper="3" effort="150" velocity="3"/></joint>
  </xacro:macro>
  <link name="base"/>
  <xacro:segment i="1" parent="base" axis="0 0 1" z="0.1"/>
  <xacro:segment i="2" parent="link1" axis="0 1 0" z="0.1"/>
  <xacro:segment i="3" parent="link2" axis="0 1 0" z="${l}"/>
  <link name="tip"/>
  <joint name="tip_joint" type="fixed"><parent link="link3"/><child link="tip"/><origin xyz="0 0 ${l}"/></joint>
</robot>
""".replace("PACKAGE", PACKAGE)


@pytest.fixture
def cloned(tmp_path):
    """A description package as a repository clone holds it: the folder's name is not the package's."""
    root = tmp_path / "Demo_Description_Repository"
    (root / "meshes").mkdir(parents=True)
    (root / "urdf").mkdir()
    (root / "package.xml").write_text(f"<package format='3'><name>{PACKAGE}</name></package>")
    (root / "meshes" / "box.stl").write_text(STL)
    (root / "urdf" / "arm.urdf.xacro").write_text(ARM_XACRO)
    return root


def test_a_package_is_found_above_the_description_by_its_package_xml_though_its_folder_has_another_name(cloned):
    urdf = cloned / "urdf" / "arm.urdf.xacro"
    mesh = resolve_uri(f"package://{PACKAGE}/meshes/box.stl", urdf, search_folders(urdf), "field")
    assert mesh == (cloned / "meshes" / "box.stl").resolve()


def test_a_missing_package_names_the_folders_looked_in_and_the_ways_to_give_it(cloned, tmp_path_factory, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    elsewhere = tmp_path_factory.mktemp("elsewhere") / "robot.urdf"  # neither in the clone nor beside it
    folders = search_folders(elsewhere)
    with pytest.raises(RobotFileError, match=f"package '{PACKAGE}'.*not found in {elsewhere.parent}.*--package-path"):
        resolve_uri(f"package://{PACKAGE}/meshes/box.stl", elsewhere, folders, "urdf.link.link1.visual")
    assert find_package(PACKAGE, search_folders(elsewhere, [cloned])) == cloned  # --package-path: the package
    assert find_package(PACKAGE, search_folders(elsewhere, [cloned.parent])) == cloned  # or a folder holding it
    monkeypatch.setenv("ROS_PACKAGE_PATH", str(cloned.parent))
    assert find_package(PACKAGE, search_folders(elsewhere)) == cloned


def test_a_missing_mesh_file_names_the_link_and_the_file(cloned):
    (cloned / "meshes" / "box.stl").unlink()
    urdf = cloned / "urdf" / "arm.urdf.xacro"
    with pytest.raises(RobotFileError, match=r"urdf.link.link1.visual.*box.stl.*does not exist"):
        resolve_uri(f"package://{PACKAGE}/meshes/box.stl", urdf, search_folders(urdf), "urdf.link.link1.visual")


def test_a_xacro_arm_loads_with_its_argument_and_its_meshes_and_the_argument_shapes_it(cloned):
    path = cloned / "urdf" / "arm.urdf.xacro"
    short = load_description_robot(path, "tip", options=DescriptionOptions(xacro_args={"reach": "0.3"}))
    long = load_description_robot(path, "tip", options=DescriptionOptions(xacro_args={"reach": "0.5"}))
    for robot, reach in ((short, 0.3), (long, 0.5)):
        assert robot.model.jointPlacements[robot.model.getJointId("joint3")].translation[2] == pytest.approx(reach)
        assert robot.sidecar.xacro_args == {"reach": str(reach)}
        visual = description_geometry(robot, pin.GeometryType.VISUAL)
        assert {Path(item.meshPath) for item in visual.geometryObjects} == {(cloned / "meshes" / "box.stl").resolve()}
    assert check_robot(short, samples=30).passed


def test_a_xacro_without_its_argument_says_which_and_how_to_give_it(cloned):
    with pytest.raises(RobotFileError, match="argument 'reach' is not given.*--robot-arg NAME:=VALUE"):
        load_description_robot(cloned / "urdf" / "arm.urdf.xacro", "tip")


def test_a_urdf_file_gets_the_drives_an_erd_arm_of_the_same_urdf_gets():
    by_file = description_sidecar(erd_urdf_path(ROBOTS["ur5"]), "tool0")
    by_name = erd_sidecar("ur5", "tool0")
    assert by_file.drives == by_name.drives and by_file.actuators == by_name.actuators
    assert by_file.urdf == str(erd_urdf_path(ROBOTS["ur5"]).resolve())
    assert "neutral posture" in by_file.sources["reference_configuration"]


def test_the_command_line_places_a_path_on_a_urdf_file_and_writes_a_sidecar_that_gives_the_same_energy(tmp_path, capsys):
    urdf = tmp_path / "ur5_robot.urdf"
    shutil.copy(erd_urdf_path(ROBOTS["ur5"]), urdf)
    sidecar, direct, reloaded = tmp_path / "ur5.yaml", tmp_path / "direct.json", tmp_path / "reloaded.json"
    at = ["--path", str(CIRCLE), "--at", "x=450,y=0,z=150"]
    package = ["--package-path", str(Path(erd_urdf_path(ROBOTS["ur5"])).parents[2])]  # its meshes' package
    assert main(["--robot", str(urdf), "--tool", "tool0", *package, *at, "--json", str(direct),
                 "--write-sidecar", str(sidecar)]) == 0
    assert "estimates" in capsys.readouterr().err
    assert main(["--robot", str(sidecar), *at, "--json", str(reloaded)]) == 0
    first, second = (json.loads(file.read_text())["at"] for file in (direct, reloaded))
    assert second["energy_J"] == pytest.approx(first["energy_J"], rel=1e-9)
    assert np.isfinite(first["energy_J"]) and first["energy_J"] > 0
    assert "urdf: ur5_robot.urdf" in sidecar.read_text()  # relative to the sidecar, which can move with it


def test_tool_on_a_sidecar_and_a_bad_robot_arg_exit_2_with_one_line(capsys):
    assert main(["--robot", "ur5", "--tool", "tool0", "--path", str(CIRCLE)]) == 2
    assert "description file (URDF, xacro, MJCF)" in capsys.readouterr().err
    assert main(["--robot", "ur5", "--robot-arg", "reach", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: --robot-arg: expected NAME:=VALUE") and len(err.strip().splitlines()) == 1


def test_robot_args_on_a_robot_not_in_xacro_and_a_missing_package_folder_are_refused(capsys, tmp_path):
    assert main(["--robot", "orthoglide", "--robot-arg", "a:=b", "--path", str(CIRCLE), "--at", "x=0"]) == 2
    assert "--robot-arg applies to robots described in xacro" in capsys.readouterr().err
    assert main(["--robot", "orthoglide", "--package-path", str(tmp_path / "none"), "--path", str(CIRCLE)]) == 2
    assert f"--package-path: no such folder: {tmp_path / 'none'}" in capsys.readouterr().err


def test_the_estimates_warning_names_the_joints_held_fixed_and_the_redundant_ones(capsys):
    assert main(["--robot", "erd:panda", "--tool", "panda_hand", "--path", str(CIRCLE), "--at", "x=400,y=0,z=300"]) in (0, 2)
    err = capsys.readouterr().err
    assert "joints held fixed: panda_finger_joint1, panda_finger_joint2" in err
    assert "redundant joints profiled along the path by the search: panda_joint3" in err
    assert main(["--robot", "erd:panda", "--tool", "panda_hand", "--path", str(CIRCLE), "--at", "x=400,y=0,z=300",
                 "--lock", "panda_joint3=0"]) in (0, 2)
    assert "joints held fixed: panda_finger_joint1, panda_finger_joint2, panda_joint3;" in capsys.readouterr().err


SUPPORT_XACRO = """<?xml version="1.0"?>
<robot xmlns:xacro="http://ros.org/wiki/xacro" name="supported">
  <xacro:arg name="variant" default=""/>
  <xacro:include filename="$(find demo_resources)/urdf/common.xacro"/>
  <link name="base"/>
  <link name="link1"><inertial><mass value="${link_mass}"/>
    <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="joint1" type="revolute"><parent link="base"/><child link="link1"/><axis xyz="0 0 1"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
</robot>
"""


def ros_industrial_tree(root: Path, mass_kg: float) -> Path:
    """A repository of ROS-Industrial's layout: the robot's support package and, beside it, a resources package its
    xacro finds with $(find demo_resources); returns the xacro."""
    for package in ("demo_support", "demo_resources"):
        (root / package / "urdf").mkdir(parents=True)
        (root / package / "package.xml").write_text(f"<package format='2'><name>{package}</name></package>")
    (root / "demo_resources" / "urdf" / "common.xacro").write_text(
        f'<robot xmlns:xacro="http://ros.org/wiki/xacro"><xacro:property name="link_mass" value="{mass_kg}"/></robot>')
    (root / "demo_support" / "urdf" / "arm.xacro").write_text(SUPPORT_XACRO)
    return root / "demo_support" / "urdf" / "arm.xacro"


def link_mass(xacro: Path, options: DescriptionOptions = DescriptionOptions()) -> float:
    """The mass of link1 in the URDF the xacro expands to (kg)."""
    urdf = expand_xacro(xacro, options.xacro_args, options.package_paths, xacro, "urdf")
    return float(ElementTree.parse(urdf).getroot().find("link[@name='link1']/inertial/mass").get("value"))


def test_a_xacro_finds_a_package_beside_its_own_in_the_repository_and_each_tree_its_own(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    first, second = ros_industrial_tree(tmp_path / "one", 3.0), ros_industrial_tree(tmp_path / "two", 5.0)
    assert link_mass(first) == 3.0
    assert link_mass(second) == 5.0  # the same package name in another clone: not the first one's
    assert link_mass(second, DescriptionOptions(package_paths=(tmp_path / "one",))) == 3.0  # --package-path first


def test_a_xacro_package_found_nowhere_is_named_with_the_folders_looked_in(tmp_path, monkeypatch):
    monkeypatch.delenv("ROS_PACKAGE_PATH", raising=False)
    monkeypatch.delenv("AMENT_PREFIX_PATH", raising=False)
    xacro = ros_industrial_tree(tmp_path, 3.0)
    shutil.rmtree(tmp_path / "demo_resources")
    with pytest.raises(RobotFileError, match=r"\$\(find demo_resources\).*not found in .*demo_support.*--package-path"):
        link_mass(xacro)


def test_a_failed_expansion_names_the_arguments_the_file_leaves_empty(tmp_path):
    xacro = tmp_path / "arm.xacro"
    xacro.write_text('<robot xmlns:xacro="http://ros.org/wiki/xacro" name="a"><xacro:arg name="dof" default=""/>'
                     '<xacro:arg name="ip" default="10.0.0.1"/>'
                     '<xacro:include filename="arms/$(arg dof)dof.xacro"/></robot>')
    with pytest.raises(RobotFileError, match=r"arguments given: none; its arguments left empty: dof;"):
        expand_xacro(xacro, {}, [], xacro, "urdf")  # arms/dof.xacro does not exist
    with pytest.raises(RobotFileError, match=r"arguments given: dof:=7;"):
        expand_xacro(xacro, {"dof": "7"}, [], xacro, "urdf")


ROS_INDUSTRIAL_URDF = """<robot name="bare">
  <link name="base_link"/><link name="link_1"/><link name="link_2"/><link name="link_3"/><link name="tool0"/>
  <joint name="joint_1" type="revolute"><parent link="base_link"/><child link="link_1"/><origin xyz="0 0 0.3"/>
    <axis xyz="0 0 1"/><limit effort="0" lower="-3" upper="3" velocity="2"/></joint>
  <joint name="joint_2" type="revolute"><parent link="link_1"/><child link="link_2"/><origin xyz="0.1 0 0.2"/>
    <axis xyz="0 1 0"/><limit effort="0" lower="-2" upper="2" velocity="2"/></joint>
  <joint name="joint_3" type="revolute"><parent link="link_2"/><child link="link_3"/><origin xyz="0 0 0.4"/>
    <axis xyz="0 1 0"/><limit effort="0" lower="-2" upper="2" velocity="2"/></joint>
  <joint name="joint_t" type="fixed"><parent link="link_3"/><child link="tool0"/><origin xyz="0.4 0 0"/></joint>
</robot>
"""


def test_a_description_without_efforts_or_inertias_is_refused_naming_both_and_what_a_sidecar_gives(tmp_path, capsys):
    """ROS-Industrial's descriptions give effort="0" and no <inertial>: the direct route names the joints and the
    links in one line, exit 2, before any estimate is made."""
    urdf = tmp_path / "bare.urdf"
    urdf.write_text(ROS_INDUSTRIAL_URDF)
    assert main(["--robot", str(urdf), "--tool", "tool0", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert len(err.strip().splitlines()) == 1
    assert "no effort limit for joint(s) joint_1, joint_2, joint_3" in err
    assert "inertia for its moving link(s) link_1, link_2, link_3 (no <inertial>)" in err
    assert "under links (e.g. links.link_1" in err and "docs/adding_a_robot.md" in err
    urdf.write_text(ROS_INDUSTRIAL_URDF.replace('effort="0"', 'effort="50"'))  # efforts given: the massless refusal
    assert main(["--robot", str(urdf), "--tool", "tool0", "--path", str(CIRCLE)]) == 2
    err = capsys.readouterr().err
    assert "3 moving link(s) of bare.urdf have no inertia" in err
    assert "--allow-massless --write-sidecar FILE writes the estimated sidecar, for you to add them to" in err
    xacro = tmp_path / "bare.xacro"  # named as the user gave it, not as its expansion in the cache
    xacro.write_text(urdf.read_text().replace('<robot name="bare">',
                                              '<robot name="bare" xmlns:xacro="http://ros.org/wiki/xacro">'))
    assert main(["--robot", str(xacro), "--tool", "tool0", "--path", str(CIRCLE)]) == 2
    assert "3 moving link(s) of bare.xacro have no inertia" in capsys.readouterr().err

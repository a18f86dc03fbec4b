"""Test robots: edited copies of a built-in robot's folder, and small robots written from scratch.

Each builder writes its files into a given folder and returns the sidecar to load (``load_robot``).
``tests/robot/test_contract.py`` runs the physics contract on every one of them.
"""

import copy
import re
import shutil
import warnings
from collections.abc import Callable
from pathlib import Path

import numpy as np
import yaml

from placement import load_robot
from placement.__main__ import main
from placement.workshop.catalog import builtin_robots_dir
from tests.support.paths import DATA

GEPETTO_FIVEBAR = DATA / "gepetto_fivebar"


def edited_copy(name: str, folder: Path, edit: Callable[[dict], None]) -> Path:
    """Copy robot ``name``'s folder into ``folder``, apply ``edit`` to its sidecar; returns the sidecar."""
    copied = folder / name
    shutil.copytree(builtin_robots_dir() / name, copied, ignore=shutil.ignore_patterns("__pycache__"))
    sidecar = copied / f"{name}.yaml"
    document = yaml.safe_load(sidecar.read_text())
    edit(document)
    sidecar.write_text(yaml.safe_dump(document))
    return sidecar


def orthoglide_motor(document: dict) -> dict:
    """The motor entry of the Orthoglide's (single) drive."""
    return next(iter(document["drives"].values()))["motor"]


# --- the five-bar in a vertical plane -------------------------------------------------------------------------------

TURN = np.array([[1.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.0, -1.0, 0.0]])  # Rx(-90 deg): base z -> y, y -> -z


def _vertical(document: dict) -> None:
    """The five-bar turned by TURN: it moves in the x-z plane, and so do gravity and its workspace."""
    document["gravity_m_s2"] = (TURN @ document["gravity_m_s2"]).tolist()
    corners = TURN @ np.array([document["workspace"]["min_m"], document["workspace"]["max_m"]]).T
    document["workspace"]["min_m"], document["workspace"]["max_m"] = corners.min(axis=1).tolist(), corners.max(axis=1).tolist()
    document["workspace"]["points_m"] = {k: (TURN @ v).tolist() for k, v in document["workspace"]["points_m"].items()}
    document["placement"] = {"plane": {"normal": [0, 1, 0]}}


def vertical_fivebar(folder: Path) -> Path:
    """The built-in five-bar turned by TURN (its base joints carry the turn): it moves in the x-z plane."""
    sidecar = edited_copy("fivebar", folder, _vertical)
    urdf = sidecar.parent / "fivebar.urdf"
    text = urdf.read_text()
    for joint in ("a1", "a2"):  # the joints on the base carry the turn
        start = text.index(f'<joint name="{joint}"')
        text = text[:start] + text[start:].replace('rpy="0 0 0"', f'rpy="{-np.pi / 2!r} 0 0"', 1)
    urdf.write_text(text)
    return sidecar


# --- the five-bar with spinning distal rods -------------------------------------------------------------------------

SPIN = ('<link name="dist{i}_hub"/>'
        '<joint name="spin{i}" type="revolute"><parent link="dist{i}_hub"/><child link="dist{i}"/>'
        '<origin xyz="0 0 0"/><axis xyz="1 0 0"/><limit lower="-3.14" upper="3.14" effort="1" velocity="1"/></joint>')


def spinning_rods_fivebar(folder: Path, locked: bool = False) -> Path:
    """The five-bar with each distal rod on an extra revolute joint about its own axis (x); ``locked``: with
    those joints locked at 0 (without, the loop leaves them free and the robot does not load)."""
    sidecar = edited_copy("fivebar", folder, lambda document: None)
    urdf = sidecar.parent / "fivebar.urdf"
    text = urdf.read_text()
    for i in (1, 2):
        elbow = f'<parent link="prox{i}"/><child link="dist{i}"/>'
        assert elbow in text
        text = text.replace(elbow, f'<parent link="prox{i}"/><child link="dist{i}_hub"/>')
        text = text.replace("</robot>", SPIN.format(i=i) + "\n</robot>")
    urdf.write_text(text)
    if locked:
        document = yaml.safe_load(sidecar.read_text())
        document["locked_joints"] = {"spin1": 0.0, "spin2": 0.0}
        sidecar.write_text(yaml.safe_dump(document))
    return sidecar


# --- the Gepetto-format five-bar, assembled -------------------------------------------------------------------------

def assembled_gepetto_fivebar(folder: Path) -> Path:
    """tests/data/gepetto_fivebar copied into ``folder`` and closed by ``placement assemble --write``."""
    copied = folder / GEPETTO_FIVEBAR.name
    shutil.copytree(GEPETTO_FIVEBAR, copied)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the estimates warning: a test of its own (tests/test_gepetto.py)
        assert main(["assemble", str(copied), "--write"]) == 0
    return copied / "placement.yaml"


# --- a two-link planar arm ------------------------------------------------------------------------------------------

ARM_LINKS = """\
  <link name="upper"><inertial><origin xyz="0.15 0 0"/><mass value="1.0"/>
    <inertia ixx="1e-4" iyy="0.0075" izz="0.0075" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="fore"><inertial><origin xyz="0.125 0 0"/><mass value="0.6"/>
    <inertia ixx="6e-5" iyy="0.003125" izz="0.003125" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"/>
"""  # the upper arm, the forearm and the tip, which the shoulder and elbow joints below move
ARM_ELBOW = """\
  <joint name="elbow" type="revolute"><parent link="upper"/><child link="fore"/><origin xyz="0.3 0 0"/><axis xyz="0 -1 0"/>
    <limit lower="-3.1416" upper="3.1416" effort="20" velocity="10"/></joint>
  <joint name="tip_joint" type="fixed"><parent link="fore"/><child link="tip"/><origin xyz="0.25 0 0"/></joint>
</robot>
"""
ARM_URDF = """<?xml version="1.0"?>
<robot name="arm2">
  <link name="base"/>
""" + ARM_LINKS + """\
  <joint name="shoulder" type="revolute"><parent link="base"/><child link="upper"/><axis xyz="0 -1 0"/>
    <limit lower="-3.1416" upper="3.1416" effort="20" velocity="10"/></joint>
""" + ARM_ELBOW
ARM_SIDECAR = {
    "name": "arm2", "description": "Two-link planar arm in the vertical x-z plane", "urdf": "arm.urdf",
    "gravity_m_s2": [0, 0, -9.81], "end_effector": {"frame": "tip", "task": "position"},
    "reference_configuration": {"shoulder": 1.0, "elbow": -1.6},  # the tip at (0.368, 0, 0.111) m
    "actuators": [{"joint": "shoulder", "drive": "servo"}, {"joint": "elbow", "drive": "servo"}],
    "drives": {"servo": {"transmission": {"type": "gear", "ratio": 50, "efficiency": 1.0},
                         "motor": {"torque_constant_Nm_per_A": 0.1, "back_emf_constant_V_s_per_rad": 0.0333,
                                   "resistance_ohm": 0.8, "inductance_H": 0.0008, "phases": 3,
                                   "rotor_inertia_kg_m2": 1e-5, "max_torque_Nm": 1.0, "max_speed_rad_s": 500}}},
    "workspace": {"type": "box", "min_m": [0.30, -0.001, 0.05], "max_m": [0.42, 0.001, 0.17]},
    "placement": {"plane": {"normal": [0, -1, 0]}},
    "sources": {"drives.servo": "EST: test servo", "workspace": "EST: test region"},
}


def planar_arm(folder: Path, edit: Callable[[dict], None] = lambda document: None) -> Path:
    """A two-link arm in the vertical x-z plane (joint axes along -y), its sidecar edited by ``edit``."""
    (folder / "arm.urdf").write_text(ARM_URDF)
    document = copy.deepcopy(ARM_SIDECAR)
    edit(document)
    sidecar = folder / "arm.yaml"
    sidecar.write_text(yaml.safe_dump(document))
    return sidecar


# --- a three-axis gantry on ball screws -----------------------------------------------------------------------------

GANTRY_URDF = """<?xml version="1.0"?>
<robot name="gantry">
  <link name="base"/>
  {links}
</robot>
"""
GANTRY_LINK = """
  <joint name="{axis}" type="prismatic">
    <parent link="{parent}"/><child link="carriage_{axis}"/>
    <origin xyz="0 0 0"/><axis xyz="{direction}"/>
    <limit lower="-1" upper="1" effort="1000" velocity="1"/>
  </joint>
  <link name="carriage_{axis}">
    <inertial><mass value="{mass}"/><origin xyz="0 0 0"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>"""
GANTRY_SIDECAR = """name: gantry
urdf: gantry.urdf
gravity_m_s2: [0.0, 0.0, -9.81]
end_effector: {frame: carriage_z, task: position}
reference_configuration: {x: 0.0, y: 0.0, z: 0.0}
actuators:
  - {joint: x, drive: screw, velocity_max: 0.5, acceleration_max: 2.0}
  - {joint: y, drive: screw, velocity_max: 0.5, acceleration_max: 2.0}
  - {joint: z, drive: screw, velocity_max: 0.5, acceleration_max: 2.0}
drives:
  screw:
    transmission: {type: ball_screw, lead_m: 0.02, efficiency: 1.0}
    motor: {torque_constant_Nm_per_A: 0.6, back_emf_constant_V_s_per_rad: 0.2, resistance_ohm: 1.0,
            inductance_H: 0.001, phases: 3, rotor_inertia_kg_m2: 1.0e-5, max_torque_Nm: 100.0, max_speed_rad_s: 1000.0}
workspace: {type: box, min_m: [-0.5, -0.5, -0.5], max_m: [0.5, 0.5, 0.5]}
"""


def gantry(folder: Path) -> Path:
    """A cartesian x-y-z gantry of three prismatic joints (8, 5 and 3 kg carriages) on ball screws."""
    links, parent = [], "base"
    for axis, direction, mass in (("x", "1 0 0", 8.0), ("y", "0 1 0", 5.0), ("z", "0 0 1", 3.0)):
        links.append(GANTRY_LINK.format(axis=axis, parent=parent, direction=direction, mass=mass))
        parent = f"carriage_{axis}"
    (folder / "gantry.urdf").write_text(GANTRY_URDF.format(links="".join(links)))
    (folder / "gantry.yaml").write_text(GANTRY_SIDECAR)
    return folder / "gantry.yaml"


# --- the UR5 with continuous joints ---------------------------------------------------------------------------------

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


def continuous_ur5(folder: Path) -> Path:
    """The UR5 on :func:`continuous_ur5_urdf`, its continuous actuators given the range [-pi, pi] in the sidecar."""
    def with_ranges(document: dict) -> None:
        document["urdf"] = "ur5.urdf"
        for actuator in document["actuators"]:
            if actuator["joint"] in CONTINUOUS:
                actuator.update(position_min=-np.pi, position_max=np.pi)

    sidecar = edited_copy("ur5", folder, with_ranges)
    (sidecar.parent / "ur5.urdf").write_text(continuous_ur5_urdf())
    return sidecar


# --- the UR5 with a tool: an offset tool tip, or a gripper's mass ---------------------------------------------------

TOOL_OFFSET_M = np.array([0.0, 0.0, 0.125])  # along the flange frame's z
TOOL_RPY_RAD = (0.3, -0.2, 1.1)


def with_tool(offset, rpy=None, source=True) -> Callable[[dict], None]:
    """A sidecar edit: the end effector is the tool tip at ``offset`` (m) and ``rpy`` (rad) from the frame."""
    def edit(document):
        document["end_effector"]["offset_m"] = [float(v) for v in offset]
        if rpy is not None:
            document["end_effector"]["rpy_rad"] = list(rpy)
        if source:
            document["sources"]["end_effector"] = "EST: a 125 mm spindle"
    return edit


GRIPPER = {"name": "gripper", "mass_kg": 1.2, "inertia_kg_m2": [2e-3, 2e-3, 1e-3, 0, 0, 0], "com_m": [0, 0, 0.05],
           "collision": {"type": "box", "size_m": [0.08, 0.05, 0.1], "xyz_m": [0, 0, 0.05]}}


def with_gripper(document: dict) -> None:
    """A sidecar edit: the robot carries GRIPPER, a 1.2 kg tool body, at its end-effector frame."""
    document["tool"] = copy.deepcopy(GRIPPER)


# --- an arm on a universal shoulder: two revolute joints and a massless body between them ---------------------------

UNIVERSAL_URDF = """<?xml version="1.0"?>
<robot name="universal_arm">
  <link name="base"/>
  <link name="gimbal"/>
""" + ARM_LINKS + """\
  <joint name="yaw" type="revolute"><parent link="base"/><child link="gimbal"/><origin xyz="0 0 0.3"/><axis xyz="0 0 1"/>
    <limit lower="-3.1416" upper="3.1416" effort="20" velocity="10"/></joint>
  <joint name="shoulder" type="revolute"><parent link="gimbal"/><child link="upper"/><origin xyz="{offset} 0 0"/>
    <axis xyz="0 -1 0"/><limit lower="-3.1416" upper="3.1416" effort="20" velocity="10"/></joint>
""" + ARM_ELBOW


def universal_shoulder_arm(folder: Path, gimbal_offset_m: float = 0.0, massless: tuple[str, ...] = ()) -> Path:
    """A three-joint arm whose shoulder is a universal joint: yaw, then shoulder (pitch), through the massless link
    ``gimbal``, which has no extent (the shoulder joint at its origin) unless ``gimbal_offset_m`` (m, along its x); the links
    ``massless`` lose their inertials. The planar arm's links and drives (:func:`planar_arm`), a position task."""
    text = UNIVERSAL_URDF.format(offset=gimbal_offset_m)
    for link in massless:
        text = re.sub(rf'(<link name="{link}">)<inertial>.*?</inertial>', r"\1", text, flags=re.S)
    (folder / "arm.urdf").write_text(text)
    document = copy.deepcopy(ARM_SIDECAR)
    document.update(name="universal_arm", description="Arm on a universal shoulder (a massless gimbal between yaw "
                    "and shoulder)", reference_configuration={"yaw": 0.3, "shoulder": 1.0, "elbow": -1.6})
    document["actuators"].insert(0, {"joint": "yaw", "drive": "servo"})
    centre = np.array([0.368 * np.cos(0.3), 0.368 * np.sin(0.3), 0.3 + 0.111])  # the tip at the reference
    document["workspace"] = {"type": "box", "min_m": (centre - 0.06).tolist(), "max_m": (centre + 0.06).tolist()}
    document["placement"] = {"free": ["x", "y", "z", "phi"]}
    sidecar = folder / "arm.yaml"
    sidecar.write_text(yaml.safe_dump(document))
    return sidecar

"""Write ``ur5_positioner.urdf``: the UR5 of example-robot-data beside a 2-axis tilt-rotate positioner.

Run ``python make_urdf.py`` in this folder after changing a number below (or after example-robot-data
changes its UR5); the test suite checks that the committed URDF is what this script writes. The
numbers' sources are under ``sources`` in ``ur5_positioner.yaml``.

The UR5 is example-robot-data's ``ur5_robot.urdf`` unchanged (links, joints, inertials, limits, meshes,
its ``base_link`` fixed to ``world`` at the origin). The positioner is a second chain from ``world``,
in front of the UR5 (along +x):

- ``positioner_pedestal``: its fixed frame (a box, for the scene; fixed to the floor: no mass counts);
- ``tilt``: a revolute joint about ``world``'s y axis (horizontal, across the UR5's line of sight),
  its axis TILT_AXIS_M from the UR5's base, 0 with the table level;
- ``positioner_cradle``: the tilting cradle with the rotary drive on it;
- ``rotate``: a revolute joint about the table's normal, the table's top RISE_M above the tilt axis;
- ``positioner_table``: the round face plate;
- ``workpiece``: the part clamped centred on the table: a closed steel shell (a small pressure vessel)
  standing on its end. Its frame, the workpiece frame the path is placed in, is at the centre of its
  top lid, z along the table's normal: the seam of ``examples/positioner_weld.yaml`` runs round the lid.
"""

from __future__ import annotations

import math
from pathlib import Path
from xml.etree import ElementTree

from example_robot_data.robots_loader import ROBOTS

from placement.robot.urdf import erd_urdf_path

TILT_AXIS_M = (0.80, 0.0, -0.25)  # the tilt axis's point in the UR5's base frame (floor below both)
RISE_M = 0.15  # the table's top above the tilt axis
TILT_RANGE_RAD = math.radians(135.0)  # each way
TILT_SPEED_RAD_S = 1.5  # below the drive's 314 rad/s / 161 = 1.95 rad/s
TILT_TORQUE_NM = 980.0  # the drive's peak: 7.16 N m x 161 x 0.85
ROTATE_RANGE_RAD = 2.0 * math.pi  # a turn each way (the cables of the torch's earth clamp allow no more)
ROTATE_SPEED_RAD_S = 2.0  # below the drive's 314 rad/s / 121 = 2.6 rad/s
ROTATE_TORQUE_NM = 390.0  # the drive's peak: 3.8 N m x 121 x 0.85
CRADLE_MASS_KG = 60.0  # the cradle's welded frame, the rotary drive and its reducer
CRADLE_SIZE_M = (0.50, 0.50, 0.12)  # its box, centred CRADLE_DROP_M below the tilt axis
CRADLE_DROP_M = 0.05
TABLE_RADIUS_M, TABLE_THICKNESS_M = 0.30, 0.025  # a steel face plate 600 mm across
STEEL_KG_M3 = 7850.0
PART_RADIUS_M, PART_HEIGHT_M, PART_WALL_M = 0.20, 0.30, 0.008  # the vessel: 400 mm across, 300 mm tall, 8 mm walls
PEDESTAL_SIZE_M = (0.40, 0.60, 0.50)  # the pedestal's box, its top below the cradle


def box_inertia(mass_kg: float, size_m: tuple[float, float, float]) -> tuple[float, float, float]:
    """A solid box's principal moments about its centre (kg m^2)."""
    a, b, c = size_m
    return mass_kg * (b * b + c * c) / 12, mass_kg * (a * a + c * c) / 12, mass_kg * (a * a + b * b) / 12


def disc_inertia(mass_kg: float, radius_m: float, thickness_m: float) -> tuple[float, float, float]:
    """A solid disc's (cylinder's) principal moments about its centre, its axis along z (kg m^2)."""
    across = mass_kg * (3 * radius_m ** 2 + thickness_m ** 2) / 12
    return across, across, mass_kg * radius_m ** 2 / 2


def table_mass_kg() -> float:
    """The face plate's mass (kg)."""
    return STEEL_KG_M3 * math.pi * TABLE_RADIUS_M ** 2 * TABLE_THICKNESS_M


def part_mass_inertia() -> tuple[float, tuple[float, float, float]]:
    """The vessel's mass (kg) and principal moments about its centre (kg m^2): a thin cylindrical wall and two
    thin end discs of the same sheet."""
    r, h, t = PART_RADIUS_M, PART_HEIGHT_M, PART_WALL_M
    wall = STEEL_KG_M3 * 2 * math.pi * r * h * t
    end = STEEL_KG_M3 * math.pi * r * r * t
    axial = wall * r * r + 2 * end * r * r / 2
    across = wall * (r * r / 2 + h * h / 12) + 2 * (end * r * r / 4 + end * (h / 2) ** 2)
    return wall + 2 * end, (across, across, axial)


def _inertial(link: ElementTree.Element, mass_kg: float, centre_z_m: float, moments: tuple[float, float, float]) -> None:
    inertial = ElementTree.SubElement(link, "inertial")
    ElementTree.SubElement(inertial, "origin", xyz=f"0 0 {centre_z_m!r}", rpy="0 0 0")
    ElementTree.SubElement(inertial, "mass", value=repr(mass_kg))
    ElementTree.SubElement(inertial, "inertia", ixx=repr(moments[0]), ixy="0", ixz="0", iyy=repr(moments[1]), iyz="0",
                           izz=repr(moments[2]))


def shape_link(name: str, shape: str, size: dict[str, str], centre_z_m: float) -> ElementTree.Element:
    """A link drawn as a box or cylinder centred ``centre_z_m`` above its frame (visual and collision)."""
    link = ElementTree.Element("link", name=name)
    for kind in ("visual", "collision"):
        element = ElementTree.SubElement(link, kind)
        ElementTree.SubElement(element, "origin", xyz=f"0 0 {centre_z_m!r}", rpy="0 0 0")
        ElementTree.SubElement(ElementTree.SubElement(element, "geometry"), shape, size)
    return link


def joint(name: str, kind: str, parent: str, child: str, xyz: str, axis: str | None = None,
          limits: tuple[float, float, float] | None = None) -> ElementTree.Element:
    """A URDF joint; ``limits`` (range, effort, speed) for a moving one."""
    element = ElementTree.Element("joint", name=name, type=kind)
    ElementTree.SubElement(element, "parent", link=parent)
    ElementTree.SubElement(element, "child", link=child)
    ElementTree.SubElement(element, "origin", xyz=xyz, rpy="0 0 0")
    if axis is not None and limits is not None:
        ElementTree.SubElement(element, "axis", xyz=axis)
        ElementTree.SubElement(element, "limit", lower=repr(-limits[0]), upper=repr(limits[0]), effort=repr(limits[1]),
                               velocity=repr(limits[2]))
    return element


def positioner() -> list[ElementTree.Element]:
    """The positioner's links and joints, from ``world``."""
    box = {"size": " ".join(repr(s) for s in CRADLE_SIZE_M)}
    cradle = shape_link("positioner_cradle", "box", box, -CRADLE_DROP_M)
    _inertial(cradle, CRADLE_MASS_KG, -CRADLE_DROP_M, box_inertia(CRADLE_MASS_KG, CRADLE_SIZE_M))
    plate = {"radius": repr(TABLE_RADIUS_M), "length": repr(TABLE_THICKNESS_M)}
    table = shape_link("positioner_table", "cylinder", plate, -TABLE_THICKNESS_M / 2)
    _inertial(table, table_mass_kg(), -TABLE_THICKNESS_M / 2, disc_inertia(table_mass_kg(), TABLE_RADIUS_M,
                                                                            TABLE_THICKNESS_M))
    vessel = {"radius": repr(PART_RADIUS_M), "length": repr(PART_HEIGHT_M)}
    part = shape_link("workpiece", "cylinder", vessel, -PART_HEIGHT_M / 2)
    mass, moments = part_mass_inertia()
    _inertial(part, mass, -PART_HEIGHT_M / 2, moments)
    pedestal_z = -CRADLE_DROP_M - CRADLE_SIZE_M[2] / 2 - PEDESTAL_SIZE_M[2] / 2 - 0.05
    pedestal = shape_link("positioner_pedestal", "box", {"size": " ".join(repr(s) for s in PEDESTAL_SIZE_M)}, pedestal_z)
    axis = " ".join(repr(c) for c in TILT_AXIS_M)
    return [pedestal, joint("positioner_pedestal_fixed", "fixed", "world", "positioner_pedestal", axis),
            cradle, joint("tilt", "revolute", "positioner_pedestal", "positioner_cradle", "0 0 0", "0 1 0",
                          (TILT_RANGE_RAD, TILT_TORQUE_NM, TILT_SPEED_RAD_S)),
            table, joint("rotate", "revolute", "positioner_cradle", "positioner_table", f"0 0 {RISE_M!r}", "0 0 1",
                         (ROTATE_RANGE_RAD, ROTATE_TORQUE_NM, ROTATE_SPEED_RAD_S)),
            part, joint("workpiece_fixed", "fixed", "positioner_table", "workpiece", f"0 0 {PART_HEIGHT_M!r}")]


def positioner_urdf() -> str:
    """The URDF text of the UR5 beside its positioner."""
    root = ElementTree.parse(erd_urdf_path(ROBOTS["ur5"])).getroot()
    root.set("name", "ur5_positioner")
    mount = next(element for element in root.findall("joint") if element.get("name") == "world_joint")
    parent = mount.find("parent")
    assert parent is not None and parent.get("link") == "world", "example-robot-data's UR5 changed its root"
    at = list(root).index(mount) + 1
    for offset, element in enumerate(positioner()):
        root.insert(at + offset, element)
    ElementTree.indent(root, space="  ")
    header = ("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Written by make_urdf.py from example-robot-data's "
              "ur5_robot.urdf: the UR5 beside a 2-axis tilt-rotate positioner (its numbers: ur5_positioner.yaml, "
              "sources). -->\n")
    return header + ElementTree.tostring(root, encoding="unicode") + "\n"


if __name__ == "__main__":
    target = Path(__file__).with_name("ur5_positioner.urdf")
    target.write_text(positioner_urdf(), encoding="utf-8")
    print(f"wrote {target}")

"""Write ``ur5_track.urdf``: the UR5 of example-robot-data on a 2 m linear track.

Run ``python make_urdf.py`` in this folder after changing a number below (or after example-robot-data
changes its UR5); the test suite checks that the committed URDF is what this script writes. The
numbers' sources are under ``sources`` in ``ur5_track.yaml``.

The UR5 is example-robot-data's ``ur5_robot.urdf`` unchanged (links, joints, inertials, limits, and
its meshes, named ``package://example-robot-data/...``), but for its root: the fixed ``world_joint``
that held ``base_link`` to ``world`` now holds it to the track's carriage. The track adds, under the
UR5's base:

- ``track_rail``: the rail, fixed to ``world`` below the UR5's base plane (a box, for the scene);
- ``track``: a prismatic joint along ``world``'s y axis, the carriage's travel, 0 at the rail's middle,
  where the UR5's base stands as the plain ``ur5`` robot's does (``--lock track=0`` is that robot);
- ``track_carriage``: the carriage plate, with the guide blocks and the drive (motor, gearbox and
  pinion) that ride on it; the UR5's ``base_link`` is bolted on its top face, at the joint's origin.

The UR5's front (its reference posture reaches along +x) faces away from the rail: the track carries
the arm along a workpiece lying in front of it.
"""

from __future__ import annotations

from pathlib import Path
from xml.etree import ElementTree

from example_robot_data.robots_loader import ROBOTS

from placement.robot.urdf import erd_urdf_path

STROKE_M = 2.0  # the carriage's travel, centred on the UR5's place as the plain ur5 robot
TRACK_SPEED_M_S = 1.5  # the track's top speed (the drive's 3000 rpm through 5:1 and a 30 mm pinion is 1.88 m/s)
TRACK_FORCE_N = 1190.0  # the drive's peak thrust: 7.16 N m x 5 / 0.030 m
CARRIAGE_MASS_KG = 20.0  # plate 13.5 kg, four guide blocks 2.4 kg, motor 3 kg and gearbox 1.5 kg with pinion
CARRIAGE_SIZE_M = (0.50, 0.40, 0.06)  # x (across the rail), y (along it), z: the carriage's box, its top at z = 0
RAIL_SIZE_M = (0.30, STROKE_M + CARRIAGE_SIZE_M[1], 0.12)  # the rail's box under the carriage, for the scene


def box_inertia(mass_kg: float, size_m: tuple[float, float, float]) -> dict[str, str]:
    """A solid box's inertia about its centre (kg m^2), as URDF ``<inertia>`` attributes."""
    a, b, c = size_m
    moments = (mass_kg * (b * b + c * c) / 12, mass_kg * (a * a + c * c) / 12, mass_kg * (a * a + b * b) / 12)
    return {"ixx": repr(moments[0]), "ixy": "0", "ixz": "0", "iyy": repr(moments[1]), "iyz": "0", "izz": repr(moments[2])}


def box_link(name: str, size_m: tuple[float, float, float], centre_z_m: float, mass_kg: float | None) -> ElementTree.Element:
    """A link drawn as a box centred ``centre_z_m`` below its frame, with the box's inertia when it has a mass."""
    link = ElementTree.Element("link", name=name)
    size, origin = " ".join(repr(s) for s in size_m), f"0 0 {centre_z_m!r}"
    for kind in ("visual", "collision"):
        element = ElementTree.SubElement(link, kind)
        ElementTree.SubElement(element, "origin", xyz=origin, rpy="0 0 0")
        ElementTree.SubElement(ElementTree.SubElement(element, "geometry"), "box", size=size)
    if mass_kg is not None:
        inertial = ElementTree.SubElement(link, "inertial")
        ElementTree.SubElement(inertial, "origin", xyz=origin, rpy="0 0 0")
        ElementTree.SubElement(inertial, "mass", value=repr(mass_kg))
        ElementTree.SubElement(inertial, "inertia", box_inertia(mass_kg, size_m))
    return link


def track_urdf() -> str:
    """The URDF text of the UR5 on its track."""
    root = ElementTree.parse(erd_urdf_path(ROBOTS["ur5"])).getroot()
    root.set("name", "ur5_track")
    mount = next(joint for joint in root.findall("joint") if joint.get("name") == "world_joint")
    parent = mount.find("parent")
    assert parent is not None and parent.get("link") == "world", "example-robot-data's UR5 changed its root"
    parent.set("link", "track_carriage")
    carriage_z = -CARRIAGE_SIZE_M[2] / 2
    rail_z = -CARRIAGE_SIZE_M[2] - RAIL_SIZE_M[2] / 2
    rail = ElementTree.Element("joint", name="track_rail_fixed", type="fixed")
    ElementTree.SubElement(rail, "parent", link="world")
    ElementTree.SubElement(rail, "child", link="track_rail")
    ElementTree.SubElement(rail, "origin", xyz="0 0 0", rpy="0 0 0")
    track = ElementTree.Element("joint", name="track", type="prismatic")
    ElementTree.SubElement(track, "parent", link="world")
    ElementTree.SubElement(track, "child", link="track_carriage")
    ElementTree.SubElement(track, "origin", xyz="0 0 0", rpy="0 0 0")
    ElementTree.SubElement(track, "axis", xyz="0 1 0")
    ElementTree.SubElement(track, "limit", lower=repr(-STROKE_M / 2), upper=repr(STROKE_M / 2),
                           effort=repr(TRACK_FORCE_N), velocity=repr(TRACK_SPEED_M_S))
    added = [box_link("track_rail", RAIL_SIZE_M, rail_z, None), rail,
             box_link("track_carriage", CARRIAGE_SIZE_M, carriage_z, CARRIAGE_MASS_KG), track]
    at = list(root).index(mount)
    for offset, element in enumerate(added):
        root.insert(at + offset, element)
    ElementTree.indent(root, space="  ")
    header = ("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<!-- Written by make_urdf.py from example-robot-data's "
              "ur5_robot.urdf: the UR5 on a 2 m linear track (the track's numbers: ur5_track.yaml, sources). -->\n")
    return header + ElementTree.tostring(root, encoding="unicode") + "\n"


if __name__ == "__main__":
    target = Path(__file__).with_name("ur5_track.urdf")
    target.write_text(track_urdf(), encoding="utf-8")
    print(f"wrote {target}")

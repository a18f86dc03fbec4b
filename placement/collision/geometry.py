"""The collision geometry of a robot in a cell: its links, its tool and the cell's bodies in one Pinocchio GeometryModel.

A link's shapes are its URDF ``<collision>`` elements; a link that has none but has ``<visual>``
elements uses those (the built-in Orthoglide, Delta and five-bar describe visuals only). Meshes
become their convex hulls (coal's ``buildConvexHull``): a hull encloses its mesh, so every distance
is a lower bound of the distance between the meshes themselves, the safe side. Cell bodies are
fixed to the base (joint 0); the tool rides on its mount frame's joint.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from xml.etree import ElementTree

import coal
import numpy as np
import pinocchio as pin

from placement.cell.cell_file import BoxShape, Cell, CylinderShape, MeshShape, Shape, SphereShape, ToolBody, mesh_path
from placement.cell.exceptions import CellFileError
from placement.exceptions import InputFileError
from placement.robot.equip import tool_of
from placement.robot.exceptions import RobotFileError
from placement.robot.model import Robot
from placement.robot.packages import description_geometry
from placement.robot.tool import declaring_file_error, pose_placement, tool_mount

LINK, TOOL, OBSTACLE, KEEP_OUT = "link", "tool", "obstacle", "keep_out"
Declared = tuple[Path, str, type[InputFileError]]  # the file declaring a shape, its field there, and the error to raise


@dataclass(frozen=True)
class Body:
    """A named rigid body of the collision scene.

    Attributes:
        name: A URDF link's name, the tool's name, or a cell body's name.
        kind: "link", "tool", "obstacle" or "keep_out".
        joint: The Pinocchio joint that moves it (0: fixed to the base).
        objects: Indices of its shapes in the geometry model.
        declared: Its shapes are declared for collisions (a URDF link's <collision> elements, a tool's
            shape, a cell body), rather than drawings standing in for them (a link's <visual>
            elements): only declared robot bodies are checked against each other.
    """

    name: str
    kind: str
    joint: int
    objects: tuple[int, ...]
    declared: bool = True

    @property
    def is_robot(self) -> bool:
        """A link or the tool (as opposed to a cell body)."""
        return self.kind in (LINK, TOOL)


@dataclass(frozen=True)
class SceneGeometry:
    """The geometry model of a robot, its tool and a cell, grouped into bodies.

    Attributes:
        geometry_model: Every shape (meshes as convex hulls), robot links first.
        bodies: The bodies, links first, then the tool, then the cell's bodies.
        notices: What the user should know about the geometry (visuals used, convex hulls), one line each.
    """

    geometry_model: pin.GeometryModel
    bodies: tuple[Body, ...]
    notices: tuple[str, ...]


def build_geometry(robot: Robot, cell: Cell | None) -> SceneGeometry:
    """The collision geometry of ``robot`` carrying its tool (see :func:`placement.robot.equip.tool_of`) in ``cell``.

    Args:
        robot: The robot (its model may be reduced by locked joints).
        cell: The cell, or None for the robot and its tool alone.

    Raises:
        RobotFileError: A mesh of the URDF cannot be found or read.
        InputFileError: A cell or tool body reuses a link's name, or its mesh cannot be read (the
            message names the file and the field).
    """
    geometry_model, used_visuals = _robot_geometry(robot)
    notices = []
    if used_visuals:
        notices.append(f"robot '{robot.name}': {len(used_visuals)} link(s) have no <collision> element; their "
                       f"<visual> shapes stand in for them against the cell, but drawings are not clearances, so "
                       f"they are not checked against the robot's other bodies ({_listed(used_visuals)})")
    bodies = _link_bodies(robot.model, geometry_model, set(used_visuals))
    tool = tool_of(robot, cell)
    if tool is not None:
        bodies += _tool_bodies(robot, *tool, geometry_model, {body.name for body in bodies})
    if cell is not None:
        bodies += _cell_bodies(cell, geometry_model, {body.name for body in bodies})
    if any(item.meshPath.lower().endswith((".stl", ".obj", ".dae")) for item in geometry_model.geometryObjects):
        notices.append("meshes are checked as their convex hulls, which enclose them: distances are lower bounds "
                       "of the distances between the meshes (the safe side)")
    return SceneGeometry(geometry_model, tuple(bodies), tuple(notices))


def _robot_geometry(robot: Robot) -> tuple[pin.GeometryModel, list[str]]:
    """The links' collision shapes (visual shapes for links without any), meshes as hulls; and the links that
    use their visuals."""
    declared = _declared_shapes(robot.urdf_path)
    used_visuals = sorted(link for link, (collision, visual) in declared.items() if visual and not collision)
    geometry_model = description_geometry(robot, pin.GeometryType.COLLISION)
    if used_visuals:
        visual = description_geometry(robot, pin.GeometryType.VISUAL)
        for item in visual.geometryObjects:
            if robot.model.frames[item.parentFrame].name in used_visuals:
                geometry_model.addGeometryObject(item)
    for item in geometry_model.geometryObjects:
        if isinstance(item.geometry, coal.BVHModelBase):
            item.geometry = _hull(item.geometry, robot.urdf_path, f"link '{robot.model.frames[item.parentFrame].name}'")
    return geometry_model, used_visuals


def _declared_shapes(urdf_path: Path) -> dict[str, tuple[bool, bool]]:
    """Whether each URDF link declares collision shapes and visual shapes."""
    root = ElementTree.parse(urdf_path).getroot()  # the robot loaded: the file parses
    return {str(link.get("name")): (link.find("collision") is not None, link.find("visual") is not None)
            for link in root.findall("link")}


def _hull(mesh: coal.BVHModelBase, path: Path, field: str) -> coal.ConvexBase:
    """The convex hull of a mesh's vertices."""
    try:
        mesh.buildConvexHull(True, "Qt")
    except (RuntimeError, ValueError) as error:
        raise RobotFileError(path, field, f"cannot take the convex hull of its mesh: {str(error)[:200]}") from None
    return mesh.convex


def _link_bodies(model: pin.Model, geometry_model: pin.GeometryModel, drawn_only: set[str]) -> list[Body]:
    """One body per link that has shapes, in the order of their first shape; ``drawn_only`` links use visuals."""
    shapes: dict[str, list[int]] = {}
    for index, item in enumerate(geometry_model.geometryObjects):
        shapes.setdefault(model.frames[item.parentFrame].name, []).append(index)
    return [Body(name, LINK, int(geometry_model.geometryObjects[indices[0]].parentJoint), tuple(indices),
                 declared=name not in drawn_only) for name, indices in shapes.items()]


def _tool_bodies(robot: Robot, tool: ToolBody, source: Path, geometry_model: pin.GeometryModel,
                 taken: set[str]) -> list[Body]:
    """The tool as a body on its mount joint (none when it has no collision shape)."""
    if tool.collision is None:
        return []
    error = declaring_file_error(robot, source)
    if tool.name in taken:
        raise error(source, "tool.name", f"'{tool.name}' is also a link of robot '{robot.name}': give the tool "
                    "another name")
    joint, joint_M_tool = tool_mount(robot, tool, source)
    index = _add(geometry_model, tool.name, joint, joint_M_tool, tool.collision, (source, "tool.collision", error))
    return [Body(tool.name, TOOL, joint, (index,))]


def _cell_bodies(cell: Cell, geometry_model: pin.GeometryModel, taken: set[str]) -> list[Body]:
    """The cell's obstacles and keep-out zones, fixed to the base."""
    bodies = []
    for name, (field, shape) in cell.bodies().items():
        if name in taken:
            raise CellFileError(cell.path, field, f"'{name}' is also the name of a robot link or of the tool: give "
                                "the body another name")
        index = _add(geometry_model, name, 0, pin.SE3.Identity(), shape, (cell.path, field, CellFileError))
        bodies.append(Body(name, OBSTACLE if field.startswith("obstacles.") else KEEP_OUT, 0, (index,)))
    return bodies


def _add(geometry_model: pin.GeometryModel, name: str, joint: int, joint_M_frame: pin.SE3, shape: Shape,
         declared: Declared) -> int:
    """Add ``shape`` (posed in a frame at ``joint_M_frame`` in ``joint``) to the model; returns its index."""
    geometry, mesh = coal_shape(shape, *declared)
    item = pin.GeometryObject(name, joint, joint_M_frame * pose_placement(shape), geometry)
    if mesh is not None:
        item.meshPath = str(mesh)
    return int(geometry_model.addGeometryObject(item))


def coal_shape(shape: Shape, source: Path, field: str,
               error: type[InputFileError]) -> tuple[coal.CollisionGeometry, Path | None]:
    """The coal geometry of a shape in its own frame (a mesh as its convex hull), and the mesh file if any.

    Args:
        shape: The shape.
        source: The file that declares it (a mesh file is relative to its folder).
        field: Where in that file, for errors.
        error: The error to raise (CellFileError, or RobotFileError for a sidecar's tool).

    Raises:
        InputFileError: (as ``error``) the mesh cannot be read or has no volume.
    """
    if isinstance(shape, BoxShape):
        return coal.Box(*shape.size_m), None
    if isinstance(shape, CylinderShape):
        return coal.Cylinder(shape.radius_m, shape.length_m), None
    if isinstance(shape, SphereShape):
        return coal.Sphere(shape.radius_m), None
    assert isinstance(shape, MeshShape)
    path = mesh_path(source.parent, shape)
    try:
        mesh = coal.MeshLoader().load(str(path), np.array(shape.scale_xyz))
        mesh.buildConvexHull(True, "Qt")
    except (RuntimeError, ValueError) as problem:
        raise error(source, f"{field}.file", f"cannot read {path} as a mesh with a volume: {str(problem)[:200]}") from None
    return mesh.convex, path


def _listed(names: Sequence[str], most: int = 8) -> str:
    return ", ".join(names[:most]) + (f", ... ({len(names) - most} more)" if len(names) > most else "")

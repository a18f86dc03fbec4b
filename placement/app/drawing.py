"""The robot as the workbench draws it: its URDF visuals and its cell's shapes as viser meshes, posed by q."""

from __future__ import annotations

import functools
from typing import Any

import numpy as np
import pinocchio as pin
import viser  # optional dependency: the [app] extra, checked by placement.app

from placement.limits.collision import collision_scene
from placement.output.palette import ARM_COLOR, CELL_COLORS, rgb, rgb_255
from placement.robot.model import Robot
from placement.robot.packages import description_geometry

PARALLEL_OPACITY = 0.35  # a parallel robot's platform: the path and the tool point stay in sight inside it
ARM_OPACITY = 0.6  # a serial arm: seen on the white page, the workpiece behind its wrist still in sight
PALE = 150  # a grey mesh colour whose channels all exceed this is drawn tinted instead (white arms on a white page)
PARALLEL_TINT = (120, 140, 170)  # a parallel robot's pale parts, beside its own blue and orange
CELL_OPACITY = {"tool": 1.0, "obstacle": 0.5, "keep_out": 0.15}


def wxyz_of(rotation: np.ndarray) -> np.ndarray:
    """A rotation matrix as viser's quaternion (w, x, y, z)."""
    quaternion = pin.Quaternion(np.asarray(rotation, dtype=float))
    return np.array([quaternion.w, quaternion.x, quaternion.y, quaternion.z])


SNAP_M, SNAP_RAD = 1e-3, float(np.radians(1.0))  # a drag snapped to whole millimetres and degrees


def snapped(placement: np.ndarray) -> np.ndarray:
    """A placement rounded to whole millimetres (x, y, z) and degrees (phi, theta, psi); m and rad."""
    step = np.array([SNAP_M] * 3 + [SNAP_RAD] * 3)
    return np.round(np.asarray(placement, dtype=float) / step) * step


def rotation_of(wxyz: np.ndarray) -> np.ndarray:
    """viser's quaternion (w, x, y, z) as a rotation matrix."""
    w, x, y, z = (float(v) for v in wxyz)
    return pin.Quaternion(w, x, y, z).normalized().toRotationMatrix()


def own_color(robot: Robot, mesh_color: np.ndarray) -> tuple[int, int, int]:
    """The colour a body of the live robot is drawn in: its description's, a pale grey tinted (a serial arm in the
    palette's ARM_COLOR, apart from the workpiece's magenta and the ghosts' green and vermillion)."""
    red, green, blue = (int(255 * c) for c in mesh_color[:3])
    if min(red, green, blue) > PALE and max(red, green, blue) - min(red, green, blue) < 24:
        return rgb_255(ARM_COLOR) if robot.is_serial else PARALLEL_TINT
    return red, green, blue


@functools.lru_cache(maxsize=128)
def mesh_arrays(path: str, scale: tuple[float, float, float]) -> tuple[np.ndarray, np.ndarray]:
    """A mesh file's vertices (float32, scaled) and faces (uint32), read once for every drawing of the robot."""
    import trimesh  # optional dependency: the [app] extra, checked by placement.app

    mesh: Any = trimesh.load(path, force="mesh")
    mesh.apply_scale(np.asarray(scale))
    return np.asarray(mesh.vertices, dtype=np.float32), np.asarray(mesh.faces, dtype=np.uint32)


class RobotDrawing:
    """The robot's URDF visuals (and its cell's shapes, as they are checked) as viser meshes, posed by q.

    Args:
        server: The page's viser server.
        robot: The robot.
        name: The scene node the bodies are drawn under.
        color: One colour for every body (a ghost), or None: each body in its own (see :func:`own_color`).
        opacity: One opacity for every body, or None: a parallel robot's see-through, a serial arm's nearly opaque.
        cell: Draw the cell's fixed bodies too (obstacles, keep-out zones); a tool is drawn either way.
    """

    def __init__(self, server: viser.ViserServer, robot: Robot, name: str = "/robot",
                 color: tuple[int, int, int] | None = None, opacity: float | None = None, cell: bool = True) -> None:
        self.robot = robot
        self.model = robot.model
        self.visual = description_geometry(robot, pin.GeometryType.VISUAL)
        own_opacity: dict[int, float] = {}
        if robot.cell is not None or robot.tool is not None:
            collision = collision_scene(robot)
            for body in collision.bodies:
                if body.kind == "link" or not (cell or body.is_robot):
                    continue
                for index in body.objects:
                    item = collision.geometry_model.geometryObjects[index].copy()
                    item.meshColor = np.array([*rgb(CELL_COLORS[body.kind][0]), CELL_OPACITY[body.kind]])
                    own_opacity[self.visual.addGeometryObject(item)] = CELL_OPACITY[body.kind]
        self.data, self.geometry_data = self.model.createData(), self.visual.createData()
        robot_opacity = ARM_OPACITY if robot.is_serial else PARALLEL_OPACITY
        self.handles: list[tuple[int, Any]] = []
        for k, item in enumerate(self.visual.geometryObjects):
            alpha = opacity if opacity is not None else own_opacity.get(k, robot_opacity * (float(item.meshColor[3]) or 1.0))
            handle = self._add(server, f"{name}/{k}", item, color or own_color(robot, item.meshColor), alpha)
            if handle is not None:
                self.handles.append((k, handle))
        self.pose(robot.reference_q)

    @staticmethod
    def _add(server: viser.ViserServer, name: str, item: Any, color: tuple[int, int, int], alpha: float) -> Any:
        """One body as a viser node (None: a shape that cannot be drawn)."""
        scene: Any = server.scene  # viser's own annotations are narrower than what it takes
        geometry, kind = item.geometry, type(item.geometry).__name__
        if kind == "Box":
            return scene.add_box(name, color=color, dimensions=tuple(2 * np.asarray(geometry.halfSide)), opacity=alpha)
        if kind == "Cylinder":
            return scene.add_cylinder(name, radius=geometry.radius, height=2 * geometry.halfLength, color=color,
                                      opacity=alpha)
        if kind == "Sphere":
            return scene.add_icosphere(name, radius=geometry.radius, color=color, opacity=alpha)
        if item.meshPath and not item.meshPath.startswith("BV"):
            vertices, faces = mesh_arrays(item.meshPath, tuple(float(s) for s in item.meshScale))
            return scene.add_mesh_simple(name, vertices, faces, color=color, opacity=alpha)
        import trimesh  # optional dependency: the [app] extra, checked by placement.app

        try:  # a convex hull or another shape of the collision scene: its vertices' hull
            hull = trimesh.Trimesh(np.array([geometry.points(i) for i in range(geometry.num_points)])).convex_hull
        except (AttributeError, RuntimeError, ValueError, IndexError):
            return None
        return scene.add_mesh_simple(name, np.asarray(hull.vertices, dtype=np.float32),
                                     np.asarray(hull.faces, dtype=np.uint32), color=color, opacity=alpha)

    def pose(self, q: np.ndarray) -> None:
        """Place every drawn body at the configuration q."""
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        pin.updateGeometryPlacements(self.model, self.data, self.visual, self.geometry_data)
        for k, handle in self.handles:
            placement = self.geometry_data.oMg[k]
            handle.position = tuple(placement.translation)
            handle.wxyz = tuple(wxyz_of(placement.rotation))

    @property
    def visible(self) -> bool:
        """Whether the bodies are shown."""
        return all(handle.visible for _, handle in self.handles)

    @visible.setter
    def visible(self, shown: bool) -> None:
        for _, handle in self.handles:
            handle.visible = shown

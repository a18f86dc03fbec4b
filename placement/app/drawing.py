"""The robot as the workbench draws it: its URDF visuals and its cell's shapes as viser meshes, posed by q."""

from __future__ import annotations

from typing import Any

import numpy as np
import pinocchio as pin
import viser  # optional dependency: the [app] extra, checked by placement.app

from placement.limits.collision import collision_scene
from placement.output.palette import CELL_COLORS, rgb
from placement.robot.model import Robot
from placement.robot.packages import description_geometry

ROBOT_OPACITY = 0.35  # the path and the tool point stay in sight inside the moving platform
PALE = 150  # a grey mesh colour whose channels all exceed this is drawn ROBOT_TINT instead (white arms on a white page)
ROBOT_TINT = (120, 140, 170)
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


class RobotDrawing:
    """The robot's URDF visuals (and its cell's shapes, as they are checked) as viser meshes, posed by q."""

    def __init__(self, server: viser.ViserServer, robot: Robot) -> None:
        import trimesh  # optional dependency: the [app] extra, checked by placement.app

        self.robot = robot
        self.model = robot.model
        self.visual = description_geometry(robot, pin.GeometryType.VISUAL)
        opacity: dict[int, float] = {}
        scene: Any = server.scene  # viser's own annotations are narrower than what it takes
        if robot.cell is not None or robot.tool is not None:
            checked = collision_scene(robot)  # not ``scene``: viser's, which draws them below
            for body in checked.bodies:
                if body.kind == "link":
                    continue
                for index in body.objects:
                    item = checked.geometry_model.geometryObjects[index].copy()
                    item.meshColor = np.array([*rgb(CELL_COLORS[body.kind][0]), CELL_OPACITY[body.kind]])
                    opacity[self.visual.addGeometryObject(item)] = CELL_OPACITY[body.kind]
        self.data, self.geometry_data = self.model.createData(), self.visual.createData()
        self.handles: list[tuple[int, Any]] = []
        for k, item in enumerate(self.visual.geometryObjects):
            geometry, color = item.geometry, tuple(int(255 * c) for c in item.meshColor[:3])
            color = ROBOT_TINT if min(color) > PALE and max(color) - min(color) < 24 else color
            name, alpha = f"/robot/{k}", opacity.get(k, ROBOT_OPACITY * (float(item.meshColor[3]) or 1.0))
            kind = type(geometry).__name__
            if kind == "Box":
                handle = scene.add_box(name, color=color, dimensions=tuple(2 * np.asarray(geometry.halfSide)),
                                              opacity=alpha)
            elif kind == "Cylinder":
                handle = scene.add_cylinder(name, radius=geometry.radius, height=2 * geometry.halfLength,
                                                   color=color, opacity=alpha)
            elif kind == "Sphere":
                handle = scene.add_icosphere(name, radius=geometry.radius, color=color, opacity=alpha)
            elif item.meshPath and not item.meshPath.startswith("BV"):
                mesh: Any = trimesh.load(item.meshPath, force="mesh")
                mesh.apply_scale(np.asarray(item.meshScale))
                handle = scene.add_mesh_simple(name, np.asarray(mesh.vertices, dtype=np.float32),
                                                      np.asarray(mesh.faces, dtype=np.uint32), color=color,
                                                      opacity=alpha)
            else:  # a convex hull or another shape of the collision scene: its vertices' hull
                try:
                    points = np.array([geometry.points(i) for i in range(geometry.num_points)])
                    hull = trimesh.Trimesh(points).convex_hull
                    handle = scene.add_mesh_simple(name, np.asarray(hull.vertices, dtype=np.float32),
                                                          np.asarray(hull.faces, dtype=np.uint32), color=color,
                                                          opacity=alpha)
                except (AttributeError, RuntimeError, ValueError, IndexError):
                    continue
            self.handles.append((k, handle))
        self.pose(robot.reference_q)

    def pose(self, q: np.ndarray) -> None:
        """Place every drawn body at the configuration q."""
        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        pin.updateGeometryPlacements(self.model, self.data, self.visual, self.geometry_data)
        for k, handle in self.handles:
            placement = self.geometry_data.oMg[k]
            handle.position = tuple(placement.translation)
            handle.wxyz = tuple(wxyz_of(placement.rotation))

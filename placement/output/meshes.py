"""Geometry sent to meshcat's viewer: mesh files drawn whole, and tubes for lines WebGL would draw 1 px wide.

meshcat 0.3.2's viewer merges the meshes of a Collada file into one geometry and, when they carry
several materials, gives it an array of materials that it then fails to draw for part of the groups
(on example-robot-data's UR5, 24–31 % of the shoulder, upper-arm and wrist triangles were missing:
the dark joint housings). :class:`WholeMeshVisualizer` reads each mesh file itself (trimesh: the
file's scene graph, its units and its materials) and sends one plain triangle mesh per colour, with
the file's normals, under the visual's node: Pinocchio's visualiser still poses that node, so every
visual keeps its exact placement, and every triangle of the file is drawn.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import cast

from placement.distribution import SCENE, require

# Optional dependencies: the [viz] extra, checked first so that a missing one is named with the extra that brings
# it; the imports below follow that check, not the top of the module.
# ruff: noqa: E402
require(SCENE)

import coal
import meshcat.geometry as g
import numpy as np
import pinocchio as pin
import trimesh
from pinocchio.visualize import MeshcatVisualizer

MESH_SUFFIXES = (".dae", ".stl", ".obj", ".ply")  # files read here; others are left to Pinocchio's visualiser


@dataclass(frozen=True)
class MeshPart:
    """The triangles of one colour of a mesh file, in the file's frame and units (as the URDF's scale expects).

    Attributes:
        vertices: (N, 3) vertex positions.
        faces: (M, 3) vertex indices of each triangle.
        normals: (N, 3) unit vertex normals.
        rgba: Colour and opacity, each in [0, 1].
    """

    vertices: np.ndarray
    faces: np.ndarray
    normals: np.ndarray
    rgba: tuple[float, float, float, float]


class NormalMeshGeometry(g.TriangularMeshGeometry):
    """A triangle mesh that carries its vertex normals (meshcat's own computes them, smoothing hard edges)."""

    def __init__(self, vertices: np.ndarray, faces: np.ndarray, normals: np.ndarray) -> None:
        super().__init__(vertices, faces)
        self.normals = np.asarray(normals, dtype=np.float32)

    def lower(self, object_data: dict) -> dict:
        data = super().lower(object_data)
        data["data"]["attributes"]["normal"] = g.pack_numpy_array(self.normals.T)
        return data


class OverlayMesh(g.Mesh):
    """A mesh drawn after everything else (three.js ``renderOrder``): with a material that skips the depth test,
    it shows through the robot; of two overlays, the higher ``render_order`` is drawn over the other."""

    def __init__(self, geometry: g.Geometry, material: g.Material, render_order: int = 10) -> None:
        super().__init__(geometry, material)
        self.render_order = render_order

    def lower(self) -> dict:
        data = super().lower()
        data["object"]["renderOrder"] = self.render_order
        return data


def overlay_material(color: int) -> g.MeshBasicMaterial:
    """An unlit colour drawn over whatever is in front of it (no depth test; transparent, so drawn last)."""
    return g.MeshBasicMaterial(color=color, transparent=True, opacity=1.0, depthTest=False, depthWrite=False)


def mesh_parts(path: Path, rgba: np.ndarray | None) -> list[MeshPart]:
    """The triangles of a mesh file grouped by colour.

    Args:
        path: A Collada, STL, OBJ or PLY file.
        rgba: The colour for the whole mesh (the URDF's material, or a cell's shape), or None for the file's own
            material colours (a file without any takes light grey).
    """
    groups: dict[tuple[float, ...], list[trimesh.Trimesh]] = {}
    for item in trimesh.load_scene(str(path), process=False).dump():  # the scene graph's placements applied
        if isinstance(item, trimesh.Trimesh) and len(item.faces):  # not a file's lines or points
            groups.setdefault(tuple(rgba) if rgba is not None else _file_color(item), []).append(item)
    parts = []
    for color, meshes in groups.items():
        mesh = meshes[0] if len(meshes) == 1 else cast(trimesh.Trimesh, trimesh.util.concatenate(meshes))
        parts.append(MeshPart(np.asarray(mesh.vertices), np.asarray(mesh.faces), np.asarray(mesh.vertex_normals),
                              (float(color[0]), float(color[1]), float(color[2]), float(color[3]))))
    return parts


def _file_color(mesh: trimesh.Trimesh) -> tuple[float, ...]:
    """The colour a file gives a mesh: its material's main colour, its vertex or face colours', or light grey."""
    visual = mesh.visual
    material = getattr(visual, "material", None)
    if material is not None:
        return tuple(np.asarray(material.main_color, dtype=float) / 255)
    if isinstance(visual, trimesh.visual.ColorVisuals) and visual.kind in ("face", "vertex"):
        return tuple(np.asarray(visual.main_color, dtype=float) / 255)
    return (0.9, 0.9, 0.9, 1.0)


def tube(segments_m: np.ndarray, radius_m: float, sides: int = 6) -> tuple[np.ndarray, np.ndarray]:
    """A thin prism around each segment, so that lines have a width on screen (WebGL ignores line widths).

    Args:
        segments_m: (M, 2, 3) segment ends (m).
        radius_m: The prisms' radius (m).
        sides: The prisms' number of sides.

    Returns:
        Vertices (M * 2 * sides, 3) and triangles (M * 2 * sides, 3): segment m's ring at its start, then at its
        end, each ring ``sides`` vertices.
    """
    segments = np.asarray(segments_m, dtype=float).reshape(-1, 2, 3)
    axis = segments[:, 1] - segments[:, 0]
    length = np.linalg.norm(axis, axis=1, keepdims=True)
    axis = np.where(length > 1e-12, axis / np.maximum(length, 1e-12), [[0.0, 0.0, 1.0]])  # a point: any axis
    helper = np.where(np.abs(axis[:, 2:3]) < 0.9, [[0.0, 0.0, 1.0]], [[1.0, 0.0, 0.0]])
    first = np.cross(axis, helper)
    first /= np.linalg.norm(first, axis=1, keepdims=True)
    second = np.cross(axis, first)
    angle = 2 * np.pi * np.arange(sides) / sides
    ring = radius_m * (np.cos(angle)[None, :, None] * first[:, None] + np.sin(angle)[None, :, None] * second[:, None])
    vertices = segments[:, :, None, :] + ring[:, None, :, :]  # (M, 2, sides, 3)
    k = np.arange(sides)
    start = (np.arange(len(segments)) * 2 * sides)[:, None]
    a, b = start + k, start + (k + 1) % sides  # this and the next vertex of the start ring
    faces = np.stack([np.stack([a, b, b + sides], -1), np.stack([a, b + sides, a + sides], -1)], axis=2)
    return vertices.reshape(-1, 3), faces.reshape(-1, 3)


class WholeMeshVisualizer(MeshcatVisualizer):
    """Pinocchio's meshcat visualiser, except that mesh files are sent as one triangle mesh per colour
    (:func:`mesh_parts`), children of the node the visualiser poses."""

    def loadViewerGeometryObject(self, geometry_object: pin.GeometryObject, geometry_type: pin.GeometryType,  # noqa: N802
                                 color: np.ndarray | None = None) -> None:
        path = Path(geometry_object.meshPath) if geometry_object.meshPath else None
        if (path is None or path.suffix.lower() not in MESH_SUFFIXES or not path.is_file()
                or not isinstance(geometry_object.geometry, coal.BVHModelBase)):  # a primitive, or a mesh's hull
            super().loadViewerGeometryObject(geometry_object, geometry_type, color)
            return
        override = np.asarray(geometry_object.meshColor) if geometry_object.overrideMaterial else None
        node = self.viewer[self.getViewerNodeName(geometry_object, geometry_type)]
        for k, part in enumerate(mesh_parts(path, override if color is None else np.asarray(color))):
            red, green, blue, alpha = part.rgba
            material = g.MeshPhongMaterial(color=int(red * 255) << 16 | int(green * 255) << 8 | int(blue * 255),
                                           transparent=alpha < 1.0, opacity=alpha)
            node[f"part_{k}"].set_object(g.Mesh(NormalMeshGeometry(part.vertices, part.faces, part.normals), material))

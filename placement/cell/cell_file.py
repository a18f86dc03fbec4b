"""Schema of a robot cell file (YAML): obstacles, keep-out zones, the workpiece region and a tool body.

Every pose is in the robot's base frame (a tool's in its mount frame): ``xyz_m`` (m) and
``rpy_rad`` (roll, pitch, yaw about fixed x, y, z axes, rad, as in URDF). A cylinder's axis is
its z axis. A mesh is an STL (or OBJ, DAE) file relative to the file that names it.

A cell file::

    margin_m: 0.01                 # clearance every robot body keeps from every obstacle (default 0.005 m)
    obstacles:
      table: {type: box, size_m: [1.2, 0.8, 0.04], xyz_m: [0.3, 0.0, -0.02]}
      post: {type: cylinder, radius_m: 0.05, length_m: 0.6, xyz_m: [0.5, 0.4, 0.3]}
    keep_out:                      # zones the robot must not enter (no margin)
      operator: {type: box, size_m: [0.6, 0.6, 2.0], xyz_m: [-0.8, 0.0, 1.0]}
    workpiece_region: {min_m: [0.3, -0.2, 0.0], max_m: [0.6, 0.2, 0.3]}
    ignore: [[base_link, table]]   # robot link / obstacle pairs that touch by design
    tool: {mass_kg: 2.0, ...}      # see ToolBody
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import AfterValidator, BeforeValidator, Field, model_validator

from placement.cell.exceptions import CellFileError
from placement.exceptions import InputFileError
from placement.schema import Number, Strict, Text, read_yaml

Positive = Annotated[Number, Field(gt=0.0)]
Vector3 = tuple[Number, Number, Number]
Name = Annotated[str, Field(min_length=1, max_length=80, pattern=r"^[A-Za-z0-9_.\-]+$")]
DEFAULT_MARGIN_M = 0.005


class Posed(Strict):
    """A pose in the enclosing frame: translation (m) and roll-pitch-yaw about fixed axes (rad)."""

    xyz_m: Vector3 = (0.0, 0.0, 0.0)
    rpy_rad: Vector3 = (0.0, 0.0, 0.0)


class BoxShape(Posed):
    """A box of edge lengths ``size_m`` (m) along its x, y, z axes, centred on its pose."""

    type: Literal["box"]
    size_m: tuple[Positive, Positive, Positive]


class CylinderShape(Posed):
    """A cylinder along its z axis, centred on its pose."""

    type: Literal["cylinder"]
    radius_m: Positive
    length_m: Positive


class SphereShape(Posed):
    """A sphere centred on its pose."""

    type: Literal["sphere"]
    radius_m: Positive


class MeshShape(Posed):
    """A mesh file (STL, OBJ, DAE) relative to the file that names it, scaled (per axis, or one factor).

    Collision checking uses the convex hull of its vertices, which encloses the mesh.
    """

    type: Literal["mesh"]
    file: Annotated[str, Field(min_length=1, max_length=500)]
    scale: Positive | tuple[Positive, Positive, Positive] = 1.0

    @property
    def scale_xyz(self) -> tuple[float, float, float]:
        """The scale factor along each axis."""
        return self.scale if isinstance(self.scale, tuple) else (self.scale,) * 3


Shape = Annotated[BoxShape | CylinderShape | SphereShape | MeshShape, Field(discriminator="type")]


class Region(Strict):
    """An axis-aligned box in the base frame (m)."""

    min_m: Vector3
    max_m: Vector3

    @model_validator(mode="after")
    def _ordered(self) -> Region:
        if any(low >= high for low, high in zip(self.min_m, self.max_m)):
            raise ValueError(f"min_m {list(self.min_m)} must be below max_m {list(self.max_m)} on every axis")
        return self


def _inertia_rows(value: Any) -> Any:
    """Six numbers [ixx, iyy, izz, ixy, ixz, iyz] as the three rows of the symmetric tensor; three rows as they are."""
    if isinstance(value, (list, tuple)) and len(value) == 6:
        xx, yy, zz, xy, xz, yz = value
        return ((xx, xy, xz), (xy, yy, yz), (xz, yz, zz))
    if isinstance(value, (list, tuple)) and len(value) == 3 and all(isinstance(row, (list, tuple)) for row in value):
        return value
    raise ValueError(f"expected six numbers [ixx, iyy, izz, ixy, ixz, iyz] or three rows of three numbers (kg m^2), "
                     f"got {str(value)[:80]}")


def _physical(value: tuple[Vector3, Vector3, Vector3]) -> tuple[Vector3, Vector3, Vector3]:
    """A symmetric, positive-definite inertia whose principal moments satisfy the triangle inequality."""
    tensor = np.array(value, dtype=float)
    if not np.allclose(tensor, tensor.T, rtol=0.0, atol=1e-12 * max(1.0, float(np.abs(tensor).max()))):
        raise ValueError(f"a 3x3 inertia must be symmetric (got {tensor.tolist()})")
    moments = np.linalg.eigvalsh(tensor)
    if not moments.min() > 0.0:
        raise ValueError(f"the inertia must be positive definite: principal moments > 0 kg m^2 "
                         f"(got {moments.tolist()})")
    if moments.sum() - 2.0 * moments.max() < -1e-12 * moments.max():
        raise ValueError(f"the principal moments must satisfy the triangle inequality, each at most the sum of "
                         f"the other two (got {moments.tolist()} kg m^2)")
    return value


InertiaTensor = Annotated[tuple[Vector3, Vector3, Vector3], BeforeValidator(_inertia_rows), AfterValidator(_physical)]
"""An inertia about a centre of mass (kg·m²): six numbers [ixx, iyy, izz, ixy, ixz, iyz] or a symmetric 3×3, positive
definite, its principal moments satisfying the triangle inequality."""


class ToolBody(Posed):
    """A rigid tool (a spindle, a gripper) fixed on a frame of the robot.

    ``xyz_m`` and ``rpy_rad`` place the tool frame in the mount ``frame`` (default: the sidecar's
    ``end_effector.frame``). The centre of mass ``com_m`` (m) and the collision shape's pose are in
    the tool frame; ``inertia_kg_m2`` is about the centre of mass, in the tool frame's axes: six
    numbers [ixx, iyy, izz, ixy, ixz, iyz] (moments first, then products) or a symmetric 3×3.
    ``tip``, a pose in the tool frame, is the tool's working point (a cutter's tip): when given, it
    follows the path instead of the sidecar's end-effector frame (and for a pose task, its axes
    are the ones held to the path).
    """

    name: Name = "tool_body"
    frame: str | None = None
    mass_kg: Positive
    com_m: Vector3 = (0.0, 0.0, 0.0)
    inertia_kg_m2: InertiaTensor
    collision: Shape | None = None
    tip: Posed | None = None

    @property
    def inertia_matrix(self) -> np.ndarray:
        """The 3×3 inertia about the centre of mass, in the tool frame (kg·m²)."""
        return np.array(self.inertia_kg_m2, dtype=float)


class CellFile(Strict):
    """The whole cell file."""

    description: Text = ""
    margin_m: Annotated[Number, Field(ge=0.0)] = Field(
        DEFAULT_MARGIN_M, description="clearance (m) every robot link and the tool keep from every obstacle")
    obstacles: dict[Name, Shape] = {}
    keep_out: dict[Name, Shape] = {}
    workpiece_region: Region | None = None
    ignore: list[tuple[str, str]] = []
    tool: ToolBody | None = None


class Cell(CellFile):
    """A loaded cell: the file's fields and the file itself (meshes are relative to its folder).

    Attributes:
        path: The cell file.
    """

    path: Path

    @property
    def folder(self) -> Path:
        """The folder that mesh files are relative to."""
        return self.path.parent

    def bodies(self) -> dict[str, tuple[str, Shape]]:
        """Every obstacle and keep-out zone by name, with its field in the file (``obstacles.NAME``, say)."""
        return {**{name: (f"obstacles.{name}", shape) for name, shape in self.obstacles.items()},
                **{name: (f"keep_out.{name}", shape) for name, shape in self.keep_out.items()}}


def load_cell(path: str | Path) -> Cell:
    """Read and validate a cell file.

    Args:
        path: The cell YAML file.

    Returns:
        The cell.

    Raises:
        CellFileError: The file is missing, is not YAML, breaks the schema, names a body twice, or
            names a mesh file that does not exist (the message names file and field).
    """
    path = Path(path)
    spec = read_yaml(path, CellFile, CellFileError)
    shared = sorted(set(spec.obstacles) & set(spec.keep_out))
    if shared:
        raise CellFileError(path, f"keep_out.{shared[0]}", f"'{shared[0]}' is also an obstacle: give every body its "
                            "own name")
    cell = Cell(path=path, **dict(spec))
    for field, shape in cell.bodies().values():
        check_mesh_file(path, field, shape, CellFileError)
    if cell.tool is not None:
        check_mesh_file(path, "tool.collision", cell.tool.collision, CellFileError)
    return cell


def check_mesh_file(path: Path, field: str, shape: Shape | None, error: type[InputFileError]) -> None:
    """A mesh shape's file must exist beside ``path`` (the file naming it).

    Raises:
        InputFileError: (as ``error``) naming ``path`` and ``field``.
    """
    if isinstance(shape, MeshShape) and not mesh_path(path.parent, shape).is_file():
        raise error(path, f"{field}.file", f"mesh file not found: {mesh_path(path.parent, shape)}")


def mesh_path(folder: Path, shape: MeshShape) -> Path:
    """The mesh file of ``shape``, relative to ``folder`` unless absolute."""
    return (folder / shape.file).resolve()

"""Schema of a robot sidecar file (YAML), the data that a URDF cannot say.

A sidecar names the URDF and adds the loop closures, the actuated joints and their drives, the
end-effector frame, gravity, the nominal workspace and the source of every number. Field names
carry their units; joint-space quantities are in the joint's SI unit (m, m/s, N for prismatic
joints; rad, rad/s, N·m for revolute joints). The full schema with examples: docs/reference/sidecar.md.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Literal

import numpy as np
from pydantic import BeforeValidator, Field, model_validator

from placement.cell.cell_file import InertiaTensor, ToolBody, check_mesh_file
from placement.drives.motors import Motor
from placement.drives.transmissions import Transmission, parse_transmission
from placement.robot.exceptions import RobotFileError
from placement.schema import Number, Strict, Text, read_yaml

NonNegative = Annotated[Number, Field(ge=0.0)]
Positive = Annotated[Number, Field(gt=0.0)]
Vector3 = tuple[Number, Number, Number]
SOURCE_STATUSES = ("PAPER", "DERIVED", "CATALOG", "PUBLISHED", "EST", "CALIBRATED")


class LinkSpring(Strict):
    """A link's compliance as a 6×6 spring (the virtual-joint method): the link, its frames and everything beyond it
    yield by a small twist ε (translation, then rotation, in the link frame's axes) at the point ``origin_m`` of the
    link frame, against the stiffness K·ε. A link inside a closed loop is not covered."""

    stiffness: list[Positive] | list[list[Number]] = Field(
        description="6 values (a diagonal) or a 6×6 symmetric positive definite matrix: N/m, N·m/rad and N/rad in its "
        "coupling blocks, translation first, in the link frame's axes")
    origin_m: Vector3 = Field((0.0, 0.0, 0.0), description="where the spring sits, in the link frame (m)")

    @model_validator(mode="after")
    def _positive_definite(self) -> LinkSpring:
        matrix = self.matrix
        if matrix.shape != (6, 6):
            raise ValueError(f"stiffness must be 6 values or a 6×6 matrix, got shape {matrix.shape}")
        if not np.allclose(matrix, matrix.T, rtol=1e-12, atol=0.0) or np.linalg.eigvalsh(matrix).min() <= 0:
            raise ValueError("stiffness must be symmetric positive definite")
        return self

    @property
    def matrix(self) -> np.ndarray:
        """(6, 6) the stiffness matrix."""
        values = np.array(self.stiffness, dtype=float)
        return np.diag(values) if values.ndim == 1 else values


class Friction(Strict):
    """Joint friction in joint units: Coulomb (N or N·m) and viscous (N·s/m or N·m·s/rad)."""

    coulomb: NonNegative = 0.0
    viscous: NonNegative = 0.0


class Drive(Strict):
    """A motor and its transmission to one actuated joint."""

    transmission: Annotated[Transmission, BeforeValidator(parse_transmission)]
    motor: Motor
    transmission_inertia_kg_m2: NonNegative = Field(
        0.0, description="inertia on the motor shaft besides the rotor (screw, coupling, gearbox input)")
    friction: Friction = Friction()
    motor_side_stiffness_Nm_per_rad: Positive | None = Field(
        None, description="torsional stiffness on the motor shaft (coupling, motor-side gear stage), reflected to the "
        "joint as k·speed_ratio²; in series with the actuator's own stiffness")

    @property
    def reflected_inertia(self) -> float:
        """Rotor and transmission inertia seen at the joint: kg (linear joint) or kg·m² (revolute)."""
        return (self.motor.rotor_inertia_kg_m2 + self.transmission_inertia_kg_m2) * self.transmission.speed_ratio**2


class Actuator(Strict):
    """An actuated joint; limits missing here are read from the URDF."""

    joint: str
    drive: str | None = None
    position_min: Number | None = None
    position_max: Number | None = None
    velocity_max: Positive | None = None
    acceleration_max: Positive | None = Field(None, description="joint acceleration bound (m/s² or rad/s²), if any")
    stiffness: Positive | None = Field(None, description="the actuated joint's stiffness at the joint: N/m (prismatic) "
                                       "or N·m/rad (revolute); in series with its drive's motor-side stiffness")


class Closure(Strict):
    """A loop closure: two frames that must coincide (point) or be welded (weld)."""

    name: str
    type: Literal["point", "weld"]
    frames: tuple[str, str]


class EndEffector(Strict):
    """The frame that follows the path, and what of it is prescribed.

    ``offset_m`` (m, in ``frame``) and ``rpy_rad`` (roll, pitch, yaw about fixed x, y, z, rad)
    place a tool tip on ``frame``; the tip is then the end-effector frame (see
    :mod:`placement.robot.tool`). For a pose task, ``tool_rpy_in_path_rad`` is the end-effector
    frame's orientation in the path frame (same convention): [pi, 0, 0] turns the tool's z axis to
    -Z_p, pointing into the workpiece.
    """

    frame: str
    task: Literal["position", "pose"]
    offset_m: Vector3 | None = None
    rpy_rad: Vector3 | None = None
    tool_rpy_in_path_rad: Vector3 | None = None

    @model_validator(mode="after")
    def _orientation_for_pose(self) -> EndEffector:
        if self.task == "position" and self.tool_rpy_in_path_rad is not None:
            raise ValueError("tool_rpy_in_path_rad applies to pose tasks only")
        return self


PLANE_VARIABLES = ("x", "y", "phi")


class Plane(Strict):
    """The plane a planar mechanism moves in, in the base frame: its normal and one of its points (m).

    Paths are then placed in this plane (see :func:`placement.placing.transform.plane_frame`): the path
    frame's Z_p is along ``normal``; x and y are the path origin's coordinates along the plane's own
    axes, from ``point_m``; phi turns the path about the normal; z, theta and psi stay 0.
    """

    normal: Vector3
    point_m: Vector3 = (0.0, 0.0, 0.0)

    @model_validator(mode="after")
    def _nonzero(self) -> Plane:
        if not sum(c * c for c in self.normal) > 1e-24:
            raise ValueError(f"normal must be a non-zero vector, got {list(self.normal)}")
        return self


class PlacementDefaults(Strict):
    """The default search space of path placements on this robot (m, rad); for a planar mechanism, its plane."""

    free: list[Literal["x", "y", "z", "phi", "theta", "psi"]] | None = None  # [] only beside redundant joints
    bounds: dict[Literal["x", "y", "z", "phi", "theta", "psi"], tuple[Number, Number]] = {}
    plane: Plane | None = None

    @model_validator(mode="after")
    def _ordered(self) -> PlacementDefaults:
        for name, (low, high) in self.bounds.items():
            if not low < high:
                raise ValueError(f"bounds.{name}: the lower bound {low} must be below the upper bound {high}")
        if self.plane is None and self.free is None:
            raise ValueError("free: expected the free placement variables, e.g. [x, y, z, phi] (or a plane)")
        off_plane = sorted({*(self.free or ()), *self.bounds} - set(PLANE_VARIABLES)) if self.plane else []
        if off_plane:
            raise ValueError(f"with a plane, paths move in it: only {', '.join(PLANE_VARIABLES)} may be free or bounded "
                             f"(got {', '.join(off_plane)})")
        return self


class Workspace(Strict):
    """The nominal workspace: an axis-aligned box in the base frame, with named points."""

    type: Literal["box"]
    min_m: Vector3
    max_m: Vector3
    points_m: dict[str, Vector3] = {}

    @model_validator(mode="after")
    def _ordered(self) -> Workspace:
        if any(lo >= hi for lo, hi in zip(self.min_m, self.max_m)):
            raise ValueError(f"min_m {list(self.min_m)} must be below max_m {list(self.max_m)} on every axis")
        return self


class Collision(Strict):
    """Self-collision settings: pairs of links never checked against each other (they touch by design).

    Links adjacent in the tree, links joined by a closure and links already touching at the
    reference configuration are skipped without being listed (see :mod:`placement.collision.pairs`).
    """

    ignore_pairs: list[tuple[str, str]] = []


class LinkInertial(Strict):
    """A URDF link's inertial, replacing the URDF's: its mass (kg), its centre of mass ``com_m`` (m) in the link
    frame, and its inertia about the centre of mass in the link frame's axes (kg·m²: [ixx, iyy, izz, ixy, ixz, iyz]
    or a symmetric 3×3), as a URDF ``<inertial>`` without rotation."""

    mass_kg: Positive
    com_m: Vector3 = (0.0, 0.0, 0.0)
    inertia_kg_m2: InertiaTensor


MAX_KNOTS = 12  # knots of a redundant coordinate's profile, at most (each is a dimension of the search)


class Redundancy(Strict):
    """Redundant coordinates the search resolves for the whole path (see :mod:`placement.placing.profiles`).

    Each joint takes a profile along the path's arc length: ``knots`` values at equal shares of it (one: a
    constant), joined by a cubic spline; the knots are placement variables named ``JOINT@K``. The
    other joints follow by inverse kinematics. ``spin``: the tool's rotation about its own axis is a
    placement variable too (``spin``), for a tool that is symmetric about its axis (a spindle).
    """

    joints: list[Text] = []
    knots: Annotated[int, Field(ge=1, le=MAX_KNOTS)] = 3
    spin: bool = False

    @model_validator(mode="after")
    def _something(self) -> Redundancy:
        if not self.joints and not self.spin:
            raise ValueError("expected joints (redundant joints to profile) or spin: true")
        return self


class Sidecar(Strict):
    """The whole sidecar file."""

    name: Text
    description: Text = ""
    urdf: str = Field(description="URDF, xacro or MJCF (.xml) path relative to this file, or 'example-robot-data:NAME'")
    xacro_args: dict[str, Text] = Field({}, description="a xacro file's arguments (ur_type: ur5e)")
    package_paths: list[str] = Field([], description="folders (relative to this file) where the URDF's "
                                     "package:// meshes and a xacro's $(find PKG) are looked for first")
    gravity_m_s2: Vector3
    end_effector: EndEffector
    reference_configuration: dict[str, Number] = {}
    locked_joints: dict[str, Number] = Field({}, description="joints held fixed at these values (m, rad)")
    redundancy: Redundancy | None = Field(None, description="actuated joints beyond the task's freedoms, each "
                                          "profiled along the path by the search")
    workpiece_frame: Text | None = Field(None, description="the frame the path is placed in when the workpiece rides "
                                         "on a chain of the robot (a positioner's table), every joint moving it named "
                                         "under redundancy.joints; default: the base frame")
    closures: list[Closure] = []
    actuators: Annotated[list[Actuator], Field(min_length=1)]
    drives: dict[str, Drive] = {}
    kinematics_plugin: str | None = Field(None, description="Python file beside this one, with a closed-form solver")
    kinematics: str | None = Field(None, description="kinematics solver by name (default: chosen for the robot)")
    workspace: Workspace | None = None
    placement: PlacementDefaults | None = None
    tool: ToolBody | None = Field(None, description="a tool body on the robot (mass and collision shape); a cell's "
                                  "tool replaces it")
    collision: Collision = Collision()
    links: dict[str, LinkInertial] = Field({}, description="inertials replacing the URDF's, by link name (a URDF "
                                           "without them, say)")
    joint_springs: dict[str, Positive] = Field({}, description="springs on passive joints (virtual joints of a "
                                               "compliant link, say), by joint name: N/m or N·m/rad")
    link_springs: dict[str, LinkSpring] = Field({}, description="links' compliance as 6×6 springs (the virtual-joint "
                                                "method), by link name; not in a closed loop")
    sources: dict[str, str] = {}


def read_sidecar(path: Path) -> Sidecar:
    """Read and validate a sidecar file.

    Raises:
        RobotFileError: The file is missing, is not YAML, or breaks the schema (the message names
            the field and what was expected).
    """
    sidecar = read_yaml(path, Sidecar, RobotFileError)
    _check_references(path, sidecar)
    return sidecar


def _check_references(path: Path, sidecar: Sidecar) -> None:
    if sidecar.placement is not None and sidecar.placement.free == [] and not (sidecar.redundancy and
                                                                              sidecar.redundancy.joints):
        raise RobotFileError(path, "placement.free", "expected at least one free placement variable, e.g. [x, y, z, "
                             "phi] (an empty list only for a robot whose redundant joints' knots are searched)")
    for i, actuator in enumerate(sidecar.actuators):
        if actuator.drive is not None and actuator.drive not in sidecar.drives:
            raise RobotFileError(path, f"actuators.{i}.drive", f"unknown drive '{actuator.drive}', expected one of "
                                 f"{sorted(sidecar.drives) or 'the names under drives (none given)'}")
    _check_tool_sources(path, sidecar)
    _check_stiffness_sources(path, sidecar)
    for name in sidecar.links:
        if not {f"links.{name}", "links"} & set(sidecar.sources):
            raise RobotFileError(path, f"links.{name}", f"a link's inertial needs its source: add the entry links.{name}: "
                                 f"\"STATUS: note\" under sources, STATUS one of {', '.join(SOURCE_STATUSES)}")
    if sidecar.tool is not None:
        check_mesh_file(path, "tool.collision", sidecar.tool.collision, RobotFileError)
    for key, text in sidecar.sources.items():
        status = text.split(":", 1)[0].strip()
        if status not in SOURCE_STATUSES:
            raise RobotFileError(path, f"sources.{key}", f"must start with one of {', '.join(SOURCE_STATUSES)} "
                                 f"followed by ':', got '{text}'")


def _check_stiffness_sources(path: Path, sidecar: Sidecar) -> None:
    """A stiffness is a measured or estimated number: each needs its ``sources`` entry (the field's own, or
    ``actuators.stiffness`` for every actuator's, ``joint_springs`` or ``link_springs`` for every spring)."""
    keys = set(sidecar.sources)
    fields = [(f"actuators.{i}.stiffness", "actuators.stiffness") for i, a in enumerate(sidecar.actuators)
              if a.stiffness is not None]
    fields += [(f"drives.{name}.motor_side_stiffness_Nm_per_rad", f"drives.{name}") for name, drive in sidecar.drives.items()
               if drive.motor_side_stiffness_Nm_per_rad is not None]
    fields += [(f"joint_springs.{name}", "joint_springs") for name in sidecar.joint_springs]
    fields += [(f"link_springs.{name}", "link_springs") for name in sidecar.link_springs]
    for field, shared in fields:
        if not {field, shared} & keys:
            raise RobotFileError(path, field, f"a stiffness needs its source: add the entry {field} (or {shared}): "
                                 f"\"STATUS: note\" under sources, STATUS one of {', '.join(SOURCE_STATUSES)}")


def _check_tool_sources(path: Path, sidecar: Sidecar) -> None:
    """A tool offset is a measured or estimated number: it needs its ``sources`` entry."""
    for field in ("offset_m", "rpy_rad"):
        key = f"end_effector.{field}"
        if getattr(sidecar.end_effector, field) is not None and not {key, "end_effector"} & set(sidecar.sources):
            raise RobotFileError(path, key, f"a tool offset needs its source: add the entry {key}: \"STATUS: note\" "
                                 f"under sources, STATUS one of {', '.join(SOURCE_STATUSES)}")

"""A loaded robot: the Pinocchio model of its spanning tree, closures, actuators and drives."""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING, Any

import numpy as np
import pinocchio as pin

from placement.robot.exceptions import RobotFileError
from placement.robot.plugins import ClosedFormFunction, load_plugin, make_closed_form

if TYPE_CHECKING:
    from placement.cell.cell_file import Cell, ToolBody
    from placement.robot.sidecar import Drive, LinkInertial, LinkSpring, PlacementDefaults, Plane, Sidecar, Workspace


@dataclass(frozen=True)
class Actuator:
    """An actuated joint with its limits (joint units: m or rad) and drive."""

    joint: str
    q_index: int
    v_index: int
    position_min: float
    position_max: float
    velocity_max: float
    drive: Drive | None
    reflected_inertia: float  # rotor and transmission inertia seen at the joint (kg or kg·m²)
    prismatic: bool  # True: m, m/s, N; False (revolute): rad, rad/s, N·m
    acceleration_max: float | None = None  # m/s² or rad/s², where the sidecar gives one
    drive_name: str | None = None  # the drive's name in the sidecar (a key of Robot.named_drives)
    own_stiffness: float | None = None  # N/m or N·m/rad: the sidecar's actuators.N.stiffness, if given

    @property
    def stiffness(self) -> float | None:
        """The actuated joint's stiffness at the joint (N/m or N·m/rad): its own (``own_stiffness``) and its drive's
        motor-side one reflected by the speed ratio squared, in series; the one given alone; None when neither is."""
        motor_side = self.drive.motor_side_stiffness_Nm_per_rad if self.drive is not None else None
        reflected = None if motor_side is None or self.drive is None else motor_side * self.drive.transmission.speed_ratio**2
        springs = [k for k in (self.own_stiffness, reflected) if k is not None]
        return 1.0 / sum(1.0 / k for k in springs) if springs else None


@dataclass(frozen=True)
class Closure:
    """A loop closure between two frames of the spanning tree."""

    name: str
    kind: str  # "point" (3 equations) or "weld" (6 equations)
    frame_ids: tuple[int, int]

    @property
    def dimension(self) -> int:
        """Number of scalar constraint equations."""
        return 3 if self.kind == "point" else 6


@dataclass(eq=False)
class Robot:
    """A robot ready for kinematics and dynamics.

    Attributes:
        name: Robot name from the sidecar.
        sidecar_path: The sidecar file it was loaded from.
        urdf_path: The URDF of its spanning tree.
        model: Pinocchio model of the tree, with gravity and reflected drive inertia (armature).
        closures: Loop closures (empty for a serial robot).
        actuators: Actuated joints in sidecar order.
        end_effector_frame_id: Pinocchio frame that follows the path.
        task: "position" (3-D point) or "pose" (position and orientation).
        reference_q: A configuration where every closure closes (used to start solvers).
        plugin: The robot's kinematics plug-in module, if it has one.
        closed_form: The plug-in's closed-form position solver, if any.
        sidecar: The validated sidecar data, for this package only: other layers read what they need
            through the properties below (a test holds them to it).
        cell: The cell the robot works in (obstacles, keep-out zones, workpiece region, tool), if
            any: its distances become a limit (see :func:`placement.robot.equip.equip`).
        massless_links: The moving links without inertia it was loaded with, as asked (``allow_massless``; see
            :mod:`placement.robot.plausibility`): its energies leave out their weight and inertia. Empty otherwise.
        package_paths: Folders where the packages its URDF's ``package://`` meshes name are looked for first
            (the sidecar's ``package_paths`` and ``--package-path``; see :mod:`placement.robot.packages`).
    """

    name: str
    sidecar_path: Path
    urdf_path: Path
    model: pin.Model
    closures: tuple[Closure, ...]
    actuators: tuple[Actuator, ...]
    end_effector_frame_id: int
    task: str
    reference_q: np.ndarray
    plugin: ModuleType | None
    closed_form: ClosedFormFunction | None
    sidecar: Sidecar
    cell: Cell | None = None
    massless_links: tuple[str, ...] = ()
    package_paths: tuple[Path, ...] = ()

    def __repr__(self) -> str:
        """A short summary (the Pinocchio model's own repr runs to pages)."""
        joints = ", ".join(actuator.joint for actuator in self.actuators)
        return (f"Robot('{self.name}', {len(self.actuators)} actuators ({joints}), {self.task} task, "
                f"{len(self.closures)} closures, from {self.sidecar_path})")

    def __getstate__(self) -> dict:
        """For another process: a loaded plug-in module does not travel, its file does."""
        state = dict(self.__dict__)
        state["plugin"] = state["closed_form"] = None
        return state

    def __setstate__(self, state: dict) -> None:
        self.__dict__.update(state)
        self.plugin = load_plugin(self.sidecar_path, self.sidecar.kinematics_plugin)
        self.closed_form = make_closed_form(self.plugin, self.model, self.sidecar_path)

    @property
    def drives(self) -> tuple[Drive, ...]:
        """The drive of every actuator, in actuator order.

        Raises:
            RobotFileError: An actuator has no drive (named in the message).
        """
        for i, actuator in enumerate(self.actuators):
            if actuator.drive is None:
                raise RobotFileError(self.sidecar_path, f"actuators.{i}.drive", f"actuator '{actuator.joint}' has no "
                                     "drive; energy and motor limits need one: name an entry of drives")
        return tuple(a.drive for a in self.actuators if a.drive is not None)

    @property
    def actuated_v_indices(self) -> np.ndarray:
        """Velocity indices of the actuated joints, in actuator order."""
        return np.array([a.v_index for a in self.actuators])

    @property
    def actuated_q_indices(self) -> np.ndarray:
        """Configuration indices of the actuated joints, in actuator order."""
        return np.array([a.q_index for a in self.actuators])

    @property
    def task_dimension(self) -> int:
        """3 for a position task, 6 for a pose task."""
        return 3 if self.task == "position" else 6

    @property
    def is_serial(self) -> bool:
        """No closure and every joint actuated."""
        return not self.closures and len(self.actuators) == self.model.nv

    @property
    def description(self) -> str:
        """The sidecar's one-line description of the robot ("" if it gives none)."""
        return self.sidecar.description

    @property
    def gravity_m_s2(self) -> tuple[float, float, float]:
        """Gravity in the base frame (m/s²), as the sidecar gives it (the model carries the same)."""
        return self.sidecar.gravity_m_s2

    @property
    def sources(self) -> dict[str, str]:
        """Where each number comes from: sidecar field -> "STATUS: note" (STATUS one of PAPER, DERIVED, CATALOG,
        PUBLISHED, EST, CALIBRATED)."""
        return self.sidecar.sources

    def source_status(self, key: str) -> str:
        """The status (EST, CATALOG, ...) of the most specific ``sources`` entry covering the sidecar field ``key``
        (the key itself, else its nearest dotted prefix: ``drives.NAME.motor``, then ``drives.NAME``), or "" when none
        does."""
        parts = key.split(".")
        for end in range(len(parts), 0, -1):
            note = self.sources.get(".".join(parts[:end]))
            if note is not None:
                return note.split(":", 1)[0].strip() if ":" in note else ""
        return ""

    @property
    def urdf_source(self) -> str:
        """The URDF as the sidecar names it: a path relative to the sidecar, or 'example-robot-data:NAME'
        (``urdf_path`` is the file itself)."""
        return self.sidecar.urdf

    @property
    def reference_configuration(self) -> dict[str, float]:
        """The joints the sidecar sets at the reference configuration, in its order, and their values (m or rad)."""
        return dict(self.sidecar.reference_configuration)

    def edited_sidecar(self, **fields: Any) -> Sidecar:
        """The robot's sidecar with these fields replaced, to build the robot anew (its assembly, say)."""
        return self.sidecar.model_copy(update=fields)

    def sidecar_document(self) -> dict[str, Any]:
        """The robot's sidecar as a YAML document: the fields that differ from their defaults (SI units)."""
        return self.sidecar.model_dump(mode="json", exclude_defaults=True, serialize_as_any=True)

    @property
    def locked_joints(self) -> dict[str, float]:
        """Joints of the URDF held fixed, and their values (m or rad); they are not in ``model``."""
        return self.sidecar.locked_joints

    @property
    def redundant_joints(self) -> tuple[str, ...]:
        """The actuated joints beyond the task's freedoms, each profiled along the path by the search (the
        sidecar's ``redundancy``), in its order; empty for a robot the path determines."""
        redundancy = self.sidecar.redundancy
        return () if redundancy is None else tuple(redundancy.joints)

    @property
    def tool_spin(self) -> bool:
        """Whether the tool's spin about its own axis is left to the search (the sidecar's ``redundancy.spin``)."""
        redundancy = self.sidecar.redundancy
        return redundancy is not None and redundancy.spin

    @property
    def profile_knots(self) -> int:
        """Knots of each redundant joint's profile along the path (1: a constant); 0 without redundant joints."""
        redundancy = self.sidecar.redundancy
        return 0 if redundancy is None or not redundancy.joints else redundancy.knots

    @property
    def redundant_q_indices(self) -> np.ndarray:
        """Configuration indices of the redundant joints, in their order."""
        return np.array([self.model.joints[self.model.getJointId(name)].idx_q for name in self.redundant_joints],
                        dtype=np.int64)

    @property
    def workpiece_frame(self) -> str | None:
        """The frame the path is placed in when the workpiece rides on a chain of the robot (a positioner's table,
        the sidecar's ``workpiece_frame``), or None: the base frame. The joints moving it are redundant joints,
        profiled along the path."""
        return self.sidecar.workpiece_frame

    @property
    def mount_frame(self) -> str:
        """The frame the sidecar names as the end effector (``end_effector.frame``): tool tips and tool bodies
        that name no frame mount on it, and a closed-form plug-in solves for it. The path follows
        ``end_effector_frame_id``: this frame, or a tool tip on it."""
        return self.sidecar.end_effector.frame

    @property
    def tool_rpy_in_path_rad(self) -> tuple[float, float, float]:
        """For a pose task, the end-effector frame's orientation in the tool frame the path prescribes (the path
        frame, without a pose list): roll, pitch, yaw about fixed x, y, z (rad); (0, 0, 0) when the sidecar
        gives none, as for a position task."""
        return self.sidecar.end_effector.tool_rpy_in_path_rad or (0.0, 0.0, 0.0)

    @property
    def kinematics_name(self) -> str | None:
        """The kinematics solver the sidecar names (``kinematics``), or None: one is then chosen for the robot
        (see :func:`placement.kinematics.base.solver_name`)."""
        return self.sidecar.kinematics

    @property
    def kinematics_plugin(self) -> str | None:
        """The file name of the robot's closed-form kinematics plug-in (beside the sidecar), or None."""
        return self.sidecar.kinematics_plugin

    @property
    def workspace(self) -> Workspace | None:
        """The nominal workspace: an axis-aligned box in the base frame (``min_m``, ``max_m``, m) with named
        points (``points_m``, m); None when the sidecar declares none."""
        return self.sidecar.workspace

    @property
    def placement_defaults(self) -> PlacementDefaults | None:
        """The default search space of path placements (the sidecar's ``placement``: free variables, bounds in
        m and rad, and a planar mechanism's plane), or None."""
        return self.sidecar.placement

    @property
    def plane(self) -> Plane | None:
        """The plane a planar mechanism moves in (base frame: a normal and a point, m), if it declares one."""
        defaults = self.sidecar.placement
        return defaults.plane if defaults is not None else None

    @property
    def tool(self) -> ToolBody | None:
        """The tool body of the robot's own description (the sidecar's ``tool``), which loading mounts, or None.
        A cell's tool replaces it at work (see :func:`placement.robot.equip.tool_of`)."""
        return self.sidecar.tool

    @property
    def link_inertials(self) -> dict[str, LinkInertial]:
        """The inertials the sidecar gives URDF links (its ``links``: mass, centre of mass, inertia), replacing the
        URDF's, by link name; the model carries them."""
        return dict(self.sidecar.links)

    @property
    def joint_springs(self) -> dict[str, float]:
        """Springs on passive joints (the sidecar's ``joint_springs``), by joint name: N/m or N·m/rad."""
        return dict(self.sidecar.joint_springs)

    @property
    def link_springs(self) -> dict[str, LinkSpring]:
        """Links' compliance as 6×6 springs (the sidecar's ``link_springs``), by link name."""
        return dict(self.sidecar.link_springs)

    @property
    def collision_ignore_pairs(self) -> tuple[tuple[str, str], ...]:
        """Pairs of links (or a link and the tool) never checked against each other: they touch by design."""
        return tuple(self.sidecar.collision.ignore_pairs)

    @property
    def named_drives(self) -> dict[str, Drive]:
        """Every drive the sidecar declares, by its name (the actuators name theirs: ``Actuator.drive_name``)."""
        return dict(self.sidecar.drives)

    def with_drives(self, drives: Mapping[str, Drive]) -> Robot:
        """The robot with some of its named drives replaced ({name: drive}); its model is shared.

        Every actuator with a drive carries the drive of its name, and that drive's reflected inertia
        (the model's armature is left as it is); ``named_drives`` gives the new drives.

        Raises:
            KeyError: A name that is not one of ``named_drives``.
        """
        unknown = sorted(set(drives) - set(self.sidecar.drives))
        if unknown:
            raise KeyError(f"unknown drive(s) {unknown}, expected some of {sorted(self.sidecar.drives)}")
        named = {**self.sidecar.drives, **drives}
        actuators = tuple(a if a.drive_name is None else dataclasses.replace(
            a, drive=named[a.drive_name], reflected_inertia=named[a.drive_name].reflected_inertia) for a in self.actuators)
        return dataclasses.replace(self, actuators=actuators, sidecar=self.sidecar.model_copy(update={"drives": named}))

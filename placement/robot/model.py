"""A loaded robot: the Pinocchio model of its spanning tree, closures, actuators and drives."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np
import pinocchio as pin

from placement.robot.exceptions import RobotFileError
from placement.robot.plugins import ClosedFormFunction, load_plugin, make_closed_form

if TYPE_CHECKING:
    from placement.cell.schema import Cell
    from placement.robot.sidecar import Drive, Sidecar


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
        sidecar: The validated sidecar data (drives, workspace, sources, ...).
        cell: The cell the robot works in (obstacles, keep-out zones, workpiece region, tool), if
            any: its distances become a limit (see :func:`placement.cell.tool.equip`).
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

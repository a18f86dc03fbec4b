"""Schema of a robot sidecar file (YAML), the data that a URDF cannot say.

A sidecar names the URDF and adds the loop closures, the actuated joints and their drives, the
end-effector frame, gravity, the nominal workspace and the source of every number. Field names
carry their units; joint-space quantities are in the joint's SI unit (m, m/s, N for prismatic
joints; rad, rad/s, N·m for revolute joints). The full schema with examples is in the README.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated, Literal

from pydantic import Field, model_validator

from placement.exceptions import RobotFileError
from placement.schema import Strict, read_yaml

NonNegative = Annotated[float, Field(ge=0.0)]
Positive = Annotated[float, Field(gt=0.0)]
Vector3 = tuple[float, float, float]
SOURCE_STATUSES = ("PAPER", "DERIVED", "CATALOG", "PUBLISHED", "EST")


class BallScrew(Strict):
    """Ball screw: joint speed (m/s) = motor speed (rad/s) * lead_m / (2 pi)."""

    type: Literal["ball_screw"]
    lead_m: Positive
    efficiency: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0


class Gear(Strict):
    """Gearbox: joint speed (rad/s) = motor speed (rad/s) / ratio."""

    type: Literal["gear"]
    ratio: Positive
    efficiency: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0


class Motor(Strict):
    """Motor constants in SI (per phase for a multi-phase motor); ``model`` names the energy model."""

    model: str = "pmsm"
    torque_constant_Nm_per_A: Positive
    back_emf_constant_V_s_per_rad: Positive
    resistance_ohm: NonNegative
    inductance_H: NonNegative
    phases: Annotated[int, Field(ge=1)]
    rotor_inertia_kg_m2: NonNegative
    max_torque_Nm: Positive
    max_speed_rad_s: Positive | None = None

    @model_validator(mode="after")
    def _converts_power_without_loss(self) -> Motor:
        # In the pmsm model the back-EMF power n·K_e·ω·I must be the shaft power τ·ω = K_t·I·ω.
        expected = self.torque_constant_Nm_per_A / self.phases
        if self.model == "pmsm" and abs(self.back_emf_constant_V_s_per_rad - expected) > 1e-3 * expected:
            raise ValueError(f"back_emf_constant_V_s_per_rad must be torque_constant_Nm_per_A / phases = {expected:.6g} "
                             "V s/rad for the pmsm model (else the motor creates or destroys energy)")
        return self


class Friction(Strict):
    """Joint friction in joint units: Coulomb (N or N·m) and viscous (N·s/m or N·m·s/rad)."""

    coulomb: NonNegative = 0.0
    viscous: NonNegative = 0.0


class Drive(Strict):
    """A motor and its transmission to one actuated joint."""

    transmission: Annotated[BallScrew | Gear, Field(discriminator="type")]
    motor: Motor
    transmission_inertia_kg_m2: NonNegative = Field(
        0.0, description="inertia on the motor shaft besides the rotor (screw, coupling, gearbox input)")
    friction: Friction = Friction()

    @property
    def speed_ratio(self) -> float:
        """Motor speed per unit joint speed: rad per m (ball screw, 2π/lead) or rad per rad (gear)."""
        t = self.transmission
        return 2 * math.pi / t.lead_m if isinstance(t, BallScrew) else t.ratio

    @property
    def reflected_inertia(self) -> float:
        """Rotor and transmission inertia seen at the joint: kg (ball screw) or kg·m² (gear)."""
        return (self.motor.rotor_inertia_kg_m2 + self.transmission_inertia_kg_m2) * self.speed_ratio**2


class Actuator(Strict):
    """An actuated joint; limits missing here are read from the URDF."""

    joint: str
    drive: str | None = None
    position_min: float | None = None
    position_max: float | None = None
    velocity_max: Positive | None = None


class Closure(Strict):
    """A loop closure: two frames that must coincide (point) or be welded (weld)."""

    name: str
    type: Literal["point", "weld"]
    frames: tuple[str, str]


class EndEffector(Strict):
    """The frame that follows the path, and what of it is prescribed.

    For a pose task, ``tool_rpy_in_path_rad`` is the end-effector frame's orientation in the path
    frame (roll, pitch, yaw about fixed x, y, z): [pi, 0, 0] turns the tool's z axis to -Z_p,
    pointing into the workpiece.
    """

    frame: str
    task: Literal["position", "pose"]
    tool_rpy_in_path_rad: Vector3 | None = None

    @model_validator(mode="after")
    def _orientation_for_pose(self) -> EndEffector:
        if self.task == "position" and self.tool_rpy_in_path_rad is not None:
            raise ValueError("tool_rpy_in_path_rad applies to pose tasks only")
        return self


class PlacementDefaults(Strict):
    """The default search space of path placements on this robot (m, rad)."""

    free: Annotated[list[Literal["x", "y", "z", "phi", "theta", "psi"]], Field(min_length=1)]
    bounds: dict[Literal["x", "y", "z", "phi", "theta", "psi"], tuple[float, float]] = {}

    @model_validator(mode="after")
    def _ordered(self) -> PlacementDefaults:
        for name, (low, high) in self.bounds.items():
            if not low < high:
                raise ValueError(f"bounds.{name}: the lower bound {low} must be below the upper bound {high}")
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


class Sidecar(Strict):
    """The whole sidecar file."""

    name: str
    description: str = ""
    urdf: str = Field(description="URDF path relative to this file, or 'example-robot-data:NAME'")
    gravity_m_s2: Vector3
    end_effector: EndEffector
    reference_configuration: dict[str, float] = {}
    locked_joints: dict[str, float] = Field({}, description="joints held fixed at these values (m, rad)")
    closures: list[Closure] = []
    actuators: Annotated[list[Actuator], Field(min_length=1)]
    drives: dict[str, Drive] = {}
    kinematics_plugin: str | None = Field(None, description="Python file beside this one, with a closed-form solver")
    workspace: Workspace | None = None
    placement: PlacementDefaults | None = None
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
    for i, actuator in enumerate(sidecar.actuators):
        if actuator.drive is not None and actuator.drive not in sidecar.drives:
            raise RobotFileError(path, f"actuators.{i}.drive", f"unknown drive '{actuator.drive}', expected one of "
                                 f"{sorted(sidecar.drives) or 'the names under drives (none given)'}")
    for key, text in sidecar.sources.items():
        status = text.split(":", 1)[0].strip()
        if status not in SOURCE_STATUSES:
            raise RobotFileError(path, f"sources.{key}", f"must start with one of {', '.join(SOURCE_STATUSES)} "
                                 f"followed by ':', got '{text}'")

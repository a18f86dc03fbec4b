"""Schema of a robot sidecar file (YAML), the data that a URDF cannot say.

A sidecar names the URDF and adds the loop closures, the actuated joints and their drives, the
end-effector frame, gravity, the nominal workspace and the source of every number. Field names
carry their units; joint-space quantities are in the joint's SI unit (m, m/s, N for prismatic
joints; rad, rad/s, N·m for revolute joints). The full schema with examples is in the README.
"""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Any, Literal

import yaml
from pydantic import BaseModel, ConfigDict, Field, ValidationError, model_validator

from placement.exceptions import RobotFileError

NonNegative = Annotated[float, Field(ge=0.0)]
Positive = Annotated[float, Field(gt=0.0)]
Vector3 = tuple[float, float, float]
SOURCE_STATUSES = ("PAPER", "DERIVED", "CATALOG", "PUBLISHED", "EST")


class _Strict(BaseModel):
    model_config = ConfigDict(extra="forbid", frozen=True)


class BallScrew(_Strict):
    """Ball screw: joint speed (m/s) = motor speed (rad/s) * lead_m / (2 pi)."""

    type: Literal["ball_screw"]
    lead_m: Positive
    efficiency: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0


class Gear(_Strict):
    """Gearbox: joint speed (rad/s) = motor speed (rad/s) / ratio."""

    type: Literal["gear"]
    ratio: Positive
    efficiency: Annotated[float, Field(gt=0.0, le=1.0)] = 1.0


class Motor(_Strict):
    """Permanent-magnet synchronous (brushless) motor, per-phase constants in SI."""

    torque_constant_Nm_per_A: Positive
    back_emf_constant_V_s_per_rad: Positive
    resistance_ohm: NonNegative
    inductance_H: NonNegative
    phases: Annotated[int, Field(ge=1)]
    rotor_inertia_kg_m2: NonNegative
    max_torque_Nm: Positive
    max_speed_rad_s: Positive | None = None


class Friction(_Strict):
    """Joint friction in joint units: Coulomb (N or N·m) and viscous (N·s/m or N·m·s/rad)."""

    coulomb: NonNegative = 0.0
    viscous: NonNegative = 0.0


class Drive(_Strict):
    """A motor and its transmission to one actuated joint."""

    transmission: Annotated[BallScrew | Gear, Field(discriminator="type")]
    motor: Motor
    transmission_inertia_kg_m2: NonNegative = Field(
        0.0, description="inertia on the motor shaft besides the rotor (screw, coupling, gearbox input)")
    friction: Friction = Friction()


class Actuator(_Strict):
    """An actuated joint; limits missing here are read from the URDF."""

    joint: str
    drive: str | None = None
    position_min: float | None = None
    position_max: float | None = None
    velocity_max: Positive | None = None


class Closure(_Strict):
    """A loop closure: two frames that must coincide (point) or be welded (weld)."""

    name: str
    type: Literal["point", "weld"]
    frames: tuple[str, str]


class EndEffector(_Strict):
    """The frame that follows the path, and what of it is prescribed."""

    frame: str
    task: Literal["position", "pose"]


class Workspace(_Strict):
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


class Sidecar(_Strict):
    """The whole sidecar file."""

    name: str
    description: str = ""
    urdf: str = Field(description="URDF path relative to this file, or 'example-robot-data:NAME'")
    gravity_m_s2: Vector3
    end_effector: EndEffector
    reference_configuration: dict[str, float] = {}
    closures: list[Closure] = []
    actuators: Annotated[list[Actuator], Field(min_length=1)]
    drives: dict[str, Drive] = {}
    kinematics_plugin: str | None = Field(None, description="Python file beside this one, with a closed-form solver")
    workspace: Workspace | None = None
    sources: dict[str, str] = {}


def read_sidecar(path: Path) -> Sidecar:
    """Read and validate a sidecar file.

    Args:
        path: The YAML file.

    Returns:
        The validated sidecar.

    Raises:
        RobotFileError: The file is missing, is not YAML, or breaks the schema (the message names
            the field and what was expected).
    """
    if not path.is_file():
        raise RobotFileError(path, "", "file not found")
    try:
        raw = yaml.safe_load(path.read_text())
    except yaml.YAMLError as error:
        raise RobotFileError(path, "", f"not valid YAML: {error}") from None
    if not isinstance(raw, dict):
        raise RobotFileError(path, "", "expected a mapping of fields at the top level")
    try:
        sidecar = Sidecar.model_validate(raw)
    except ValidationError as error:
        first = error.errors()[0]
        raise RobotFileError(path, _dotted(first["loc"]), _explain(first)) from None
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


def _dotted(loc: tuple[Any, ...]) -> str:
    return ".".join(str(part) for part in loc if part not in ("ball_screw", "gear"))


def _explain(error: dict[str, Any]) -> str:
    if error["type"] == "extra_forbidden":
        return f"unknown field; allowed here: {', '.join(_allowed_fields(error['loc'][:-1]))}"
    if error["type"] == "missing":
        return "required field is missing"
    message = error["msg"].removeprefix("Value error, ")
    return f"{message} (got {error['input']!r})"


def _allowed_fields(loc: tuple[Any, ...]) -> list[str]:
    annotation: Any = Sidecar
    for part in loc:
        annotation = _step(annotation, part)
    model = _model_of(annotation)
    return sorted(model.model_fields) if model else []


def _step(annotation: Any, part: Any) -> Any:
    """The annotation of the child ``part`` (field name, dict key, list index or union tag)."""
    origin = getattr(annotation, "__origin__", None)
    if origin is dict:
        return annotation.__args__[1]
    if origin is list:
        return annotation.__args__[0]
    if part in ("ball_screw", "gear"):
        return BallScrew if part == "ball_screw" else Gear
    model = _model_of(annotation)
    field = model.model_fields.get(part) if model else None
    return field.annotation if field else None


def _model_of(annotation: Any) -> Any:
    if isinstance(annotation, type) and issubclass(annotation, BaseModel):
        return annotation
    if getattr(annotation, "__origin__", None) in (dict, list):
        return None
    for arg in getattr(annotation, "__args__", ()):
        found = _model_of(arg)
        if found is not None:
            return found
    return None

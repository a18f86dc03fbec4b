"""Effort bounds given beside a robot description (``--effort JOINT=VALUE``), for joints it leaves unbounded.

Drives are estimated from each actuated joint's effort bound (:mod:`placement.workshop.estimates`). Some
descriptions bound none: onshape-to-robot's MJCF exports give their ``<position>`` actuators a ``kp`` only, and
ROS-Industrial's URDFs often write ``effort="0"``. The user then gives the bound, a servo's peak torque (N·m) or
an axis's peak force (N), without editing the file; the sources say it was given so.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from pathlib import Path

import pinocchio as pin

from placement.exceptions import listed
from placement.robot.exceptions import ExampleRobotError
from placement.robot.mjcf import MjcfJoint
from placement.robot.sidecar import Sidecar

GIVEN_ON_COMMAND_LINE = "on the command line"  # in the sources of a drive sized from an --effort bound


def give_efforts(path: Path, model: pin.Model, efforts: Mapping[str, float],
                 joints: dict[str, MjcfJoint] | None = None) -> None:
    """Set the effort bounds ``efforts`` (N or N·m by joint name) on ``model``, and on an MJCF's ``joints`` (whose
    ``effort_from`` then names the option).

    Args:
        path: The description file, for the messages.
        model: Its Pinocchio model (changed in place).
        efforts: The bounds by joint name (N or N·m), each positive and finite (checked by the command line).
        joints: An MJCF's joints (:func:`placement.robot.mjcf.read_mjcf`; changed in place), or None for a URDF.

    Raises:
        ExampleRobotError: A name that is not a joint of one degree of freedom of the model.
    """
    movable = [model.names[j] for j in range(1, model.njoints) if model.joints[j].nv == 1]
    unknown = [name for name in efforts if name not in movable]
    if unknown:
        raise ExampleRobotError(f"{path}: --effort names {listed(unknown, 8)}, not a joint of the description: "
                                f"expected one of {listed(movable, 12)}")
    for name, effort in efforts.items():
        v = model.joints[model.getJointId(name)].idx_v
        model.effortLimit[v] = effort
        if hasattr(model, "lowerEffortLimit"):  # Pinocchio 4 keeps a bound per side
            model.lowerEffortLimit[v] = -effort
        if joints is not None:
            joints[name] = dataclasses.replace(joints.get(name) or MjcfJoint(None, "", 0.0, 0.0, 0.0),
                                               effort=effort, effort_from=_given(name, effort))


def with_effort_sources(sidecar: Sidecar, path: Path, efforts: Mapping[str, float]) -> Sidecar:
    """``sidecar`` (estimated from the description ``path``) whose drives' sources say which effort bounds
    ``efforts`` (by joint name) were given on the command line."""
    sources = dict(sidecar.sources)
    for actuator in sidecar.actuators:
        key = f"drives.{actuator.drive}.motor"
        if actuator.joint in efforts and key in sources:
            effort = efforts[actuator.joint]
            sources[key] += f"; the effort bound {effort:g} given by {_given(actuator.joint, effort)}, not by {path.name}"
    return sidecar.model_copy(update={"sources": sources})


def _given(name: str, effort: float) -> str:
    """How an effort bound was given, in the sources."""
    return f"--effort {name}={effort:g} {GIVEN_ON_COMMAND_LINE}"

"""Limits as margins: how close a placement comes to each limit, which actuator, where.

A margin is normalised so that 0 is the limit and 1 is comfortably far: (limit − value)/scale,
with the joint range, the speed limit, the torque limit or the workspace side as the scale.
A placement is feasible when every margin is ≥ 0 at every sample.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.drives import MotorTrace, drives_of
from placement.robot import Robot




@dataclass(frozen=True)
class Margin:
    """The tightest point of one kind of limit along the path.

    Attributes:
        kind: "joint lower limit", "joint upper limit", "joint speed", "motor torque",
            "motor speed" or "workspace".
        where: The actuator's joint name, or the workspace axis.
        margin: (limit − value)/scale at the tightest sample; negative means violated.
        value: The value there (SI: m, m/s, rad/s, N·m, or m for the workspace).
        limit: The limit it is compared with.
        sample: Index of the tightest sample.
        unit: Unit of value and limit.
    """

    kind: str
    where: str
    margin: float
    value: float
    limit: float
    sample: int
    unit: str


def margin_fields(robot: Robot, position: np.ndarray, velocity: np.ndarray, motor: MotorTrace,
                  tool_position_m: np.ndarray) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray, list[str], list[str]]]:
    """Per-sample margins of every limit kind the robot declares.

    Args:
        robot: The robot.
        position, velocity: (..., N, n_act) actuator positions and velocities.
        motor: Motor trace, (..., N, n_act).
        tool_position_m: (..., N, 3) tool point in the base frame.

    Returns:
        For each kind: (margin, value, limit) arrays of shape (..., N, m), the m column names and
        the m units.
    """
    names = [a.joint for a in robot.actuators]
    lengths = ["m" if a.prismatic else "rad" for a in robot.actuators]
    speeds = [f"{unit}/s" for unit in lengths]
    torques = ["N m"] * len(names)
    low = np.array([a.position_min for a in robot.actuators])
    high = np.array([a.position_max for a in robot.actuators])
    speed = np.array([a.velocity_max for a in robot.actuators])
    span = high - low
    drives = drives_of(robot)
    torque = np.array([d.motor.max_torque_Nm for d in drives])
    shape = position.shape
    fields = {
        "joint lower limit": ((position - low) / span, position, np.broadcast_to(low, shape), names, lengths),
        "joint upper limit": ((high - position) / span, position, np.broadcast_to(high, shape), names, lengths),
        "joint speed": ((speed - np.abs(velocity)) / speed, velocity, np.broadcast_to(speed, shape), names, speeds),
        "motor torque": ((torque - np.abs(motor.torque_Nm)) / torque, motor.torque_Nm, np.broadcast_to(torque, shape),
                         names, torques),
    }
    if all(d.motor.max_speed_rad_s is not None for d in drives):
        top = np.array([d.motor.max_speed_rad_s for d in drives])
        fields["motor speed"] = ((top - np.abs(motor.speed_rad_s)) / top, motor.speed_rad_s,
                                 np.broadcast_to(top, shape), names, ["rad/s"] * len(names))
    workspace = robot.sidecar.workspace
    if workspace is not None:
        lo, hi = np.array(workspace.min_m), np.array(workspace.max_m)
        side = hi - lo
        margin = np.concatenate([(tool_position_m - lo) / side, (hi - tool_position_m) / side], axis=-1)
        value = np.concatenate([tool_position_m, tool_position_m], axis=-1)
        limit = np.broadcast_to(np.concatenate([lo, hi]), margin.shape)
        fields["workspace"] = (margin, value, limit, ["x min", "y min", "z min", "x max", "y max", "z max"], ["m"] * 6)
    return fields


def worst_margins(fields: dict) -> tuple[np.ndarray, list[str]]:
    """Tightest margin over the samples of every limit (each kind, each actuator or axis).

    Returns:
        (..., n_limits) margins and the n_limits labels "kind: where". Keeping the limits apart
        (rather than their minimum) keeps each one smooth for the local search.
    """
    margins = np.concatenate([margin.min(axis=-2) for margin, *_ in fields.values()], axis=-1)
    labels = [f"{kind}: {name}" for kind, (*_, names, _units) in fields.items() for name in names]
    return margins, labels


def tightest(fields: dict) -> list[Margin]:
    """The tightest sample of each kind for one placement (arrays of shape (N, m))."""
    out = []
    for kind, (margin, value, limit, names, units) in fields.items():
        sample, column = np.unravel_index(np.argmin(margin), margin.shape)
        out.append(Margin(kind=kind, where=names[column], margin=float(margin[sample, column]),
                          value=float(value[sample, column]), limit=float(limit[sample, column]), sample=int(sample),
                          unit=units[column]))
    return out

"""Joint limits of the actuated joints: position range, speed, and acceleration where the sidecar gives one."""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField, PathBound
from placement.dynamics.path_dynamics import PathDynamics
from placement.robot.model import Robot


def _names_and_units(robot: Robot, suffix: str = "") -> tuple[tuple[str, ...], tuple[str, ...]]:
    actuators = robot.actuators
    return (tuple(a.joint for a in actuators), tuple(("m" if a.prismatic else "rad") + suffix for a in actuators))


class JointRange(Limit):
    """Each actuated joint within [position_min, position_max]; the scale is the range."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        actuators = batch.robot.actuators
        low = np.array([a.position_min for a in actuators])
        high = np.array([a.position_max for a in actuators])
        position, span = batch.distinct(batch.position), high - low
        names, units = _names_and_units(batch.robot)
        return [MarginField("joint lower limit", (position - low) / span, position,
                            np.broadcast_to(low, position.shape), names, units, batch.distinct_samples),
                MarginField("joint upper limit", (high - position) / span, position,
                            np.broadcast_to(high, position.shape), names, units, batch.distinct_samples)]


class JointSpeed(Limit):
    """|joint speed| within velocity_max."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        speed = _speed_max(batch.robot)
        velocity = batch.distinct(batch.velocity)
        names, units = _names_and_units(batch.robot, "/s")
        return [MarginField("joint speed", (speed - np.abs(velocity)) / speed, velocity,
                            np.broadcast_to(speed, velocity.shape), names, units, batch.distinct_samples)]

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        return [PathBound("joint speed", dynamics.joint_velocity, _speed_max(robot))]


class JointAcceleration(Limit):
    """|joint acceleration| within acceleration_max, for the actuators that give one."""

    def applies_to(self, robot: Robot) -> bool:
        return any(a.acceleration_max is not None for a in robot.actuators)

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        bounded, top = _bounded_accelerations(batch.robot)
        acceleration = batch.acceleration[..., bounded]
        names, units = _names_and_units(batch.robot, "/s^2")
        return [MarginField("joint acceleration", (top - np.abs(acceleration)) / top, acceleration,
                            np.broadcast_to(top, acceleration.shape), tuple(names[i] for i in bounded),
                            tuple(units[i] for i in bounded))]

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        bounded, top = _bounded_accelerations(robot)
        return [PathBound("joint acceleration", dynamics.joint_acceleration.columns(bounded, dynamics.shape), top)]


def _speed_max(robot: Robot) -> np.ndarray:
    """(n_act,) every actuated joint's top speed."""
    return np.array([a.velocity_max for a in robot.actuators], dtype=float)


def _bounded_accelerations(robot: Robot) -> tuple[list[int], np.ndarray]:
    """The actuators that give an acceleration bound, and their bounds."""
    bounded = [i for i, a in enumerate(robot.actuators) if a.acceleration_max is not None]
    return bounded, np.array([robot.actuators[i].acceleration_max for i in bounded], dtype=float)


LIMITS.add("joint_range", JointRange())
LIMITS.add("joint_speed", JointSpeed())
LIMITS.add("joint_acceleration", JointAcceleration())

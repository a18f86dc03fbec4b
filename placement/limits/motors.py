"""Motor limits: peak torque, and speed where every drive declares one."""

from __future__ import annotations

import numpy as np

from placement.batch import EvaluatedBatch
from placement.drives.trace import drives_of
from placement.limits.base import LIMITS, Limit, MarginField
from placement.robot.model import Robot


class MotorTorque(Limit):
    """|motor torque| within max_torque_Nm."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        top = np.array([d.motor.max_torque_Nm for d in drives_of(batch.robot)])
        torque = batch.motor.torque_Nm
        names = tuple(a.joint for a in batch.robot.actuators)
        return [MarginField("motor torque", (top - np.abs(torque)) / top, torque, np.broadcast_to(top, torque.shape),
                            names, ("N m",) * len(names))]


class MotorSpeed(Limit):
    """|motor speed| within max_speed_rad_s, when every drive gives one."""

    def applies_to(self, robot: Robot) -> bool:
        return all(d.motor.max_speed_rad_s is not None for d in drives_of(robot))

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        top = np.array([d.motor.max_speed_rad_s for d in drives_of(batch.robot)], dtype=float)
        speed = batch.motor.speed_rad_s
        names = tuple(a.joint for a in batch.robot.actuators)
        return [MarginField("motor speed", (top - np.abs(speed)) / top, speed, np.broadcast_to(top, speed.shape),
                            names, ("rad/s",) * len(names))]


LIMITS.add("motor_torque", MotorTorque())
LIMITS.add("motor_speed", MotorSpeed())

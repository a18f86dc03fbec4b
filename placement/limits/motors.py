"""Motor limits: peak torque, speed where every drive declares one, and phase voltage where a drive gives its bus
voltage."""

from __future__ import annotations

import numpy as np

from placement.drives.trace import drives_of, phase_voltage_V
from placement.evaluation.batch import EvaluatedBatch
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


class DriveVoltage(Limit):
    """|R·I + L·dI/dt + K_e·ω| within the phase voltage the bus allows, for the drives that give a bus voltage.

    dI/dt is each interval's (I_end − I_start)/Δt; a sample takes the larger voltage of the intervals
    on either side of it. Intervals of zero width (a piece's start, or an instant where the optimal
    timing law switches its acceleration) carry no dI/dt.
    """

    def applies_to(self, robot: Robot) -> bool:
        return any(d.motor.bus_voltage_V is not None for d in drives_of(robot))

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        motors = [d.motor for d in drives_of(batch.robot)]
        bounded = [i for i, m in enumerate(motors) if m.bus_voltage_V is not None]
        voltage = phase_voltage_V(batch.robot, batch.motor, batch.widths_by_placement_s)[..., bounded]
        top = np.array([motors[i].phase_voltage_limit_V for i in bounded], dtype=float)
        names = tuple(batch.robot.actuators[i].joint for i in bounded)
        return [MarginField("drive voltage", (top - np.abs(voltage)) / top, voltage, np.broadcast_to(top, voltage.shape),
                            names, ("V",) * len(names))]


LIMITS.add("motor_torque", MotorTorque())
LIMITS.add("motor_speed", MotorSpeed())
LIMITS.add("drive_voltage", DriveVoltage())

"""Motor limits: peak torque, speed where a drive declares one, and phase voltage where a drive gives its bus voltage.

Each comes from the drive equations of :class:`placement.energy.trace.Drives`, on the motor
trace for the margins and on the motion along the path for the optimal timing law's bounds.
"""

from __future__ import annotations

import numpy as np

from placement.contract.batch import EvaluatedBatch
from placement.contract.limit import LIMITS, Limit, MarginField, PathBound
from placement.dynamics.path_dynamics import PathDynamics
from placement.energy.trace import Drives
from placement.robot.model import Robot


class MotorTorque(Limit):
    """|motor torque| within max_torque_Nm."""

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        top = Drives.of(batch.robot).max_torque_Nm
        torque = batch.motor.torque_Nm
        names = tuple(a.joint for a in batch.robot.actuators)
        return [MarginField("motor torque", (top - np.abs(torque)) / top, torque, np.broadcast_to(top, torque.shape),
                            names, ("N m",) * len(names))]

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        drives = Drives.of(robot)
        return [PathBound("motor torque", torque, drives.max_torque_Nm) for torque in drives.torque_forms(dynamics)]


class MotorSpeed(Limit):
    """|motor speed| within max_speed_rad_s, for the drives that give one."""

    def applies_to(self, robot: Robot) -> bool:
        return bool(np.isfinite(Drives.of(robot).max_speed_rad_s).any())

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        top = Drives.of(batch.robot).max_speed_rad_s
        bounded = np.flatnonzero(np.isfinite(top))
        speed = batch.distinct(batch.motor.speed_rad_s)[..., bounded]
        names = tuple(batch.robot.actuators[i].joint for i in bounded)
        return [MarginField("motor speed", (top[bounded] - np.abs(speed)) / top[bounded], speed,
                            np.broadcast_to(top[bounded], speed.shape), names, ("rad/s",) * len(names),
                            batch.distinct_samples)]

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        drives = Drives.of(robot)
        bounded = np.flatnonzero(np.isfinite(drives.max_speed_rad_s))
        speed = drives.motor_speed(dynamics.joint_velocity).columns(bounded, dynamics.shape)
        return [PathBound("motor speed", speed, drives.max_speed_rad_s[bounded])]


class DriveVoltage(Limit):
    """|R·I + L·dI/dt + K_e·ω| within the phase voltage the bus allows, for the drives that give a bus voltage.

    dI/dt is each interval's (I_end − I_start)/Δt; a sample takes the larger voltage of the intervals
    on either side of it. Intervals of zero width (a piece's start, or an instant where the optimal
    timing law switches its acceleration) carry no dI/dt. Along the path, the optimal timing law keeps
    R·I + K_e·ω within the limit; L·dI/dt is not affine in the path motion and is checked on the
    timed samples (with real windings it never binds: the current changes slowly between switches).
    """

    def applies_to(self, robot: Robot) -> bool:
        return bool(np.isfinite(Drives.of(robot).phase_voltage_limit_V).any())

    def fields(self, batch: EvaluatedBatch) -> list[MarginField]:
        drives = Drives.of(batch.robot)
        bounded = np.flatnonzero(np.isfinite(drives.phase_voltage_limit_V))
        voltage = drives.phase_voltage_V(batch.motor, batch.widths_by_placement_s)[..., bounded]
        top = drives.phase_voltage_limit_V[bounded]
        names = tuple(batch.robot.actuators[i].joint for i in bounded)
        return [MarginField("drive voltage", (top - np.abs(voltage)) / top, voltage, np.broadcast_to(top, voltage.shape),
                            names, ("V",) * len(names))]

    def path_bounds(self, robot: Robot, dynamics: PathDynamics) -> list[PathBound]:
        drives = Drives.of(robot)
        bounded = np.flatnonzero(np.isfinite(drives.phase_voltage_limit_V))
        speed = drives.motor_speed(dynamics.joint_velocity)
        return [PathBound("drive voltage", drives.resistive_voltage(torque, speed).columns(bounded, dynamics.shape),
                          drives.phase_voltage_limit_V[bounded]) for torque in drives.torque_forms(dynamics)]


LIMITS.add("motor_torque", MotorTorque())
LIMITS.add("motor_speed", MotorSpeed())
LIMITS.add("drive_voltage", DriveVoltage())

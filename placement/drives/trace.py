"""From actuator effort and motion to motor speed, torque and current.

A transmission turns joint speed into motor speed (ω = k·q̇). The dynamics' effort includes the
rotor and screw inertia (the joint armature); that part acts on the motor side, while the rest of
the effort, plus joint friction (Coulomb and viscous, from the sidecar), passes through the
transmission, whose efficiency η divides the motor torque when the motor drives the load and
multiplies it when the load drives the motor. The current is I = τ/K_t.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.exceptions import RobotFileError
from placement.robot.model import Robot
from placement.robot.sidecar import Drive


@dataclass(frozen=True)
class MotorTrace:
    """Motor quantities per sample and actuator, arrays of shape (..., N, n_act).

    Attributes:
        speed_rad_s: Motor shaft speed.
        torque_Nm: Motor electromagnetic torque.
        current_A: Phase current amplitude I = τ/K_t.
    """

    speed_rad_s: np.ndarray
    torque_Nm: np.ndarray
    current_A: np.ndarray

    def __getitem__(self, index: int | slice) -> MotorTrace:
        """The trace of one placement (or a range) of a batch."""
        return MotorTrace(self.speed_rad_s[index], self.torque_Nm[index], self.current_A[index])


def drives_of(robot: Robot) -> list[Drive]:
    """The drive of every actuator, or an error naming the first actuator that has none."""
    drives = []
    for i, actuator in enumerate(robot.actuators):
        if actuator.drive is None:
            raise RobotFileError(robot.sidecar_path, f"actuators.{i}.drive", f"actuator '{actuator.joint}' has no "
                                 "drive; energy and motor limits need one: name an entry of drives")
        drives.append(actuator.drive)
    return drives


def phase_voltage_V(robot: Robot, trace: MotorTrace, dt_s: np.ndarray) -> np.ndarray:
    """(K, N, n_act) phase voltage R·I + L·dI/dt + K_e·ω of each drive at each sample.

    Args:
        robot: The robot (its drives' motor constants).
        trace: Motor speed and current, (K, N, n_act).
        dt_s: (K, N-1) widths of the intervals between samples; one of zero width (a piece's start, or an
            instant where the optimal timing law switches its acceleration) carries no dI/dt.

    Returns:
        At each sample, the larger voltage of the intervals on either side of it, each with its own dI/dt.
    """
    motors = [d.motor for d in drives_of(robot)]
    resistance, inductance, emf = (np.array([getattr(m, name) for m in motors]) for name in
                                   ("resistance_ohm", "inductance_H", "back_emf_constant_V_s_per_rad"))
    current = trace.current_A
    dt = dt_s[..., None]
    with np.errstate(divide="ignore", invalid="ignore"):
        drop = np.where(dt > 0, inductance * np.diff(current, axis=1) / dt, 0.0)  # L·dI/dt of each interval
    before = resistance * current + emf * trace.speed_rad_s
    after = before.copy()
    before[:, 1:] += drop
    after[:, :-1] += drop
    return np.where(np.abs(before) >= np.abs(after), before, after)


def motor_trace(robot: Robot, effort: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray) -> MotorTrace:
    """Motor speed, torque and current from actuator efforts and motion.

    Args:
        robot: The robot (its actuators' drives).
        effort: (..., N, n_act) efforts from the dynamics (N or N·m), rotor inertia included.
        velocity: Same shape, joint velocities (m/s or rad/s).
        acceleration: Same shape, joint accelerations (m/s² or rad/s²).

    Returns:
        The motor trace, same shapes.
    """
    drives = drives_of(robot)
    ratio = np.array([d.transmission.speed_ratio for d in drives])
    efficiency = np.array([d.transmission.efficiency for d in drives])
    coulomb = np.array([d.friction.coulomb for d in drives])
    viscous = np.array([d.friction.viscous for d in drives])
    kt = np.array([d.motor.torque_constant_Nm_per_A for d in drives])
    rotor = np.array([a.reflected_inertia for a in robot.actuators]) * acceleration  # motor side, at the joint
    load = effort - rotor + coulomb * np.sign(velocity) + viscous * velocity  # through the transmission
    motoring = load * velocity >= 0
    torque = load / ratio * np.where(motoring, 1 / efficiency, efficiency) + rotor / ratio
    return MotorTrace(speed_rad_s=velocity * ratio, torque_Nm=torque, current_A=torque / kt)

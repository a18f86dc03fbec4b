"""From actuator effort and motion to motor speed, torque, current and voltage: the drive equations, once.

A transmission turns joint speed into motor speed (ω = k·q̇). The dynamics' effort includes the
rotor and screw inertia (the joint armature); that part acts on the motor side, while the rest of
the effort, plus joint friction (Coulomb and viscous, from the sidecar), passes through the
transmission, whose efficiency η divides the motor torque when the motor drives the load and
multiplies it when the load drives the motor. The current is I = τ/K_t and the phase voltage
R·I + L·dI/dt + K_e·ω.

:class:`Drives` writes these equations once. They take arrays (a motion sampled in time: the
motor trace) or :class:`placement.dynamics.path_dynamics.PathForm` (a motion along the path, affine in
s̈, ṡ² and ṡ: the bounds that the motor limits put on the optimal timing law).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TypeVar

import numpy as np

from placement.dynamics.path_dynamics import PathDynamics, PathForm
from placement.robot.model import Robot

Quantity = TypeVar("Quantity", np.ndarray, PathForm)
BUILT_KEPT = 64  # robots' drives kept built, at most


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


@dataclass(frozen=True)
class Drives:
    """The drives of a robot's actuators, as arrays in actuator order (SI), and their equations.

    Attributes:
        ratio: Motor speed per unit joint speed (rad/m or rad/rad).
        efficiency: Transmission efficiency η.
        coulomb_friction: Coulomb friction at the joint (N or N·m).
        viscous_friction: Viscous friction at the joint (N·s/m or N·m·s/rad).
        reflected_inertia: Rotor and transmission inertia seen at the joint (kg or kg·m²).
        torque_constant_Nm_per_A, resistance_ohm, inductance_H, back_emf_V_s_per_rad: Motor constants.
        max_torque_Nm: Peak motor torque.
        continuous_torque_Nm: Rated continuous (RMS) motor torque (inf where the drive gives none).
        max_speed_rad_s: Top motor speed (inf where the drive gives none).
        phase_voltage_limit_V: The largest phase voltage the drive applies (inf where it gives no bus voltage).
    """

    ratio: np.ndarray
    efficiency: np.ndarray
    coulomb_friction: np.ndarray
    viscous_friction: np.ndarray
    reflected_inertia: np.ndarray
    torque_constant_Nm_per_A: np.ndarray
    resistance_ohm: np.ndarray
    inductance_H: np.ndarray
    back_emf_V_s_per_rad: np.ndarray
    max_torque_Nm: np.ndarray
    continuous_torque_Nm: np.ndarray
    max_speed_rad_s: np.ndarray
    phase_voltage_limit_V: np.ndarray

    @classmethod
    def of(cls, robot: Robot) -> Drives:
        """The robot's drives (an error names the first actuator without one), built once per tuple of actuators
        (the limits and the motor trace of every evaluated batch ask for them; the arrays are read-only)."""
        known = _BUILT.get(id(robot.actuators))
        if known is not None and known[0] is robot.actuators:
            return known[1]
        built = cls._build(robot)
        for array in vars(built).values():
            array.setflags(write=False)
        if len(_BUILT) >= BUILT_KEPT:
            _BUILT.clear()
        _BUILT[id(robot.actuators)] = (robot.actuators, built)  # the tuple kept alive: its id stays its own
        return built

    @classmethod
    def _build(cls, robot: Robot) -> Drives:
        drives = robot.drives
        motors = [d.motor for d in drives]

        def column(values: list) -> np.ndarray:
            return np.array([np.inf if value is None else value for value in values], dtype=float)

        return cls(ratio=column([d.transmission.speed_ratio for d in drives]),
                   efficiency=column([d.transmission.efficiency for d in drives]),
                   coulomb_friction=column([d.friction.coulomb for d in drives]),
                   viscous_friction=column([d.friction.viscous for d in drives]),
                   reflected_inertia=column([a.reflected_inertia for a in robot.actuators]),
                   torque_constant_Nm_per_A=column([m.torque_constant_Nm_per_A for m in motors]),
                   resistance_ohm=column([m.resistance_ohm for m in motors]),
                   inductance_H=column([m.inductance_H for m in motors]),
                   back_emf_V_s_per_rad=column([m.back_emf_constant_V_s_per_rad for m in motors]),
                   max_torque_Nm=column([m.max_torque_Nm for m in motors]),
                   continuous_torque_Nm=column([m.continuous_torque_Nm for m in motors]),
                   max_speed_rad_s=column([m.max_speed_rad_s for m in motors]),
                   phase_voltage_limit_V=column([m.phase_voltage_limit_V for m in motors]))

    def transmitted(self, effort: Quantity, velocity: Quantity, acceleration: Quantity,
                    direction: np.ndarray) -> Quantity:
        """The effort the transmission carries: the dynamics' effort less its motor-side (rotor) part, plus
        friction; ``direction`` is the sign of the joint velocity."""
        return (effort - self.reflected_inertia * acceleration + self.coulomb_friction * direction
                + self.viscous_friction * velocity)

    def motor_torque(self, transmitted: Quantity, acceleration: Quantity, gain: np.ndarray) -> Quantity:
        """Motor torque: the transmitted effort times the transmission's gain (:attr:`driving_gain` or
        :attr:`braking_gain`), plus the rotor's part."""
        return gain * transmitted + self.reflected_inertia * acceleration / self.ratio

    @property
    def driving_gain(self) -> np.ndarray:
        """Motor torque per unit transmitted effort when the motor drives the load: 1/(k·η)."""
        return 1 / (self.ratio * self.efficiency)

    @property
    def braking_gain(self) -> np.ndarray:
        """Motor torque per unit transmitted effort when the load drives the motor: η/k."""
        return self.efficiency / self.ratio

    def motor_speed(self, velocity: Quantity) -> Quantity:
        """Motor shaft speed from joint speed."""
        return self.ratio * velocity

    def current(self, torque: Quantity) -> Quantity:
        """Phase current amplitude from motor torque."""
        return torque / self.torque_constant_Nm_per_A

    def resistive_voltage(self, torque: Quantity, motor_speed: Quantity) -> Quantity:
        """R·I + K_e·ω: the phase voltage but for the inductive L·dI/dt."""
        return self.resistance_ohm * self.current(torque) + self.back_emf_V_s_per_rad * motor_speed

    def trace(self, effort: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray) -> MotorTrace:
        """Motor speed, torque and current from actuator efforts and motion, arrays (..., N, n_act)."""
        transmitted = self.transmitted(effort, velocity, acceleration, np.sign(velocity))
        gain = np.where(transmitted * velocity >= 0, self.driving_gain, self.braking_gain)
        torque = self.motor_torque(transmitted, acceleration, gain)
        return MotorTrace(speed_rad_s=self.motor_speed(velocity), torque_Nm=torque, current_A=self.current(torque))

    def torque_forms(self, dynamics: PathDynamics) -> list[PathForm]:
        """The motor torque along the path as forms: driving, and braking where a transmission loses power.

        Which of the two applies depends on the motion; a timing law that keeps both within a limit
        keeps the torque within it (conservative by η² while braking, exact for η = 1).
        """
        velocity, acceleration = dynamics.joint_velocity, dynamics.joint_acceleration
        transmitted = self.transmitted(dynamics.effort, velocity, acceleration, np.sign(dynamics.velocity))
        lossy = bool(np.any(self.efficiency != 1.0))
        gains = [self.driving_gain] + ([self.braking_gain] if lossy else [])
        return [self.motor_torque(transmitted, acceleration, gain) for gain in gains]

    def phase_voltage_V(self, trace: MotorTrace, dt_s: np.ndarray) -> np.ndarray:
        """(K, N, n_act) phase voltage R·I + L·dI/dt + K_e·ω of each drive at each sample.

        Args:
            trace: Motor speed and current, (K, N, n_act).
            dt_s: (K, N-1) widths of the intervals between samples; one of zero width (a piece's start, or an
                instant where the optimal timing law switches its acceleration) carries no dI/dt.

        Returns:
            At each sample, the larger voltage of the intervals on either side of it, each with its own dI/dt.
        """
        current, dt = trace.current_A, dt_s[..., None]
        with np.errstate(divide="ignore", invalid="ignore"):
            drop = np.where(dt > 0, self.inductance_H * np.diff(current, axis=1) / dt, 0.0)  # L·dI/dt of each interval
        before = self.resistive_voltage(trace.torque_Nm, trace.speed_rad_s)
        after = before.copy()
        before[:, 1:] += drop
        after[:, :-1] += drop
        return np.where(np.abs(before) >= np.abs(after), before, after)


def motor_trace(robot: Robot, effort: np.ndarray, velocity: np.ndarray, acceleration: np.ndarray) -> MotorTrace:
    """Motor speed, torque and current from actuator efforts and motion (:meth:`Drives.trace`).

    Args:
        robot: The robot (its actuators' drives).
        effort: (..., N, n_act) efforts from the dynamics (N or N·m), rotor inertia included.
        velocity: Same shape, joint velocities (m/s or rad/s).
        acceleration: Same shape, joint accelerations (m/s² or rad/s²).

    Returns:
        The motor trace, same shapes.
    """
    return Drives.of(robot).trace(effort, velocity, acceleration)


_BUILT: dict[int, tuple[tuple, Drives]] = {}  # id(robot.actuators) -> (robot.actuators, their Drives)

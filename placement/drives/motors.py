"""Motor models: from motor speed and current to electric power. A plug-in family.

A motor model maps one actuator's samples to the power of each interval between them, split into
parts (W). The built-in ``pmsm`` is the paper's permanent-magnet synchronous motor: with n phases,

    P = n·(R·I² + L·I·dI/dt + K_e·ω·I),

integrated so that the inductive part sums exactly to n·L/2·(I_end² − I_start²). A package adds a
model under the entry-point group ``placement.motor_models`` (the entry's object is an instance of
a :class:`MotorModel` subclass); a drive names it in ``motor.model`` and may give it extra
constants in ``motor.parameters``.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from dataclasses import dataclass
from typing import Annotated

import numpy as np
from pydantic import Field, model_validator

from placement.registry import Registry
from placement.schema import Count, Number, Strict

NonNegative = Annotated[Number, Field(ge=0.0)]
Positive = Annotated[Number, Field(gt=0.0)]


@dataclass(frozen=True)
class PowerParts:
    """Electric power of intervals between samples, by part (W), arrays of one shape.

    Attributes:
        joule_W: Copper losses.
        inductive_W: Power into the windings' magnetic field (integrates to the stored energy change).
        back_emf_W: Power converted to shaft power.
    """

    joule_W: np.ndarray
    inductive_W: np.ndarray
    back_emf_W: np.ndarray

    @property
    def total_W(self) -> np.ndarray:
        """The electric power drawn."""
        return self.joule_W + self.inductive_W + self.back_emf_W


class Motor(Strict):
    """Motor constants in SI (per phase for a multi-phase motor); ``model`` names the energy model."""

    model: str = "pmsm"
    torque_constant_Nm_per_A: Positive
    back_emf_constant_V_s_per_rad: Positive
    resistance_ohm: NonNegative
    inductance_H: NonNegative
    phases: Annotated[Count, Field(ge=1)]
    rotor_inertia_kg_m2: NonNegative
    max_torque_Nm: Positive
    max_speed_rad_s: Positive | None = None
    bus_voltage_V: Positive | None = Field(None, description="DC bus voltage of the drive: bounds the phase voltage "
                                                             "R·I + L·dI/dt + K_e·ω (see phase_voltage_limit_V)")
    continuous_torque_Nm: Positive | None = Field(None, description="rated continuous (RMS) torque: the thermal "
                                                                     "limit of a duty cycle (see placement.energy.duty)")
    parameters: dict[str, Number] = Field({}, description="extra constants of a plug-in motor model")

    @property
    def phase_voltage_limit_V(self) -> float | None:
        """The largest phase voltage amplitude the drive can apply: V_bus/√3 for a three-phase motor (space-vector
        modulation), V_bus for one with one or two phases (an H-bridge each); None without a bus voltage."""
        if self.bus_voltage_V is None:
            return None
        return self.bus_voltage_V / np.sqrt(3.0) if self.phases == 3 else self.bus_voltage_V

    @model_validator(mode="after")
    def _consistent_with_its_model(self) -> Motor:
        if self.model not in MOTOR_MODELS:
            raise ValueError(f"unknown motor model '{self.model}', expected one of {', '.join(MOTOR_MODELS.names())}")
        MOTOR_MODELS.get(self.model).check(self)
        return self


class MotorModel(ABC):
    """Electric power of a motor from its speed and current."""

    def check(self, motor: Motor) -> None:
        """Raise ValueError when the constants are inconsistent with this model (default: accept)."""
        return None

    def step_energy(self, motor: Motor, current_before_A: np.ndarray,
                    current_after_A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Energy exchanged when the current steps from one value to another at an instant (the optimal
        timing law's acceleration switches), as (given back ≤ 0, taken ≥ 0), J (default: none)."""
        zero = np.zeros(np.broadcast(current_before_A, current_after_A).shape)
        return zero, zero

    @abstractmethod
    def interval_power(self, motor: Motor, speed_rad_s: np.ndarray, current_A: np.ndarray,
                       dt_s: np.ndarray) -> PowerParts:
        """Power of every interval between samples, by part (W).

        Args:
            motor: The motor's constants.
            speed_rad_s: (..., N) shaft speed.
            current_A: (..., N) phase current amplitude.
            dt_s: (N-1,) interval widths, or (..., N-1), each placement's own; an interval of zero width is
                not integrated.

        Returns:
            The parts, each (..., N-1) W.
        """


class Pmsm(MotorModel):
    """Permanent-magnet synchronous motor, the paper's model."""

    def check(self, motor: Motor) -> None:
        # The back-EMF power n·K_e·ω·I must be the shaft power τ·ω = K_t·I·ω.
        expected = motor.torque_constant_Nm_per_A / motor.phases
        if abs(motor.back_emf_constant_V_s_per_rad - expected) > 1e-3 * expected:
            raise ValueError(f"back_emf_constant_V_s_per_rad must be torque_constant_Nm_per_A / phases = "
                             f"{expected:.6g} V s/rad for the pmsm model (else the motor creates or destroys energy)")

    def interval_power(self, motor: Motor, speed_rad_s: np.ndarray, current_A: np.ndarray,
                       dt_s: np.ndarray) -> PowerParts:
        n = motor.phases
        i0, i1 = current_A[..., :-1], current_A[..., 1:]
        w0, w1 = speed_rad_s[..., :-1], speed_rad_s[..., 1:]
        with np.errstate(invalid="ignore", divide="ignore"):
            di_dt = np.where(dt_s > 0, (i1 - i0) / dt_s, 0.0)
        return PowerParts(joule_W=n * motor.resistance_ohm * (i0**2 + i1**2) / 2,
                          inductive_W=n * motor.inductance_H * (i0 + i1) / 2 * di_dt,
                          back_emf_W=n * motor.back_emf_constant_V_s_per_rad * (w0 * i0 + w1 * i1) / 2)

    def step_energy(self, motor: Motor, current_before_A: np.ndarray,
                    current_after_A: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The windings' magnetic energy n·L·I²/2 as the current steps: what falls is given back, what rises is
        taken; a step through zero gives back all of the first and takes all of the second."""
        half = motor.phases * motor.inductance_H / 2
        before, after = half * current_before_A**2, half * current_after_A**2
        through_zero = current_before_A * current_after_A < 0
        given = np.where(through_zero, -before, np.minimum(after - before, 0.0))
        taken = np.where(through_zero, after, np.maximum(after - before, 0.0))
        return given, taken


MOTOR_MODELS: Registry[MotorModel] = Registry("motor model", "placement.motor_models", MotorModel)
MOTOR_MODELS.add("pmsm", Pmsm())


def register_motor_model(name: str, model: MotorModel) -> None:
    """Make a motor model available, in this process, to drives whose ``motor.model`` is ``name``."""
    MOTOR_MODELS.register(name, model)

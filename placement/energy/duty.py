"""Duty cycle: each motor's RMS torque over a cycle against its rated continuous torque, and cycles per hour.

A motor's winding heats with its copper loss, ∝ τ², and cools with a time constant of minutes; over
cycles much shorter than that it stays within its rating when the RMS torque over one period,
sqrt(∫τ² dt / period), is at most the rated continuous torque τ_c (the RMS-torque rule of servo
motor sizing). The cycle is the path run once (its motor torque τ(t), integrated by the trapezoid
rule on the intervals the energy integrates, so a zero-width interval carries nothing), then a rest
of ``rest_s`` during which the motor holds the path's end pose still, with the tool out of the cut:
the hold torque τ_h is the motor torque of the gravity effort there (no motion, no process force, no
Coulomb friction at rest). Over a period of duration T + r the mean square torque is
(∫τ² dt + τ_h²·r)/(T + r); the most cycles per hour is 3600/(T + r*), with r* the shortest rest at
least ``rest_s`` that brings every motor within its rating:

    r* = max(rest_s, max_i (∫τ_i² dt − τ_c,i²·T)/(τ_c,i² − τ_h,i²))   (over the motors with τ_h,i < τ_c,i);

a motor whose hold torque reaches its rating heats during every rest, so for it the shortest rest,
``rest_s``, is best: none (0 cycles per hour) if its period is over the rating even then.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.energy.trace import Drives
from placement.robot.model import Robot

SECONDS_PER_HOUR = 3600.0


def squared_torque_integral(torque_Nm: np.ndarray, widths_s: np.ndarray) -> np.ndarray:
    """Running ∫τ² dt from the first sample to each, by the trapezoid rule, (..., N, n_act) N²·m²·s.

    Args:
        torque_Nm: (..., N, n_act) motor torque at each sample.
        widths_s: (..., N-1) width of each interval between samples (0 where a new piece starts).
    """
    square = torque_Nm**2
    pieces = widths_s[..., None] * (square[..., 1:, :] + square[..., :-1, :]) / 2
    return np.concatenate([np.zeros_like(square[..., :1, :]), np.cumsum(pieces, axis=-2)], axis=-2)


def rating_status(robot: Robot) -> tuple[str, ...]:
    """Per actuator, the status of its continuous torque's source ("EST", "CATALOG", ...; "" when the sidecar gives
    none for it or its drive), read from the most specific of ``drives.NAME.motor.continuous_torque_Nm``,
    ``drives.NAME.motor`` and ``drives.NAME``."""
    return tuple(robot.source_status(f"drives.{actuator.drive_name}.motor.continuous_torque_Nm")
                 for actuator in robot.actuators)


@dataclass(frozen=True)
class DutyCycle:
    """One placement's duty cycle, per actuator where the arrays are (SI).

    Attributes:
        cycle_s: Time of one pass of the path, T.
        rest_s: The rest asked for between passes.
        continuous_torque_Nm: Each motor's rated continuous torque τ_c (inf where the drive gives none).
        rms_torque_Nm: RMS motor torque over one period T + rest_s.
        hold_torque_Nm: Motor torque holding the path's end pose at rest.
        cycles_per_hour: The most passes per hour that keep every rated motor within its rating
            (0 when a hold torque alone exceeds a rating).
        limited_by: The actuator whose rating sets ``cycles_per_hour`` (None: the cycle and the rest do).
    """

    cycle_s: float
    rest_s: float
    continuous_torque_Nm: np.ndarray
    rms_torque_Nm: np.ndarray
    hold_torque_Nm: np.ndarray
    cycles_per_hour: float
    limited_by: int | None

    @property
    def ratio(self) -> np.ndarray:
        """RMS torque over the rated continuous torque (0 where the drive gives no rating)."""
        return self.rms_torque_Nm / self.continuous_torque_Nm


def duty_cycle(drives: Drives, torque_Nm: np.ndarray, widths_s: np.ndarray, hold_effort: np.ndarray,
               rest_s: float = 0.0) -> DutyCycle:
    """The duty cycle of one placement (module docstring).

    Args:
        drives: The robot's drives.
        torque_Nm: (N, n_act) motor torque along the path.
        widths_s: (N-1,) widths of the intervals between samples (0 where a new piece starts).
        hold_effort: (n_act,) actuator efforts holding the path's end pose still (N or N·m).
        rest_s: Rest between passes (s), ≥ 0.
    """
    cycle = float(np.sum(widths_s))
    squared = squared_torque_integral(torque_Nm, widths_s)[-1]
    still = np.zeros_like(hold_effort)
    hold = np.abs(drives.trace(hold_effort, still, still).torque_Nm)
    rated = drives.continuous_torque_Nm
    rms = np.sqrt((squared + hold**2 * rest_s) / (cycle + rest_s))
    needed = np.full(len(rated), -np.inf)  # the shortest rest each rated motor needs (s)
    cools = np.isfinite(rated) & (hold < rated)
    needed[cools] = (squared[cools] - rated[cools] ** 2 * cycle) / (rated[cools] ** 2 - hold[cools] ** 2)
    # A hold torque at or over the rating: every second of rest heats, so the shortest rest is best
    heats = np.isfinite(rated) & ~cools
    needed[heats & (squared + hold**2 * rest_s > rated**2 * (cycle + rest_s))] = np.inf
    worst = int(np.argmax(needed))
    rest = max(rest_s, float(needed[worst]))
    return DutyCycle(cycle_s=cycle, rest_s=rest_s, continuous_torque_Nm=rated, rms_torque_Nm=rms, hold_torque_Nm=hold,
                     cycles_per_hour=SECONDS_PER_HOUR / (cycle + rest) if np.isfinite(rest) else 0.0,
                     limited_by=worst if needed[worst] > rest_s else None)

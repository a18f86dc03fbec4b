"""Electric energy of the drives along a sampled path, with regeneration modes.

The default motor model (``pmsm``) is the paper's: per actuator, with n phases,

    P = n·(R·I² + L·I·dI/dt + K_e·ω·I),      E = ∫ P dt.

Power is integrated interval by interval between consecutive samples of the same piece (the
paper's timing law integrates each segment on its own): the Joule and back-EMF parts by the
trapezoidal rule, the inductive part as n·L·Ī·ΔI, so that it sums exactly to
n·L/2·(I_end² − I_start²) on each piece. What happens to negative power decides the answer:

    clip      per-axis clipping: braking energy is burnt in each drive (default)
    bus       shared DC bus: axes exchange power, the sum is clipped
    signed    full regeneration: negative power is given back
    absolute  braking costs as much as driving

and always E_absolute ≥ E_clip ≥ E_bus ≥ E_signed. Another motor model can be registered with
:func:`register_motor_model` and named in a drive's ``motor.model`` field.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from placement.drives import MotorTrace, drives_of
from placement.exceptions import PlacementError
from placement.robot import Robot
from placement.sidecar import Motor

REGENERATION_MODES = ("clip", "bus", "signed", "absolute")

# A motor model maps one actuator's samples to the power of each interval between them (W):
# f(motor, speed_rad_s (..., N), current_A (..., N), dt_s (N-1,)) -> {"joule", "inductive", "back_emf"},
# each (..., N-1); an interval of zero width is not integrated.
MotorModel = Callable[[Motor, np.ndarray, np.ndarray, np.ndarray], dict[str, np.ndarray]]
_MOTOR_MODELS: dict[str, MotorModel] = {}


def register_motor_model(name: str, model: MotorModel) -> None:
    """Make a motor model available to drives whose ``motor.model`` is ``name``."""
    _MOTOR_MODELS[name] = model


def pmsm_power(motor: Motor, speed_rad_s: np.ndarray, current_A: np.ndarray, dt_s: np.ndarray) -> dict[str, np.ndarray]:
    """Interval power parts (W) of a permanent-magnet synchronous motor (the paper's model)."""
    n = motor.phases
    i0, i1 = current_A[..., :-1], current_A[..., 1:]
    w0, w1 = speed_rad_s[..., :-1], speed_rad_s[..., 1:]
    with np.errstate(invalid="ignore", divide="ignore"):
        di_dt = np.where(dt_s > 0, (i1 - i0) / dt_s, 0.0)
    return {"joule": n * motor.resistance_ohm * (i0**2 + i1**2) / 2,
            "inductive": n * motor.inductance_H * (i0 + i1) / 2 * di_dt,
            "back_emf": n * motor.back_emf_constant_V_s_per_rad * (w0 * i0 + w1 * i1) / 2}


register_motor_model("pmsm", pmsm_power)


@dataclass(frozen=True)
class Energy:
    """Energies (J) for one or many placements; actuator axis last.

    Attributes:
        total_J: (...,) electric energy drawn under the regeneration mode.
        per_actuator_J: (..., n_act) each drive's share (for ``bus``: its signed energy, since
            the bus pools the drives; the total is then not their sum).
        joule_J, inductive_J, back_emf_J: (..., n_act) signed integrals of the power parts.
        mechanical_J: (..., n_act) signed integral of motor shaft power τ·ω.
        regeneration: The mode used.
    """

    total_J: np.ndarray
    per_actuator_J: np.ndarray
    joule_J: np.ndarray
    inductive_J: np.ndarray
    back_emf_J: np.ndarray
    mechanical_J: np.ndarray
    regeneration: str


def interval_widths(t_s: np.ndarray, piece: np.ndarray) -> np.ndarray:
    """(N-1,) durations of the intervals between samples; 0 where a new piece starts."""
    return np.where(piece[1:] == piece[:-1], np.diff(t_s), 0.0)


def interval_power(robot: Robot, trace: MotorTrace, dt_s: np.ndarray) -> dict[str, np.ndarray]:
    """Power parts of every interval between samples, by each drive's motor model, (..., N-1, n_act) W."""
    parts: dict[str, list[np.ndarray]] = {"joule": [], "inductive": [], "back_emf": []}
    for i, drive in enumerate(drives_of(robot)):
        model = _MOTOR_MODELS.get(drive.motor.model)
        if model is None:
            raise PlacementError(f"unknown motor model '{drive.motor.model}' for actuator {robot.actuators[i].joint}: "
                                 f"registered models are {', '.join(sorted(_MOTOR_MODELS))}")
        for key, value in model(drive.motor, trace.speed_rad_s[..., i], trace.current_A[..., i], dt_s).items():
            parts[key].append(value)
    return {key: np.stack(values, axis=-1) for key, values in parts.items()}


def sample_power(robot: Robot, trace: MotorTrace, t_s: np.ndarray, piece: np.ndarray) -> np.ndarray:
    """Electric power of each drive at each sample (N, n_act), W, signed.

    The mean of the powers of the intervals on either side of a sample within its piece, so that
    the trapezoidal integral of the samples approaches the energy as the time step shrinks.
    """
    dt = interval_widths(t_s, piece)
    power = sum(interval_power(robot, trace, dt).values())  # (N-1, n_act)
    valid = (dt > 0)[:, None]
    left = np.vstack([np.zeros((1, power.shape[1])), np.where(valid, power, 0.0)])
    right = np.vstack([np.where(valid, power, 0.0), np.zeros((1, power.shape[1]))])
    count = np.concatenate([[0], valid[:, 0]]) + np.concatenate([valid[:, 0], [0]])
    return (left + right) / np.maximum(count, 1)[:, None]


def electric_energy(robot: Robot, trace: MotorTrace, t_s: np.ndarray, piece: np.ndarray,
                    regeneration: str = "clip") -> Energy:
    """Integrate the drives' electric power along the path.

    Args:
        robot: The robot (its drives).
        trace: Motor speed, torque and current, (..., N, n_act).
        t_s: (N,) sample times.
        piece: (N,) piece index of each sample (intervals across pieces are not integrated).
        regeneration: One of REGENERATION_MODES.

    Returns:
        The energies.
    """
    if regeneration not in REGENERATION_MODES:
        raise PlacementError(f"unknown regeneration mode '{regeneration}': expected one of {', '.join(REGENERATION_MODES)}")
    dt = interval_widths(t_s, piece)
    stacked = interval_power(robot, trace, dt)
    power = sum(stacked.values())
    shaft = trace.torque_Nm * trace.speed_rad_s
    mechanical = (shaft[..., :-1, :] + shaft[..., 1:, :]) / 2

    def integral(p: np.ndarray) -> np.ndarray:
        return np.einsum("...na,n->...a", p, dt)

    # Every mode sums the actuators first, then integrates, so the ordering of the modes holds
    # exactly in floating point, interval by interval.
    shaped = {"clip": np.maximum(power, 0.0), "absolute": np.abs(power)}.get(regeneration, power)
    pooled = shaped.sum(axis=-1)
    total = np.einsum("...n,n->...", np.maximum(pooled, 0.0) if regeneration == "bus" else pooled, dt)
    per_actuator = integral(shaped)
    return Energy(total_J=total, per_actuator_J=per_actuator, joule_J=integral(stacked["joule"]),
                  inductive_J=integral(stacked["inductive"]), back_emf_J=integral(stacked["back_emf"]),
                  mechanical_J=integral(mechanical), regeneration=regeneration)

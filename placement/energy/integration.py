"""Electric energy of the drives along a sampled path.

Power comes from each drive's motor model (:mod:`placement.drives.motors`) and is integrated
interval by interval between consecutive samples of the same piece (the paper's timing law
integrates each segment on its own): the Joule and back-EMF parts by the trapezoidal rule, the
inductive part so that it sums exactly to n·L/2·(I_end² − I_start²) on each piece. Where two
samples of a piece share an instant (the optimal timing law switches its acceleration there, and
the current steps), the model's step energy counts what the windings give back and take. What
happens to negative power is the regeneration policy's (:mod:`placement.energy.regeneration`),
applied to a step's energies as to an interval's.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.drives.motors import MOTOR_MODELS, Motor, MotorModel, PowerParts
from placement.energy.regeneration import REGENERATION
from placement.energy.trace import MotorTrace
from placement.robot.model import Robot


@dataclass(frozen=True)
class Energy:
    """Energies (J) for one or many placements; actuator axis last.

    Attributes:
        total_J: (...,) electric energy drawn under the regeneration mode.
        per_actuator_J: (..., n_act) each drive's share (for ``bus``: its signed energy, since
            the bus pools the drives; the total is then not their sum).
        joule_J, inductive_J, back_emf_J: (..., n_act) signed integrals of the power parts.
        mechanical_J: (..., n_act) signed integral of motor shaft power τ·ω.
        regeneration: The policy used.
    """

    total_J: np.ndarray
    per_actuator_J: np.ndarray
    joule_J: np.ndarray
    inductive_J: np.ndarray
    back_emf_J: np.ndarray
    mechanical_J: np.ndarray
    regeneration: str


def interval_widths(t_s: np.ndarray, piece: np.ndarray) -> np.ndarray:
    """(..., N-1) durations of the intervals between samples of times (..., N); 0 where a new piece starts."""
    return np.where(piece[1:] == piece[:-1], np.diff(t_s), 0.0)


def motor_models(robot: Robot) -> list[tuple[MotorModel, Motor]]:
    """Each actuator's motor model and its constants."""
    return [(MOTOR_MODELS.get(d.motor.model), d.motor) for d in robot.drives]


def interval_power(robot: Robot, trace: MotorTrace, dt_s: np.ndarray) -> PowerParts:
    """Power parts of every interval between samples, by each drive's motor model, (..., N-1, n_act) W."""
    parts = [model.interval_power(motor, trace.speed_rad_s[..., i], trace.current_A[..., i], dt_s)
             for i, (model, motor) in enumerate(motor_models(robot))]
    return PowerParts(*(_columns([getattr(p, name) for p in parts]) for name in ("joule_W", "inductive_W", "back_emf_W")))


def sample_power(robot: Robot, trace: MotorTrace, t_s: np.ndarray, piece: np.ndarray) -> np.ndarray:
    """Electric power of each drive at each sample (N, n_act), W, signed.

    The mean of the powers of the intervals on either side of a sample within its piece, so that
    the trapezoidal integral of the samples approaches the energy as the time step shrinks.
    """
    dt = interval_widths(t_s, piece)
    power = interval_power(robot, trace, dt).total_W  # (N-1, n_act)
    valid = (dt > 0)[:, None]
    left = np.vstack([np.zeros((1, power.shape[1])), np.where(valid, power, 0.0)])
    right = np.vstack([np.where(valid, power, 0.0), np.zeros((1, power.shape[1]))])
    count = np.concatenate([[0], valid[:, 0]]) + np.concatenate([valid[:, 0], [0]])
    return (left + right) / np.maximum(count, 1)[:, None]


@dataclass(frozen=True)
class DrivePower:
    """What the drives draw along a sampled path before a regeneration policy counts it (the same under every
    policy): the intervals, their power and the policy-free integrals.

    Attributes:
        dt_s: (N-1,) or (..., N-1) interval widths (0 where a new piece starts).
        parts: Power parts of every interval, (..., N-1, n_act) W.
        joule_J, inductive_J, back_emf_J: (..., n_act) integrals of the parts over the intervals (without the
            current steps' energies).
        mechanical_J: (..., n_act) integral of motor shaft power τ·ω.
        stepped: (S,) the intervals where two samples of a piece share an instant, for some placement.
        steps: (S,) or (..., S) where they do, on those intervals.
        step_J: Where ``steps`` has any: what each drive's windings give back and take on those intervals
            (:func:`step_energies`), (..., S, n_act) each, else None.
    """

    dt_s: np.ndarray
    parts: PowerParts
    joule_J: np.ndarray
    inductive_J: np.ndarray
    back_emf_J: np.ndarray
    mechanical_J: np.ndarray
    stepped: np.ndarray
    steps: np.ndarray
    step_J: tuple[np.ndarray, np.ndarray] | None


def _integral(power_W: np.ndarray, dt_s: np.ndarray) -> np.ndarray:
    """(..., n_act) the integral of (..., N-1, n_act) interval powers over intervals of widths ``dt_s``."""
    return np.einsum("...na,...n->...a", power_W, dt_s)


def drive_power(robot: Robot, trace: MotorTrace, t_s: np.ndarray, piece: np.ndarray) -> DrivePower:
    """The drives' power along the path and its policy-free integrals (arguments as :func:`electric_energy`)."""
    dt = interval_widths(t_s, piece)
    parts = interval_power(robot, trace, dt)
    shaft = trace.torque_Nm * trace.speed_rad_s
    mechanical = (shaft[..., :-1, :] + shaft[..., 1:, :]) / 2
    steps = (dt == 0) & (piece[1:] == piece[:-1])
    stepped = np.flatnonzero(steps.reshape(-1, steps.shape[-1]).any(axis=0))  # the optimal law's: half the intervals
    return DrivePower(dt_s=dt, parts=parts, joule_J=_integral(parts.joule_W, dt),
                      inductive_J=_integral(parts.inductive_W, dt), back_emf_J=_integral(parts.back_emf_W, dt),
                      mechanical_J=_integral(mechanical, dt), stepped=stepped, steps=np.take(steps, stepped, axis=-1),
                      step_J=step_energies(robot, trace, stepped) if len(stepped) else None)


def electric_energy(robot: Robot, trace: MotorTrace, t_s: np.ndarray, piece: np.ndarray,
                    regeneration: str = "clip", power: DrivePower | None = None) -> Energy:
    """Integrate the drives' electric power along the path.

    Args:
        robot: The robot (its drives).
        trace: Motor speed, torque and current, (..., N, n_act).
        t_s: (N,) sample times, or (..., N), each placement's own.
        piece: (N,) piece index of each sample (intervals across pieces are not integrated).
        regeneration: A regeneration policy's name (see :mod:`placement.energy.regeneration`).
        power: The same drives' :func:`drive_power` along the same path, if known (one per batch serves every
            policy).

    Returns:
        The energies.

    Raises:
        UnknownMemberError: No such regeneration policy.
    """
    policy = REGENERATION.get(regeneration)
    drive = drive_power(robot, trace, t_s, piece) if power is None else power
    dt = drive.dt_s
    # Every policy sums the actuators first, then integrates, so the ordering of the built-in
    # policies holds exactly in floating point, interval by interval.
    shaped = policy.axis_power(drive.parts.total_W)
    supply = policy.supply_power(_over_actuators(shaped))
    # each placement's own times (the optimal law): a row sum, which is the same for a placement in any batch, as
    # einsum's is not then
    total = (supply * dt).sum(axis=-1) if dt.ndim > 1 else np.einsum("...n,...n->...", supply, dt)
    per_actuator = _integral(shaped, dt)
    inductive = drive.inductive_J
    if drive.step_J is not None:
        steps, (given, taken) = drive.steps, drive.step_J
        drawn = np.where(steps[..., None], policy.axis_power(given) + policy.axis_power(taken), 0.0)
        total = total + np.where(steps, policy.supply_power(_over_actuators(drawn)), 0.0).sum(axis=-1)
        per_actuator = per_actuator + _over_intervals(drawn)
        inductive = inductive + _over_intervals(np.where(steps[..., None], given + taken, 0.0))
    return Energy(total_J=total, per_actuator_J=per_actuator, joule_J=drive.joule_J, inductive_J=inductive,
                  back_emf_J=drive.back_emf_J, mechanical_J=drive.mechanical_J, regeneration=regeneration)


def _over_actuators(power: np.ndarray) -> np.ndarray:
    """(..., N-1) the sum of (..., N-1, n_act) over the actuators, one after the other (as numpy's sum, which runs
    about thirty times slower over so short an axis)."""
    total = power[..., 0]
    for column in range(1, power.shape[-1]):
        total = total + power[..., column]
    return total


def _over_intervals(energy: np.ndarray) -> np.ndarray:
    """(..., n_act) the sum of (..., N-1, n_act) over the intervals, actuator by actuator (numpy's sum over the middle
    axis runs about fifteen times slower)."""
    return np.stack([energy[..., column].sum(axis=-1) for column in range(energy.shape[-1])], axis=-1)


def step_energies(robot: Robot, trace: MotorTrace, intervals: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """What each drive's windings give back (≤ 0) and take (≥ 0), J, if its current stepped between the two samples
    of each of some ``intervals`` (S,) at an instant, by its motor model: (..., S, n_act) each."""
    steps = [model.step_energy(motor, np.take(trace.current_A[..., i], intervals, axis=-1),
                               np.take(trace.current_A[..., i], intervals + 1, axis=-1))
             for i, (model, motor) in enumerate(motor_models(robot))]  # take: each placement's numbers contiguous
    return _columns([s[0] for s in steps]), _columns([s[1] for s in steps])


def _columns(columns: list[np.ndarray]) -> np.ndarray:
    """(..., n_act) from the n_act arrays (...) of each drive, each drive's numbers contiguous
    (:func:`placement.dynamics.path_dynamics.sample_rows` says why)."""
    return np.moveaxis(np.stack(columns), 0, -1)

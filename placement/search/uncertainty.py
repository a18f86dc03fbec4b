"""Error bars: how far the drives' uncertain constants move the energies, the gain and the ranking of the basins.

Each constant of each named drive that the energy depends on (the motor's resistance, torque and back-EMF
constants, inductance and rotor inertia; the transmission's efficiency and inertia; friction where it is not
zero) gets a relative range from its source status in the sidecar's ``sources`` (the longest key that is a
prefix of ``drives.NAME.motor.FIELD``): EST (or no source stated) ± EST_SPREAD, CALIBRATED ± CALIBRATED_SPREAD
(the calibration's fitted intervals are not stored in the sidecar: this is a stated default), PUBLISHED,
CATALOG, PAPER and DERIVED ± STATED_SPREAD; an efficiency stays at most 1. The link masses (EST too, in the
URDF) are not varied: their range would need the model rebuilt.

Propagation:

- **First order**, by central differences of the exact model (each constant moved by DIFFERENCE_STEP of itself
  either way, or one way where its range ends at its value): the interval is value + Σ_i min/max(g_i (low_i - p_i),
  g_i (high_i - p_i)), the linearised worst case over the box of ranges, for the best and worst energies and
  for the gain (from the same perturbed evaluations).
- **Sampling**, as a check and for the ranking: SAMPLES draws of every constant at once, uniform in its range
  (a fixed seed); the probability that another basin's placement has less energy than the best's is the share
  of draws where it does (the rank robustness is one less that).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot

EST_SPREAD = 0.20  # relative half-range of an estimated constant (EST, or no source stated)
CALIBRATED_SPREAD = 0.05  # of a calibrated one (a stated default: the fitted intervals are not in the sidecar)
STATED_SPREAD = 0.02  # of a published, catalogue, paper or derived one
SPREADS = {"EST": EST_SPREAD, "CALIBRATED": CALIBRATED_SPREAD, "PUBLISHED": STATED_SPREAD, "CATALOG": STATED_SPREAD,
           "PAPER": STATED_SPREAD, "DERIVED": STATED_SPREAD}
DIFFERENCE_STEP = 1e-3  # central differences: each constant moved by this share of itself
SAMPLES = 64  # parameter draws of the sampling check and the rank robustness
FIELDS = (("motor", "resistance_ohm"), ("motor", "torque_constant_Nm_per_A"), ("motor", "back_emf_constant_V_s_per_rad"),
          ("motor", "inductance_H"), ("motor", "rotor_inertia_kg_m2"), ("transmission", "efficiency"),
          ("", "transmission_inertia_kg_m2"), ("friction", "coulomb"), ("friction", "viscous"))
UPPER = {"efficiency": 1.0}  # a constant that cannot exceed this


@dataclass(frozen=True)
class Parameter:
    """One uncertain constant of a named drive: ``drives.DRIVE.GROUP.FIELD`` (GROUP empty: the drive's own field)."""

    drive: str
    group: str
    field: str
    value: float
    low: float
    high: float
    status: str

    @property
    def key(self) -> str:
        """Its sidecar key, as ``sources`` names it."""
        return ".".join(part for part in ("drives", self.drive, self.group, self.field) if part)


@dataclass(frozen=True)
class Interval:
    """A quantity and its first-order interval over the parameters' ranges, with the range of the sampled values."""

    value: float
    low: float
    high: float
    sampled_low: float
    sampled_high: float


@dataclass(frozen=True)
class Uncertainty:
    """The error bars of a search's answer (module docstring).

    Attributes:
        parameters: The constants varied, with their ranges and source status.
        best, worst: The best and worst placements' energies (J), None where not computed.
        gain: The gain (a share), None without both.
        other_basin_wins: The share of parameter draws in which another basin's placement takes less energy than
            the best's (0 without other basins).
        samples: Parameter draws.
        slopes: (n_parameters, n_placements) the energies' derivatives by each parameter (J per the parameter's unit)
            at the best, the worst and the other basins' placements, in that order (those given).
    """

    parameters: tuple[Parameter, ...]
    best: Interval | None
    worst: Interval | None
    gain: Interval | None
    other_basin_wins: float
    samples: int
    slopes: np.ndarray
    method: str = "first order by central differences of the exact model; checked by uniform sampling"


def uncertain_parameters(robot: Robot) -> tuple[Parameter, ...]:
    """The drives' constants that the energy depends on, with their ranges from their source status (module
    docstring); a constant at 0 has no relative range and is left out."""
    found = []
    for name, drive in robot.named_drives.items():
        for group, field in FIELDS:
            owner = drive if not group else getattr(drive, group, None)
            value = getattr(owner, field, None)
            if not isinstance(value, int | float) or value == 0:
                continue
            key = ".".join(part for part in ("drives", name, group, field) if part)
            status = robot.source_status(key) or "unstated"
            spread = SPREADS.get(status, EST_SPREAD)
            found.append(Parameter(name, group, field, float(value), float(value) * (1 - spread),
                                   min(float(value) * (1 + spread), UPPER.get(field, np.inf)), status))
    return tuple(found)


def with_values(robot: Robot, parameters: tuple[Parameter, ...], values: np.ndarray) -> Robot:
    """The robot with each parameter set to its value in ``values`` (same order)."""
    drives = dict(robot.named_drives)
    for parameter, value in zip(parameters, values, strict=True):
        drive = drives[parameter.drive]
        if parameter.group:
            part = getattr(drive, parameter.group).model_copy(update={parameter.field: float(value)})
            drives[parameter.drive] = drive.model_copy(update={parameter.group: part})
        else:
            drives[parameter.drive] = drive.model_copy(update={parameter.field: float(value)})
    return robot.with_drives(drives)


def _energies(robot: Robot, path: ToolPath, settings: EvaluatorSettings, placements: np.ndarray) -> np.ndarray:
    with Evaluator(robot, path, settings) as evaluator:
        return np.asarray(evaluator.evaluate(placements).value, dtype=float)


def energy_uncertainty(robot: Robot, path: ToolPath, settings: EvaluatorSettings, best: np.ndarray | None,
                       worst: np.ndarray | None = None, others: np.ndarray | None = None) -> Uncertainty:
    """The error bars of the best and worst placements' energies, the gain and the basins' ranking (module docstring).

    Args:
        robot: The robot (its named drives are varied).
        path: The tool path.
        settings: How placements are evaluated (the search's: the objective must be the energy).
        best, worst: (6,) placements (m, rad), or None.
        others: (K, 6) other basins' placements (the rank robustness), or None.
    """
    parameters = uncertain_parameters(robot)
    rows = [p for p in (best, worst) if p is not None]
    placements = np.vstack(rows + ([others] if others is not None and len(others) else []))
    nominal = np.array([p.value for p in parameters])
    base = _energies(robot, path, settings, placements)
    slopes = np.zeros((len(parameters), len(placements)))
    for k, parameter in enumerate(parameters):
        up = min(parameter.value * (1 + DIFFERENCE_STEP), parameter.high)
        down = parameter.value * (1 - DIFFERENCE_STEP)
        moved = [nominal.copy(), nominal.copy()]
        moved[0][k], moved[1][k] = down, up
        low, high = (_energies(with_values(robot, parameters, m), path, settings, placements) for m in moved)
        slopes[k] = (high - low) / (up - down)
    rng = np.random.default_rng(0)
    lows, highs = np.array([p.low for p in parameters]), np.array([p.high for p in parameters])
    draws = rng.uniform(lows, highs, (SAMPLES, len(parameters)))
    sampled = np.array([_energies(with_values(robot, parameters, d), path, settings, placements) for d in draws])
    offsets = np.stack([lows - nominal, highs - nominal])  # (2, n_parameters)

    def interval(values: np.ndarray, gradient: np.ndarray, samples: np.ndarray) -> Interval:
        steps = gradient[None, :] * offsets
        return Interval(float(values), float(values + steps.min(axis=0).sum()), float(values + steps.max(axis=0).sum()),
                        float(samples.min()), float(samples.max()))

    found: dict[str, Interval | None] = {"best": None, "worst": None, "gain": None}
    for row, key in enumerate(key for key, p in (("best", best), ("worst", worst)) if p is not None):
        found[key] = interval(base[row], slopes[:, row], sampled[:, row])
    if best is not None and worst is not None:
        def gain(b: np.ndarray, w: np.ndarray) -> np.ndarray:
            return (w - b) / np.maximum(np.abs(w), np.abs(b))
        # the gain's gradient by the chain rule on the same central differences
        larger = max(abs(base[0]), abs(base[1]))
        gradient = (slopes[:, 1] - slopes[:, 0]) / larger - (base[1] - base[0]) * slopes[:, 1 if abs(base[1]) >= abs(
            base[0]) else 0] * np.sign(base[1] if abs(base[1]) >= abs(base[0]) else base[0]) / larger**2
        found["gain"] = interval(gain(base[0], base[1]), gradient, gain(sampled[:, 0], sampled[:, 1]))
    first_other = len(rows)
    wins = 0.0
    if best is not None and len(placements) > first_other:
        wins = float(np.mean(sampled[:, first_other:].min(axis=1) < sampled[:, 0]))
    return Uncertainty(parameters, found["best"], found["worst"], found["gain"], wins, SAMPLES, slopes)

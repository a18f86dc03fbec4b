"""The time-optimal timing law: the fastest motion along a placed path that the robot allows.

Along a path p(s) sampled in arc length s, every joint moves as q(s), so its velocity and
acceleration are q'·ṡ and q'·s̈ + q''·ṡ², and the dynamics (projected RNEA, linear in the
accelerations, quadratic in the velocities) give each actuator's effort exactly as

    F(s) = A(s)·s̈ + B(s)·ṡ² + C(s),

with C the static load (gravity and process forces), A the inertia along the path and B the
centripetal and Coriolis part, from three batched RNEA calls. Every limit of the robot is then
linear in (s̈, ṡ²) at each sample, the form that TOPP-RA (Pham and Pham, IEEE T-RO 2018, the
``toppra`` package) solves for the time-optimal ṡ(s):

- joint speed, motor speed and the path's feed: bounds on ṡ²;
- joint acceleration (where the sidecar gives ``acceleration_max``): |q'·s̈ + q''·ṡ²| ≤ a_max;
- motor torque τ = k·(F − J_r·q̈ + friction) + J_r·q̈/ratio, k = 1/(ratio·η) when the motor drives
  and η/ratio when it brakes (:mod:`placement.drives.trace`): both k are bounded, so braking is
  held to the driving bound (conservative by η², exact for η = 1), and the viscous friction's
  ṡ = √(ṡ²) is bounded by its tangent above and its chord below (exact at rest and at the
  speed bound);
- drive voltage (where the sidecar gives ``bus_voltage_V``): R·I + K_e·ω within the phase voltage
  (:class:`placement.limits.motors.DriveVoltage`). The inductive L·dI/dt is not linear in (s̈, ṡ²):
  the limit checks it on the timed samples, and a placement whose timing exceeds it is infeasible.
  Within the intervals, where s̈ is constant, the current changes slowly (with the Orthoglide's
  6 mH, the term never binds); its steps where s̈ switches carry no dI/dt.

TOPP-RA keeps each limit at both ends of every interval between samples, with a margin of
``SAFETY``. Its s̈ is constant on each interval and switches at the samples, so the exact chain
evaluates each interval on its own (a sample inside a run appears twice, zero time apart:
:attr:`placement.path.samples.PathGeometry.evaluated_samples`); where the current steps there, the
energy integration counts what the windings give back and take. :mod:`placement.limits` then
checks the timed samples like any other timing's. The tool stops wherever the realistic law stops
(corners, gaps, changes of the tool's rate of turning): each run between stops is timed rest to
rest, and the samples grow denser towards the stops, where the tool moves slowest.
"""

from __future__ import annotations

import logging
from functools import cache
from types import ModuleType
from typing import TYPE_CHECKING

import numpy as np

from placement.drives.trace import drives_of
from placement.dynamics.path import PathDynamics
from placement.robot.model import Robot
from placement.timing.law import TimeLaw

if TYPE_CHECKING:
    from placement.path.samples import PathGeometry

SAFETY = 0.99  # share of each limit the timing law may use (the exact chain checks the rest)








@cache
def _toppra() -> tuple[ModuleType, type]:
    """toppra and the constraint class built on it, imported on first use (toppra loads matplotlib: 0.4 s)."""
    import toppra
    import toppra.algorithm
    import toppra.constraint

    logging.getLogger("toppra").setLevel(logging.ERROR)  # an infeasible run is an answer, reported by the limits

    class Given(toppra.constraint.LinearConstraint):
        """Constraint rows a·s̈ + b·ṡ² + c ≤ 0 and bounds on ṡ², computed beforehand for one run."""

        def __init__(self, a: np.ndarray | None, b: np.ndarray | None, c: np.ndarray | None,
                     x_max: np.ndarray) -> None:
            super().__init__()
            self.set_discretization_type(toppra.constraint.DiscretizationType.Interpolation)
            self.identical = True
            self._rows = (a, b, c)
            self._x_max = x_max

        def compute_constraint_params(self, path: object, gridpoints: np.ndarray, *args: object,
                                      **kwargs: object) -> tuple:
            a, b, c = self._rows
            xbound = np.column_stack([np.zeros(len(gridpoints)), self._x_max])
            if a is None:
                return None, None, None, None, None, None, xbound
            rows = a.shape[1]
            a, b, c, F, g, _, _ = toppra.constraint.canlinear_colloc_to_interpolate(
                a, b, c, np.eye(rows), np.zeros(rows), None, None, gridpoints, identical=True)
            return a, b, c, F, g, None, xbound

    return toppra, Given


class _Interval:
    """The path interval of one run (what TOPP-RA asks of a path when the constraints are given)."""

    def __init__(self, length_m: float) -> None:
        self.path_interval = np.array([0.0, length_m])


def speed_bound(robot: Robot, dynamics: PathDynamics, feed_m_s: np.ndarray) -> np.ndarray:
    """(K, N) the highest ṡ (m/s) that the joint and motor speed limits and the feed allow at each sample."""
    drives = drives_of(robot)
    joint = np.array([a.velocity_max for a in robot.actuators], dtype=float)
    motor = np.array([d.motor.max_speed_rad_s or np.inf for d in drives]) / np.array(
        [d.transmission.speed_ratio for d in drives])
    rate = np.abs(dynamics.velocity)
    with np.errstate(divide="ignore"):
        per_actuator = SAFETY * np.minimum(joint, motor) / rate
    return np.minimum(per_actuator.min(axis=-1), feed_m_s)


def limit_rows(robot: Robot, dynamics: PathDynamics, speed_max: np.ndarray) -> tuple[np.ndarray, ...]:
    """Rows a·s̈ + b·ṡ² + c ≤ 0, (K, N, rows) each, of the torque, drive voltage and joint acceleration limits.

    A term linear in ṡ (viscous friction, back-EMF) is bounded by ṡ ≤ (ṡ² + x̄)/(2·√x̄) (the tangent
    at x̄ = ``speed_max``²) where it raises the constrained value, and by ṡ ≥ ṡ²/√x̄ (the chord) where it
    lowers it: both hold for every ṡ up to ``speed_max``, so the rows never allow what the limit forbids.
    """
    drives = drives_of(robot)
    ratio = np.array([d.transmission.speed_ratio for d in drives])
    efficiency = np.array([d.transmission.efficiency for d in drives])
    coulomb = np.array([d.friction.coulomb for d in drives])
    viscous = np.array([d.friction.viscous for d in drives])
    reflected = np.array([a.reflected_inertia for a in robot.actuators])
    d = dynamics
    bar = np.maximum(speed_max, 1e-12)[..., None]  # √x̄, the speed bound
    rows: list[tuple[np.ndarray, ...]] = []

    def bound(a: np.ndarray, b: np.ndarray, c: np.ndarray, w: np.ndarray, top: np.ndarray, columns: np.ndarray) -> None:
        """|a·s̈ + b·ṡ² + c + w·ṡ| ≤ top on some actuator columns."""
        a, b, c, w = (np.broadcast_to(term, d.velocity.shape)[..., columns] for term in (a, b, c, w))
        for sign in (1.0, -1.0):
            raising = sign * w > 0
            slope = np.where(raising, sign * w / (2 * bar), sign * w / bar)
            offset = np.where(raising, sign * w * bar / 2, 0.0)
            rows.append((sign * a, sign * b + slope, sign * c + offset - SAFETY * top[columns]))

    every = np.arange(len(drives))
    load = (d.inertia - reflected * d.velocity, d.centripetal - reflected * d.curvature,
            d.static + coulomb * np.sign(d.velocity))
    rotor = (reflected * d.velocity / ratio, reflected * d.curvature / ratio, 0.0)
    torque_top = np.array([dr.motor.max_torque_Nm for dr in drives])
    voltage_top = np.array([dr.motor.phase_voltage_limit_V or np.inf for dr in drives])
    voltage = np.flatnonzero(np.isfinite(voltage_top))
    ohm = np.array([dr.motor.resistance_ohm / dr.motor.torque_constant_Nm_per_A for dr in drives])  # V per N m
    emf = np.array([dr.motor.back_emf_constant_V_s_per_rad for dr in drives]) * ratio * d.velocity  # V per m/s
    gains = [1 / (ratio * efficiency)] + ([efficiency / ratio] if np.any(efficiency != 1.0) else [])
    for gain in gains:  # motor torque per unit load: driving, and braking where the transmission loses power
        a, b, c = (gain * part + turn for part, turn in zip(load, rotor))
        w = gain * viscous * d.velocity
        bound(a, b, c, w, torque_top, every)
        if len(voltage):  # R·I + K_e·ω; the limit checks L·dI/dt on the timed samples
            bound(ohm * a, ohm * b, ohm * c, ohm * w + emf, voltage_top, voltage)
    acceleration_top = np.array([a.acceleration_max or np.inf for a in robot.actuators], dtype=float)
    accelerated = np.flatnonzero(np.isfinite(acceleration_top))
    if len(accelerated):
        bound(d.velocity, d.curvature, np.zeros(1), np.zeros(1), acceleration_top, accelerated)
    return tuple(np.concatenate([row[i] for row in rows], axis=-1) for i in range(3))


def time_optimal(robot: Robot, geometry: PathGeometry, dynamics: PathDynamics, reachable: np.ndarray) -> TimeLaw:
    """The time-optimal timing of each placement, run by run, rest to rest (module docstring).

    Args:
        robot: The robot (its actuators' limits and drives).
        geometry: The path sampled in arc length.
        dynamics: The K placements' joint rates and effort coefficients along it.
        reachable: (K,) placements whose every sample has a configuration (others are not timed).

    Returns:
        The timing law of each placement.
    """
    speed_max = speed_bound(robot, dynamics, geometry.feed_m_s)
    a, b, c = limit_rows(robot, dynamics, speed_max)
    k, n = speed_max.shape
    speed, acceleration = np.zeros((k, n)), np.zeros((k, n))
    timed = np.asarray(reachable, dtype=bool).copy()
    for i in np.flatnonzero(timed):
        for start, stop in zip(geometry.run_starts[:-1], geometry.run_starts[1:]):
            run = slice(start, stop)
            solved = _time_run(geometry.arc_m[run], a[i, run], b[i, run], c[i, run], speed_max[i, run] ** 2)
            if solved is None:
                timed[i] = False
                break
            speed[i, run], acceleration[i, run] = solved
    speed[~timed], acceleration[~timed] = 0.0, 0.0
    return TimeLaw(_times(geometry, speed, timed), speed, acceleration, timed)


def _time_run(arc_m: np.ndarray, a: np.ndarray, b: np.ndarray, c: np.ndarray,
              x_max: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
    """ṡ at each sample and s̈ after it of one run, rest to rest, or None when no timing exists."""
    toppra, given = _toppra()
    constraints = [given(None, None, None, x_max), given(a, b, c, x_max)]
    solver = toppra.algorithm.TOPPRA(constraints, _Interval(float(arc_m[-1])), gridpoints=arc_m,
                                     solver_wrapper="seidel")
    s_ddot, s_dot, _ = solver.compute_parameterization(0.0, 0.0)
    if s_dot is None or s_ddot is None or not np.isfinite(s_dot).all():
        return None
    return s_dot, np.append(s_ddot, s_ddot[-1])


def _times(geometry: PathGeometry, speed: np.ndarray, timed: np.ndarray) -> np.ndarray:
    """(K, N) sample times: s̈ is constant between samples, so each interval takes 2·Δs/(ṡ_i + ṡ_i+1)."""
    ds = np.diff(geometry.arc_m)
    with np.errstate(divide="ignore", invalid="ignore"):
        dt = np.where(geometry.joins, 0.0, 2 * ds / (speed[:, 1:] + speed[:, :-1]))
    dt = np.where(timed[:, None], dt, np.diff(geometry.samples.t_s))
    return np.concatenate([np.zeros((len(speed), 1)), np.cumsum(dt, axis=1)], axis=1)

"""The time-optimal timing law: the fastest motion along a placed path that the robot allows.

Along a path p(s) sampled in arc length s, every joint moves as q(s), so its velocity and
acceleration are q'·ṡ and q'·s̈ + q''·ṡ², and the dynamics give each actuator's effort exactly as
F(s) = A(s)·s̈ + B(s)·ṡ² + C(s) (:mod:`placement.dynamics.path_dynamics`). Every limit on how fast the
path is run states its bounds in that form, |a·s̈ + b·ṡ² + c + w·ṡ| ≤ top at each sample
(:meth:`placement.contract.limit.Limit.path_bounds`), and this law keeps those of every limit that
applies to the robot, an installed one included. The built-in ones:

- joint speed and motor speed (where a drive gives one), and the path's feed: bounds on ṡ;
- joint acceleration (where the sidecar gives ``acceleration_max``): |q'·s̈ + q''·ṡ²| ≤ a_max;
- motor torque (:class:`placement.energy.trace.Drives`), driving and braking: braking is held to
  the driving bound too (conservative by η², exact for η = 1);
- drive voltage (where the sidecar gives ``bus_voltage_V``): R·I + K_e·ω within the phase voltage
  (:class:`placement.limits.motors.DriveVoltage`, which checks L·dI/dt on the timed samples).

A bound with a term in ṡ alone is a speed bound. Otherwise the term w·ṡ (viscous friction,
back-EMF) is not linear in (s̈, ṡ²), the variables of TOPP-RA (Pham and Pham, IEEE T-RO 2018; its
passes compiled and batched over the placements in :mod:`placement.timing.topp`): it is bounded
by its tangent ṡ ≤ (ṡ² + x̄)/(2·√x̄) at the speed bound x̄ = ṡ_max² where it raises the bounded
value, and by its chord ṡ ≥ ṡ²/√x̄ where it lowers it. Both hold for every ṡ up to the speed
bound, so the rows never allow what the limit forbids.

TOPP-RA keeps each bound at both ends of every interval between samples, with a margin of
``SAFETY``. Its s̈ is constant on each interval and switches at the samples, so the exact chain
evaluates each interval on its own (a sample inside a run appears twice, zero time apart:
:attr:`placement.path.samples.PathGeometry.evaluated_samples`); where the current steps there, the
energy integration counts what the windings give back and take. :mod:`placement.limits` then
checks the timed samples like any other timing's. The tool stops wherever the realistic law stops
(corners, gaps, changes of the tool's rate of turning): each run between stops is timed rest to
rest, and the samples grow denser towards the stops, where the tool moves slowest. A hold (a
G-code dwell) is a run of two samples at rest, not timed by TOPP-RA but by its duration.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numba import njit

from placement.contract.limit import PathBound, path_bounds
from placement.dynamics.path_dynamics import PathDynamics
from placement.path.time_law import TimeLaw
from placement.robot.model import Robot
from placement.timing.topp import time_placements

if TYPE_CHECKING:
    from placement.path.samples import PathGeometry

SAFETY = 0.99  # share of each limit the timing law may use (the exact chain checks the rest)


def speed_bound(bounds: list[PathBound], feed_m_s: np.ndarray, placements: int) -> np.ndarray:
    """(K, N) the highest ṡ (m/s) that the speed bounds and the feed (N,) allow at each sample of K placements."""
    speed = np.broadcast_to(feed_m_s, (placements, len(feed_m_s)))
    for bound in bounds:
        if bound.form.speed_only:
            with np.errstate(divide="ignore"):
                per_column = SAFETY * bound.top / np.abs(bound.form.w)
            speed = np.minimum(speed, per_column.min(axis=-1, initial=np.inf))
    return speed


def bound_rows(bounds: list[PathBound], speed_max: np.ndarray) -> tuple[np.ndarray, ...]:
    """Rows a·s̈ + b·ṡ² + c ≤ 0, (K, N, rows) each, of the bounds that are not speed bounds (module docstring)."""
    bar = np.maximum(speed_max, 1e-12)  # √x̄, the speed bound
    kept = [bound for bound in bounds if not bound.form.speed_only]
    width = sum(2 * np.size(bound.top) for bound in kept)
    rows_a, rows_b, rows_c = (np.empty(speed_max.shape + (width,)) for _ in range(3))
    first = 0
    for bound in kept:
        shape = speed_max.shape + np.shape(bound.top)
        a, b, c, w = (_columns(term, shape) for term in bound.form.terms)
        _bound_rows(a, b, c, w, bar, np.array(bound.top, dtype=float), rows_a, rows_b, rows_c, first)
        first += 2 * shape[-1]
    return rows_a, rows_b, rows_c


def _columns(term: np.ndarray | float, shape: tuple[int, ...]) -> np.ndarray:
    """A form's term broadcast to ``shape`` (K, N, m), as a read-only C-contiguous (m, K, N) array: without a copy
    when laid out column by column (:func:`placement.dynamics.path_dynamics.sample_rows`), and the same array type for the
    kernel whatever the term (one compiled version)."""
    columns = np.ascontiguousarray(np.moveaxis(np.broadcast_to(np.asarray(term, dtype=float), shape), -1, 0))
    columns = columns.view()
    columns.flags.writeable = False
    return columns


@njit(cache=True)
def _bound_rows(a: np.ndarray, b: np.ndarray, c: np.ndarray, w: np.ndarray, bar: np.ndarray, top: np.ndarray,
                rows_a: np.ndarray, rows_b: np.ndarray, rows_c: np.ndarray, first: int) -> None:
    """The rows of |a·s̈ + b·ṡ² + c + w·ṡ| ≤ top, the terms (m, K, N), into the columns ``first`` to ``first`` + 2·m
    of ``rows_a``, ``rows_b`` and ``rows_c`` (K, N, rows): the bound on +form, then on −form, column by column;
    ``bar`` (K, N) is √x̄ (module docstring)."""
    m, k_count, n_count = a.shape
    for k in range(k_count):
        for n in range(n_count):
            s = bar[k, n]
            for j in range(m):
                v = w[j, k, n]
                tangent, chord, lift = v / (2 * s), v / s, v * s / 2  # ±w·ṡ's bounds, for either sign negated
                for half, sign, raising in ((0, 1.0, v > 0), (m, -1.0, v < 0)):
                    slope, offset = (tangent, lift) if raising else (chord, 0.0)
                    rows_a[k, n, first + half + j] = sign * a[j, k, n]
                    rows_b[k, n, first + half + j] = sign * (b[j, k, n] + slope)
                    rows_c[k, n, first + half + j] = sign * (c[j, k, n] + offset) - SAFETY * top[j]


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
    bounds = path_bounds(robot, dynamics)
    speed_max = speed_bound(bounds, geometry.feed_m_s, len(reachable))
    a, b, c = bound_rows(bounds, speed_max)
    held = geometry.hold_intervals_s[geometry.run_starts[:-1]] > 0  # holds: at rest, timed by their durations
    speed, acceleration, timed = time_placements(geometry.arc_m, geometry.run_starts, held, a, b, c, speed_max**2,
                                                 reachable)
    return TimeLaw(_times(geometry, speed, timed), speed, acceleration, timed)


def _times(geometry: PathGeometry, speed: np.ndarray, timed: np.ndarray) -> np.ndarray:
    """(K, N) sample times: s̈ is constant between samples, so each interval takes 2·Δs/(ṡ_i + ṡ_i+1); a hold its
    duration."""
    ds = np.diff(geometry.arc_m)
    with np.errstate(divide="ignore", invalid="ignore"):
        dt = np.where(geometry.joins, 0.0, 2 * ds / (speed[:, 1:] + speed[:, :-1]))
    dt = np.where(geometry.hold_intervals_s > 0, geometry.hold_intervals_s, dt)
    dt = np.where(timed[:, None], dt, np.diff(geometry.samples.t_s))
    return np.concatenate([np.zeros((len(speed), 1)), np.cumsum(dt, axis=1)], axis=1)

"""A timing found placement by placement (the optimal law's), and the chain rule of rates timed along the path."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from placement.path.samples import PathGeometry, PathSamples


@dataclass(frozen=True)
class TimeLaw:
    """The timing of K placements of a path sampled by a :class:`placement.path.samples.PathGeometry`.

    Attributes:
        t_s: (K, N) time of each sample from the start of the path.
        speed_m_s: (K, N) ṡ, the tool's speed along the path.
        acceleration_m_s2: (K, N) s̈ on the interval after each sample (the one before, at a run's end).
        timed: (K,) whether every run found a timing; a placement without one holds ṡ = s̈ = 0 at the
            geometry's nominal times (its efforts are static), and :mod:`placement.limits` reports it.
    """

    t_s: np.ndarray
    speed_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    timed: np.ndarray

    @property
    def duration_s(self) -> np.ndarray:
        """(K,) the time to run the whole path (infinite without a timing)."""
        return np.where(self.timed, self.t_s[:, -1] - self.t_s[:, 0], np.inf)

    def at_samples(self, geometry: PathGeometry) -> TimeLaw:
        """This timing (at ``geometry``'s samples) at its evaluated samples, each interval with its own s̈
        (:attr:`placement.path.samples.PathGeometry.evaluated_samples`)."""
        return TimeLaw(self.t_s[:, geometry.grid_rows], self.speed_m_s[:, geometry.grid_rows],
                       self.acceleration_m_s2[:, geometry.interval_rows], self.timed)

    def resampled(self, source: PathGeometry, target: PathGeometry) -> TimeLaw:
        """This timing, found on ``source``'s samples, at the samples of ``target``, another sampling of the
        same path (a denser one, to check the limits between the samples): s̈ is constant between the
        source's samples, so ṡ² grows linearly in s and each time follows exactly."""
        k = len(self.timed)
        speed, acceleration = np.zeros((k, len(target))), np.zeros((k, len(target)))
        t_s = np.broadcast_to(target.samples.t_s, (k, len(target))).copy()
        runs = zip(source.run_starts[:-1], source.run_starts[1:], target.run_starts[:-1], target.run_starts[1:])
        for start, stop, first, last in runs:
            arc = source.arc_m[start:stop]
            i = start + np.clip(np.searchsorted(arc, target.arc_m[first:last], side="right") - 1, 0, len(arc) - 2)
            ds = target.arc_m[first:last] - source.arc_m[i]
            v0, u, t0 = self.speed_m_s[:, i], self.acceleration_m_s2[:, i], self.t_s[:, i]
            v = np.sqrt(np.maximum(v0**2 + 2 * u * ds, 0.0))
            with np.errstate(divide="ignore", invalid="ignore"):
                t = t0 + np.where(v0 + v > 0, 2 * ds / (v0 + v), 0.0)
            v[:, -1], t[:, -1] = self.speed_m_s[:, stop - 1], self.t_s[:, stop - 1]  # at rest, exactly
            speed[:, first:last], acceleration[:, first:last] = v, u
            t_s[self.timed, first:last] = t[self.timed]
        speed[~self.timed], acceleration[~self.timed] = 0.0, 0.0
        return TimeLaw(t_s, speed, acceleration, self.timed)

    def timed_samples(self, unit: PathSamples, placement: int) -> PathSamples:
        """The path's samples at unit speed (:class:`placement.path.samples.PathGeometry`) timed as one placement is."""
        speed, acceleration = self.speed_m_s[placement][:, None], self.acceleration_m_s2[placement][:, None]
        velocity, linear = timed_rates(unit.velocity_m_s, unit.acceleration_m_s2, speed, acceleration)
        timed = dataclasses.replace(unit, t_s=self.t_s[placement], velocity_m_s=velocity, acceleration_m_s2=linear)
        if unit.angular_velocity_rad_s is None or unit.angular_acceleration_rad_s2 is None:
            return timed
        angular_velocity, angular = timed_rates(unit.angular_velocity_rad_s, unit.angular_acceleration_rad_s2, speed,
                                                acceleration)
        return dataclasses.replace(timed, angular_velocity_rad_s=angular_velocity, angular_acceleration_rad_s2=angular)


def timed_rates(per_m: np.ndarray, per_m2: np.ndarray, speed_m_s: np.ndarray,
                acceleration_m_s2: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Rate and acceleration in time of a quantity with derivatives ``per_m`` and ``per_m2`` along the path, moved at
    ṡ and s̈: x' · ṡ and x' · s̈ + x'' · ṡ²."""
    return per_m * speed_m_s, per_m * acceleration_m_s2 + per_m2 * speed_m_s**2



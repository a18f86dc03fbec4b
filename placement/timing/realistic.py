"""The realistic timing law: stops at corners and gaps, a jerk-limited (double-S) feed profile in between.

The tool stops at every sharp corner, at every gap a skipped rapid leaves, and wherever a pose
list's orientation changes its rate of turning (:func:`placement.path.segments.split_runs`).
Between stops it follows a rest-to-rest profile of bounded acceleration and jerk, cruising at
the lowest feed of the segments it crosses; on arcs the feed is lowered until the tangential and
centripetal acceleration and jerk together stay within the bounds.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from placement.exceptions import PlacementError

if TYPE_CHECKING:
    from placement.path.samples import PathSamples
    from placement.path.segments import Run
    from placement.path.toolpath import ToolPath

ARC_SAFETY = 0.98  # share of the bounds used on arcs, where they are checked on samples


class DoubleS:
    """Rest-to-rest jerk-limited motion over a distance: seven phases of constant jerk.

    Args:
        distance_m: Distance to travel (> 0).
        speed_m_s, acceleration_m_s2, jerk_m_s3: Bounds; the peak speed is lowered when the
            distance is too short to reach it.
    """

    def __init__(self, distance_m: float, speed_m_s: float, acceleration_m_s2: float, jerk_m_s3: float) -> None:
        self.jerk = jerk_m_s3
        self.acceleration = acceleration_m_s2

        def ramp(v: float) -> tuple[float, float]:  # (jerk time, acceleration time) to reach v
            if v * jerk_m_s3 >= acceleration_m_s2**2:
                tj = acceleration_m_s2 / jerk_m_s3
                return tj, tj + v / acceleration_m_s2
            tj = np.sqrt(v / jerk_m_s3)
            return tj, 2 * tj

        speed = speed_m_s
        if speed * ramp(speed)[1] > distance_m:  # too short to reach the speed: bisect on the peak
            low, high = 0.0, speed
            for _ in range(100):
                speed = 0.5 * (low + high)
                low, high = (speed, high) if speed * ramp(speed)[1] < distance_m else (low, speed)
        tj, ta = ramp(speed)
        cruise = max(0.0, (distance_m - speed * ta) / speed)
        self.durations = np.array([tj, ta - 2 * tj, tj, cruise, tj, ta - 2 * tj, tj])
        self.jerks = np.array([1, 0, -1, 0, -1, 0, 1]) * jerk_m_s3
        self.duration_s = float(self.durations.sum())
        # State (s, v, a) at the start of each phase.
        self._starts = [(0.0, 0.0, 0.0)]
        for duration, jerk in zip(self.durations, self.jerks):
            self._starts.append(self._advance(*self._starts[-1], jerk, duration))
        self.distance_m = self._starts[-1][0]

    @staticmethod
    def _advance(s, v, a, jerk, t):
        return (s + v * t + a * t**2 / 2 + jerk * t**3 / 6, v + a * t + jerk * t**2 / 2, a + jerk * t)

    def __call__(self, t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Arc length (m), speed (m/s) and tangential acceleration (m/s²) at times ``t_s``."""
        edges = np.concatenate([[0.0], np.cumsum(self.durations)])
        phase = np.clip(np.searchsorted(edges, t_s, side="right") - 1, 0, 6)
        s0, v0, a0 = (np.array([state[i] for state in self._starts[:7]])[phase] for i in range(3))
        s, v, a = self._advance(s0, v0, a0, self.jerks[phase], t_s - edges[phase])
        return s, np.maximum(v, 0.0), a


def sample_realistic(path: ToolPath, step_s: float) -> PathSamples:
    """The path's samples, ``step_s`` apart at most within each run, each run along its feed profile."""
    runs = path.runs()
    profiles = [run_profile(path, run) for run in runs]
    counts = path.sample_counts([profile.duration_s for profile in profiles], step_s)
    parts, start, piece, done = [], 0.0, 0, 0
    held, start, piece = path.hold_parts(0, start, piece)
    parts += held
    for run, profile, count in zip(runs, profiles, counts):
        t = np.linspace(0.0, profile.duration_s, count)
        piece += run.after_gap
        parts.append({"t": start + t, **run.along(*profile(t), path.oriented), "piece": np.full(len(t), piece)})
        start += profile.duration_s
        done += len(run.segments)
        held, start, after = path.hold_parts(done, start, piece + 1)  # the run ends at rest before a hold
        parts += held
        piece = after if held else piece
    samples = path.assemble(parts)
    # Successive runs of one piece meet at rest at a corner: drop the duplicated corner instant.
    keep = np.concatenate([[True], (np.diff(samples.t_s) > 0) | (np.diff(samples.piece) != 0)])
    return samples.rows(keep)


def run_profile(path: ToolPath, run: Run) -> DoubleS:
    """The feed profile of a corner-to-corner run, within the path's acceleration and jerk bounds.

    The run cruises at the lowest feed of its segments.
    """
    length = run.length_m
    feed = min(path.speed_m_s(s) for s in run.segments)
    acceleration, jerk = path.timing.max_acceleration_m_s2, path.timing.max_jerk_m_s3
    assert acceleration is not None and jerk is not None  # the realistic law's schema requires them
    if all(s.center_m is None for s in run.segments):
        return DoubleS(length, feed, acceleration, jerk)
    # On arcs the centripetal acceleration v²/r and its rate add to the tangential ones: share
    # the bounds, then slow down until the sampled acceleration and jerk are within them.
    speed = min(feed, np.sqrt(acceleration / np.sqrt(2) * min(s.radius_m for s in run.segments if s.radius_m)))
    for _ in range(80):
        profile = DoubleS(length, speed, acceleration / np.sqrt(2), jerk / 2)
        t = np.linspace(0.0, profile.duration_s, 4001)
        acc = run.along(*profile(t))["acceleration"]
        rate = np.diff(acc, axis=0) / np.diff(t)[:, None]
        if (np.linalg.norm(acc, axis=1).max() <= ARC_SAFETY * acceleration
                and np.linalg.norm(rate, axis=1).max() <= ARC_SAFETY * jerk):
            return profile
        speed *= 0.95
    raise PlacementError(f"no feed profile keeps the path within {acceleration} m/s^2 and {jerk} m/s^3")

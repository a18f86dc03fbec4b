"""The realistic timing law: stops at corners and gaps, a jerk-limited feed profile with look-ahead in between.

The tool stops at every sharp corner, at every gap a skipped rapid leaves, and wherever a pose
list's orientation changes its rate of turning (:func:`placement.path.segments.split_runs`).
Between stops the feed drops only where the geometry requires it and rises again where it allows:

- each run is cut into *stretches*, consecutive segments with one feed and one curvature vector
  (a line, an arc or a chain of arcs of one radius). A stretch's speed cap is its feed, on a
  curve of curvature κ also ``sqrt(a_max / (√2·κ))`` (the centripetal acceleration v²κ within
  a_max/√2) and ``(j_max / (2·κ²))^(1/3)`` (the centripetal jerk κ²v³ within j_max/2); the
  tangential acceleration and jerk are then held within a_max/√2 and j_max/2 there, so that the
  two together stay within the bounds (on a line the whole bounds are tangential);
- where two stretches meet the speed is at most both caps; where the curvature jumps (a line
  entering an arc, an arc reversing), the centripetal acceleration jumps by v²·|Δ(κn)|, which no
  finite jerk does: the controller spreads it over one interpolation period, taken as the path
  file's sampling step Δt (``time_step_s``; a finer sampling, ``--time-step``, leaves the motion
  as it is), so the speed there is at most ``sqrt(j_max·Δt / |Δ(κn)|)``;
- forward and backward passes over the stretch ends find the highest speeds each stretch can
  join under its tangential bounds, every change of speed a jerk-limited S-curve from and to
  zero acceleration; in each stretch the speed rises to the highest peak its length allows
  (its cap at most), cruises, and falls to its end's speed;
- on curved stretches the sampled tangential + centripetal acceleration and its rate are then
  checked, and a stretch's cap lowered until they are within ``ARC_SAFETY`` of the bounds.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from placement.exceptions import InfeasibleError

if TYPE_CHECKING:
    from placement.path.samples import PathSamples
    from placement.path.segments import Run, Segment
    from placement.path.timed_path import TimedPath

ARC_SAFETY = 0.98  # share of the bounds used on curved stretches, where they are checked on samples
CURVATURE_TOLERANCE_1_M = 1e-6  # curvature vectors closer than this (1/m) are one: no jump at the join
CHECK_SAMPLES = 1001  # samples of a curved stretch's profile where the acceleration and jerk are checked
BISECTIONS = 100


def _ramp(change_m_s: float, acceleration: float, jerk: float) -> tuple[float, float]:
    """(jerk time, whole time) of an S-curve changing the speed by ``change_m_s`` from and to zero acceleration."""
    if change_m_s * jerk >= acceleration**2:
        tj = acceleration / jerk
        return tj, tj + change_m_s / acceleration
    tj = float(np.sqrt(change_m_s / jerk))
    return tj, 2 * tj


def _change_m(v0: float, v1: float, acceleration: float, jerk: float) -> float:
    """Distance (m) an S-curve from ``v0`` to ``v1`` takes: the mean speed times the time (the curve is symmetric)."""
    return (v0 + v1) / 2 * _ramp(abs(v1 - v0), acceleration, jerk)[1]


def _change_phases(v0: float, v1: float, acceleration: float, jerk: float) -> list[tuple[float, float]]:
    """(duration s, jerk m/s³) of the three phases of the S-curve from ``v0`` to ``v1``."""
    tj, whole = _ramp(abs(v1 - v0), acceleration, jerk)
    sign = 1.0 if v1 >= v0 else -1.0
    return [(tj, sign * jerk), (whole - 2 * tj, 0.0), (tj, -sign * jerk)]


def _highest(low: float, high: float, fits: Callable[[float], bool]) -> float:
    """The highest speed in [low, high] that ``fits`` (a monotone test true at ``low``), by bisection."""
    if fits(high):
        return high
    for _ in range(BISECTIONS):
        middle = 0.5 * (low + high)
        low, high = (middle, high) if fits(middle) else (low, middle)
    return low


class Profile:
    """A motion along a distance in phases of constant jerk, from rest.

    Args:
        phases: (duration s, jerk m/s³) of each phase, in order.
    """

    def __init__(self, phases: list[tuple[float, float]]) -> None:
        kept = [(t, j) for t, j in phases if t > 0]
        self.durations = np.array([t for t, _ in kept])
        self.jerks = np.array([j for _, j in kept])
        self.duration_s = float(self.durations.sum())
        self._edges = np.concatenate([[0.0], np.cumsum(self.durations)])
        starts = [(0.0, 0.0, 0.0)]  # (s, v, a) at the start of each phase
        for duration, jerk in kept:
            starts.append(self._advance(*starts[-1], jerk, duration))
        self._starts = np.array(starts)
        self.distance_m = float(self._starts[-1, 0])

    @staticmethod
    def _advance(s, v, a, jerk, t):
        return (s + v * t + a * t**2 / 2 + jerk * t**3 / 6, v + a * t + jerk * t**2 / 2, a + jerk * t)

    def __call__(self, t_s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Arc length (m), speed (m/s) and tangential acceleration (m/s²) at times ``t_s``."""
        phase = np.clip(np.searchsorted(self._edges, t_s, side="right") - 1, 0, len(self.durations) - 1)
        s0, v0, a0 = self._starts[phase].T
        s, v, a = self._advance(s0, v0, a0, self.jerks[phase], t_s - self._edges[phase])
        return s, np.maximum(v, 0.0), a


class DoubleS(Profile):
    """Rest-to-rest jerk-limited motion over a distance: seven phases of constant jerk.

    Args:
        distance_m: Distance to travel (> 0).
        speed_m_s, acceleration_m_s2, jerk_m_s3: Bounds; the peak speed is lowered when the
            distance is too short to reach it.
    """

    def __init__(self, distance_m: float, speed_m_s: float, acceleration_m_s2: float, jerk_m_s3: float) -> None:
        super().__init__(_stretch_phases(0.0, 0.0, distance_m, speed_m_s, acceleration_m_s2, jerk_m_s3)[0])


def _stretch_phases(v_in: float, v_out: float, length_m: float, cap_m_s: float, acceleration: float,
                    jerk: float) -> tuple[list[tuple[float, float]], float]:
    """Phases of a stretch entered at ``v_in`` and left at ``v_out``: up to the highest peak its length allows
    (``cap_m_s`` at most), a cruise, down; and that peak (m/s)."""
    peak = _highest(max(v_in, v_out), cap_m_s, lambda v: _change_m(v_in, v, acceleration, jerk)
                    + _change_m(v, v_out, acceleration, jerk) <= length_m)
    cruise = length_m - _change_m(v_in, peak, acceleration, jerk) - _change_m(peak, v_out, acceleration, jerk)
    return (_change_phases(v_in, peak, acceleration, jerk) + [(max(cruise, 0.0) / peak, 0.0)]
            + _change_phases(peak, v_out, acceleration, jerk)), peak


@dataclass
class Stretch:
    """Consecutive segments of a run with one feed and one curvature vector, and the speed they run at.

    Attributes:
        first, stop: Index of its first segment in the run, and one past its last.
        length_m: Its length.
        curvature_1_m: κ, 0 on a line.
        acceleration_m_s2, jerk_m_s3: The tangential bounds (shared with the centripetal ones on a curve).
        cap_m_s: The highest speed allowed on it, and ``bound`` what sets it ("feed", "centripetal
            acceleration", "centripetal jerk", "sampled acceleration and jerk").
        peak_m_s: The highest speed reached (below the cap where the stretch is too short).
    """

    first: int
    stop: int
    length_m: float
    curvature_1_m: float
    acceleration_m_s2: float
    jerk_m_s3: float
    cap_m_s: float
    bound: str
    peak_m_s: float = 0.0

    @property
    def limited_by(self) -> str:
        """What bounds the speed reached: the cap's reason, or the stretch's length (too short to reach it)."""
        return self.bound if self.peak_m_s >= self.cap_m_s * (1 - 1e-9) else f"length (short of the {self.bound} cap)"


class RunProfile(Profile):
    """The feed profile of a corner-to-corner run, with look-ahead (module docstring).

    Attributes:
        stretches: Its stretches, in order, with the speed each reaches and what bounds it.
        joins_m_s: (len(stretches) + 1,) the speed where each stretch starts, then at the end (0).
    """

    def __init__(self, phases: list[tuple[float, float]], stretches: list[Stretch], joins_m_s: np.ndarray) -> None:
        super().__init__(phases)
        self.stretches = stretches
        self.joins_m_s = joins_m_s


def _curvature(segment: Segment, at_end: bool) -> np.ndarray:
    """The curvature vector d²p/ds² (1/m) at a segment's start or end."""
    s = np.array([segment.length_m if at_end else 0.0])
    return segment.point(s, np.ones(1), np.zeros(1))[2][0]


def _stretches(path: TimedPath, run: Run) -> tuple[list[Stretch], list[float]]:
    """A run's stretches with their caps, and the speed bound where each meets the one before (curvature jumps)."""
    acceleration, jerk = path.timing.max_acceleration_m_s2, path.timing.max_jerk_m_s3
    assert acceleration is not None and jerk is not None  # the realistic law's schema requires them
    stretches: list[Stretch] = []
    jumps: list[float] = []
    for k, segment in enumerate(run.segments):
        feed = path.speed_m_s(segment)
        kappa = float(np.linalg.norm(_curvature(segment, False)))
        if k and feed == path.speed_m_s(run.segments[k - 1]) and np.linalg.norm(
                _curvature(segment, False) - _curvature(run.segments[k - 1], True)) <= CURVATURE_TOLERANCE_1_M:
            stretches[-1].stop, stretches[-1].length_m = k + 1, stretches[-1].length_m + segment.length_m
            continue
        if k:
            jumps.append(float(np.linalg.norm(_curvature(segment, False) - _curvature(run.segments[k - 1], True))))
        caps = {"feed": feed}
        if kappa > CURVATURE_TOLERANCE_1_M:
            caps["centripetal acceleration"] = float(np.sqrt(acceleration / np.sqrt(2) / kappa))
            caps["centripetal jerk"] = float(np.cbrt(jerk / 2 / kappa**2))
            tangential = (acceleration / np.sqrt(2), jerk / 2)
        else:
            tangential = (acceleration, jerk)
        bound = min(caps, key=lambda name: caps[name])
        stretches.append(Stretch(k, k + 1, segment.length_m, kappa, *tangential, caps[bound], bound))
    return stretches, jumps


def _plan(stretches: list[Stretch], jumps: list[float], period_s: float,
          jerk: float) -> tuple[list[tuple[float, float]], np.ndarray]:
    """The phases of a run through its stretches, and the speed at each stretch's start then at the end."""
    limit = np.zeros(len(stretches) + 1)
    for k in range(1, len(stretches)):
        limit[k] = min(stretches[k - 1].cap_m_s, stretches[k].cap_m_s,
                       np.sqrt(jerk * period_s / jumps[k - 1]) if jumps[k - 1] > CURVATURE_TOLERANCE_1_M else np.inf)
    speed = limit.copy()
    for k, stretch in enumerate(stretches):  # forward: as fast as accelerating from the stretch's start allows
        speed[k + 1] = _reach(speed[k], speed[k + 1], stretch)
    for k in range(len(stretches) - 1, -1, -1):  # backward: as fast as braking to the stretch's end allows
        speed[k] = _reach(speed[k + 1], speed[k], stretches[k])
    phases: list[tuple[float, float]] = []
    for k, stretch in enumerate(stretches):
        own, stretch.peak_m_s = _stretch_phases(speed[k], speed[k + 1], stretch.length_m, stretch.cap_m_s,
                                                stretch.acceleration_m_s2, stretch.jerk_m_s3)
        phases += own
    return phases, speed


def _reach(start_m_s: float, bound_m_s: float, stretch: Stretch) -> float:
    """The highest speed (``bound_m_s`` at most) an S-curve from ``start_m_s`` reaches within the stretch's length."""
    return _highest(min(start_m_s, bound_m_s), bound_m_s, lambda v: _change_m(
        start_m_s, v, stretch.acceleration_m_s2, stretch.jerk_m_s3) <= stretch.length_m)


def run_profile(path: TimedPath, run: Run) -> RunProfile:
    """The feed profile of a corner-to-corner run with look-ahead (module docstring).

    Args:
        path: The path, with the realistic law's acceleration and jerk bounds and its file's sampling step
            (the controller's interpolation period at curvature jumps).
        run: One of its runs.

    Raises:
        InfeasibleError: No cap keeps a curved stretch's sampled acceleration and jerk within the bounds.
    """
    acceleration, jerk = path.timing.max_acceleration_m_s2, path.timing.max_jerk_m_s3
    assert acceleration is not None and jerk is not None  # the realistic law's schema requires them
    stretches, jumps = _stretches(path, run)
    bounds = run.bounds_m
    for _ in range(80):
        phases, speeds = _plan(stretches, jumps, path.time_step_s, jerk)
        profile = RunProfile(phases, stretches, speeds)
        dense = np.linspace(0.0, profile.duration_s, 20 * CHECK_SAMPLES)  # where each stretch is, in time
        arc = profile(dense)[0]
        over = [stretch for stretch in stretches if stretch.curvature_1_m > CURVATURE_TOLERANCE_1_M
                and not _within(profile, run, dense[(arc > bounds[stretch.first]) & (arc < bounds[stretch.stop])],
                                acceleration, jerk)]
        if not over:
            return profile
        for stretch in over:
            stretch.cap_m_s, stretch.bound = 0.95 * stretch.peak_m_s, "sampled acceleration and jerk"
    raise InfeasibleError(f"no feed profile keeps the path within {acceleration} m/s^2 and {jerk} m/s^3")


def _within(profile: Profile, run: Run, inside_s: np.ndarray, acceleration: float, jerk: float) -> bool:
    """Whether the sampled acceleration and its rate stay within ``ARC_SAFETY`` of the bounds between the first and
    last of the times ``inside_s`` (a stretch's, its ends excluded: the curvature may jump there)."""
    if len(inside_s) < 2:
        return True
    t = np.linspace(inside_s[0], inside_s[-1], CHECK_SAMPLES)
    acc = run.along(*profile(t))["acceleration"]
    rate = np.diff(acc, axis=0) / np.diff(t)[:, None]
    return bool(np.linalg.norm(acc, axis=1).max() <= ARC_SAFETY * acceleration
                and np.linalg.norm(rate, axis=1).max() <= ARC_SAFETY * jerk)


def sample_realistic(path: TimedPath, step_s: float) -> PathSamples:
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


@dataclass(frozen=True)
class SegmentSpeed:
    """The speed a segment of the path reaches under the realistic law, and what bounds it.

    Attributes:
        segment: Index of the segment in the path.
        feed_m_s: Its programmed feed.
        reached_m_s: The highest speed reached on it.
        bound: What bounds that speed (:attr:`Stretch.limited_by`).
    """

    segment: int
    feed_m_s: float
    reached_m_s: float
    bound: str


def segment_speeds(path: TimedPath) -> list[SegmentSpeed]:
    """The speed each segment reaches under the realistic law and what bounds it."""
    out: list[SegmentSpeed] = []
    for run in path.runs():
        profile = run_profile(path, run)
        t = np.linspace(0.0, profile.duration_s, 20 * CHECK_SAMPLES)
        s, v, _ = profile(t)
        index = np.clip(np.searchsorted(run.bounds_m, s, side="right") - 1, 0, len(run.segments) - 1)
        for stretch in profile.stretches:
            for k in range(stretch.first, stretch.stop):
                reached = float(v[index == k].max(initial=0.0))
                out.append(SegmentSpeed(len(out), path.speed_m_s(run.segments[k]), reached, stretch.limited_by))
    return out

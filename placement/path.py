"""Tool paths in their own frame F_p: shapes, timing laws, process forces, sampling.

A path file (YAML) describes the path in the path frame (the path lies in the X_p Y_p plane, the
tool axis is Z_p, the origin is the frame origin the placement moves), the feed rate, the process
forces and the timing law. Lengths are in the file's ``units`` (m or mm); speeds, accelerations
and forces carry their unit in their field name.

Process forces are the forces on the tool from the workpiece, in the path frame, with t the unit
feed direction and z = Z_p the tool axis (pointing out of the workpiece)::

    F = -feed·t + radial·(z × t) + axial·z

so positive ``feed`` opposes the motion, positive ``radial`` pushes the tool to the left of the
feed direction, and positive ``axial`` pushes it back along the tool axis. Negative values flip
a component. The radial direction lies in the X_p Y_p plane: it vanishes on a segment along Z_p
(a plunge), where only the feed and axial forces act.

Timing laws:
    paper: constant feed on each segment, each segment independent (corners ignored), as in
        Ur-Rehman et al.; energies are integrated segment by segment.
    realistic: the tool stops at every sharp corner and follows a jerk-limited (double-S) feed
        profile with bounded acceleration and jerk; on arcs the feed is lowered until the
        tangential and centripetal acceleration and jerk together stay within the bounds; one
        continuous motion.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path as FilePath
from typing import Annotated, Literal

import numpy as np
from pydantic import Field, model_validator

from placement.exceptions import PathFileError, PlacementError
from placement.schema import Number, Strict, Text, read_yaml

Positive = Annotated[Number, Field(gt=0.0)]
LENGTH_SCALE = {"m": 1.0, "mm": 1e-3}
CORNER_ANGLE_RAD = np.radians(1.0)  # a tangent turn above this is a corner (exact stop)
ARC_SAFETY = 0.98  # share of the bounds used on arcs, where they are checked on samples
MIN_LENGTH_M = 1e-6
MAX_SAMPLES = 1_000_000  # samples of one path: about 0.5 GB through the whole chain


class Rectangle(Strict):
    """W x L rectangle centred on the origin, W along X_p; run A(-W/2,-L/2) -> B -> C -> D."""

    type: Literal["rectangle"]
    width: Positive
    length: Positive


class Polyline(Strict):
    """Straight segments through points [x, y] or [x, y, z] of the path frame."""

    type: Literal["polyline"]
    points: Annotated[list[tuple[Number, Number] | tuple[Number, Number, Number]], Field(min_length=2, max_length=100_000)]
    closed: bool = False


class Circle(Strict):
    """Full circle centred on the origin, from (r, 0) anticlockwise about Z_p."""

    type: Literal["circle"]
    radius: Positive


class Arc(Strict):
    """Arc centred on the origin from angle start_deg, turning sweep_deg (positive anticlockwise)."""

    type: Literal["arc"]
    radius: Positive
    start_deg: Number = 0.0
    sweep_deg: Annotated[Number, Field(ge=-360.0, le=360.0)]

    @model_validator(mode="after")
    def _nonzero(self) -> Arc:
        if self.sweep_deg == 0:
            raise ValueError("sweep_deg must not be 0")
        return self


class ProcessForces(Strict):
    """Forces on the tool from the workpiece (N): see the module docstring for signs."""

    feed: Number = 0.0
    radial: Number = 0.0
    axial: Number = 0.0


class Timing(Strict):
    """Timing law; the realistic mode needs the acceleration and jerk bounds."""

    mode: Literal["paper", "realistic"] = "paper"
    max_acceleration_m_s2: Positive | None = None
    max_jerk_m_s3: Positive | None = None

    @model_validator(mode="after")
    def _bounds(self) -> Timing:
        if self.mode == "realistic" and (self.max_acceleration_m_s2 is None or self.max_jerk_m_s3 is None):
            raise ValueError("the realistic timing law needs max_acceleration_m_s2 and max_jerk_m_s3")
        return self


class PathFile(Strict):
    """The whole path file."""

    name: Text = ""
    units: Literal["m", "mm"]
    shape: Annotated[Rectangle | Polyline | Circle | Arc, Field(discriminator="type")]
    feed_m_s: Positive
    process_forces_N: ProcessForces = ProcessForces()
    timing: Timing = Timing()
    time_step_s: Positive = 0.001


@dataclass(frozen=True)
class Segment:
    """A line (radius 0) or an arc of the path, in metres, in the path frame."""

    start_m: np.ndarray
    end_m: np.ndarray
    center_m: np.ndarray | None = None
    radius_m: float = 0.0
    start_angle_rad: float = 0.0
    sweep_rad: float = 0.0

    @property
    def length_m(self) -> float:
        if self.center_m is None:
            return float(np.linalg.norm(self.end_m - self.start_m))
        return abs(self.sweep_rad) * self.radius_m

    def point(self, s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray) -> tuple[np.ndarray, ...]:
        """Position, velocity, acceleration (N, 3) and unit tangent at arc lengths ``s`` (m)."""
        s, s_dot, s_ddot = (np.asarray(x, dtype=float)[:, None] for x in (s, s_dot, s_ddot))
        if self.center_m is None:
            tangent = (self.end_m - self.start_m) / self.length_m
            tangent = np.broadcast_to(tangent, (len(s), 3))
            return self.start_m + s * tangent, s_dot * tangent, s_ddot * tangent, tangent
        sign = np.sign(self.sweep_rad)
        angle = self.start_angle_rad + sign * s[:, 0] / self.radius_m
        radial = np.stack([np.cos(angle), np.sin(angle), np.zeros_like(angle)], axis=1)
        tangent = sign * np.stack([-np.sin(angle), np.cos(angle), np.zeros_like(angle)], axis=1)
        position = self.center_m + self.radius_m * radial
        return position, s_dot * tangent, s_ddot * tangent - s_dot**2 / self.radius_m * radial, tangent


@dataclass(frozen=True)
class PathSamples:
    """A sampled path in the path frame, one row per sample.

    Attributes:
        t_s: (N,) time from the start of the path.
        position_m, velocity_m_s, acceleration_m_s2: (N, 3) tool point motion.
        tangent: (N, 3) unit feed direction.
        force_on_tool_N: (N, 3) process force on the tool from the workpiece.
        piece: (N,) index of the independently integrated piece each sample belongs to
            (the segment in the paper's timing law; a single piece otherwise).
    """

    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    tangent: np.ndarray
    force_on_tool_N: np.ndarray
    piece: np.ndarray

    def __len__(self) -> int:
        return len(self.t_s)


@dataclass(frozen=True)
class ToolPath:
    """A path ready to be sampled: geometry (m), feed, forces and timing law."""

    name: str
    segments: tuple[Segment, ...]
    feed_m_s: float
    forces: ProcessForces
    timing: Timing
    time_step_s: float

    @property
    def length_m(self) -> float:
        """Total path length."""
        return sum(segment.length_m for segment in self.segments)

    def sample(self, time_step_s: float | None = None) -> PathSamples:
        """Sample the path in time with the given step (default: the file's ``time_step_s``)."""
        step = self.time_step_s if time_step_s is None else time_step_s
        if not 0 < step < np.inf:
            raise PlacementError(f"the sampling time step must be a finite number > 0 s, got {step}")
        if self.timing.mode == "paper":
            return self._sample_paper(step)
        return self._sample_realistic(step)

    def _sample_counts(self, durations_s: list[float], step: float) -> list[int]:
        """Samples of each independently timed piece; refuses more than MAX_SAMPLES in all."""
        counts = [max(2, int(np.ceil(d / step)) + 1) if d / step < MAX_SAMPLES else MAX_SAMPLES + 1 for d in durations_s]
        if sum(counts) > MAX_SAMPLES:
            raise PlacementError(f"the path '{self.name}' lasts {sum(durations_s):.4g} s: sampled every {step:g} s it "
                                 f"would need more than {MAX_SAMPLES:,} samples; use a larger time step (time_step_s "
                                 "in the path file, or --time-step), or check the path's size and feed")
        return counts

    def half_turn_symmetric(self) -> bool:
        """Whether a half turn about Z_p maps the path onto itself, piece by piece.

        Each independently timed piece (a segment in the paper's timing law, a corner-to-corner
        run in the realistic one) must map onto a piece run the same way; the energy of such a
        path is then the same at phi and phi + 180°, and phi only needs a half turn of range.
        """
        runs = [[s] for s in self.segments] if self.timing.mode == "paper" else _tangent_continuous_runs(self.segments)
        fractions = np.linspace(0.0, 1.0, 9)

        def points(run: list[Segment]) -> np.ndarray:
            return _along(run, fractions * sum(s.length_m for s in run), np.zeros(9), np.zeros(9))[0]

        shapes = [points(run) for run in runs]
        turned = [shape * np.array([-1.0, -1.0, 1.0]) for shape in shapes]
        return all(any(np.allclose(t, s, atol=1e-12) for s in shapes) for t in turned)

    def _sample_paper(self, step: float) -> PathSamples:
        parts, start = [], 0.0
        durations = [segment.length_m / self.feed_m_s for segment in self.segments]
        for k, (segment, duration, count) in enumerate(zip(self.segments, durations,
                                                             self._sample_counts(durations, step))):
            t = np.linspace(0.0, duration, count)
            motion = segment.point(self.feed_m_s * t, np.full_like(t, self.feed_m_s), np.zeros_like(t))
            parts.append((start + t, *motion, np.full(len(t), k)))
            start += duration
        return self._assemble(parts)

    def _sample_realistic(self, step: float) -> PathSamples:
        runs = _tangent_continuous_runs(self.segments)
        profiles = [self._profile(run) for run in runs]
        counts = self._sample_counts([profile.duration_s for profile in profiles], step)
        parts, start = [], 0.0
        for run, profile, count in zip(runs, profiles, counts):
            t = np.linspace(0.0, profile.duration_s, count)
            s, s_dot, s_ddot = profile(t)
            parts.append((start + t, *_along(run, s, s_dot, s_ddot), np.zeros(len(t), dtype=int)))
            start += profile.duration_s
        samples = self._assemble(parts)
        # Successive runs meet at rest at a corner: drop the duplicated corner instant.
        keep = np.concatenate([[True], np.diff(samples.t_s) > 0])
        return PathSamples(*(getattr(samples, f)[keep] for f in PathSamples.__dataclass_fields__))

    def _profile(self, run: list[Segment]) -> DoubleS:
        """The feed profile of a corner-to-corner run, within the acceleration and jerk bounds."""
        length = sum(s.length_m for s in run)
        acceleration, jerk = self.timing.max_acceleration_m_s2, self.timing.max_jerk_m_s3
        assert acceleration is not None and jerk is not None  # the realistic law's schema requires them
        if all(s.center_m is None for s in run):
            return DoubleS(length, self.feed_m_s, acceleration, jerk)
        # On arcs the centripetal acceleration v²/r and its rate add to the tangential ones: share
        # the bounds, then slow down until the sampled acceleration and jerk are within them.
        speed = min(self.feed_m_s, np.sqrt(acceleration / np.sqrt(2) * min(s.radius_m for s in run if s.radius_m)))
        for _ in range(80):
            profile = DoubleS(length, speed, acceleration / np.sqrt(2), jerk / 2)
            t = np.linspace(0.0, profile.duration_s, 4001)
            acc = _along(run, *profile(t))[2]
            rate = np.diff(acc, axis=0) / np.diff(t)[:, None]
            if (np.linalg.norm(acc, axis=1).max() <= ARC_SAFETY * acceleration
                    and np.linalg.norm(rate, axis=1).max() <= ARC_SAFETY * jerk):
                return profile
            speed *= 0.95
        raise PlacementError(f"no feed profile keeps the path within {acceleration} m/s^2 and {jerk} m/s^3")

    def _assemble(self, parts: list[tuple[np.ndarray, ...]]) -> PathSamples:
        t, position, velocity, acceleration, tangent, piece = (np.concatenate(column) for column in zip(*parts))
        z = np.array([0.0, 0.0, 1.0])
        force = (-self.forces.feed * tangent + self.forces.radial * np.cross(z, tangent) + self.forces.axial * z)
        return PathSamples(t, position, velocity, acceleration, tangent, force, piece)


def _tangent_continuous_runs(segments: tuple[Segment, ...]) -> list[list[Segment]]:
    """Group consecutive segments whose tangents join smoothly (no corner between them)."""
    runs = [[segments[0]]]
    for previous, segment in zip(segments, segments[1:]):
        end_tangent = previous.point(np.array([previous.length_m]), np.ones(1), np.zeros(1))[3][0]
        start_tangent = segment.point(np.zeros(1), np.ones(1), np.zeros(1))[3][0]
        turn = np.arccos(np.clip(end_tangent @ start_tangent, -1.0, 1.0))
        if turn > CORNER_ANGLE_RAD:
            runs.append([segment])
        else:
            runs[-1].append(segment)
    return runs


def _along(run: list[Segment], s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray) -> tuple[np.ndarray, ...]:
    """Motion along consecutive segments at arc lengths ``s`` measured from the run's start."""
    bounds = np.cumsum([0.0] + [seg.length_m for seg in run])
    index = np.clip(np.searchsorted(bounds, s, side="right") - 1, 0, len(run) - 1)
    out = [np.zeros((len(s), 3)) for _ in range(4)]
    for k, segment in enumerate(run):
        mask = index == k
        if mask.any():
            for column, value in zip(out, segment.point(s[mask] - bounds[k], s_dot[mask], s_ddot[mask])):
                column[mask] = value
    return tuple(out)


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


def load_path(path: str | FilePath) -> ToolPath:
    """Read and validate a path file.

    Args:
        path: The YAML file.

    Returns:
        The path, in metres.

    Raises:
        PathFileError: The file is missing, not YAML, or breaks the schema.
    """
    path = FilePath(path)
    spec = read_yaml(path, PathFile, PathFileError)
    segments = _segments(spec)
    if not segments:
        raise PathFileError(path, "shape.points", "the points must not all coincide")
    if sum(segment.length_m for segment in segments) < MIN_LENGTH_M:
        raise PathFileError(path, "shape", f"the path is shorter than {MIN_LENGTH_M * 1e6:g} µm")
    return ToolPath(name=spec.name or path.stem, segments=segments, feed_m_s=spec.feed_m_s,
                    forces=spec.process_forces_N, timing=spec.timing, time_step_s=spec.time_step_s)


def _segments(spec: PathFile) -> tuple[Segment, ...]:
    scale = LENGTH_SCALE[spec.units]
    shape = spec.shape
    if isinstance(shape, Rectangle):
        w, l = shape.width * scale / 2, shape.length * scale / 2
        corners = [(-w, -l), (w, -l), (w, l), (-w, l)]
        return _lines([*corners, corners[0]])
    if isinstance(shape, Polyline):
        points = [tuple(np.array(p, dtype=float) * scale) for p in shape.points]
        return _lines(points + ([points[0]] if shape.closed else []))
    radius = shape.radius * scale
    start = 0.0 if isinstance(shape, Circle) else np.radians(shape.start_deg)
    sweep = 2 * np.pi if isinstance(shape, Circle) else np.radians(shape.sweep_deg)
    center = np.zeros(3)

    def on_circle(angle: float) -> np.ndarray:
        return np.array([radius * np.cos(angle), radius * np.sin(angle), 0.0])

    return (Segment(on_circle(start), on_circle(start + sweep), center, radius, start, sweep),)


def _lines(points: list) -> tuple[Segment, ...]:
    points = [np.pad(np.asarray(p, dtype=float), (0, 3 - len(p))) for p in points]
    return tuple(Segment(a, b) for a, b in zip(points, points[1:]) if np.linalg.norm(b - a) > 0)

"""Tool paths in their own frame F_p: shapes, timing laws, process forces, sampling.

A path file (YAML) describes the path in the path frame (the tool axis is Z_p, pointing out of the
workpiece; the origin is the frame origin the placement moves), the feed rate, the process forces
and the timing law. Lengths are in the file's ``units`` (m or mm); speeds, accelerations and
forces carry their unit in their field name. The shapes (docs/paths.md has the whole format):

    rectangle, polyline, circle, arc: geometry written in the file, run at ``feed_m_s``.
    gcode: a G-code program (:mod:`placement.gcode`), which sets its own units (G20/G21) and the
        feed of each move (F): ``units`` and ``feed_m_s`` are refused. ``rapids`` says whether its
        G0 moves are skipped (left out, leaving gaps) or timed at a rapid feed.
    poses: a pose list (:mod:`placement.poses`) in the file's units: without times, a polyline
        run at ``feed_m_s`` whose tool orientation turns uniformly along each segment; with times
        (a t column), a C² interpolation through the poses at their times, with no ``feed_m_s``
        or ``timing``.

Process forces are the forces on the tool from the workpiece, in the path frame, with t the unit
feed direction and z = Z_p the tool axis (pointing out of the workpiece)::

    F = -feed·t + radial·(z × t) + axial·z

so positive ``feed`` opposes the motion, positive ``radial`` pushes the tool to the left of the
feed direction, and positive ``axial`` pushes it back along the tool axis. Negative values flip
a component. The radial direction lies in the X_p Y_p plane: it vanishes on a segment along Z_p
(a plunge), where only the feed and axial forces act. One set of forces acts on every feed move
(rapids are force-free), or a set per kind of move: ``rapid`` on G0 moves, ``plunging`` where a
feed move runs within 45° of -Z_p (into the workpiece: t·Z_p < -cos 45°, decided sample by
sample), ``cutting`` elsewhere.

Timing laws (a timed pose list has its own times instead):
    paper: constant feed on each segment, each segment independent (corners ignored), as in
        Ur-Rehman et al.; energies are integrated segment by segment. Each segment runs at its
        own feed (a G-code move at its F).
    realistic: the tool stops at every sharp corner, at every gap a skipped rapid leaves, and
        wherever a pose list's orientation changes its rate of turning; between such stops it
        follows a jerk-limited (double-S) feed profile with bounded acceleration and jerk,
        cruising at the lowest feed of the segments it crosses; on arcs the feed is lowered
        until the tangential and centripetal acceleration and jerk together stay within the
        bounds. One continuous motion between gaps, each gap starting a new piece.
    optimal: the fastest motion the robot allows at each placement (:mod:`placement.timing`):
        stops where the realistic law stops, and in between the feed is as high as the robot's
        joint speed and acceleration, motor speed and torque (and drive voltage, where given)
        allow, never above the segment's feed. It depends on the placement, so the path is
        sampled along its arc length here (at unit speed) and timed by the evaluator. The
        acceleration and jerk bounds, which shape the realistic law's feed profile, are not used.

A segment's feed is ``feed_ratio`` times the path's ``feed_m_s`` (for G-code, the program's
highest F), so replacing ``feed_m_s`` (the feed command) scales every feed but the rapid feed;
for a timed pose list it scales the list's speeds (times shrink by the same factor).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass, fields
from functools import cached_property
from pathlib import Path as FilePath
from typing import Annotated, Any, Literal

import numpy as np
from pydantic import Field, model_validator

from placement.exceptions import PathFileError, PlacementError
from placement.gcode import read_program
from placement.poses import TimedPoses, pose_segments, read_poses
from placement.schema import Number, Strict, Text, read_yaml
from placement.segments import Segment

Positive = Annotated[Number, Field(gt=0.0)]
LENGTH_SCALE = {"m": 1.0, "mm": 1e-3}
CORNER_ANGLE_RAD = np.radians(1.0)  # a tangent turn above this is a corner (exact stop)
ARC_SAFETY = 0.98  # share of the bounds used on arcs, where they are checked on samples
MIN_LENGTH_M = 1e-6
GAP_M = 1e-9  # segments whose ends are farther apart leave a gap (a skipped rapid) between them
TURNING_RATE_TOLERANCE_RAD_M = 1e-9  # a larger change of turning rate between segments is an orientation corner
PLUNGE_COSINE = np.cos(np.radians(45.0))  # a feed move within 45° of -Z_p (into the workpiece) is plunging
MAX_SAMPLES = 1_000_000  # samples of one path: about 0.5 GB through the whole chain
DEFAULT_TIME_STEP_S = 0.001  # the sampling step of a file that gives none ...
DEFAULT_SPACING_M = 0.0005  # ... or longer, to keep samples this far apart at the path's fastest feed
MIN_RUN_SAMPLES = 8  # samples of a run between stops, at least, for the optimal timing law
END_SPLIT = 4  # a run's first and last intervals (leaving and reaching a stop, the slowest) are cut in this many


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


class Gcode(Strict):
    """A G-code program, its file named relative to the path file (:mod:`placement.gcode`)."""

    type: Literal["gcode"]
    file: Text


class Poses(Strict):
    """A pose list (CSV or JSON), its file named relative to the path file (:mod:`placement.poses`)."""

    type: Literal["poses"]
    file: Text
    orientation: Literal["none", "quaternion_xyzw", "rpy_deg"] = "none"  # poses.ORIENTATION_COLUMNS


class ProcessForces(Strict):
    """Forces on the tool from the workpiece (N): see the module docstring for signs."""

    feed: Number = 0.0
    radial: Number = 0.0
    axial: Number = 0.0


class ForceKinds(Strict):
    """Process forces: one set (feed, radial, axial) for cutting and plunging moves alike, rapids
    force-free; or a set per kind of move (cutting required, plunging as cutting and rapid free
    unless given)."""

    feed: Number | None = None
    radial: Number | None = None
    axial: Number | None = None
    cutting: ProcessForces | None = None
    plunging: ProcessForces | None = None
    rapid: ProcessForces | None = None

    @model_validator(mode="after")
    def _one_form(self) -> ForceKinds:
        flat = [name for name in ("feed", "radial", "axial") if getattr(self, name) is not None]
        kinds = [name for name in ("cutting", "plunging", "rapid") if getattr(self, name) is not None]
        if flat and kinds:
            raise ValueError(f"give either feed, radial, axial (cutting and plunging alike) or a set per kind of move "
                             f"(cutting, plunging, rapid), not both (got {', '.join(flat + kinds)})")
        if kinds and self.cutting is None:
            raise ValueError(f"the per-kind form needs cutting (got {', '.join(kinds)})")
        return self

    def resolve(self) -> ForceSet:
        """The forces of each kind of move."""
        if self.cutting is None:
            flat = ProcessForces(feed=self.feed or 0.0, radial=self.radial or 0.0, axial=self.axial or 0.0)
            return ForceSet(flat, flat, ProcessForces())
        return ForceSet(self.cutting, self.plunging or self.cutting, self.rapid or ProcessForces())


@dataclass(frozen=True)
class ForceSet:
    """Process forces by kind of move: cutting, plunging (module docstring) and rapid."""

    cutting: ProcessForces
    plunging: ProcessForces
    rapid: ProcessForces


class Rapids(Strict):
    """What a G-code program's rapids (G0) count for: nothing (skip) or their time at a rapid feed."""

    mode: Literal["skip", "timed"] = "skip"
    feed_m_s: Positive | None = None

    @model_validator(mode="after")
    def _feed(self) -> Rapids:
        if (self.mode == "timed") != (self.feed_m_s is not None):
            raise ValueError("timed rapids need feed_m_s (the machine's rapid feed), skipped ones take none")
        return self


class Timing(Strict):
    """Timing law; the realistic mode needs the acceleration and jerk bounds."""

    mode: Literal["paper", "realistic", "optimal"] = "paper"
    max_acceleration_m_s2: Positive | None = None
    max_jerk_m_s3: Positive | None = None

    @model_validator(mode="after")
    def _bounds(self) -> Timing:
        if self.mode == "realistic" and (self.max_acceleration_m_s2 is None or self.max_jerk_m_s3 is None):
            raise ValueError("the realistic timing law needs max_acceleration_m_s2 and max_jerk_m_s3")
        return self


class PathFile(Strict):
    """The whole path file; G-code has its own ``units`` and feeds, a timed pose list its own timing (load_path)."""

    name: Text = ""
    units: Literal["m", "mm"] | None = None
    shape: Annotated[Rectangle | Polyline | Circle | Arc | Gcode | Poses, Field(discriminator="type")]
    feed_m_s: Positive | None = None
    rapids: Rapids | None = None
    process_forces_N: ForceKinds = ForceKinds()
    timing: Timing = Timing()
    time_step_s: Positive | None = None


def default_time_step_s(feed_m_s: float) -> float:
    """The sampling step of a file that gives none: 1 ms, or longer for a slow path, so that samples are at
    most ``DEFAULT_SPACING_M`` apart at its fastest feed (a G-code program at F100 needs no 1 ms samples)."""
    return max(DEFAULT_TIME_STEP_S, DEFAULT_SPACING_M / feed_m_s)


@dataclass(frozen=True)
class PathSamples:
    """A sampled path in the path frame, one row per sample.

    Attributes:
        t_s: (N,) time from the start of the path.
        position_m, velocity_m_s, acceleration_m_s2: (N, 3) tool point motion.
        tangent: (N, 3) unit feed direction.
        force_on_tool_N: (N, 3) process force on the tool from the workpiece.
        piece: (N,) index of the independently integrated piece each sample belongs to
            (the segment in the paper's timing law; in the realistic one a stretch of contiguous
            motion, a new piece starting after each skipped rapid).
        rotation: (N, 3, 3) tool frame in the path frame, for a pose list with orientations (else None).
        angular_velocity_rad_s, angular_acceleration_rad_s2: (N, 3) its rates, in the path frame.
    """

    t_s: np.ndarray
    position_m: np.ndarray
    velocity_m_s: np.ndarray
    acceleration_m_s2: np.ndarray
    tangent: np.ndarray
    force_on_tool_N: np.ndarray
    piece: np.ndarray
    rotation: np.ndarray | None = None
    angular_velocity_rad_s: np.ndarray | None = None
    angular_acceleration_rad_s2: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.t_s)

    def rows(self, index: np.ndarray) -> PathSamples:
        """Some of the samples (an index or a mask)."""
        def pick(value: Any) -> Any:  # an array, or None for absent orientation fields
            return None if value is None else value[index]

        return PathSamples(*(pick(getattr(self, f.name)) for f in fields(PathSamples)))


@dataclass(frozen=True)
class PathGeometry:
    """A path sampled along its arc length for the optimal timing law, run by run.

    Attributes:
        samples: The samples at unit speed (ṡ = 1 m/s, s̈ = 0): velocity is the unit tangent,
            acceleration the curvature vector d²p/ds², angular rates per unit speed; ``t_s`` is
            the time at the feed bound (a lower bound of the path's duration under any timing).
        run_starts: (R + 1,) index of the first sample of each run between stops, then N.
        arc_m: (N,) arc length from the start of the sample's run.
        feed_m_s: (N,) the feed bound at each sample (its segment's feed).
    """

    samples: PathSamples
    run_starts: np.ndarray
    arc_m: np.ndarray
    feed_m_s: np.ndarray

    def __len__(self) -> int:
        return len(self.arc_m)

    @cached_property
    def grid_rows(self) -> np.ndarray:
        """The sample of each evaluated sample (:attr:`evaluated_samples`)."""
        return np.concatenate([np.column_stack([j, j + 1]).ravel() for j in self._intervals()])

    @cached_property
    def interval_rows(self) -> np.ndarray:
        """The sample starting the interval whose s̈ each evaluated sample carries."""
        return np.concatenate([np.repeat(j, 2) for j in self._intervals()])

    @cached_property
    def evaluated_samples(self) -> PathSamples:
        """The samples the exact chain evaluates under the optimal timing law.

        The law's s̈ is constant between samples and switches at them, so each interval is
        evaluated on its own: a sample inside a run appears twice, zero time apart, as the end of
        the interval before it and the start of the one after. Integrals over time then follow
        each interval's own acceleration, and every limit is checked on both sides of a switch.
        """
        return self.samples.rows(self.grid_rows)

    def _intervals(self) -> list[np.ndarray]:
        """The first sample of each interval between samples, run by run."""
        return [np.arange(start, stop - 1) for start, stop in zip(self.run_starts[:-1], self.run_starts[1:])]


@dataclass(frozen=True)
class ToolPath:
    """A path ready to be sampled: geometry (m), feeds, forces and timing law.

    Attributes:
        feed_m_s: The feed of a segment whose ``feed_ratio`` is 1 (the highest F of a G-code
            program); every segment's feed scales with it.
        rapid_feed_m_s: The feed of rapid segments (timed G-code rapids), not scaled with feed_m_s.
        timed: A pose list with times, sampled by its own interpolation instead of the segments
            (the polyline through its points); its speeds scale by feed_m_s over its mean speed.
    """

    name: str
    segments: tuple[Segment, ...]
    feed_m_s: float
    forces: ForceSet
    timing: Timing
    time_step_s: float
    rapid_feed_m_s: float | None = None
    timed: TimedPoses | None = None

    @property
    def length_m(self) -> float:
        """Total path length."""
        return sum(segment.length_m for segment in self.segments)

    def speed_m_s(self, segment: Segment) -> float:
        """The feed a segment of this path is run at."""
        if segment.rapid:
            assert self.rapid_feed_m_s is not None  # load_path keeps rapids only with their feed
            return self.rapid_feed_m_s
        return segment.feed_ratio * self.feed_m_s

    def sample(self, time_step_s: float | None = None) -> PathSamples:
        """Sample the path in time with the given step (default: the file's ``time_step_s``)."""
        step = self.time_step_s if time_step_s is None else time_step_s
        if not 0 < step < np.inf:
            raise PlacementError(f"the sampling time step must be a finite number > 0 s, got {step}")
        if self.timed is not None:
            count = self._sample_counts([self.timed.duration_s * self.timed.mean_speed_m_s / self.feed_m_s], step)[0]
            return self._assemble([self.timed.sample(count, self.feed_m_s / self.timed.mean_speed_m_s)])
        if self.timing.mode == "paper":
            return self._sample_paper(step)
        if self.timing.mode == "optimal":
            return self.geometry(step).samples
        return self._sample_realistic(step)

    def geometry(self, time_step_s: float | None = None, refine: int = 1) -> PathGeometry:
        """The path sampled along its arc length, run by run, for the optimal timing law.

        Each run between stops (the realistic law's) gets samples evenly spaced in arc length,
        its ends included, about ``time_step_s`` apart at the path's fastest feed (at least
        ``MIN_RUN_SAMPLES``); consecutive runs share their stop's position, each with its own tangent.
        The first and last intervals, where the tool leaves or reaches a stop, are each cut in
        ``END_SPLIT`` parts growing as the squares 1, 4, 9, ..., which a constant acceleration from
        rest runs in equal times. ``refine`` then cuts every interval in as many equal parts: the
        coarser samples are among the finer ones (a re-check's sampling).

        Raises:
            PlacementError: A timed pose list (timed by its own t column), or more than MAX_SAMPLES
                samples at ``time_step_s`` (before ``refine``).
        """
        step = self.time_step_s if time_step_s is None else time_step_s
        if self.timed is not None:
            raise PlacementError(f"the path '{self.name}' is a pose list with times: it is timed by its t column, "
                                 "not by the optimal timing law")
        if not 0 < step < np.inf:
            raise PlacementError(f"the sampling time step must be a finite number > 0 s, got {step}")
        runs = _runs(self.segments)
        fastest = max(self.speed_m_s(s) for s in self.segments)
        nominal = [sum(s.length_m for s in run) / fastest for run, _ in runs]
        counts = [max(MIN_RUN_SAMPLES, count) for count in self._sample_counts(nominal, step)]
        parts, piece, arcs, feeds, starts = [], 0, [], [], [0]
        for (run, after_gap), count in zip(runs, counts):
            bounds = np.cumsum([0.0] + [s.length_m for s in run])
            speeds = np.array([self.speed_m_s(s) for s in run])
            arc = _run_arc(bounds[-1], count, refine, bounds[1:-1][np.diff(speeds) != 0])
            count = len(arc)
            piece += after_gap
            parts.append({"t": np.zeros(count), **_along(run, arc, np.ones(count), np.zeros(count), self.oriented),
                          "piece": np.full(count, piece)})
            # A sample where the feed changes (within MIN_LENGTH_M) takes the lower one: the speed never exceeds a
            # segment's feed, between samples either (the speed changes monotonically between them).
            after = np.clip(np.searchsorted(bounds, arc + MIN_LENGTH_M, side="right") - 1, 0, len(run) - 1)
            before = np.clip(np.searchsorted(bounds, arc - MIN_LENGTH_M, side="right") - 1, 0, len(run) - 1)
            arcs.append(arc)
            feeds.append(np.minimum(speeds[after], speeds[before]))
            starts.append(starts[-1] + count)
        arc_m, feed = np.concatenate(arcs), np.concatenate(feeds)
        # Nominal times: each run at its feed bound throughout (a lower bound of any timing's).
        steps = np.where(run_joins(np.array(starts)), 0.0, np.diff(arc_m) / feed[1:])
        nominal_t = np.concatenate([[0.0], np.cumsum(steps)])
        samples = self._assemble(parts)
        return PathGeometry(dataclasses.replace(samples, t_s=nominal_t), np.array(starts), arc_m, feed)

    @property
    def oriented(self) -> bool:
        """Whether the path carries tool orientations (a pose list with orientation columns)."""
        return any(segment.rotation is not None for segment in self.segments)

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
        run in the realistic one) must map onto a piece run the same way at the same feed; the
        energy of such a path is then the same at phi and phi + 180°, and phi only needs a half
        turn of range. A timed pose list, or one whose orientation changes, is taken not to be.
        """
        if self.timed is not None or not self._constant_orientation():
            return False
        runs = [[s] for s in self.segments] if self.timing.mode == "paper" else [run for run, _ in _runs(self.segments)]
        fractions = np.linspace(0.0, 1.0, 9)

        def points(run: list[Segment]) -> np.ndarray:
            return _along(run, fractions * sum(s.length_m for s in run), np.zeros(9), np.zeros(9))["position"]

        shapes = [(points(run), [self.speed_m_s(s) for s in run]) for run in runs]
        turned = [(shape * np.array([-1.0, -1.0, 1.0]), speeds) for shape, speeds in shapes]
        return all(any(np.allclose(t, s, atol=1e-12) and t_speeds == speeds for s, speeds in shapes)
                   for t, t_speeds in turned)

    def _constant_orientation(self) -> bool:
        rotations = [s.rotation for s in self.segments if s.rotation is not None]
        turns = [s.turn_rad for s in self.segments if s.turn_rad is not None]
        return all(np.array_equal(r, rotations[0]) for r in rotations) and all(not np.any(t) for t in turns)

    def _sample_paper(self, step: float) -> PathSamples:
        parts, start = [], 0.0
        durations = [segment.length_m / self.speed_m_s(segment) for segment in self.segments]
        for k, (segment, duration, count) in enumerate(zip(self.segments, durations,
                                                             self._sample_counts(durations, step))):
            t = np.linspace(0.0, duration, count)
            speed = self.speed_m_s(segment)
            motion = _along([segment], speed * t, np.full_like(t, speed), np.zeros_like(t), self.oriented)
            parts.append({"t": start + t, **motion, "piece": np.full(len(t), k)})
            start += duration
        return self._assemble(parts)

    def _sample_realistic(self, step: float) -> PathSamples:
        runs = _runs(self.segments)
        profiles = [self._profile(run) for run, _ in runs]
        counts = self._sample_counts([profile.duration_s for profile in profiles], step)
        parts, start, piece = [], 0.0, 0
        for (run, after_gap), profile, count in zip(runs, profiles, counts):
            t = np.linspace(0.0, profile.duration_s, count)
            piece += after_gap
            parts.append({"t": start + t, **_along(run, *profile(t), self.oriented), "piece": np.full(len(t), piece)})
            start += profile.duration_s
        samples = self._assemble(parts)
        # Successive runs of one piece meet at rest at a corner: drop the duplicated corner instant.
        keep = np.concatenate([[True], (np.diff(samples.t_s) > 0) | (np.diff(samples.piece) != 0)])
        return samples.rows(keep)

    def _profile(self, run: list[Segment]) -> DoubleS:
        """The feed profile of a corner-to-corner run, within the acceleration and jerk bounds.

        The run cruises at the lowest feed of its segments.
        """
        length = sum(s.length_m for s in run)
        feed = min(self.speed_m_s(s) for s in run)
        acceleration, jerk = self.timing.max_acceleration_m_s2, self.timing.max_jerk_m_s3
        assert acceleration is not None and jerk is not None  # the realistic law's schema requires them
        if all(s.center_m is None for s in run):
            return DoubleS(length, feed, acceleration, jerk)
        # On arcs the centripetal acceleration v²/r and its rate add to the tangential ones: share
        # the bounds, then slow down until the sampled acceleration and jerk are within them.
        speed = min(feed, np.sqrt(acceleration / np.sqrt(2) * min(s.radius_m for s in run if s.radius_m)))
        for _ in range(80):
            profile = DoubleS(length, speed, acceleration / np.sqrt(2), jerk / 2)
            t = np.linspace(0.0, profile.duration_s, 4001)
            acc = _along(run, *profile(t))["acceleration"]
            rate = np.diff(acc, axis=0) / np.diff(t)[:, None]
            if (np.linalg.norm(acc, axis=1).max() <= ARC_SAFETY * acceleration
                    and np.linalg.norm(rate, axis=1).max() <= ARC_SAFETY * jerk):
                return profile
            speed *= 0.95
        raise PlacementError(f"no feed profile keeps the path within {acceleration} m/s^2 and {jerk} m/s^3")

    def _assemble(self, parts: list[dict[str, np.ndarray]]) -> PathSamples:
        column = {key: np.concatenate([part[key] for part in parts]) for key in parts[0]}
        tangent = column["tangent"]
        z = np.array([0.0, 0.0, 1.0])
        plunging = tangent[:, 2] < -PLUNGE_COSINE
        kind = np.where(column["rapid"], 2, np.where(plunging, 1, 0))  # cutting, plunging, rapid
        sets = (self.forces.cutting, self.forces.plunging, self.forces.rapid)
        feed, radial, axial = (np.array([getattr(f, name) for f in sets])[kind][:, None]
                               for name in ("feed", "radial", "axial"))
        force = -feed * tangent + radial * np.cross(z, tangent) + axial * z
        return PathSamples(column["t"], column["position"], column["velocity"], column["acceleration"], tangent,
                           force, column["piece"], column.get("rotation"), column.get("angular_velocity"),
                           column.get("angular_acceleration"))


def run_joins(run_starts: np.ndarray) -> np.ndarray:
    """(N-1,) which intervals between samples join two runs (:class:`PathGeometry`): zero long, the stop's position
    shared, taking no time."""
    joins = np.zeros(run_starts[-1] - 1, dtype=bool)
    joins[run_starts[1:-1] - 1] = True
    return joins


def _run_arc(length_m: float, count: int, refine: int, feed_changes_m: np.ndarray) -> np.ndarray:
    """Arc lengths of a run's samples (:meth:`ToolPath.geometry`): ``count`` evenly spaced, the end intervals
    cut in ``END_SPLIT`` growing as squares, a sample where the feed changes, then every interval in ``refine``
    equal parts."""
    even = np.linspace(0.0, length_m, count)
    ends = even[1] * (np.arange(1, END_SPLIT) / END_SPLIT) ** 2
    arc = np.concatenate([[0.0], ends, even[1:-1], length_m - ends[::-1], [length_m]])
    near = np.abs(arc[None, :] - feed_changes_m[:, None]).min(axis=1, initial=np.inf) <= MIN_LENGTH_M
    arc = np.union1d(arc, feed_changes_m[~near])
    return np.append(np.linspace(arc[:-1], arc[1:], refine, endpoint=False).T.ravel(), length_m)


def _runs(segments: tuple[Segment, ...]) -> list[tuple[list[Segment], bool]]:
    """Group consecutive segments into runs without a corner, a gap or a change of turning rate between them
    (an orientation that turns at another rate per metre would jump in angular velocity).

    Returns:
        The runs, each with whether a gap (a skipped rapid) comes before it.
    """
    runs = [([segments[0]], False)]
    for previous, segment in zip(segments, segments[1:]):
        gap = bool(np.linalg.norm(segment.start_m - previous.end_m) > GAP_M)
        end_tangent = previous.point(np.array([previous.length_m]), np.ones(1), np.zeros(1))[3][0]
        start_tangent = segment.point(np.zeros(1), np.ones(1), np.zeros(1))[3][0]
        turn = np.arccos(np.clip(end_tangent @ start_tangent, -1.0, 1.0))
        kink = np.linalg.norm(_turning_rate(segment) - _turning_rate(previous)) > TURNING_RATE_TOLERANCE_RAD_M
        if gap or kink or turn > CORNER_ANGLE_RAD:
            runs.append(([segment], gap))
        else:
            runs[-1][0].append(segment)
    return runs


def _turning_rate(segment: Segment) -> np.ndarray:
    """The tool's angular velocity per unit feed speed on a segment, in the path frame (rad/m)."""
    if segment.rotation is None or segment.turn_rad is None:
        return np.zeros(3)
    return segment.rotation @ segment.turn_rad / segment.length_m


def _along(run: list[Segment], s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray,
           oriented: bool = False) -> dict[str, np.ndarray]:
    """Motion along consecutive segments at increasing arc lengths ``s`` measured from the run's start.

    Returns:
        position, velocity, acceleration, tangent (N, 3) and rapid (N,): whether on a rapid segment;
        if ``oriented``, also rotation (N, 3, 3), angular_velocity and angular_acceleration (N, 3).
    """
    bounds = np.cumsum([0.0] + [seg.length_m for seg in run])
    index = np.clip(np.searchsorted(bounds, s, side="right") - 1, 0, len(run) - 1)
    names = ("position", "velocity", "acceleration", "tangent")
    out: dict[str, np.ndarray] = {name: np.zeros((len(s), 3)) for name in names}
    out["rapid"] = np.zeros(len(s), dtype=bool)
    if oriented:
        out.update(rotation=np.zeros((len(s), 3, 3)), angular_velocity=np.zeros((len(s), 3)),
                   angular_acceleration=np.zeros((len(s), 3)))
    present = np.unique(index)
    starts = np.searchsorted(index, present, side="left")
    stops = np.searchsorted(index, present, side="right")
    for k, lo, hi in zip(present, starts, stops):
        segment = run[k]
        for name, value in zip(names, segment.point(s[lo:hi] - bounds[k], s_dot[lo:hi], s_ddot[lo:hi])):
            out[name][lo:hi] = value
        out["rapid"][lo:hi] = segment.rapid
        if oriented:
            turning = segment.orientation(s[lo:hi] - bounds[k], s_dot[lo:hi], s_ddot[lo:hi])
            for name, value in zip(("rotation", "angular_velocity", "angular_acceleration"), turning):
                out[name][lo:hi] = value
    return out


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
    """Read and validate a path file (and the G-code program it names, if any).

    Args:
        path: The YAML file.

    Returns:
        The path, in metres.

    Raises:
        PathFileError: The file (or its program) is missing, malformed, or breaks the schema;
            a G-code program's errors (GcodeError) name its line and word.
    """
    path = FilePath(path)
    spec = read_yaml(path, PathFile, PathFileError)
    _check_fields(path, spec)
    rapid_feed, timed = None, None
    if isinstance(spec.shape, Gcode):
        program = read_program(path.parent / spec.shape.file)
        rapids = spec.rapids or Rapids()
        segments = tuple(s for s in program.segments if not s.rapid or rapids.mode == "timed")
        feed, rapid_feed = program.feed_m_s, rapids.feed_m_s
    elif isinstance(spec.shape, Poses):
        assert spec.units is not None  # _check_fields
        file = path.parent / spec.shape.file
        table = read_poses(file, spec.shape.orientation, LENGTH_SCALE[spec.units])
        # A timed list is sampled by its splines; its polyline (length, report) needs no orientation.
        segments = pose_segments(file, table if table.t_s is None else dataclasses.replace(table, rotation=None))
        if table.t_s is not None:
            timed = TimedPoses(table.t_s, table.position_m, table.rotation)
            _check_timed(path, spec, timed)
            feed = timed.mean_speed_m_s
        else:
            _check_untimed(path, spec)
            assert spec.feed_m_s is not None  # _check_untimed
            feed = spec.feed_m_s
    else:
        segments = _segments(spec)
        assert spec.feed_m_s is not None  # _check_fields
        feed = spec.feed_m_s
    if not segments:
        raise PathFileError(path, "shape.file" if isinstance(spec.shape, Poses) else "shape.points",
                            "the points must not all coincide")
    if sum(segment.length_m for segment in segments) < MIN_LENGTH_M:
        raise PathFileError(path, "shape", f"the path is shorter than {MIN_LENGTH_M * 1e6:g} µm")
    return ToolPath(name=spec.name or path.stem, segments=segments, feed_m_s=feed,
                    forces=spec.process_forces_N.resolve(), timing=spec.timing,
                    time_step_s=spec.time_step_s if spec.time_step_s is not None else default_time_step_s(feed),
                    rapid_feed_m_s=rapid_feed, timed=timed)


def _check_fields(path: FilePath, spec: PathFile) -> None:
    """The fields a shape requires or refuses: a G-code program has its own units and feeds."""
    if isinstance(spec.shape, Gcode):
        if spec.units is not None:
            raise PathFileError(path, "units", "a G-code program sets its own units (G21 mm, the default, or G20 "
                                               "inches): remove units")
        if spec.feed_m_s is not None:
            raise PathFileError(path, "feed_m_s", "a G-code program's feeds are its F words: remove feed_m_s (the "
                                                  "feed command scales them all)")
        return
    for name in ("units",) if isinstance(spec.shape, Poses) else ("units", "feed_m_s"):
        if getattr(spec, name) is None:
            raise PathFileError(path, name, "required field is missing")
    if spec.rapids is not None:
        raise PathFileError(path, "rapids", f"rapids belong to G-code programs, not to a {spec.shape.type}")


def _check_untimed(path: FilePath, spec: PathFile) -> None:
    """A pose list without times is timed by the path's feed."""
    if spec.feed_m_s is None:
        raise PathFileError(path, "feed_m_s", "required field is missing (a pose list without a t column is run at "
                                              "this feed)")


def _check_timed(path: FilePath, spec: PathFile, timed: TimedPoses) -> None:
    """A pose list with times is timed by them: no feed, no timing law."""
    for name in ("feed_m_s", "timing"):
        if name in spec.model_fields_set:
            raise PathFileError(path, name, "the pose list's t column times the path: remove this field (the feed "
                                            "command scales the list's speeds)")
    if timed.mean_speed_m_s <= 0:
        raise PathFileError(path, "shape.file", "the poses with times do not move: every point is the same")


def _segments(spec: PathFile) -> tuple[Segment, ...]:
    assert spec.units is not None and not isinstance(spec.shape, (Gcode, Poses))  # _check_fields
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

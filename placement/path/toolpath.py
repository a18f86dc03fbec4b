"""A tool path ready to be sampled: its segments (m), feeds, process forces and timing law."""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass
from functools import cached_property

import numpy as np
from scipy.spatial import cKDTree

from placement.exceptions import SettingsError
from placement.path.paper_law import sample_paper
from placement.path.path_file import ForceSet, Timing
from placement.path.poses import TimedPoses
from placement.path.realistic_law import sample_realistic
from placement.path.samples import END_SPLIT, MAX_SAMPLES, MIN_PATH_STEPS, MIN_RUN_SAMPLES, PathGeometry, PathSamples, run_joins
from placement.path.segments import Hold, Run, Segment, segments_motion, split_runs

MIN_LENGTH_M = 1e-6
SHAPE_POINTS = 9  # points of each piece compared by half_turn_symmetric
SHAPE_NEIGHBOURS = 4  # pieces whose middle is nearest a turned one's that half_turn_symmetric compares it with
PLUNGE_COSINE = np.cos(np.radians(45.0))  # a feed move within 45° of -Z_p (into the workpiece) is plunging


@dataclass(frozen=True)
class ToolPath:
    """A path ready to be sampled: geometry (m), feeds, forces and timing law.

    Attributes:
        feed_m_s: The feed of a segment whose ``feed_ratio`` is 1 (the highest F of a G-code
            program); every segment's feed scales with it.
        rapid_feed_m_s: The feed of rapid segments (timed G-code rapids), not scaled with feed_m_s.
        timed: A pose list with times, sampled by its own interpolation instead of the segments
            (the polyline through its points); its speeds scale by feed_m_s over its mean speed.
        notes: What the reader of a G-code program left out, for the user (printed once each).
        holds: Where the tool rests for a while (G-code dwells), in order; the segment before each ends
            in an exact stop. The paper and realistic timing laws sample each as a piece of its own, the
            optimal law as a run of two samples at rest, timed by its duration.
        max_deflection_m: The largest deflection of the tool under the process forces a feasible placement may
            have (m; :mod:`placement.stiffness`), or None: none is required.
        loaded_stiffness: The deflection is the nonlinear equilibrium under the finite process force (the loaded
            correction, :mod:`placement.stiffness.loaded`), not the linear C·w.
    """

    name: str
    segments: tuple[Segment, ...]
    feed_m_s: float
    forces: ForceSet
    timing: Timing
    time_step_s: float
    rapid_feed_m_s: float | None = None
    timed: TimedPoses | None = None
    notes: tuple[str, ...] = ()
    holds: tuple[Hold, ...] = ()
    max_deflection_m: float | None = None
    loaded_stiffness: bool = False

    @property
    def length_m(self) -> float:
        """Total path length."""
        return sum(segment.length_m for segment in self.segments)

    def __repr__(self) -> str:
        """A short summary (the segments' arrays left out)."""
        return (f"ToolPath('{self.name}', {len(self.segments)} segments, {self.length_m * 1e3:.4g} mm, feed "
                f"{self.feed_m_s:.4g} m/s, {self.timing.mode} timing)")

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
            raise SettingsError(f"the sampling time step must be a finite number > 0 s, got {step}")
        if self.timed is not None:
            count = self.sample_counts([self.timed.duration_s * self.timed.mean_speed_m_s / self.feed_m_s], step)[0]
            return self.assemble([self.timed.sample(count, self.feed_m_s / self.timed.mean_speed_m_s)])
        if self.timing.mode == "paper":
            return sample_paper(self, step)
        if self.timing.mode == "optimal":
            return self.geometry(step).samples
        return sample_realistic(self, step)

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
            SettingsError: A timed pose list (timed by its own t column), or more than MAX_SAMPLES
                samples at ``time_step_s`` (before ``refine``).
        """
        step = self.time_step_s if time_step_s is None else time_step_s
        if self.timed is not None:
            raise SettingsError(f"the path '{self.name}' is a pose list with times: it is timed by its t column, "
                                "not by the optimal timing law")
        if not 0 < step < np.inf:
            raise SettingsError(f"the sampling time step must be a finite number > 0 s, got {step}")
        runs = self.runs()
        fastest = max(self.speed_m_s(s) for s in self.segments)
        nominal = [run.length_m / fastest for run in runs]
        counts = [max(MIN_RUN_SAMPLES, count) for count in self.sample_counts(nominal, step)]
        parts, piece, arcs, feeds, starts, hold_s, done = [], 0, [], [], [0], [], 0

        def add_holds(after: int) -> None:  # each hold a run of two samples at rest, timed by its duration
            for part, hold in zip(self.hold_parts(after, 0.0, piece)[0], [h for h in self.holds if h.after == after]):
                parts.append({**part, "t": np.zeros(2), "piece": np.full(2, piece)})
                arcs.append(np.zeros(2))
                feeds.append(np.full(2, fastest))
                starts.append(starts[-1] + 2)
                hold_s.append(hold.duration_s)

        add_holds(0)
        for run, count in zip(runs, counts):
            bounds = run.bounds_m
            speeds = np.array([self.speed_m_s(s) for s in run.segments])
            arc = _run_arc(bounds[-1], count, refine, bounds[1:-1][np.diff(speeds) != 0])
            count = len(arc)
            piece += run.after_gap
            parts.append({"t": np.zeros(count), **run.along(arc, np.ones(count), np.zeros(count), self.oriented),
                          "piece": np.full(count, piece)})
            # A sample where the feed changes (within MIN_LENGTH_M) takes the lower one: the speed never exceeds a
            # segment's feed, between samples either (the speed changes monotonically between them).
            after = np.clip(np.searchsorted(bounds, arc + MIN_LENGTH_M, side="right") - 1, 0, len(speeds) - 1)
            before = np.clip(np.searchsorted(bounds, arc - MIN_LENGTH_M, side="right") - 1, 0, len(speeds) - 1)
            arcs.append(arc)
            feeds.append(np.minimum(speeds[after], speeds[before]))
            starts.append(starts[-1] + count)
            hold_s.append(0.0)
            done += len(run.segments)
            add_holds(done)
        arc_m, feed = np.concatenate(arcs), np.concatenate(feeds)
        # Nominal times: each run at its feed bound throughout (a lower bound of any timing's), each hold its duration.
        geometry = PathGeometry(self.assemble(parts), np.array(starts), arc_m, feed, np.array(hold_s))
        steps = np.where(run_joins(np.array(starts)), 0.0, np.diff(arc_m) / feed[1:])
        steps = np.where(geometry.hold_intervals_s > 0, geometry.hold_intervals_s, steps)
        nominal_t = np.concatenate([[0.0], np.cumsum(steps)])
        return dataclasses.replace(geometry, samples=dataclasses.replace(geometry.samples, t_s=nominal_t))

    @cached_property
    def oriented(self) -> bool:
        """Whether the path carries tool orientations (a pose list with orientation columns); looked up once."""
        return any(segment.rotation is not None for segment in self.segments)

    def motion(self, index: np.ndarray, s: np.ndarray, s_dot: np.ndarray, s_ddot: np.ndarray) -> dict[str, np.ndarray]:
        """Each sample's motion on its own segment ``index`` at arc length ``s`` (m) from its start, moved at ṡ and
        s̈, with the orientation's if the path has one (:func:`placement.path.segments.segments_motion`)."""
        return segments_motion(self.segments, index, s, s_dot, s_ddot, self.oriented)

    def runs(self, by_segment: bool = False) -> list[Run]:
        """The runs the tool moves through without stopping (:func:`placement.path.segments.split_runs`), or each segment
        on its own (``by_segment``: the paper's timing law)."""
        return [Run((segment,)) for segment in self.segments] if by_segment else split_runs(self.segments)

    def hold_parts(self, after: int, start_s: float, piece: int) -> tuple[list[dict[str, np.ndarray]], float, int]:
        """The samples of the holds after segment ``after`` - 1, each a piece of its own from ``piece`` on: the tool
        at rest at the segment's end, with its end tangent and kind of move (so the process force of the move it
        ends keeps acting), sampled at its start and end (nothing changes in between, so the trapezoidal energy of
        the two is exact). Returns the parts, the time after them and the next piece."""
        holds = [hold for hold in self.holds if hold.after == after]
        if not holds:
            return [], start_s, piece
        segment = self.segments[after - 1] if after else self.segments[0]
        at = np.array([segment.length_m if after else 0.0])
        position, _, _, tangent = segment.point(at, np.zeros(1), np.zeros(1))
        rotation = segment.orientation(at, np.zeros(1), np.zeros(1))[0] if self.oriented else None
        parts = []
        n = 2
        for hold in holds:
            part = {"t": start_s + np.linspace(0.0, hold.duration_s, n), "position": np.repeat(position, n, axis=0),
                    "velocity": np.zeros((n, 3)), "acceleration": np.zeros((n, 3)),
                    "tangent": np.repeat(tangent, n, axis=0), "rapid": np.full(n, segment.rapid),
                    "piece": np.full(n, piece)}
            if rotation is not None:
                part.update(rotation=np.repeat(rotation, n, axis=0), angular_velocity=np.zeros((n, 3)),
                            angular_acceleration=np.zeros((n, 3)))
            parts.append(part)
            start_s, piece = start_s + hold.duration_s, piece + 1
        return parts, start_s, piece

    def sample_counts(self, durations_s: list[float], step: float) -> list[int]:
        """Samples of each independently timed piece.

        Raises:
            SettingsError: More than MAX_SAMPLES samples in all, or a step longer than the path's duration over
                MIN_PATH_STEPS: the energy would be integrated over a handful of samples, and corners, arcs and
                accelerations left out (``--time-step 1e6`` on the 0.27 s groove gave 8 samples and 4.39 J
                instead of 4.80 J).
        """
        total = sum(durations_s)
        if step > total / MIN_PATH_STEPS:
            raise SettingsError(f"the sampling time step {step:g} s cannot sample the path '{self.name}', which lasts "
                                f"{total:.4g} s: give a time step of at most {total / MIN_PATH_STEPS:.3g} s "
                                "(time_step_s in the path file, or --time-step); the default is 1 ms")
        counts = [max(2, int(np.ceil(d / step)) + 1) if d / step < MAX_SAMPLES else MAX_SAMPLES + 1 for d in durations_s]
        if sum(counts) > MAX_SAMPLES:
            raise SettingsError(f"the path '{self.name}' lasts {sum(durations_s):.4g} s: sampled every {step:g} s it "
                                f"would need more than {MAX_SAMPLES:,} samples; use a larger time step (time_step_s "
                                "in the path file, or --time-step), or check the path's size and feed")
        return counts

    def half_turn_symmetric(self) -> bool:
        """Whether a half turn about Z_p maps the path onto itself, piece by piece.

        Each independently timed piece (a segment in the paper's timing law, a corner-to-corner
        run in the realistic one) must map onto a piece run the same way at the same feed; the
        energy of such a path is then the same at phi and phi + 180°, and phi only needs a half
        turn of range. A timed pose list, one whose orientation changes, or one with holds is taken not to be.
        """
        if self.timed is not None or self.holds or not self._constant_orientation():
            return False
        pieces = self.runs(by_segment=self.timing.mode == "paper")
        shapes = _piece_shapes(pieces).reshape(len(pieces), -1)
        feeds: dict[tuple[float, ...], int] = {}  # each piece's feeds, as a number per distinct tuple
        speeds = np.array([feeds.setdefault(tuple(self.speed_m_s(s) for s in run.segments), len(feeds))
                           for run in pieces])
        turned = shapes * np.tile([-1.0, -1.0, 1.0], SHAPE_POINTS)
        # Each turned piece against the pieces of nearest middle points: np.allclose(turned, piece, atol=1e-12) and
        # the same feeds
        middle = slice(3 * (SHAPE_POINTS // 2), 3 * (SHAPE_POINTS // 2) + 3)
        _, nearest = cKDTree(shapes[:, middle]).query(turned[:, middle], k=min(SHAPE_NEIGHBOURS, len(pieces)))
        nearest = nearest.reshape(len(pieces), -1)
        close = (np.abs(turned[:, None] - shapes[nearest]) <= 1e-12 + 1e-5 * np.abs(shapes[nearest])).all(axis=2)
        return bool((close & (speeds[nearest] == speeds[:, None])).any(axis=1).all())

    def _constant_orientation(self) -> bool:
        rotations = [s.rotation for s in self.segments if s.rotation is not None]
        turns = [s.turn_rad for s in self.segments if s.turn_rad is not None]
        return all(np.array_equal(r, rotations[0]) for r in rotations) and all(not np.any(t) for t in turns)

    def assemble(self, parts: list[dict[str, np.ndarray]]) -> PathSamples:
        """Samples from their parts (columns t, position, velocity, acceleration, tangent, rapid, piece and the
        orientation's), with the process force of each sample's kind of move."""
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


def _piece_shapes(pieces: list[Run]) -> np.ndarray:
    """(P, SHAPE_POINTS, 3) points of each piece at evenly spaced shares of its length, ends included."""
    fractions = np.linspace(0.0, 1.0, SHAPE_POINTS)
    if all(len(run.segments) == 1 for run in pieces):  # a segment each (the paper's law): all at once
        segments = [run.segments[0] for run in pieces]
        s = (fractions[None, :] * np.array([run.length_m for run in pieces])[:, None]).ravel()
        index = np.repeat(np.arange(len(pieces)), SHAPE_POINTS)
        zero = np.zeros(len(s))
        return segments_motion(segments, index, s, zero, zero)["position"].reshape(len(pieces), SHAPE_POINTS, 3)
    zero = np.zeros(SHAPE_POINTS)
    return np.array([run.along(fractions * run.length_m, zero, zero)["position"] for run in pieces])


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

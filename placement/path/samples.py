"""Sampled paths: samples in time (:class:`PathSamples`) and along the arc length for the optimal
timing law (:class:`PathGeometry`), and the sampling defaults and bounds."""

from __future__ import annotations

from dataclasses import dataclass, fields
from functools import cached_property
from typing import Any

import numpy as np

MAX_SAMPLES = 1_000_000  # samples of one path: about 0.5 GB through the whole chain
MIN_PATH_STEPS = 10  # a sampling step longer than a tenth of the path's duration cannot sample it


DEFAULT_TIME_STEP_S = 0.001  # the sampling step of a file that gives none ...


DEFAULT_SPACING_M = 0.0005  # ... or longer, to keep samples this far apart at the path's fastest feed


MIN_RUN_SAMPLES = 8  # samples of a run between stops, at least, for the optimal timing law


END_SPLIT = 4  # a run's first and last intervals (leaving and reaching a stop, the slowest) are cut in this many


def default_time_step_s(feed_m_s: float, length_m: float) -> float:
    """The sampling step of a file that gives none: 1 ms, or longer for a slow path, so that samples are at
    most ``DEFAULT_SPACING_M`` apart at its fastest feed (a G-code program at F100 needs no 1 ms samples);
    shorter for a path run in less than 2·MIN_PATH_STEPS ms, so that it gets 2·MIN_PATH_STEPS samples at least."""
    return min(max(DEFAULT_TIME_STEP_S, DEFAULT_SPACING_M / feed_m_s), length_m / feed_m_s / (2 * MIN_PATH_STEPS))


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
        hold_s: (R,) each run's duration if it is a hold (two samples at rest, a G-code dwell), else 0
            (None: no holds).
    """

    samples: PathSamples
    run_starts: np.ndarray
    arc_m: np.ndarray
    feed_m_s: np.ndarray
    hold_s: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.arc_m)

    @cached_property
    def hold_intervals_s(self) -> np.ndarray:
        """(N-1,) the duration of each interval between samples that is a hold, 0 for the others."""
        durations = np.zeros(max(len(self.arc_m) - 1, 0))
        if self.hold_s is not None:
            held = np.flatnonzero(self.hold_s > 0)
            durations[self.run_starts[held]] = self.hold_s[held]
        return durations

    @cached_property
    def joins(self) -> np.ndarray:
        """(N-1,) which intervals between samples join two runs (:func:`run_joins`)."""
        return run_joins(self.run_starts)

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


def run_joins(run_starts: np.ndarray) -> np.ndarray:
    """(N-1,) which intervals between samples join two runs (:class:`PathGeometry`): zero long, the stop's position
    shared, taking no time."""
    joins = np.zeros(run_starts[-1] - 1, dtype=bool)
    joins[run_starts[1:-1] - 1] = True
    return joins



"""The paper's timing law: each segment at its own constant feed, on its own (Ur-Rehman et al.).

The tool jumps to each segment's feed at its start and drops to rest at its end; corners are
ignored, and each segment is a piece of its own, integrated independently; so is each hold (a
G-code dwell), the tool at rest for its duration.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from placement.path.samples import PathSamples
    from placement.path.timed_path import TimedPath


def sample_paper(path: TimedPath, step_s: float) -> PathSamples:
    """The path's samples, ``step_s`` apart at most within each segment, each segment at its feed; each hold (a
    dwell) a piece of its own after its segment.

    Every segment's samples are computed at once (:func:`placement.path.segments.segments_motion`), with the
    values a segment-by-segment ``numpy.linspace`` gives; the times add up segment by segment.
    """
    segments = path.segments
    speeds = [path.speed_m_s(segment) for segment in segments]
    durations = [segment.length_m / speed for segment, speed in zip(segments, speeds)]
    counts = np.array(path.sample_counts(durations, step_s))
    index = np.repeat(np.arange(len(segments)), counts)
    ends = np.cumsum(counts) - 1  # each segment's last sample
    within = np.arange(len(index)) - (ends - counts + 1)[index]
    t = within * (np.array(durations) / (counts - 1))[index]  # numpy.linspace(0, duration, count), segment by segment
    t[ends] = durations
    speed = np.array(speeds)[index]
    motion = path.motion(index, speed * t, speed, np.zeros_like(t))
    held_after = {hold.after for hold in path.holds}
    parts, start, piece = path.hold_parts(0, 0.0, 0)
    starts, pieces, holds = np.empty(len(segments)), np.empty(len(segments), dtype=int), {}
    for k, duration in enumerate(durations):
        starts[k], pieces[k] = start, piece
        start, piece = start + duration, piece + 1
        if k + 1 in held_after:  # each hold a piece of its own after its segment
            holds[k], start, piece = path.hold_parts(k + 1, start, piece)
    motion.update(t=starts[index] + t, piece=pieces[index])
    first = 0
    for last in sorted({*holds, len(segments) - 1}):
        parts.append({key: value[first:ends[last] + 1] for key, value in motion.items()})
        parts += holds.get(last, [])
        first = ends[last] + 1
    return path.assemble(parts)

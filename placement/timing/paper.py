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
    from placement.timing.interface import TimedPath


def sample_paper(path: TimedPath, step_s: float) -> PathSamples:
    """The path's samples, ``step_s`` apart at most within each segment, each segment at its feed; each hold (a
    dwell) a piece of its own after its segment."""
    parts, start, piece = [], 0.0, 0
    durations = [segment.length_m / path.speed_m_s(segment) for segment in path.segments]
    pieces = zip(path.runs(by_segment=True), durations, path.sample_counts(durations, step_s))
    held, start, piece = path.hold_parts(0, start, piece)
    parts += held
    for k, (run, duration, count) in enumerate(pieces):
        t = np.linspace(0.0, duration, count)
        speed = path.speed_m_s(run.segments[0])
        motion = run.along(speed * t, np.full_like(t, speed), np.zeros_like(t), path.oriented)
        parts.append({"t": start + t, **motion, "piece": np.full(len(t), piece)})
        held, start, piece = path.hold_parts(k + 1, start + duration, piece + 1)
        parts += held
    return path.assemble(parts)

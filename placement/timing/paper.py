"""The paper's timing law: each segment at its own constant feed, on its own (Ur-Rehman et al.).

The tool jumps to each segment's feed at its start and drops to rest at its end; corners are
ignored, and each segment is a piece of its own, integrated independently.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from placement.path.samples import PathSamples
    from placement.path.toolpath import ToolPath


def sample_paper(path: ToolPath, step_s: float) -> PathSamples:
    """The path's samples, ``step_s`` apart at most within each segment, each segment at its feed."""
    parts, start = [], 0.0
    durations = [segment.length_m / path.speed_m_s(segment) for segment in path.segments]
    pieces = zip(path.runs(by_segment=True), durations, path.sample_counts(durations, step_s))
    for k, (run, duration, count) in enumerate(pieces):
        t = np.linspace(0.0, duration, count)
        speed = path.speed_m_s(run.segments[0])
        motion = run.along(speed * t, np.full_like(t, speed), np.zeros_like(t), path.oriented)
        parts.append({"t": start + t, **motion, "piece": np.full(len(t), k)})
        start += duration
    return path.assemble(parts)

"""Energy against feed at one placement: what a faster or slower feed costs per part.

For each feed rate the path is timed again by its own timing law and evaluated by the exact
model at the given placement: the time per part (one pass of the path), the energy per part, and
whether every limit holds (else the binding one). A production engineer's first question.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.realistic_law import segment_speeds
from placement.path.toolpath import ToolPath
from placement.robot.model import Robot


@dataclass(frozen=True)
class FeedStudy:
    """Time and energy per part against feed (SI units).

    Attributes:
        feeds_m_s: (F,) programmed feed rates.
        top_speed_m_s: (F,) the fastest the tool moves (below the feed where the timing law cannot reach it).
        speed_bound: (F,) what bounds that speed: "feed", under the realistic law what bounds its fastest
            segment (:func:`placement.path.realistic_law.segment_speeds`: "centripetal acceleration", "length
            (short of the feed cap)", ...), under the optimal law "robot limits" below the feed.
        time_s: (F,) duration of one pass.
        energy_J: (F,) electric energy of one pass (NaN where a sample is unreachable).
        feasible: (F,) whether every limit holds.
        binding: (F,) the tightest limit, "kind (where)".
    """

    feeds_m_s: np.ndarray
    top_speed_m_s: np.ndarray
    speed_bound: tuple[str, ...]
    time_s: np.ndarray
    energy_J: np.ndarray
    feasible: np.ndarray
    binding: tuple[str, ...]


def feed_study(robot: Robot, path: ToolPath, placement: np.ndarray, feeds_m_s: np.ndarray,
               evaluation: EvaluatorSettings = EvaluatorSettings()) -> FeedStudy:
    """Evaluate one placement of the path at each feed rate (m/s), timed by the path's timing law, as ``evaluation``
    says (regeneration policy, sampling step, ...; the energy is reported whatever its objective)."""
    times, speeds, bounds, energies, feasible, binding = [], [], [], [], [], []
    for feed in feeds_m_s:
        fed = dataclasses.replace(path, feed_m_s=float(feed))
        detail = Evaluator(robot, fed, evaluation).detail(np.asarray(placement, dtype=float))
        times.append(detail.duration_s)
        speeds.append(float(np.linalg.norm(detail.samples.velocity_m_s, axis=1).max()))
        bounds.append(_speed_bound(fed, speeds[-1]))
        energies.append(float(detail.energy.total_J) if detail.reachable else np.nan)
        feasible.append(detail.feasible)
        tightest = min(detail.margins, key=lambda m: m.margin)
        binding.append(f"{tightest.kind} ({tightest.where})")
    return FeedStudy(np.asarray(feeds_m_s, dtype=float), np.array(speeds), tuple(bounds), np.array(times),
                     np.array(energies), np.array(feasible), tuple(binding))


def _speed_bound(path: ToolPath, top_speed_m_s: float) -> str:
    """What bounds the top speed of ``path`` at its feed (:attr:`FeedStudy.speed_bound`)."""
    if path.timing.mode == "realistic" and path.timed is None:
        fastest = max(segment_speeds(path), key=lambda segment: segment.reached_m_s)
        return fastest.bound
    fastest_feed = max(path.speed_m_s(segment) for segment in path.segments)
    if path.timing.mode == "optimal" and top_speed_m_s < fastest_feed * (1 - 1e-6):
        return "robot limits"
    return "feed"

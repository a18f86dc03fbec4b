"""Guides for the search of a long path: cheaper models of it that steer the search, checked against the exact one.

A path with many samples costs too much to evaluate the thousands of times a search does: a CAM polyline of
100,000 points under the paper's timing law has 200,000 samples, each segment being timed on its own with two
samples at least whatever the time step, and a 4,700-line surface program 15,000 even at the global search's
coarse step. A path with more than GUIDE_THRESHOLD samples at its own step, or COARSE_THRESHOLD at the coarse
one, is searched on guides instead: the same path with each stretch of consecutive straight segments (same
feed and kind of move, no orientation, stop or hold between them) merged into chords, each at most a given
length and turning by at most a given angle in all, so that a chord stays within about length · angle / 8 of
the points it skips. The global search's guide has about GLOBAL_SEGMENTS chords, sampled at the coarse step,
and the polish's about POLISH_SEGMENTS, sampled at most POLISH_SAMPLES times over the path's duration. Under
the realistic and optimal laws, which time runs rather than segments, the guides are the path itself, the
polish's sampled at that coarser step.

The exact model ranks nothing but checks everything reported: each reported placement is evaluated at the
path's own sampling and on the 4x denser re-check, as for any path, and the report gives the polish guide's
value there beside the exact one (the gap). The tolerance box around an optimum is found on the polish's guide,
and says so.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.segments import Segment
from placement.path.toolpath import ToolPath

GUIDE_THRESHOLD = 20_000  # a path with more samples than this at its own step is searched on guides ...
COARSE_THRESHOLD = 1_024  # ... and so is one with more than this at the global search's coarse step
GLOBAL_SEGMENTS = 128  # chords of the global search's guide, about
POLISH_SEGMENTS = 1_000  # chords of the polish's guide, about
GLOBAL_TURN_RAD = np.radians(20.0)  # a chord of the global search's guide turns by at most this in all
POLISH_TURN_RAD = np.radians(5.0)  # a chord of the polish's guide turns by at most this in all
POLISH_SAMPLES = 2_000  # the polish's guide's time step is at least the path's duration over this


@dataclass(frozen=True)
class SearchModels:
    """The models a search evaluates: the global search's, the polish's and, when they are guides, the exact one.

    Attributes:
        coarse_path, coarse: The global search's path and evaluator settings.
        polish_path, polish: The polish's path and evaluator settings.
        exact: The path's own sampling (the reported values'); the polish's when it is not a guide.
        guided: Whether the global search and the polish run on guides (module docstring).
    """

    coarse_path: ToolPath
    coarse: EvaluatorSettings
    polish_path: ToolPath
    polish: EvaluatorSettings
    exact: EvaluatorSettings
    guided: bool = False


def search_models(path: ToolPath, coarse: EvaluatorSettings, fine: EvaluatorSettings) -> SearchModels:
    """The models of a search: the path itself at the ``coarse`` and ``fine`` sampling
    (:func:`placement.search.optimize.search_sampling`), or guides (module docstring) with ``fine`` the exact
    model, for a path with more than GUIDE_THRESHOLD samples at its own step or COARSE_THRESHOLD at the coarse one
    (a timed pose list has neither: it is sampled in time whatever its points)."""
    samples = path.sample(fine.time_step_s)
    if path.timed is not None or (len(samples) <= GUIDE_THRESHOLD
                                  and len(path.sample(coarse.time_step_s)) <= COARSE_THRESHOLD):
        return SearchModels(path, coarse, path, fine, fine)
    step = max(fine.time_step_s or path.time_step_s, float(np.ptp(samples.t_s)) / POLISH_SAMPLES)
    polish = dataclasses.replace(fine, time_step_s=step)
    if path.timing.mode != "paper":
        return SearchModels(path, coarse, path, polish, fine, guided=True)
    length = path.length_m
    return SearchModels(merge_lines(path, length / GLOBAL_SEGMENTS, GLOBAL_TURN_RAD), coarse,
                        merge_lines(path, length / POLISH_SEGMENTS, POLISH_TURN_RAD), polish, fine, guided=True)


def guide_value(guide: Evaluator, placement: np.ndarray) -> float:
    """The objective of a (1, 6) placement on a guide's model (the exact one is the report's)."""
    return float(guide.evaluate(placement).value[0])


def merge_lines(path: ToolPath, max_length_m: float, max_turn_rad: float) -> ToolPath:
    """The path with stretches of consecutive straight segments merged into chords (module docstring): a chord
    grows segment by segment while it stays at most ``max_length_m`` long and its segments turn by at most
    ``max_turn_rad`` in all; holds stay after the same points of the path."""
    segments = path.segments
    held = {hold.after for hold in path.holds}
    merged: list[Segment] = []
    new_index = {0: 0}  # the number of chords before each old segment boundary where a group ends
    group: list[Segment] = []
    length, turn = 0.0, 0.0
    for k, segment in enumerate(segments):
        if group and _joins(group[-1], segment, length + segment.length_m, turn, max_length_m, max_turn_rad):
            turn += _turn(group[-1], segment)
            group.append(segment)
            length += segment.length_m
        else:
            if group:
                merged.append(_chord(group))
                new_index[k] = len(merged)
            group, length, turn = [segment], segment.length_m, 0.0
        if k + 1 in held or not _plain(segment):  # a hold or a stop ends the group
            merged.append(_chord(group))
            new_index[k + 1] = len(merged)
            group, length, turn = [], 0.0, 0.0
    if group:
        merged.append(_chord(group))
    new_index[len(segments)] = len(merged)
    holds = tuple(dataclasses.replace(hold, after=new_index[hold.after]) for hold in path.holds)
    return dataclasses.replace(path, name=f"{path.name} (guide)", segments=tuple(merged), holds=holds)


def _plain(segment: Segment) -> bool:
    """Whether a segment may be merged: a straight one without orientation or a stop at its end."""
    return (segment.center_m is None and segment.rotation is None and segment.turn_rad is None
            and not segment.exact_stop and not segment.exact_path)


def _joins(last: Segment, segment: Segment, length_m: float, turn_rad: float, max_length_m: float,
           max_turn_rad: float) -> bool:
    """Whether ``segment`` may extend the chord that ends with ``last``."""
    return (_plain(last) and _plain(segment) and last.rapid == segment.rapid and last.feed_ratio == segment.feed_ratio
            and bool(np.array_equal(last.end_m, segment.start_m)) and length_m <= max_length_m
            and turn_rad + _turn(last, segment) <= max_turn_rad)


def _turn(first: Segment, second: Segment) -> float:
    """The angle between two straight segments' directions (rad)."""
    a, b = first.end_m - first.start_m, second.end_m - second.start_m
    return float(np.arccos(np.clip(a @ b / (first.length_m * second.length_m), -1.0, 1.0)))


def _chord(group: list[Segment]) -> Segment:
    """The straight segment from the first segment's start to the last one's end, of the first one's kind."""
    return group[0] if len(group) == 1 else dataclasses.replace(group[0], end_m=group[-1].end_m)

"""Guides for the search of a long path: cheaper models of it that steer the search, checked against the exact one.

A path with many samples costs too much to evaluate the thousands of times a search does: a CAM polyline of
100,000 points under the paper's timing law has 200,000 samples, each segment being timed on its own with two
samples at least whatever the time step, and a 4,700-line surface program 9,500 even at the global search's
coarse step. A path with more than GUIDE_THRESHOLD samples at its own step, or COARSE_THRESHOLD at the coarse
one, is searched on guides instead.

The polish's guide is the same path with each stretch of consecutive lines and plane arcs of at most a half turn
(same feed and kind of move, no orientation, stop or hold between them) merged into chords, each at most a given
length and within a share of that length of every point of the path it skips, along its arcs too (a CAM program's
small arcs between lines would otherwise keep most of its segments): about POLISH_SEGMENTS chords, sampled at a
step of at least the path's duration over POLISH_SAMPLES.

The global search's guide is merged alike into about GLOBAL_SEGMENTS chords when they make at most COARSE_THRESHOLD
samples at the coarse step (a smooth contour of 100,000 points: 129 chords). Else it samples the path at
GLOBAL_MOMENTS moments, one drawn at random (with a fixed seed) in each of as many equal shares of its moving time: at
each, a piece of the path one time step of its own sampling long, at its feed, two samples each
(:func:`sampled_moments`). Under the paper's law the power at a sample depends on where the tool is and how it moves
there, so the guide's objective, times the time each piece stands for over its own (``coarse_scale``), is a stratified
quadrature of the path's (its holds left out), whatever the number of segments: a 65,000-segment raster, whose zigzags
no chord can merge, costs the global search 2 * GLOBAL_MOMENTS samples a placement, where merged chords keep its
zigzags (13,800 chords, 27,600 samples, for a CAMotics raster). Both guides have pieces of negligible length at the
path's farthest points (:func:`with_extremes`), to see the limits that bind there: a chord may pass inside a small
scribble's farthest point.
Under the realistic and optimal laws, which time runs rather than segments, the guides are the path itself,
the polish's sampled at that coarser step.

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
from placement.path.samples import MIN_PATH_STEPS
from placement.path.segments import Segment
from placement.path.toolpath import ToolPath

GUIDE_THRESHOLD = 20_000  # a path with more samples than this at its own step is searched on guides ...
COARSE_THRESHOLD = 1_024  # ... and so is one with more than this at the global search's coarse step
GLOBAL_MOMENTS = COARSE_THRESHOLD // 2  # moments of the global search's guide, two samples each: as many samples as
# a path searched without guides may have at the coarse step (128 moments were 3 % off on a 0.1 m/s CAMotics painting
# of 177,409 segments of 0.12 mm, 512 1.2 % and 1,024 0.3 %, on average over 24 placements; rankings kept)
EXTREME_SHARE = 1e-4  # each piece at an extreme is this share of the guide's mean segment long
EXTREME_SHORTFALL_M = 1e-6  # ... added where the guide falls short of the path's reach by more than this
CUBE_DIRECTIONS = np.array([d for d in np.ndindex(3, 3, 3) if d != (1, 1, 1)], dtype=float) - 1  # faces, edges, corners
GLOBAL_HORIZONTAL, POLISH_HORIZONTAL = 36, 360  # directions of the X_p Y_p plane the guides reach as far as the path

GLOBAL_SEED = 0  # the moments' seed: the same guide for every search seed
GLOBAL_SEGMENTS = 128  # chords of the global search's guide, about, when they are few enough (module docstring)
GLOBAL_DEVIATION = 1 / 40  # ... each straying from the points it skips by this share of its length, at most
POLISH_SEGMENTS = 1_000  # chords of the polish's guide, about
POLISH_DEVIATION = 1 / 100  # ... of the polish's guide, at most
POLISH_SAMPLES = 2_000  # the polish's guide's time step is at least the path's duration over this


def extreme_directions(horizontal: int) -> np.ndarray:
    """(26 + horizontal, 3) a cube's 26 directions and ``horizontal`` of the X_p Y_p plane, evenly spread."""
    angle = np.linspace(0.0, 2 * np.pi, horizontal, endpoint=False)
    return np.vstack([CUBE_DIRECTIONS, np.column_stack([np.cos(angle), np.sin(angle), np.zeros(horizontal)])])


@dataclass(frozen=True)
class SearchModels:
    """The models a search evaluates: the global search's, the polish's and, when they are guides, the exact one.

    Attributes:
        coarse_path, coarse: The global search's path and evaluator settings.
        polish_path, polish: The polish's path and evaluator settings.
        exact: The path's own sampling (the reported values'); the polish's when it is not a guide.
        guided: Whether the global search and the polish run on guides (module docstring).
        coarse_scale: The time the global search's guide stands for over its own duration (1 when it is the path):
            times the guide's objective, for one that adds up over time (energy), an estimate of the path's.
    """

    coarse_path: ToolPath
    coarse: EvaluatorSettings
    polish_path: ToolPath
    polish: EvaluatorSettings
    exact: EvaluatorSettings
    guided: bool = False
    coarse_scale: float = 1.0


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
    polish_m = path.length_m / POLISH_SEGMENTS
    chords = with_extremes(merge_lines(path, polish_m, polish_m * POLISH_DEVIATION), path,
                           extreme_directions(POLISH_HORIZONTAL))
    global_m = path.length_m / GLOBAL_SEGMENTS
    global_chords = with_extremes(merge_lines(path, global_m, global_m * GLOBAL_DEVIATION), path,
                                  extreme_directions(GLOBAL_HORIZONTAL))
    if len(global_chords.sample(coarse.time_step_s)) <= COARSE_THRESHOLD:
        return SearchModels(global_chords, coarse, chords, polish, fine, guided=True)
    piece_s = min(fine.time_step_s or path.time_step_s, _moving_s(path) / GLOBAL_MOMENTS / MIN_PATH_STEPS)
    moments = with_extremes(sampled_moments(path, GLOBAL_MOMENTS, piece_s, np.random.default_rng(GLOBAL_SEED)), path,
                            extreme_directions(GLOBAL_HORIZONTAL))
    # each piece two samples: its duration over the step is 1, give or take rounding, which ceil would make 2
    global_step = dataclasses.replace(coarse, time_step_s=piece_s * (1 + 1e-6))
    return SearchModels(moments, global_step, chords, polish, fine, guided=True,
                        coarse_scale=_moving_s(path) / (GLOBAL_MOMENTS * piece_s))


def guide_value(guide: Evaluator, placement: np.ndarray) -> float:
    """The objective of a (1, 6) placement on a guide's model (the exact one is the report's)."""
    return float(guide.evaluate(placement).value[0])


def sampled_moments(path: ToolPath, count: int, piece_s: float, rng: np.random.Generator) -> ToolPath:
    """The path at ``count`` moments of its moving time (module docstring), one drawn uniformly in each of ``count``
    equal shares of it: at each, the piece of its segment ``piece_s`` long in time centred there, at that segment's
    feed (its arc, helix and turn of the tool continued past the segment's end where the segment is shorter), a
    segment of its own. The holds are left out.

    Args:
        path: A path timed by the paper's law (each segment at its feed).
        count: Moments.
        piece_s: Each piece's duration (s).
        rng: Draws the moments.
    """
    segments = path.segments
    speeds = np.array([path.speed_m_s(segment) for segment in segments])
    lengths = np.array([segment.length_m for segment in segments])
    ends_s = np.cumsum(lengths / speeds)
    moments_s = (np.arange(count) + rng.uniform(size=count)) * ends_s[-1] / count
    index = np.minimum(np.searchsorted(ends_s, moments_s, side="right"), len(segments) - 1)
    along_m = lengths[index] - (ends_s[index] - moments_s) * speeds[index]  # where each moment is on its segment
    pieces = []
    for k, centre_m in zip(index.tolist(), along_m.tolist()):
        piece_m = speeds[k] * piece_s
        start_m = min(max(centre_m - piece_m / 2, 0.0), max(lengths[k] - piece_m, 0.0))
        pieces.append(_piece(segments[k], start_m, piece_m))
    return dataclasses.replace(path, name=f"{path.name} (moments)", segments=tuple(pieces), holds=())


def with_extremes(guide: ToolPath, path: ToolPath, directions: np.ndarray) -> ToolPath:
    """A guide with, after its segments, a piece EXTREME_SHARE of its mean segment long at each of the path's
    farthest segment ends along ``directions`` (:func:`extreme_directions`: a cube's 26, and those of the X_p Y_p
    plane, which a turn phi of the placement brings onto the workspace box's sides) that the guide's own segment ends
    fall short of by more than EXTREME_SHORTFALL_M: the search sees where the path reaches farthest (its workspace and
    joint limits bind there; chords within 0.4 mm of a 0.12 mm scribble's points missed them by 0.12 mm, and the
    polish ended 0.3 mm outside the box), at a cost to its objective of about EXTREME_SHARE over its number of
    segments each (386 pieces at most: 4e-5 of a 1,000-chord guide's)."""
    segments = path.segments
    ends = np.array([[s.start_m for s in segments], [s.end_m for s in segments]]).reshape(-1, 3)  # starts, then ends
    own = np.array([s.start_m for s in guide.segments] + [s.end_m for s in guide.segments])
    reach, guide_reach = ends @ directions.T, (own @ directions.T).max(axis=0)
    short = np.flatnonzero(reach.max(axis=0) > guide_reach + EXTREME_SHORTFALL_M)
    farthest = {divmod(int(k), len(segments)) for k in np.argmax(reach[:, short], axis=0)}
    length_m = EXTREME_SHARE * guide.length_m / len(guide.segments)
    pieces = [_piece(segments[k], 0.0 if at_end == 0 else segments[k].length_m - length_m, length_m)
              for at_end, k in sorted(farthest)]
    return dataclasses.replace(guide, segments=guide.segments + tuple(pieces))


def _moving_s(path: ToolPath) -> float:
    """The path's moving time under the paper's law (s): each segment's length at its feed."""
    return float(sum(segment.length_m / path.speed_m_s(segment) for segment in path.segments))


def _piece(segment: Segment, start_m: float, length_m: float) -> Segment:
    """The stretch of ``segment`` from ``start_m`` along it, ``length_m`` long, as a segment: its line, arc or helix
    and its tool's turn continued the same way where it reaches past the segment's end."""
    share, start_share = length_m / segment.length_m, start_m / segment.length_m
    ends = segment.point(np.array([start_m, start_m + length_m]), np.ones(2), np.zeros(2))[0]
    if segment.center_m is None:
        shape: dict[str, object] = {}
    else:
        shape = {"center_m": segment.center_m + segment.rise_m * start_share * segment.axes[:, 2],
                 "start_angle_rad": segment.start_angle_rad + segment.sweep_rad * start_share,
                 "sweep_rad": segment.sweep_rad * share, "rise_m": segment.rise_m * share}
    if segment.turn_rad is not None:
        rotation = segment.orientation(np.array([start_m]), np.zeros(1), np.zeros(1))[0][0]
        shape |= {"rotation": rotation, "turn_rad": segment.turn_rad * share}
    return dataclasses.replace(segment, start_m=ends[0], end_m=ends[1], **shape)  # type: ignore[arg-type]


def merge_lines(path: ToolPath, max_length_m: float, tolerance_m: float) -> ToolPath:
    """The path with stretches of consecutive lines and flat arcs merged into chords (module docstring): from each
    segment on, the longest chord at most ``max_length_m`` long, and at least ``tolerance_m``, whose skipped points
    are within ``tolerance_m`` of it, and the arcs between them too (found by doubling then halving the number of
    segments merged; an arc strays from its own chord by its sagitta, and that chord from the long one by no more
    than the farther of its ends, so the two added bound the arc's distance): a stretch that
    comes back near its start (a small hole's contour) is never one chord, which would have no direction (and a
    zero-length chord no samples); holds stay after the same points."""
    segments = path.segments
    count = len(segments)
    starts, ends = (np.array([getattr(s, name) for s in segments]) for name in ("start_m", "end_m"))
    along = np.concatenate([[0.0], np.cumsum([segment.length_m for segment in segments])])
    plain = np.array([_plain(segment) for segment in segments])
    sagitta = np.array([0.0 if s.center_m is None else s.radius_m * (1 - np.cos(s.sweep_rad / 2)) for s in segments])
    kinds = [(segment.rapid, segment.feed_ratio) for segment in segments]
    joins = np.zeros(count + 1, dtype=bool)  # joins[k]: segment k may extend a chord ending with segment k - 1
    joins[1:count] = (plain[1:] & plain[:-1] & (ends[:-1] == starts[1:]).all(axis=1)
                      & np.array([a == b for a, b in zip(kinds, kinds[1:])], dtype=bool))
    joins[[hold.after for hold in path.holds]] = False
    stops = np.flatnonzero(~joins)

    def close(first: int, last: int) -> bool:  # the chord over segments first..last stays near their points
        chord = ends[last] - starts[first]
        points = ends[first:last] - starts[first]
        share = np.clip(points @ chord / max(float(chord @ chord), 1e-300), 0.0, 1.0)
        stray = np.linalg.norm(points - share[:, None] * chord, axis=1).max(initial=0.0)
        return bool(stray + sagitta[first:last + 1].max() <= tolerance_m)

    merged, new_index, first = [], {0: 0}, 0
    while first < count:
        furthest = min(stops[np.searchsorted(stops, first, side="right")] - 1,
                       int(np.searchsorted(along, along[first] + max_length_m, side="right")) - 2)
        good, step = first, 1
        while good + step <= furthest and close(first, good + step):
            good, step = good + step, 2 * step
        bad = min(good + step, furthest + 1)
        while bad - good > 1:
            middle = (good + bad) // 2
            good, bad = (middle, bad) if close(first, middle) else (good, middle)
        while good > first and float(np.sum((ends[good] - starts[first])**2)) < tolerance_m**2:
            good -= 1  # back from a loop's end (a small hole's contour) to a chord that has a direction
        merged.append(segments[first] if good == first else _chord(segments[first], ends[good]))
        first = good + 1
        new_index[first] = len(merged)
    holds = tuple(dataclasses.replace(hold, after=new_index[hold.after]) for hold in path.holds)
    return dataclasses.replace(path, name=f"{path.name} (guide)", segments=tuple(merged), holds=holds)


def _plain(segment: Segment) -> bool:
    """Whether a segment may be merged: a line, or a plane arc of at most a half turn (its sagitta bounds how far it
    strays from its chord), without orientation or a stop at its end."""
    flat = segment.center_m is None or (segment.rise_m == 0.0 and abs(segment.sweep_rad) <= np.pi)
    return (flat and segment.rotation is None and segment.turn_rad is None
            and not segment.exact_stop and not segment.exact_path)


def _chord(segment: Segment, end_m: np.ndarray) -> Segment:
    """The line from ``segment``'s start to ``end_m``, with its feed and kind of move."""
    return dataclasses.replace(segment, end_m=end_m, center_m=None, radius_m=0.0, start_angle_rad=0.0, sweep_rad=0.0,
                               plane=None, rise_m=0.0)

"""Tolerance: the largest box around an optimum inside which every limit holds and the objective stays close.

A shop places a workpiece to within some error. Around an optimum x*, this finds half-widths h
(one per free variable, m or rad) such that every placement in the box x* ± h is feasible (reachable,
every margin ≥ 0) and its objective is at most ``within`` (a share, 0.01 for 1 %) of |f(x*)| worse
than f(x*), on the exact model (the :class:`Evaluator`, at the path's own sampling). How:

1. Per axis, a scan then a bisection: x* ± w·e_j at the widths w = r_j, r_j/2, ..., r_j/1024
   (:data:`SCAN_LEVELS`; r_j the distance to the search space's nearer bound on that axis), and h_j
   between the largest of them below the first that fails and that one (:data:`BISECTIONS` halvings).
   The scan keeps an axis along which the objective dips back (a rectangle turned by 90° costs about
   what it costs unturned) from reaching past the rise in between.
2. The box of these h is then scaled by the largest s ≤ 1 (bisection, :data:`SCALE_BISECTIONS`
   halvings) at which the corners of x* ± s·h are acceptable (all 2^n up to four free variables, a
   fixed draw of :data:`CORNERS_IN_SEARCH` of them beyond): objectives grow along several axes at
   once, so a box of the per-axis widths is usually too wide at its corners.
3. The box x* ± s·h is checked at the corners of step 2 and at :data:`INTERIOR_SAMPLES` points
   spread through it (a scrambled Sobol sequence, fixed seed); if any fails, s shrinks by :data:`SHRINK` and the
   check repeats (at most :data:`MAX_SHRINKS` times; then the box is the optimum alone).

Residual risk: an unacceptable pocket inside the box missed by the corners, the axis points and the
samples (a limit that only bites in a small region, such as a collision corner), and anything between
the path's samples (the report's 4x denser re-check is of the optimum only). Cost: about
2n·(SCAN_LEVELS + BISECTIONS) + min(2^n, 16)·(SCALE_BISECTIONS + 2) + INTERIOR_SAMPLES
evaluations: 312 for the Orthoglide's four free variables, about 380 for six (plus 80 for each shrink
of step 3). Beyond four free variables, only 16 of the 2^n corners are tried: a larger residual risk.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.stats import qmc

from placement.evaluation.evaluator import Evaluator
from placement.search.space import PlacementSpace

SCAN_LEVELS = 11  # widths scanned per axis: its reach times 1, 1/2, ..., 1/1024
BISECTIONS = 6  # halvings between the last width scanned that holds and the first that fails
SCALE_BISECTIONS = 5  # halvings of the scale that brings the corners in
CORNERS_IN_SEARCH = 16  # corners tried at each of those halvings (all of them up to four free variables)
INTERIOR_SAMPLES = 64  # points of the final check spread inside the box
SHRINK = 0.8  # the scale's factor when the final check fails
MAX_SHRINKS = 3


@dataclass(frozen=True)
class ToleranceBox:
    """The box around an optimum (module docstring).

    Attributes:
        free: The free variables' names, in the search space's order.
        half_width: (n_free,) half-widths (m for x, y, z; rad for angles): the box is the optimum ± these.
        within: The share of the objective allowed (0.01: 1 %).
        evaluations: Placements evaluated to find and check it.
        corners_checked: Corners of the box in its final check (all 2^n up to four free variables).
        inside_checked: Points inside the box in its final check.
        guided: Whether the box was found and checked on a long path's guide (:mod:`placement.search.coarse_guide`)
            instead of the exact model.
    """

    free: tuple[str, ...]
    half_width: np.ndarray
    within: float
    evaluations: int
    corners_checked: int
    inside_checked: int
    guided: bool = False


def tolerance_box(evaluator: Evaluator, space: PlacementSpace, placement: np.ndarray, lower_is_better: bool,
                  within: float = 0.01) -> ToleranceBox:
    """The largest box (± per free variable) around an optimum where every limit holds and the objective stays within
    ``within`` of the optimum's (module docstring).

    Args:
        evaluator: The exact model of the path and robot the optimum was found with.
        space: The search space (its free variables and bounds).
        placement: (6,) the optimum (m, rad).
        lower_is_better: Whether the optimum is a minimum of the evaluator's objective (else a maximum).
        within: Share of |objective| the objective may worsen by (> 0).
    """
    placement = np.asarray(placement, dtype=float)
    centre = placement[space.indices]
    count = [0]
    reference = float(evaluator.evaluate(placement[None]).value[0])
    direction = 1.0 if lower_is_better else -1.0

    def acceptable(points: np.ndarray) -> np.ndarray:
        """(K,) whether each of (K, n_free) points is feasible with its objective within the share."""
        count[0] += len(points)
        evaluation = evaluator.evaluate(space.full(points))
        worse = direction * (evaluation.value - reference)
        return evaluation.feasible & (worse <= within * abs(reference))

    n = len(centre)
    reach = np.where(space.period > 0, space.period / 2,  # a periodic angle has no edge: the objective wraps it
                     np.minimum(centre - space.lower, space.upper - centre))
    axes = np.eye(n)

    def both_sides(widths: np.ndarray) -> np.ndarray:
        """(m, n) whether x* ± widths[i, j]·e_j are both acceptable, for (m, n) widths."""
        steps = widths[..., None] * axes  # (m, n, n)
        ok = acceptable(np.concatenate([centre + steps, centre - steps]).reshape(-1, n)).reshape(2, *widths.shape)
        return ok[0] & ok[1]

    # The scan: the bracket's widths from the smallest up; an axis's width stops below its first failure
    levels = reach * 2.0 ** -np.arange(SCAN_LEVELS - 1, -1, -1)[:, None]  # (SCAN_LEVELS, n), ascending
    fails = ~both_sides(levels)
    first = np.where(fails.any(axis=0), fails.argmax(axis=0), SCAN_LEVELS)
    low = np.where(first > 0, levels[np.maximum(first - 1, 0), np.arange(n)], 0.0)
    high = np.where(first < SCAN_LEVELS, levels[np.minimum(first, SCAN_LEVELS - 1), np.arange(n)], reach)
    bracketed = first < SCAN_LEVELS
    for _ in range(BISECTIONS):
        middle = (low + high) / 2
        ok = both_sides(middle[None])[0] | ~bracketed
        low, high = np.where(ok & bracketed, middle, low), np.where(ok, high, middle)
    corners = np.array(np.meshgrid(*[[-1.0, 1.0]] * n, indexing="ij")).reshape(n, -1).T
    inside = qmc.Sobol(n, scramble=True, seed=0).random(INTERIOR_SAMPLES) * 2 - 1
    tried = corners if len(corners) <= CORNERS_IN_SEARCH else corners[
        np.random.default_rng(0).choice(len(corners), CORNERS_IN_SEARCH, replace=False)]
    if acceptable(centre + tried * low).all():
        scale = 1.0
    else:
        lo, hi = 0.0, 1.0
        for _ in range(SCALE_BISECTIONS):
            share = (lo + hi) / 2
            lo, hi = (share, hi) if acceptable(centre + tried * low * share).all() else (lo, share)
        scale = lo
    for _ in range(MAX_SHRINKS):
        if acceptable(centre + np.concatenate([tried, inside]) * low * scale).all():
            break
        scale *= SHRINK
    else:
        scale = 0.0
    return ToleranceBox(space.free, low * scale, within, count[0], len(tried), INTERIOR_SAMPLES)

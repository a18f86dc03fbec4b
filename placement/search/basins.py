"""Basins: the distinct local optima of a search, not a single point.

A global search's final population has usually gathered in one basin; which one can depend on the seed
(the paper's groove has two, the rectangle turned by about 0° and by about 90°, 0.02 % apart). So the
polish starts from the best point of each region the global search has *visited*, not only from its
final population: among every feasible placement it evaluated, a start is one that no better feasible
placement lies within START_RADIUS of (a share of the box along each free variable, across a periodic
variable's wrap too). The best :data:`placement.search.local.POLISH_STARTS` of those are polished (a start that
breaks a limit on the polish's finer sampling too: the polish brings it back); the polished optima closer than
:data:`placement.search.local.BASIN_RADIUS` to a better one are the same basin, and the others are the
search's basins, best first.

A redundant arm's profiles add a start of their own. The global search's population gathers on one branch of the
arm's self-motion (the Panda's elbow, joint 3 near +76° or near -75° on the circle; the UR5 on its track following
the seam one way or the other), whichever its seed favours, and the other branch, the better one on some paths, is
rarely visited and never polished. So the best of the polished starts (polished on the global search's model, see
:func:`converged_starts`) is also flipped onto the other branch
(:func:`flipped_branches`): its redundant joints' knots negated, and its mirror image through the base's x-z plane
(y, phi and psi negated too, the knots with them), the same placement on the other branch for an arm whose chain is
nearly symmetric about that plane (a serial arm's usually is, the offsets aside). These are starts too, and the
branches are compared polished, as every basin is.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from placement.placing.profiles import SPIN
from placement.placing.transform import VARIABLES
from placement.search.local import BASIN_RADIUS, POLISH_STARTS, Problem, best_feasible, polish_across, signed_objective
from placement.search.space import PlacementSpace

START_RADIUS = 0.1  # a visited point is a start when no better feasible one lies within this share of the box
START_POOL = 2_000  # best feasible visited points among which the starts are found (the distance matrix's side)
MIRRORED = ("y", "phi", "psi")  # negated by the reflection through the base's x-z plane (rotations about x and z turn
# the other way, those about y do not), with every redundant joint's knots
COARSE_POLISHES = POLISH_STARTS + 3  # a redundant arm's polishes on the global search's sampling, at most: POLISH_STARTS + 1
# regions' best points and two flips of its branch (flipped_branches)
RUNNER_UP_SHARE = 0.05  # basins within this share of the best's objective are reported beside it


@dataclass(frozen=True)
class Basin:
    """A distinct local optimum of one direction's search, as the report prints it.

    Attributes:
        placement: (n,) the placement as printed (m, rad): the six variables, then a redundant robot's (spin, knots).
        value: The objective there, at the path's own sampling.
        recheck_value: The objective there on the 4x denser sampling (NaN when it fails that re-check).
        holds: Whether every limit holds there, once printed, on the path's samples and the denser ones.
    """

    placement: np.ndarray
    value: float
    recheck_value: float
    holds: bool


def scaled_distance(a: np.ndarray, b: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """The largest distance along any free variable between points ``a`` (..., n) and ``b`` (..., n), as a share of
    that variable's range (the shorter way round a periodic one)."""
    scale = np.where(space.upper > space.lower, space.upper - space.lower, 1.0)
    return np.abs(space.difference(a, b) / scale).max(axis=-1)


def basin_starts(points: np.ndarray, signed: np.ndarray, space: PlacementSpace, count: int) -> np.ndarray:
    """The best ``count`` visited points that no better one lies within START_RADIUS of (module docstring).

    Args:
        points: (K, n_free) feasible points the global search evaluated.
        signed: (K,) their objective, signed so that lower is better.
        space: The search space.
        count: Starts wanted, at most.

    Returns:
        (m, n_free) the starts, best first (m ≤ count).
    """
    order = np.argsort(signed, kind="stable")[:START_POOL]
    pool = points[order]
    starts: list[int] = []
    for k in range(len(pool)):  # best first: a point is a start unless a better one (earlier) is near
        if k == 0 or scaled_distance(pool[k], pool[:k], space).min() > START_RADIUS:
            starts.append(k)
            if len(starts) == count:
                break
    return pool[starts]


def flipped_branches(point: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """A start on the other branch of a redundant arm's self-motion (module docstring), two ways, within the box: every
    free knot of a redundant joint's profile negated (a revolute joint turned the other way, a track's carriage moved
    the other way), the placement kept; and the whole arm's mirror image through the base's x-z plane, its free y,
    phi and psi negated too. None when no knot is free (a robot without redundancy has no other branch to reach
    this way).

    Args:
        point: (n_free,) free values of a start.
        space: The search space.

    Returns:
        (m, n_free) the flipped starts (m = 0 without a free knot), in the space's range (a periodic angle wrapped,
        the others clipped to their bounds).
    """
    knots = _free_knots(space)
    if not knots.any():
        return np.zeros((0, len(space.free)))
    flips = np.array([knots, knots | np.isin(space.free, MIRRORED)])
    images = space.wrap(np.where(flips, -np.asarray(point, dtype=float), point))
    return np.where(space.period > 0, images, np.clip(images, space.lower, space.upper))


def has_branches(space: PlacementSpace) -> bool:
    """Whether a knot of a redundant joint's profile is free: the search then has branches to flip
    (:func:`flipped_branches`)."""
    return bool(_free_knots(space).any())


def _free_knots(space: PlacementSpace) -> np.ndarray:
    """(n_free,) bool: which free variables are knots of a redundant joint's profile."""
    return np.array([name not in VARIABLES and name != SPIN for name in space.free], dtype=bool)


def converged_starts(problem: Problem, space: PlacementSpace) -> list[np.ndarray]:
    """The polish's starts: the best point of each of a few distinct regions the global search visited
    (:func:`basin_starts`). For a redundant arm, the branches of its self-motion are compared converged:
    from those points, and from the best of where they end flipped onto the other branch, polishes on the global
    search's model (its margins read as values: with a cell, a collision's beyond the clearance may be a lower
    bound, which only shapes a start), and the POLISH_STARTS best distinct ends of those, best first."""
    if not has_branches(space):
        return list(basin_starts(*problem.feasible_seen(), space, POLISH_STARTS))
    converged = [polish_across(problem, start, space)
                 for start in basin_starts(*problem.feasible_seen(), space, COARSE_POLISHES - 2)]
    best = best_feasible(problem, converged)
    flipped = flipped_branches(converged[0] if best is None else best, space)
    converged += [polish_across(problem, start, space)  # not from a start the arm does not reach: the polish stays there
                  for start, value in zip(flipped, problem.lookup(flipped)[0]) if np.isfinite(value)]
    values = signed_objective(problem, np.array(converged))
    return [converged[k] for k in distinct(converged, list(values), space, BASIN_RADIUS)[:POLISH_STARTS]]


def distinct(optima: list[np.ndarray], signed: list[float], space: PlacementSpace,
             radius: float) -> list[int]:
    """Indices of the optima that are no closer than ``radius`` (share of the box) to a better one, best first."""
    kept: list[int] = []
    for k in np.argsort(signed, kind="stable"):
        if all(scaled_distance(optima[k], optima[j], space) > radius for j in kept):
            kept.append(int(k))
    return kept


def unresolved(best_value: float, best_recheck: float, basin: Basin) -> bool:
    """Whether a runner-up basin is within the 4x re-check's resolution of the best: the two objectives differ by
    less than either one's change on the denser sampling (the sampling, not the placement, may then decide)."""
    resolution = max(abs(best_recheck - best_value), abs(basin.recheck_value - basin.value))
    return bool(not np.isfinite(resolution) or abs(basin.value - best_value) <= resolution)

"""The last step of the polish: across the objective's kinks, by gradient sampling.

The energy is smooth in the placement only piece by piece: each drive's power is clipped at zero interval by
interval (the ``clip`` regeneration policy, the default; ``absolute`` too), and where a drive barely moves along a
side of the path, its power crosses zero on many intervals at once as the placement changes. The best placement
then often lies where several of these kinks meet, at the bottom of a narrow crease: on the paper's groove the
energy rises on either side of its optimum along every variable, by slopes ten and more times larger than its fall
along the crease. SLSQP models the objective as smooth (a quasi-Newton Hessian, a backtracking line search): on a
kink its step is no descent, it backtracks until the objective changes by less than its tolerance, and reports
convergence wherever on the crease it arrived (seed 8 of the groove 2.3e-6 above the crease's lowest point, seeds
0 to 9 spread over 2.9e-6).

Gradient sampling (Burke, Lewis and Overton, SIAM J. Optim. 15, 2005) takes it from there: the gradients at the
point and at n + 1 points around it (n free variables), within a radius, span the kinks near it; the shortest vector of their
convex hull is the steepest descent of the objective smoothed over that radius (along the crease, on one). A line
search along it moves while it gains; when it gains nothing, the radius shrinks, down to RADIUS_END (and it grows
while the longest step gains most). The points are drawn afresh each time, each with its mirror image through the
point (a crease through the point has samples on both sides), by a generator of fixed seed: the same for every
seed of the search. The variables are the polish's (unit curvature), and a point that breaks a limit or leaves the
box is no step (the polish's SLSQP brings a point onto a limit; this step keeps it feasible). From a point on a limit
(the pocket's best) it does not start: its steps along the limit would break it and be refused (SLSQP, which follows
a limit, has polished it), and it would only spend evaluations. Nor from a point on a bound of the box (the UR5's
best, on its tilt's bound): there too its steps leave the box and are refused (on the UR5's seeds 0-2, 276
evaluations each gained nothing); the search of the printed lattice that follows (:mod:`placement.search.lattice`)
goes on along the bound.
"""

from __future__ import annotations

import numpy as np
from scipy.optimize import nnls

from placement.search.local import GRADIENT_STEP, Problem, unit_curvature
from placement.search.space import PlacementSpace

RADIUS_START = 1e-2  # the sampling radius, at first, in the polish's variables (unit curvature)
RADIUS_END = 1e-4  # ... and the radius below which the search stops (the search of the printed lattice goes on from
# there, placement.search.lattice; with 1e-5 the groove's seeds 0-9 ended on the same two printed points, at 5 % more evaluations)
RADIUS_SHRINK = 10.0  # the radius is divided by this when a line search gains nothing
RADIUS_GROWTH = 4.0  # ... and multiplied by this when its longest step gains most
RADIUS_LARGEST = 1.0  # ... up to this
LINE_STEPS = 2.0 ** np.arange(5, -5, -1)  # a line search's trial steps, in radii, tried in one batch
SUFFICIENT_DECREASE = 1e-4  # a step gains at least this share of its length times the descent's slope
ITERATIONS = 40  # line searches, at most
BINDING = 1e-6  # a point where a limit's margin is less than this lies on the limit (the polish ends on one within round-off)
BOUND_SHARE = 1e-9  # a point within this share of a variable's range of its bound lies on the bound
SAMPLING_SEED = 38  # the sampled points' generator's: fixed, so that every seed of the search samples the same points


def across_kinks(problem: Problem, x: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """Gradient sampling from a feasible ``x`` (free values; module docstring): a feasible point at least as good (``x``
    itself where a limit binds there or it lies on a bound).

    Args:
        problem: The polish's problem (its points are evaluated once each).
        x: (n_free,) the point, keeping every limit.
        space: The search space (its bounds; a periodic variable has none).

    Returns:
        (n_free,) the point reached, in the space's range.
    """
    bounded = space.period == 0
    on_bound = np.isclose(x[bounded], space.lower[bounded], rtol=0.0, atol=BOUND_SHARE * _range(space)[bounded]) | (
        np.isclose(x[bounded], space.upper[bounded], rtol=0.0, atol=BOUND_SHARE * _range(space)[bounded]))
    if problem.lookup(x)[1].min(initial=np.inf) < BINDING or on_bound.any():
        return x
    n = len(x)
    box = _range(space)
    scale = box / unit_curvature(problem, x, box)  # a placement is u * scale
    step = GRADIENT_STEP * box / scale  # the forward differences' step in u: GRADIENT_STEP of each variable's range
    pairs = (n + 2) // 2  # points sampled around the point, each with its mirror image: n + 1 at least, as the method needs
    draw = np.random.default_rng(SAMPLING_SEED)  # the same points for every seed of the search
    u, value, radius = x / scale, _signed(problem, space, x[None])[0], RADIUS_START
    for _ in range(ITERATIONS):
        if radius < RADIUS_END:
            break
        offsets = draw.uniform(-1.0, 1.0, (pairs, n))  # fresh points each time, in the cube of the radius
        descent = _shortest_gradient(problem, u, radius * np.vstack([offsets, -offsets]), step, scale)
        slope = float(np.linalg.norm(descent)) if descent is not None else 0.0
        if descent is None or slope == 0.0:
            radius /= RADIUS_SHRINK
            continue
        trials = u - (radius * LINE_STEPS / slope)[:, None] * descent
        values = _signed(problem, space, trials * scale)
        gains = values < value - SUFFICIENT_DECREASE * radius * LINE_STEPS * slope
        if not gains.any():
            radius /= RADIUS_SHRINK
            continue
        best = int(np.argmin(np.where(gains, values, np.inf)))
        u, value = trials[best], values[best]
        if best == 0:  # the longest step gained most: the crease goes on further than the radius sees
            radius = min(radius * RADIUS_GROWTH, RADIUS_LARGEST)
    return space.wrap(u * scale)


def _shortest_gradient(problem: Problem, u: np.ndarray, offsets: np.ndarray, step: np.ndarray,
                       scale: np.ndarray) -> np.ndarray | None:
    """The shortest vector of the convex hull of the signed objective's gradients (forward differences, one batch)
    at ``u + offsets``, in u; None where one of them is not finite. Not at ``u`` itself: a point where a line search
    stopped often lies on a kink, where forward differences mix the slopes of its sides."""
    n = len(u)
    centres = u + offsets
    points = (centres[:, None, :] + np.vstack([np.zeros(n), np.diag(step)])[None]).reshape(-1, n)
    values = problem.sign * problem.lookup(points * scale)[0].reshape(len(centres), n + 1)
    gradients = (values[:, 1:] - values[:, :1]) / step
    if not np.isfinite(gradients).all():
        return None
    return _shortest_in_hull(gradients)


def _shortest_in_hull(vectors: np.ndarray) -> np.ndarray:
    """The shortest vector of the convex hull of (m, n) ``vectors``: min |Σ λ_k v_k| over λ ≥ 0, Σ λ_k = 1 (non-negative
    least squares, the sum's condition as a heavily weighted row)."""
    weight = 1e3 * max(1.0, float(np.abs(vectors).max()))
    matrix = np.vstack([vectors.T, np.full((1, len(vectors)), weight)])
    shares = nnls(matrix, np.concatenate([np.zeros(vectors.shape[1]), [weight]]))[0]
    return (shares / shares.sum()) @ vectors


def _signed(problem: Problem, space: PlacementSpace, points: np.ndarray) -> np.ndarray:
    """The signed objective of (K, n_free) points (lower is better), +inf where one breaks a limit, leaves the box (a
    periodic variable has no edge) or has no finite objective."""
    values, margins = problem.lookup(points)
    bounded = space.period == 0
    inside = ((points[:, bounded] >= space.lower[bounded]) & (points[:, bounded] <= space.upper[bounded])).all(axis=1)
    usable = inside & (margins >= 0).all(axis=1) & np.isfinite(values)
    return np.where(usable, problem.sign * values, np.inf)


def _range(space: PlacementSpace) -> np.ndarray:
    """Each free variable's range (its period for a periodic one; 1 where the range is empty)."""
    return np.where(space.period > 0, space.period, np.where(space.upper > space.lower, space.upper - space.lower, 1.0))

"""The search's problem over the free variables, and its local polish.

:class:`Problem` gives the objective and the limits' margins of points of the free variables,
each point evaluated once. The polish (SLSQP, forward-difference gradients in one batch) starts
from the global search's best candidates of a few distinct basins; it ends on the feasible side
of the limits it reaches, and goes on across a periodic variable's edge where it ends on one.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import OptimizeResult, minimize

from placement.evaluation.evaluator import Evaluator
from placement.evaluation.results import Evaluation
from placement.search.space import PlacementSpace

POLISH_STARTS = 3  # distinct candidates polished locally
INWARD_SHARES = np.array([0.0, 1e-6, 1e-5, 1e-4, 1e-3])  # a repair's pulls towards the box centre, tried in order
GRADIENT_STEP = 1e-7  # forward-difference step of the polish, as a share of each variable's range
BASIN_RADIUS = 0.02  # candidates within this share of the box of one another share a basin
EDGE_SHARE = 1e-6  # a polish ending within this share of a period of a periodic variable's edge goes on across it
STALL_ITERATIONS = 10  # the polish stops when this many iterations improve the objective by at most
STALL_TOLERANCE = 1e-9  # this share of it (SLSQP otherwise dithers on a limit until its iteration cap)


class Problem:
    """Objective and constraints over the free variables, sharing one evaluation per point.

    ``sign * value`` is minimised: +1 searches the best placement of a lower-is-better objective.
    """

    def __init__(self, evaluator: Evaluator, space: PlacementSpace, sign: float) -> None:
        self.evaluator, self.space, self.sign = evaluator, space, sign
        self.required = evaluator.settings.margin  # margins are kept less this: >= 0 is feasible
        self._cache: dict[bytes, tuple[float, np.ndarray]] = {}
        # (unreachable, violation, x, margins) of the least infeasible point seen, a reachable one before any other:
        # an unreachable point's margins are all UNREACHABLE_MARGIN, a small violation beside a motor overloaded 50 times
        self.least_infeasible: tuple[bool, float, np.ndarray, np.ndarray] | None = None
        self.best_feasible: float | None = None  # signed value of the best feasible point seen

    def lookup(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        points = self.space.wrap(np.atleast_2d(points))  # a periodic variable is evaluated in its range
        todo = [p for p in points if p.tobytes() not in self._cache]
        if todo:
            evaluation = self.evaluator.evaluate(self.space.full(np.array(todo)))
            self._remember(np.array(todo), evaluation)
        values = [self._cache[p.tobytes()] for p in points]
        return np.array([v[0] for v in values]), np.array([v[1] for v in values])

    def _remember(self, points: np.ndarray, evaluation: Evaluation) -> None:
        if len(self._cache) > 200_000:
            self._cache.clear()
        margins_less_required = evaluation.margins - self.required
        violations = np.clip(-margins_less_required, 0.0, None).sum(axis=1)
        for point, value, margins, reachable, violation in zip(points, evaluation.value.tolist(), margins_less_required,
                                                               evaluation.reachable.tolist(), violations.tolist(),
                                                               strict=True):
            self._cache[point.tobytes()] = (value, margins)
            rank = (not reachable, violation)
            if violation > 0 and (self.least_infeasible is None or rank < self.least_infeasible[:2]):
                self.least_infeasible = (not reachable, violation, point, margins)
            elif violation == 0 and math.isfinite(value):
                signed = self.sign * value
                self.best_feasible = signed if self.best_feasible is None else min(self.best_feasible, signed)

    def objective(self, points: np.ndarray) -> np.ndarray:
        """Signed objective of (n_free, S) or (n_free,) points (scipy's layouts)."""
        value, _ = self.lookup(np.asarray(points).T)
        return np.where(np.isfinite(value), self.sign * value, 1e30)

    def margins(self, points: np.ndarray) -> np.ndarray:
        """Tightest margin of every limit less the required one, (n_limits, S) or (n_limits,)."""
        _, margins = self.lookup(np.asarray(points).T)
        return margins.T if np.ndim(points) > 1 else margins[0]


def polish_across(problem: Problem, start: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """The polish from ``start`` in the space's box; if it ends on a periodic variable's edge, on again from there
    in a box that leaves that variable free for half a period either way (the objective wraps it: no bound cuts
    through a basin at the range's edge). The result lies in the space's range."""
    x = _polish(problem, start, list(zip(space.lower, space.upper)))
    edge = EDGE_SHARE * np.where(space.period > 0, space.period, np.inf)
    if not ((np.abs(x - space.lower) <= edge) | (np.abs(x - space.upper) <= edge)).any():
        return x
    half = space.period / 2
    cyclic = half > 0
    box = list(zip(np.where(cyclic, x - half, space.lower), np.where(cyclic, x + half, space.upper)))
    return space.wrap(_polish(problem, x, box))


def inward_until_feasible(problem: Problem, x: np.ndarray, space: PlacementSpace) -> np.ndarray | None:
    """``x``, or ``x`` pulled towards the centre of the search box by the least of INWARD_SHARES of the way that
    keeps every limit (None if none does): a repair by SLSQP often ends a hair outside a limit on the box's edge."""
    centre = (space.lower + space.upper) / 2
    candidates = x + INWARD_SHARES[:, None] * (centre - x)
    feasible = (problem.lookup(candidates)[1] >= 0).all(axis=1)
    return candidates[np.argmax(feasible)] if feasible.any() else None


def distinct_basins(candidates: np.ndarray, space: PlacementSpace) -> list[np.ndarray]:
    """The best candidates of POLISH_STARTS distinct basins, best first: skipping any within BASIN_RADIUS of the box
    of one already kept (across a periodic variable's wrap too)."""
    kept: list[np.ndarray] = []
    for candidate in candidates:
        if not _near(candidate, kept, space):
            kept.append(candidate)
        if len(kept) == POLISH_STARTS:
            break
    return kept


def _near(point: np.ndarray, others: list[np.ndarray], space: PlacementSpace) -> bool:
    """Whether ``point`` lies within BASIN_RADIUS of the box of one of ``others`` (across a periodic variable's wrap too)."""
    scale = np.where(space.upper > space.lower, space.upper - space.lower, 1.0)
    return any(np.abs(space.difference(point, other) / scale).max() <= BASIN_RADIUS for other in others)


def _polish(problem: Problem, start: np.ndarray, bounds: list) -> np.ndarray:
    """SLSQP from ``start``; from a feasible start, returns a feasible point at least as good."""
    scale = np.array([hi - lo if hi > lo else 1.0 for lo, hi in bounds])  # search in box units

    def differences(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Forward-difference gradient of the objective and Jacobian of the margins, in one batch."""
        points = (u + np.vstack([np.zeros(len(u)), GRADIENT_STEP * np.eye(len(u))])) * scale
        value, margins = problem.lookup(points)
        return (problem.sign * (value[1:] - value[0]) / GRADIENT_STEP,
                (margins[1:] - margins[0]).T / GRADIENT_STEP)

    result = minimize(lambda u: problem.objective(u * scale)[0], start / scale, method="SLSQP",
                      jac=lambda u: differences(u)[0], callback=_stall_detector(),
                      bounds=[(lo / s, hi / s) for (lo, hi), s in zip(bounds, scale)],
                      constraints=[{"type": "ineq", "fun": lambda u: problem.margins(u * scale),
                                    "jac": lambda u: differences(u)[1]}],
                      options={"maxiter": 100, "ftol": 1e-10})
    polished = np.clip(result.x * scale, [b[0] for b in bounds], [b[1] for b in bounds])
    if not (problem.lookup(start)[1] >= 0).all():  # an infeasible start: take what SLSQP reached
        return polished
    polished = _feasible_towards(problem, start, polished)
    value, _ = problem.lookup(polished)
    start_value, _ = problem.lookup(start)
    return polished if problem.sign * value[0] <= problem.sign * start_value[0] else start


def _stall_detector() -> Callable[..., None]:
    """An SLSQP callback that stops the polish once STALL_ITERATIONS iterations gained at most STALL_TOLERANCE."""
    history: list[float] = []

    def callback(intermediate_result: OptimizeResult) -> None:  # scipy passes the result by this name
        history.append(float(intermediate_result.fun))
        if len(history) > STALL_ITERATIONS:
            before = history[-STALL_ITERATIONS - 1]
            if before - min(history[-STALL_ITERATIONS:]) <= STALL_TOLERANCE * abs(before):
                raise StopIteration

    return callback


def _feasible_towards(problem: Problem, feasible: np.ndarray, target: np.ndarray) -> np.ndarray:
    """The point nearest ``target`` on the segment from ``feasible`` that keeps every limit.

    The local search ends on the limits, often a hair outside them; bisection brings it back.
    """
    if (problem.lookup(target)[1] >= 0).all():
        return target
    inside, outside = 0.0, 1.0
    for _ in range(40):
        middle = (inside + outside) / 2
        if (problem.lookup(feasible + middle * (target - feasible))[1] >= 0).all():
            inside = middle
        else:
            outside = middle
    return feasible + inside * (target - feasible)

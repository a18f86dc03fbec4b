"""The search's problem over the free variables, and its local polish.

:class:`Problem` gives the objective and the limits' margins of points of the free variables,
each point evaluated once. The polish (SLSQP, forward-difference gradients in one batch) starts
from the best points of a few distinct regions the global search visited (:mod:`placement.search.basins`);
it ends on the feasible side of the limits it reaches, and goes on across a periodic variable's edge where it
ends on one.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np
from scipy.optimize import OptimizeResult, minimize

from placement.evaluation.evaluator import Evaluator
from placement.evaluation.results import Evaluation
from placement.search.space import PlacementSpace

POLISH_STARTS = 3  # starts of distinct basins polished locally (placement.search.basins)
INWARD_SHARES = np.array([0.0, 1e-6, 1e-5, 1e-4, 1e-3])  # a repair's pulls towards the box centre, tried in order
GRADIENT_STEP = 1e-7  # forward-difference step of the polish, as a share of each variable's range
CURVATURE_STEP = 1e-3  # central-difference step of the polish's curvatures, as a share of each variable's range
CURVATURE_ROOT_RANGE = (1e-3, 1e6)  # the square roots of those curvatures are kept within this range
BASIN_RADIUS = 0.02  # candidates within this share of the box of one another share a basin
EDGE_SHARE = 1e-6  # a polish ending within this share of a range of its trust box's edge goes on from there
TRUST_SHARE = 0.1  # the polish's trust box reaches this share of each variable's range either way
TRUST_ROUNDS = 5  # trust boxes, at most, one after the other
STALL_ITERATIONS = 4  # the polish stops when this many iterations improve the objective by at most
STALL_TOLERANCE = 1e-9  # this share of it (SLSQP otherwise dithers on a limit or a kink until its iteration cap; on a
# kink, placement.search.kinks goes on)


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

    def feasible_seen(self) -> tuple[np.ndarray, np.ndarray]:
        """(K, n_free) the feasible points evaluated so far (every limit kept, finite objective) and (K,) their signed
        objective (lower is better)."""
        n = len(self.space.free)
        seen = [(key, value) for key, (value, margins) in self._cache.items()
                if math.isfinite(value) and (margins >= 0).all()]
        if not seen:
            return np.zeros((0, n)), np.zeros(0)
        points = np.array([np.frombuffer(key, dtype=float) for key, _ in seen]).reshape(-1, n)
        return points, self.sign * np.array([value for _, value in seen])

    def objective(self, points: np.ndarray) -> np.ndarray:
        """Signed objective of (n_free, S) or (n_free,) points (scipy's layouts)."""
        value, _ = self.lookup(np.asarray(points).T)
        return np.where(np.isfinite(value), self.sign * value, 1e30)

    def margins(self, points: np.ndarray) -> np.ndarray:
        """Tightest margin of every limit less the required one, (n_limits, S) or (n_limits,)."""
        _, margins = self.lookup(np.asarray(points).T)
        return margins.T if np.ndim(points) > 1 else margins[0]


def polish_across(problem: Problem, start: np.ndarray, space: PlacementSpace) -> np.ndarray:
    """The polish from ``start`` in a trust box of TRUST_SHARE of the space's range either way of it (within the
    space's bounds, but across a periodic variable's edge: the objective wraps it, and no bound cuts through a basin
    there, where the paper's groove has one), again from where it ends while that is on the trust box's edge, at
    most TRUST_ROUNDS times: SLSQP's first steps, before it knows the curvature, otherwise leave the basin. The
    result lies in the space's range."""
    cyclic = space.period > 0
    reach = TRUST_SHARE * np.where(cyclic, space.period, space.upper - space.lower)
    edge = EDGE_SHARE * np.where(cyclic, space.period, space.upper - space.lower)
    x = np.asarray(start, dtype=float)
    for _ in range(TRUST_ROUNDS):
        low = np.where(cyclic, x - reach, np.maximum(space.lower, x - reach))
        high = np.where(cyclic, x + reach, np.minimum(space.upper, x + reach))
        polished = _polish(problem, x, list(zip(low, high)))
        on_trust_edge = ((np.abs(polished - low) <= edge) & (cyclic | (low > space.lower))) | (
            (np.abs(polished - high) <= edge) & (cyclic | (high < space.upper)))
        x = space.wrap(polished)
        if not on_trust_edge.any():
            break
    return x


def inward_until_feasible(problem: Problem, x: np.ndarray, space: PlacementSpace) -> np.ndarray | None:
    """``x``, or ``x`` pulled towards the centre of the search box by the least of INWARD_SHARES of the way that
    keeps every limit (None if none does): a repair by SLSQP often ends a hair outside a limit on the box's edge."""
    centre = (space.lower + space.upper) / 2
    candidates = x + INWARD_SHARES[:, None] * (centre - x)
    feasible = (problem.lookup(candidates)[1] >= 0).all(axis=1)
    return candidates[np.argmax(feasible)] if feasible.any() else None


def _polish(problem: Problem, start: np.ndarray, bounds: list) -> np.ndarray:
    """SLSQP from ``start``, in variables of unit curvature (:func:`unit_curvature`); from a feasible start, returns a
    feasible point at least as good."""
    box = np.array([hi - lo if hi > lo else 1.0 for lo, hi in bounds])
    scale = box / unit_curvature(problem, start, box)  # a placement is u * scale
    step = GRADIENT_STEP * box / scale  # in u: GRADIENT_STEP of each variable's range

    def differences(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Forward-difference gradient of the objective and Jacobian of the margins, in one batch."""
        points = (u + np.vstack([np.zeros(len(u)), np.diag(step)])) * scale
        value, margins = problem.lookup(points)
        return problem.sign * (value[1:] - value[0]) / step, (margins[1:] - margins[0]).T / step

    iterates: list[np.ndarray] = []
    result = minimize(lambda u: problem.objective(u * scale)[0], start / scale, method="SLSQP",
                      jac=lambda u: differences(u)[0], callback=_stall_detector(iterates),
                      bounds=[(lo / s, hi / s) for (lo, hi), s in zip(bounds, scale)],
                      constraints=[{"type": "ineq", "fun": lambda u: problem.margins(u * scale),
                                    "jac": lambda u: differences(u)[1]}],
                      options={"maxiter": 100, "ftol": 1e-10})
    lows, highs = [b[0] for b in bounds], [b[1] for b in bounds]
    polished = np.clip(result.x * scale, lows, highs)
    best_iterate = best_feasible(problem, [np.clip(u * scale, lows, highs) for u in [result.x, *iterates]])
    polished = polished if best_iterate is None else best_iterate
    if not (problem.lookup(start)[1] >= 0).all():  # an infeasible start: take what SLSQP reached
        return polished
    polished = _feasible_towards(problem, start, polished)
    value, _ = problem.lookup(polished)
    start_value, _ = problem.lookup(start)
    return polished if problem.sign * value[0] <= problem.sign * start_value[0] else start


def unit_curvature(problem: Problem, x: np.ndarray, box: np.ndarray) -> np.ndarray:
    """Per variable, the square root of the signed objective's second derivative at ``x`` in box units (central
    differences of CURVATURE_STEP of the box, one batch), or 1 where it is not positive and finite (a limit or the
    reach's edge nearby, or a saddle): the polish divides each variable by it, so that SLSQP's first guess of the
    Hessian, the identity, fits (the groove's is otherwise conditioned 1:10,000, and SLSQP's first steps leave the
    basin)."""
    n = len(x)
    steps = np.diag(CURVATURE_STEP * box)
    value = problem.sign * problem.lookup(np.vstack([x, x + steps, x - steps]))[0]
    second = (value[1:n + 1] + value[n + 1:] - 2 * value[0]) / CURVATURE_STEP**2
    usable = np.isfinite(second) & (second > 0)
    return np.clip(np.sqrt(np.where(usable, second, 1.0)), *CURVATURE_ROOT_RANGE)


def _stall_detector(iterates: list[np.ndarray]) -> Callable[..., None]:
    """An SLSQP callback that stops the polish once STALL_ITERATIONS iterations gained at most STALL_TOLERANCE, and
    keeps every iterate in ``iterates`` (SLSQP's iterates may go uphill, and its result is the last one)."""
    history: list[float] = []

    def callback(intermediate_result: OptimizeResult) -> None:  # scipy passes the result by this name
        iterates.append(np.array(intermediate_result.x, dtype=float))
        history.append(float(intermediate_result.fun))
        if len(history) > STALL_ITERATIONS:
            before = history[-STALL_ITERATIONS - 1]
            if before - min(history[-STALL_ITERATIONS:]) <= STALL_TOLERANCE * abs(before):
                raise StopIteration

    return callback


def signed_objective(problem: Problem, points: np.ndarray) -> np.ndarray:
    """(K,) signed objective (lower is better) of (K, n_free) points on the problem's model, +inf where a limit is
    broken or the objective is not finite."""
    values, margins = problem.lookup(points)
    return np.where((margins >= 0).all(axis=1) & np.isfinite(values), problem.sign * values, np.inf)


def best_feasible(problem: Problem, points: list[np.ndarray]) -> np.ndarray | None:
    """The best of ``points`` that keeps every limit on the problem's model, or None."""
    signed_values = signed_objective(problem, np.array(points))
    return points[int(np.argmin(signed_values))] if np.isfinite(signed_values).any() else None


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

"""The optimality gap: a lower bound on the best feasible objective, by a Lipschitz branch and bound over the box.

The free box is partitioned into cells (DIRECT-style: a cell is cut in three along the variable of largest
``L_i · h_i``, its centre kept). On a cell of centre ``c`` and half-widths ``h``, a function whose partial
derivatives are bounded by ``L_i`` satisfies ``f(x) ≥ f(c) − Σ_i L_i h_i``; the least such bound over the cells
that may still hold a better feasible placement is a lower bound on the best feasible objective, and
"best found − lower bound" the gap. Each round cuts the cells of least bound, evaluating the new centres in one
batch on the exact model (the path's own sampling), until the budget of evaluations is spent.

The bound is **estimated**, never proven: the ``L_i`` are the largest partial derivatives seen (central
differences at GRADIENT_POINTS points spread over the box, and the slopes between each cut cell's centre and its
children's, which can only raise them) times a safety factor (SAFETY). A function steeper somewhere than anything
sampled, times the factor, can break the bound.

What is dropped, and on what grounds:

- a cell whose bound is not below the best feasible value known (the search's or a feasible centre's): it holds no
  better placement (under the estimate);
- a cell where a limit is broken throughout: the limit's margin at the centre plus its own estimated slope bounds
  (sampled alike, same factor) times ``h`` is still negative (an estimate too);
- a cell whose centre is out of the robot's reach (no objective there) once it is no larger than OUT_OF_REACH_SHARE
  of the box along every variable: it is cut until then, and the bound *assumes* that no better feasible placement
  lies in such a small cell around an unreachable centre. The share of the box so dropped is reported.

A cell cut in three keeps its centre for the middle child, so each cut costs two evaluations.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from placement.evaluation.evaluator import Evaluator
from placement.search.local import Problem
from placement.search.space import PlacementSpace

SAFETY = 2.0  # the sampled slope bounds are multiplied by this
GRADIENT_POINTS = 32  # points of the box where the slopes are sampled by central differences
GRADIENT_STEP = 1e-6  # the central differences' step, as a share of each variable's range
CURVATURE_STEP = 1e-3  # gradients this share of the range apart give the second derivatives' bounds
OUT_OF_REACH_SHARE = 1 / 81  # a cell with an unreachable centre is dropped once no wider than this share of the box
CUTS_PER_ROUND = 16  # cells cut per round (their new centres are one batch)
BUDGET = 4_096  # evaluations of the branch and bound by default (the slope sampling's come on top)

Function = Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]  # (K, n) -> (K,) signed values, (K, L) margins


@dataclass(frozen=True)
class OptimalityGap:
    """A lower bound on the best feasible objective over a search's box, and the gap to the best found.

    Attributes:
        best: The best feasible objective known (the search's, or a better cell centre's), objective units.
        lower_bound: The lower bound on the best feasible objective (an upper bound for a higher-is-better objective).
        kind: "estimated" (slope bounds sampled, times ``safety``); never a proof (module docstring).
        evaluations: Placements evaluated (slope sampling and cells).
        safety: The factor on the sampled slope bounds.
        lipschitz: (n_free,) the slope bounds used at the end, objective units per unit of each free variable (m, rad).
        curvature: (n_free, n_free) the second derivatives' bounds used, objective units per unit of each two.
        cells: Cells that may still hold a better feasible placement at the end.
        out_of_reach_share: The share of the box's volume dropped as small cells with an unreachable centre.
        seconds: Wall time of the bound (s).
    """

    best: float
    lower_bound: float
    kind: str
    evaluations: int
    safety: float
    lipschitz: np.ndarray
    curvature: np.ndarray
    cells: int
    out_of_reach_share: float
    seconds: float = 0.0

    @property
    def gap(self) -> float:
        """|best found − lower bound| (objective units)."""
        return abs(self.best - self.lower_bound)

    @property
    def relative(self) -> float:
        """The gap as a share of the best found (absolute when that is 0)."""
        return self.gap / (abs(self.best) or 1.0)


@dataclass(frozen=True)
class Bound:
    """The branch and bound's outcome in signed units (lower is better): see :class:`OptimalityGap`."""

    best: float
    lower_bound: float
    evaluations: int
    lipschitz: np.ndarray
    curvature: np.ndarray
    cells: int
    out_of_reach_share: float


def _probe(function: Function, points: np.ndarray, step: np.ndarray) -> tuple[np.ndarray, ...]:
    """Values, central-difference gradients (objective and margins) and margins at (K, n) points, in one batch.

    Returns:
        (K,) values, (K, n) their gradients, (K, L) margins, (K, L, n) the margins' gradients.
    """
    n = points.shape[1]
    offsets = np.vstack([np.zeros(n), np.diag(step), -np.diag(step)])  # (2n + 1, n)
    values, margins = function((points[:, None, :] + offsets[None]).reshape(-1, n))
    values, margins = values.reshape(len(points), 2 * n + 1), margins.reshape(len(points), 2 * n + 1, -1)
    with np.errstate(invalid="ignore"):  # out of reach: inf − inf, a NaN gradient, which no bound uses
        gradient = (values[:, 1:n + 1] - values[:, n + 1:]) / (2 * step)
    margin_gradient = np.moveaxis((margins[:, 1:n + 1] - margins[:, n + 1:]) / (2 * step[:, None]), 1, 2)
    return values[:, 0], gradient, margins[:, 0], margin_gradient


def curvature_bounds(function: Function, lower: np.ndarray, upper: np.ndarray, points: int, safety: float,
                     rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """Sampled bounds, times ``safety``, on the objective's partial derivatives (n,) and second derivatives
    |∂²f/∂x_i∂x_j| (n, n), and on each limit's margin's partial derivatives (L, n), from gradients (central
    differences of GRADIENT_STEP) at ``points`` points spread over the box and at CURVATURE_STEP from each along
    each variable; and the evaluations spent."""
    n = len(lower)
    width = upper - lower
    step, reach = GRADIENT_STEP * width, CURVATURE_STEP * width
    centres = rng.uniform(lower + reach + step, upper - reach - step, (points, n))
    moved = (centres[:, None, :] + np.vstack([np.zeros(n), np.diag(reach)])[None]).reshape(-1, n)
    values, gradient, _, margin_gradient = _probe(function, moved, step)
    usable = np.isfinite(values)
    slope = safety * np.abs(np.where(usable[:, None], gradient, 0.0)).max(axis=0, initial=0.0)
    margin_slope = safety * np.abs(np.where(usable[:, None, None], margin_gradient, 0.0)).max(axis=0, initial=0.0)
    values, gradient = values.reshape(points, n + 1), gradient.reshape(points, n + 1, n)
    both = np.isfinite(values[:, :1]) & np.isfinite(values[:, 1:])  # (points, n): the base and the moved one
    change = np.abs(gradient[:, 1:, :] - gradient[:, :1, :]) / reach[None, :, None]  # [point, j moved, i]
    curvature = safety * np.where(both[:, :, None], change, 0.0).max(axis=0, initial=0.0)
    return slope, np.maximum(curvature, curvature.T), margin_slope, len(moved) * (2 * n + 1)


def branch_and_bound(function: Function, lower: np.ndarray, upper: np.ndarray, incumbent: float, budget: int,
                     safety: float = SAFETY, gradient_points: int = GRADIENT_POINTS, seed: int = 0) -> Bound:
    """A lower bound on the least feasible signed value of ``function`` over the box [lower, upper] (module docstring).

    Args:
        function: (K, n) points -> (K,) signed values (lower is better; not finite where out of reach) and (K, L)
            margins (feasible where all ≥ 0).
        lower, upper: (n,) the box.
        incumbent: The best feasible signed value known (inf if none).
        budget: Evaluations of cells, at most (2n + 1 per cell centre; the bounds' sampling's come on top).
        safety: The factor on the sampled derivative bounds.
        gradient_points: Points where the derivative bounds are sampled.
        seed: Seed of those points.
    """
    lower, upper = np.asarray(lower, float), np.asarray(upper, float)
    width, n = upper - lower, len(lower)
    step = GRADIENT_STEP * width
    slope, curvature, margin_slope, evaluations = curvature_bounds(function, lower, upper, gradient_points, safety,
                                                                   np.random.default_rng(seed))
    centre, half = ((lower + upper) / 2)[None], (width / 2)[None]
    value, gradient, margins, margin_gradient = _probe(function, centre, step)
    spent = 2 * n + 1
    cells = _Cells(centre, half, value, gradient, margins, margin_gradient)
    best = min(incumbent, _best_feasible(value, margins))
    while spent + 2 * (2 * n + 1) <= budget:  # every cell is kept: the bounds may rise, and a cell set aside come back
        slope, margin_slope = _raised(slope, margin_slope, cells, safety)
        open_ = cells.open(slope, curvature, margin_slope, best, width)
        if not open_.any():
            break
        bounds = np.where(open_, cells.bounds(slope, curvature), np.inf)
        count = min(CUTS_PER_ROUND, int(open_.sum()), (budget - spent) // (2 * (2 * n + 1)))
        cut = np.argsort(bounds, kind="stable")[:count]
        axis = np.where(np.isfinite(cells.value[cut]), np.argmax(slope * cells.half[cut], axis=1),
                        np.argmax(cells.half[cut] / width, axis=1))
        offset = np.zeros((len(cut), n))
        offset[np.arange(len(cut)), axis] = 2 * cells.half[cut, axis] / 3
        children = np.vstack([cells.centre[cut] - offset, cells.centre[cut] + offset])
        probed = _probe(function, children, step)
        spent += len(children) * (2 * n + 1)
        best = min(best, _best_feasible(probed[0], probed[2]))
        cells.half[cut, axis] /= 3
        cells.extend(children, np.vstack([cells.half[cut], cells.half[cut]]), *probed)
    slope, margin_slope = _raised(slope, margin_slope, cells, safety)
    open_ = cells.open(slope, curvature, margin_slope, best, width)
    bound = min(best, float(cells.bounds(slope, curvature)[open_].min(initial=np.inf)))
    small = cells.small_out_of_reach(width)
    return Bound(best=best, lower_bound=bound, evaluations=evaluations + spent, lipschitz=slope, curvature=curvature,
                 cells=int(open_.sum()), out_of_reach_share=float(np.prod(2 * cells.half[small] / width, axis=1).sum()))


@dataclass
class _Cells:
    """The partition's cells: centres and half-widths (K, n), and at each centre the value (K,), its gradient (K, n),
    the margins (K, L) and their gradients (K, L, n)."""

    centre: np.ndarray
    half: np.ndarray
    value: np.ndarray
    gradient: np.ndarray
    margins: np.ndarray
    margin_gradient: np.ndarray

    def extend(self, centre: np.ndarray, half: np.ndarray, value: np.ndarray, gradient: np.ndarray,
               margins: np.ndarray, margin_gradient: np.ndarray) -> None:
        """Add cells."""
        self.centre, self.half = np.vstack([self.centre, centre]), np.vstack([self.half, half])
        self.value, self.gradient = np.concatenate([self.value, value]), np.vstack([self.gradient, gradient])
        self.margins = np.vstack([self.margins, margins])
        self.margin_gradient = np.concatenate([self.margin_gradient, margin_gradient])

    def bounds(self, slope: np.ndarray, curvature: np.ndarray) -> np.ndarray:
        """Each cell's lower bound, the better of the first-order one, f(c) − Σ L_i h_i, and the second-order one,
        f(c) − Σ |g_i(c)| h_i − ½ Σ M_ij h_i h_j; −inf where the centre is out of reach or its gradient unknown."""
        first = self.value - self.half @ slope
        second = (self.value - (np.abs(self.gradient) * self.half).sum(axis=1)
                  - 0.5 * np.einsum("ki,ij,kj->k", self.half, curvature, self.half))
        usable = np.isfinite(self.value) & np.isfinite(self.gradient).all(axis=1)
        return np.where(usable, np.maximum(first, second), -np.inf)

    def open(self, slope: np.ndarray, curvature: np.ndarray, margin_slope: np.ndarray, best: float,
             width: np.ndarray) -> np.ndarray:
        """Which cells may still hold a feasible placement better than ``best``: their bound is below it, no limit is
        broken throughout them (an unreachable centre's margins say nothing), and they are not a small cell around
        an unreachable centre (:meth:`small_out_of_reach`)."""
        broken = ((self.margins + self.half @ margin_slope.T) < 0).any(axis=1) & np.isfinite(self.value)
        return (self.bounds(slope, curvature) < best) & ~broken & ~self.small_out_of_reach(width)

    def small_out_of_reach(self, width: np.ndarray) -> np.ndarray:
        """Which cells have an unreachable centre and are no wider than OUT_OF_REACH_SHARE of the box along any
        variable (module docstring: such a cell is assumed to hold no better feasible placement)."""
        return ~np.isfinite(self.value) & ((2 * self.half / width).max(axis=1) <= OUT_OF_REACH_SHARE)


def _best_feasible(value: np.ndarray, margins: np.ndarray) -> float:
    """The least finite value of the points that keep every limit (inf if none)."""
    feasible = np.isfinite(value) & (margins >= 0).all(axis=1)
    return float(value[feasible].min(initial=np.inf))


def _raised(slope: np.ndarray, margin_slope: np.ndarray, cells: _Cells, safety: float) -> tuple[np.ndarray, np.ndarray]:
    """The first-order bounds raised where a cell centre's gradient, times ``safety``, is steeper."""
    usable = np.isfinite(cells.value) & np.isfinite(cells.gradient).all(axis=1)
    slope = np.maximum(slope, safety * np.abs(cells.gradient[usable]).max(axis=0, initial=0.0))
    margin_slope = np.maximum(margin_slope, safety * np.abs(np.nan_to_num(cells.margin_gradient[usable])).max(
        axis=0, initial=0.0))
    return slope, margin_slope


def optimality_gap(evaluator: Evaluator, space: PlacementSpace, sign: float, best_value: float,
                   budget: int = BUDGET, safety: float = SAFETY, seed: int = 0) -> OptimalityGap:
    """The optimality gap of a search's best placement: :func:`branch_and_bound` over the space's free box on the exact
    model (``evaluator``: the path's own sampling), the search's best as the incumbent.

    Args:
        evaluator: The exact model.
        space: The search's space.
        sign: +1 when lower objective values are better, -1 otherwise.
        best_value: The search's best feasible objective value (objective units).
        budget: Evaluations of cell centres, at most.
        safety: The factor on the sampled slope bounds.
        seed: Seed of the slope sampling's points.
    """
    tic = time.perf_counter()
    problem = Problem(evaluator, space, sign)

    def signed(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        values, margins = problem.lookup(points)
        return sign * values, margins

    bound = branch_and_bound(signed, space.lower, space.upper, sign * best_value, budget, safety, seed=seed)
    return OptimalityGap(best=sign * bound.best, lower_bound=sign * bound.lower_bound, kind="estimated",
                         evaluations=bound.evaluations, safety=safety, lipschitz=bound.lipschitz, curvature=bound.curvature,
                         cells=bound.cells,
                         out_of_reach_share=bound.out_of_reach_share, seconds=time.perf_counter() - tic)

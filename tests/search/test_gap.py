"""The optimality gap (placement.search.gap): the stated lower bound holds on problems whose optimum is known, and
the gap closes as the budget grows. The bound is an estimate (sampled derivative bounds times a safety factor):
these problems are ones where the estimate holds, and a factor far too small is shown to break it."""

import numpy as np
import pytest

from placement import load_robot
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.load import load_path
from placement.search.gap import branch_and_bound, optimality_gap
from placement.search.local import Problem
from placement.search.space import default_space
from tests.support.paths import EXAMPLE

CAMEL_LOWER, CAMEL_UPPER = np.array([-3.0, -2.0]), np.array([3.0, 2.0])
CAMEL_MINIMUM = -1.0316284534898774  # the six-hump camel's global minimum, at (±0.0898, ∓0.7126)


def camel(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The six-hump camel function (six local minima, two global), unconstrained."""
    x, y = points[:, 0], points[:, 1]
    return (4 - 2.1 * x**2 + x**4 / 3) * x**2 + x * y + (-4 + 4 * y**2) * y**2, np.zeros((len(points), 0))


def small_feasible_square(points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(x − 2)² + (y − 1)², feasible on the square |x − 1| ≤ 0.01, |y − 1.5| ≤ 0.01 only (two margins), and out of
    reach (no value) where x + y > 5: the optimum is 0.99² + 0.49² at (1.01, 1.49), the unconstrained 0 infeasible."""
    x, y = points[:, 0], points[:, 1]
    value = np.where(x + y > 5, np.inf, (x - 2) ** 2 + (y - 1) ** 2)
    return value, np.column_stack([0.01 - np.abs(x - 1), 0.01 - np.abs(y - 1.5)])


SQUARE_MINIMUM = 0.99**2 + 0.49**2


@pytest.mark.parametrize("incumbent", [np.inf, -0.2155])  # none known; a search stuck in a local minimum
def test_the_bound_holds_on_the_camel_and_the_gap_closes_with_budget(incumbent):
    bounds = [branch_and_bound(camel, CAMEL_LOWER, CAMEL_UPPER, incumbent, budget).lower_bound
              for budget in (500, 2_000, 8_000, 32_000)]
    assert all(bound <= CAMEL_MINIMUM for bound in bounds)
    assert np.all(np.diff(bounds) > 0)  # closing
    assert CAMEL_MINIMUM - bounds[-1] < 0.1


def test_the_bound_holds_under_limits_and_out_of_reach_and_closes():
    """Cells where a limit is broken throughout are dropped (else the bound would be the unconstrained 0), and only
    those: dropping more loses the small feasible square (a planted defect does)."""
    results = [branch_and_bound(small_feasible_square, np.array([-3.0, -3.0]), np.array([3.5, 3.2]), np.inf, budget)
               for budget in (1_000, 16_000)]
    assert all(result.lower_bound <= SQUARE_MINIMUM * (1 + 1e-12) for result in results)
    assert results[-1].best == pytest.approx(SQUARE_MINIMUM, rel=1e-9)  # a feasible centre at the optimum
    assert SQUARE_MINIMUM - results[-1].lower_bound < SQUARE_MINIMUM - results[0].lower_bound
    assert SQUARE_MINIMUM - results[-1].lower_bound < 1e-6


def test_a_far_too_small_safety_factor_breaks_the_bound():
    """The bound is an estimate: with the sampled derivative bounds divided by 20 it is above the true optimum."""
    assert branch_and_bound(camel, CAMEL_LOWER, CAMEL_UPPER, np.inf, 8_000, safety=0.05).lower_bound > CAMEL_MINIMUM


@pytest.fixture(scope="module")
def groove_two_variables():
    """The paper's groove on the Orthoglide with x and phi free: the exact model and its minimum on a fine grid."""
    robot = load_robot("orthoglide")
    path = load_path(EXAMPLE)
    space = default_space(robot, free=("x", "phi"), half_turn=path.half_turn_symmetric())
    evaluator = Evaluator(robot, path, EvaluatorSettings(threads=1, workers=1))
    x, phi = np.meshgrid(np.linspace(space.lower[0], space.upper[0], 81),
                         np.linspace(space.lower[1], space.upper[1], 81))
    values, margins = Problem(evaluator, space, 1.0).lookup(np.column_stack([x.ravel(), phi.ravel()]))
    feasible = (margins >= 0).all(axis=1) & np.isfinite(values)
    yield evaluator, space, float(values[feasible].min())
    evaluator.close()


def test_on_the_groove_the_bound_is_below_a_fine_grid_and_closes_with_budget(groove_two_variables):
    evaluator, space, grid_minimum = groove_two_variables
    gaps = [optimality_gap(evaluator, space, 1.0, grid_minimum, budget) for budget in (1_000, 4_000)]
    assert all(gap.lower_bound <= grid_minimum and gap.kind == "estimated" for gap in gaps)
    assert gaps[1].gap < gaps[0].gap
    assert gaps[1].relative < 0.01

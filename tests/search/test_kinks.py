"""The polish's last step across the objective's kinks (gradient sampling), on functions with known minima."""

import numpy as np
import pytest

from placement.search.kinks import _shortest_in_hull, across_kinks
from placement.search.local import polish_across
from placement.search.space import PlacementSpace


class _Crease:
    """A minimum at the bottom of a narrow crease, as the groove's energy has one (per-interval clipping of the drives'
    power): 10·|x − y| + (x + y − 0.5)², least (0) at x = y = 0.25; optionally a limit x ≤ ``x_max``."""

    sign = 1.0

    def __init__(self, space: PlacementSpace, x_max: float = 10.0) -> None:
        self.space, self.x_max = space, x_max

    def lookup(self, points):
        points = np.atleast_2d(points)
        x, y = points[:, 0], points[:, 1]
        value = 10 * np.abs(x - y) + (x + y - 0.5) ** 2
        return value, (self.x_max - x)[:, None]

    def objective(self, points):
        return self.lookup(np.asarray(points).T)[0]

    def margins(self, points):
        _, margins = self.lookup(np.asarray(points).T)
        return margins.T if np.ndim(points) > 1 else margins[0]


def _space() -> PlacementSpace:
    return PlacementSpace(free=("x", "y"), lower=np.array([-1.0, -1.0]), upper=np.array([1.0, 1.0]), fixed=np.zeros(6))


def test_the_shortest_vector_of_two_gradients_hull_runs_along_their_kink():
    """Either side of 10·|x − y| + x + y: gradients (11, −9) and (−9, 11); the shortest of their hull is (1, 1)."""
    assert _shortest_in_hull(np.array([[11.0, -9.0], [-9.0, 11.0]])) == pytest.approx([1.0, 1.0], abs=1e-9)
    assert _shortest_in_hull(np.array([[3.0, 4.0]])) == pytest.approx([3.0, 4.0])


def test_gradient_sampling_reaches_the_bottom_of_a_crease_where_slsqp_stops():
    space = _space()
    problem = _Crease(space)
    start = np.array([-0.4, -0.38])
    polished = polish_across(problem, start, space)
    reached = across_kinks(problem, polished, space)
    # SLSQP, a smooth method, stops on the crease short of its lowest point (the defect this step mends) ...
    assert problem.lookup(polished)[0][0] > 1e-4
    # ... gradient sampling goes down along it to the minimum.
    assert reached == pytest.approx([0.25, 0.25], abs=1e-4)
    assert problem.lookup(reached)[0][0] < 1e-6


def test_gradient_sampling_keeps_every_limit_and_never_worsens():
    """With the limit x ≤ 0.1 the least feasible value lies on it (at x = 0.1, y ≈ 0.1): each step keeps the limit."""
    space = _space()
    problem = _Crease(space, x_max=0.1)
    start = np.array([-0.4, -0.38])
    reached = across_kinks(problem, start, space)
    assert reached[0] <= 0.1
    assert problem.lookup(reached)[0][0] <= problem.lookup(start)[0][0]
    assert reached == pytest.approx([0.1, 0.1], abs=1e-3)


def test_gradient_sampling_does_not_start_on_a_limit():
    """On the limit x ≤ 0.1 (the polish ends there), its steps along the limit would break it: it leaves the point."""
    space = _space()
    problem = _Crease(space, x_max=0.1)
    on_limit = np.array([0.1, 0.0])
    assert np.array_equal(across_kinks(problem, on_limit, space), on_limit)

"""The search of the printed lattice, on functions whose best printed point is known."""

from types import SimpleNamespace

import numpy as np
import pytest

from placement.search.lattice import lattice_search
from placement.search.reporting import reported_point
from placement.search.space import PlacementSpace, printed

MM = 1e-3


class _Model:
    """An objective of (x, y) in mm, with an optional limit x <= ``x_max_mm``; counts the placements it evaluates."""

    def __init__(self, objective, x_max_mm: float = np.inf) -> None:
        self.objective, self.x_max_mm, self.evaluated = objective, x_max_mm, []

    def evaluate(self, placements: np.ndarray) -> SimpleNamespace:
        self.evaluated.extend(map(tuple, placements))
        u, v = placements[:, 0] / MM, placements[:, 1] / MM
        return SimpleNamespace(value=self.objective(u, v), feasible=u <= self.x_max_mm)


def _space() -> PlacementSpace:
    return PlacementSpace(free=("x", "y"), lower=np.array([-0.01, -0.01]), upper=np.array([0.01, 0.01]),
                          fixed=np.zeros(6))


def _brute_force(model: _Model, cells: int = 60) -> np.ndarray:
    """The best printed (x, y) (mm) that keeps the limit among every one within ``cells`` steps of 0.01 mm of 0."""
    grid = np.array([[printed(i * 1e-5, False), printed(j * 1e-5, False), 0, 0, 0, 0]
                     for i in range(-cells, cells + 1) for j in range(-cells, cells + 1)])
    u, v = grid[:, 0] / MM, grid[:, 1] / MM
    values = np.where(u <= model.x_max_mm, model.objective(u, v), np.inf)
    return grid[np.argmin(values), :2] / MM


def _cell_corners(x_mm: np.ndarray) -> np.ndarray:
    """(4, 2) the printed corners (mm) of the cell of 0.01 mm around ``x_mm``."""
    low = np.floor(x_mm / 0.01) * 0.01
    return np.array([low + 0.01 * np.array(bits) for bits in ((0, 0), (0, 1), (1, 0), (1, 1))])


def test_the_search_goes_along_a_crease_to_the_best_printed_point():
    """10·|y − x| + (x + y − 0.1074)² (mm): a crease along the diagonal, least at x = y = 0.0537 mm, and of the printed
    points at x = y = 0.05 mm. From a point on the crease short of its minimum (where a smooth polish stops), the
    search goes down the crease to it (its first points reach x = y = 0.03 mm, then two diagonal moves); rounding the
    start, or its cell's best corner, is three steps off."""
    model = _Model(lambda u, v: 10 * np.abs(v - u) + (u + v - 0.1074) ** 2)
    assert _brute_force(model) == pytest.approx([0.05, 0.05], abs=1e-9)
    start_mm = np.array([0.0213, 0.0213])
    search = lattice_search(model, np.array([*start_mm * MM, 0, 0, 0, 0]), _space(), 1.0)
    assert search.placements[0][:2] / MM == pytest.approx([0.05, 0.05], abs=1e-9)
    assert search.usable[0] and search.moves == 2
    assert not np.any(np.all(np.isclose(_cell_corners(start_mm), [0.05, 0.05]), axis=1))
    # Each printed point is evaluated once, as printed (the placements read back exactly).
    assert len(model.evaluated) == len(set(model.evaluated)) == len(search.placements)
    assert all(printed(p[0], False) == p[0] and printed(p[1], False) == p[1] for p in search.placements)


def test_the_best_printed_point_on_the_feasible_side_of_a_limit():
    """1000·(y − 0.618034·x − 0.0086)² + (x − 0.0517)² with the limit x ≤ 0.0413 mm (as the pocket's optimum lies on
    a limit): the optimum lies on the limit, in the cell x 0.04-0.05, y 0.03-0.04 mm; its feasible corners lie off the
    narrow valley, and the best feasible printed point is two cells away, at x = y = 0.02 mm, where the valley passes
    nearer a printed point."""
    model = _Model(lambda u, v: 1000 * (v - 0.618034 * u - 0.0086) ** 2 + (u - 0.0517) ** 2, x_max_mm=0.0413)
    best = _brute_force(model)
    assert best == pytest.approx([0.02, 0.02], abs=1e-9)
    optimum_mm = np.array([0.0413, 0.618034 * 0.0413 + 0.0086])
    search = lattice_search(model, np.array([*optimum_mm * MM, 0, 0, 0, 0]), _space(), 1.0)
    assert search.placements[0][:2] / MM == pytest.approx(best, abs=1e-9)
    corners = _cell_corners(optimum_mm)
    feasible = corners[corners[:, 0] <= 0.0413]
    assert model.objective(*best) < 0.5 * model.objective(*feasible.T).min()
    # Every usable point keeps the limit, and they come best first.
    usable = search.placements[search.usable]
    assert (usable[:, 0] / MM <= 0.0413).all()
    values = model.objective(usable[:, 0] / MM, usable[:, 1] / MM)
    assert (np.diff(values) >= 0).all()


def test_a_point_outside_the_box_is_not_evaluated():
    """An optimum on the box's bound (x = 0.01 m): no point beyond it is evaluated or reported."""
    model = _Model(lambda u, v: -u + (v - 0.013) ** 2)
    search = lattice_search(model, np.array([0.01, 0.013 * MM, 0, 0, 0, 0]), _space(), 1.0)
    assert max(p[0] for p in model.evaluated) <= 0.01
    assert search.placements[0][:2] / MM == pytest.approx([10.0, 0.01], abs=1e-9)


class _Limited:
    """The objective 1000 x + y (mm) under the limit x >= ``x_min_mm``, as an Evaluator's evaluation and re-check: the
    path's samples see the limit at 0, the denser ones (the re-check) at 0.005 mm, as a limit reached between two of
    the path's samples."""

    def __init__(self, x_min_mm: float) -> None:
        self.x_min_mm = x_min_mm

    def evaluate(self, placements: np.ndarray) -> SimpleNamespace:
        u, v = placements[:, 0] / MM, placements[:, 1] / MM
        margin = (u - self.x_min_mm)[:, None]
        return SimpleNamespace(value=1000 * u + v, feasible=margin[:, 0] >= 0, margins=margin, limits=("x min",),
                               reachable=np.ones(len(u), dtype=bool))

    def recheck(self, placements: np.ndarray, source) -> SimpleNamespace:
        return self.evaluate(placements)


def test_a_printed_point_the_denser_samples_refuse_gives_way_to_the_lattices_best_on_them():
    """The lattice's best points on the path's samples lie on the limit (x = 0, y walked down to its bound), which
    the denser samples break, and so does the point pulled towards the box's centre (x = 0 is the centre): the
    lattice searched on the denser samples gives the best printed point that keeps the limit there, x = 0.01 mm,
    y at its bound (the search before gave up: "no candidate keeps every limit")."""
    space = PlacementSpace(free=("x", "y"), lower=np.array([-0.01, -0.0001]), upper=np.array([0.01, 0.0001]),
                           fixed=np.zeros(6))
    fine, dense = _Limited(0.0), _Limited(0.005)
    x, note, check = reported_point([np.array([0.0, 0.0])], fine, dense, space, 1.0)
    assert x / MM == pytest.approx([0.01, -0.1], abs=1e-9)
    assert note is None and check.feasible[0]

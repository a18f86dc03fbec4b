"""The optimiser finds the true optimum: checked against a dense grid sweep of the exact model."""

import json
import subprocess
import sys

import numpy as np
import pytest

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path import load_path
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from tests.support.paths import EXAMPLE

pytestmark = pytest.mark.slow  # about a minute on a 2-core machine: starts first under -n 2

GRID = 41
PRINTED_GRID = 1e-4  # the energy one 0.01 mm step of the printed grid moves at a limit, as a share
ROUND_OFF = 1e-9  # "never worse than the grid" up to round-off: optima sit on limits the grid can hit exactly


@pytest.fixture(scope="module")
def case():
    """30 x 60 mm rectangle at z = 0, phi = 0; x and y free; a coarse time step keeps it quick."""
    from placement import load_robot

    robot = load_robot("orthoglide")
    path = load_path(EXAMPLE)
    space = default_space(robot, free=("x", "y"))
    step = 0.002
    xs, ys = (np.linspace(lo, hi, GRID) for lo, hi in zip(space.lower, space.upper))
    grid = np.stack(np.meshgrid(xs, ys, indexing="ij"), axis=-1).reshape(-1, 2)
    evaluation = Evaluator(robot, path, EvaluatorSettings(time_step_s=step)).evaluate(space.full(grid))
    feasible = evaluation.value[evaluation.feasible]
    result = optimize_placement(robot, path, space=space, evaluation=EvaluatorSettings(time_step_s=step),
                                settings=SearchSettings(seed=3))
    return robot, path, space, step, feasible, result


def test_minimum_is_at_least_as_good_as_the_grid_and_close_to_it(case):
    *_, feasible, result = case
    best = result.best.detail.energy.total_J
    assert best <= feasible.min() * (1 + ROUND_OFF)
    assert best >= feasible.min() * (1 - 0.005)
    assert result.best.detail.feasible


def test_maximum_is_at_least_as_bad_as_the_grid_and_close_to_it(case):
    *_, feasible, result = case
    worst = result.worst.detail.energy.total_J
    # The reported worst lies on the printed grid (0.01 mm), inside the limit it sits on: a grid step costs energy.
    assert worst >= feasible.max() * (1 - PRINTED_GRID)
    assert worst <= feasible.max() * (1 + 0.005)
    # The gain agrees with the grid's own (E_max - E_min)/E_max, within the 0.5 % of each optimum.
    assert result.gain == pytest.approx((feasible.max() - feasible.min()) / feasible.max(), rel=0.01)


def test_the_denser_recheck_agrees(case):
    *_, result = case
    for optimum in (result.best, result.worst):
        assert optimum.sampling_gap < 0.01


def test_phi_range_follows_the_path_symmetry(case, tmp_path):
    robot = case[0]
    arc = tmp_path / "arc.yaml"
    arc.write_text("units: mm\nshape: {type: arc, radius: 20, sweep_deg: 90}\nfeed_m_s: 0.3\n")
    assert load_path(EXAMPLE).half_turn_symmetric() and not load_path(arc).half_turn_symmetric()
    half = default_space(robot, half_turn=True)
    full = default_space(robot)
    assert half.upper[-1] == pytest.approx(np.pi / 2) and full.upper[-1] == pytest.approx(np.pi)


def test_same_seed_same_result(case):
    robot, path, space, step, _, result = case
    again = optimize_placement(robot, path, space=space, evaluation=EvaluatorSettings(time_step_s=step),
                               settings=SearchSettings(seed=3, worst=False))
    np.testing.assert_array_equal(again.best.detail.placement, result.best.detail.placement)
    assert again.worst is None and again.gain is None


def test_a_path_too_large_for_the_workspace_is_reported_with_the_binding_limit(tmp_path, case):
    robot = case[0]
    file = tmp_path / "big.yaml"
    file.write_text("units: mm\nshape: {type: rectangle, width: 150, length: 300}\nfeed_m_s: 0.66\ntime_step_s: 0.004\n")
    result = optimize_placement(robot, load_path(file))
    assert result.best is None and result.worst is None
    assert "workspace" in result.infeasible and "m against a limit" in result.infeasible


def test_the_duration_is_announced_once_before_the_search_starts():
    from placement import load_robot

    events: list = []
    robot = load_robot("orthoglide")
    optimize_placement(robot, load_path(EXAMPLE), space=default_space(robot, free=("x", "y")),
                       evaluation=EvaluatorSettings(time_step_s=0.004),
                       settings=SearchSettings(population=8, max_generations=3, best=True, worst=False),
                       progress=lambda: events.append("generation"), announce=events.append)
    assert events[1:] == ["generation"] * (len(events) - 1) and len(events) > 1
    assert 0 < events[0] < np.inf


def test_both_directions_searched_at_once_find_what_one_after_the_other_finds():
    """In a fresh process, which may fork, the best and worst searches run in a process each; in another, the same
    searches run one after the other in that process (a one-thread pool instead of the process pool). The optima
    are the same, number for number."""
    script = ("import json, sys\n"
              "from concurrent.futures import ThreadPoolExecutor\n"
              "from placement import load_path, load_robot\n"
              "from placement.dynamics.inverse import openmp_started\n"
              "from placement.evaluation.evaluator import Evaluator, EvaluatorSettings\n"
              "from placement.search import optimize\n"
              "robot, path = load_robot('ur5'), load_path('examples/rect.yaml')\n"
              "probe = Evaluator(robot, path, EvaluatorSettings(threads=1))\n"
              "assert not openmp_started() and optimize.in_parallel(probe, probe, 2)\n"
              "if sys.argv[1] == 'one_after_the_other':\n"
              "    optimize.process_pool = lambda workers, initializer, initargs: ThreadPoolExecutor(\n"
              "        1, initializer=initializer, initargs=initargs)\n"
              "result = optimize.optimize_placement(robot, path, settings=optimize.SearchSettings(max_generations=4))\n"
              "print(json.dumps([o.detail.value for o in (result.best, result.worst)]))\n")

    def optima(mode: str) -> list[float]:
        output = subprocess.run([sys.executable, "-c", script, mode], capture_output=True, text=True, timeout=600,
                                check=True)
        return json.loads(output.stdout.strip().splitlines()[-1])

    assert optima("at_once") == optima("one_after_the_other")


def test_the_evaluation_settings_are_plain_data_that_each_search_takes_once():
    """EvaluatorSettings keeps several objectives as a tuple (hashable, picklable); a Pareto front takes its objectives
    once, and a sweep maps one objective: both refuse otherwise before any work."""
    import pickle

    from placement import load_robot
    from placement.exceptions import PlacementError
    from placement.search.pareto import pareto_front
    from placement.search.sweep import sweep

    settings = EvaluatorSettings(objective=["energy", "dexterity"], time_step_s=0.004)  # a list: kept as a tuple
    assert settings.objectives == ("energy", "dexterity") and settings.objective == ("energy", "dexterity")
    assert pickle.loads(pickle.dumps(settings)) == settings and hash(settings) == hash(settings)
    assert EvaluatorSettings().objectives == ("energy",)
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    with pytest.raises(PlacementError, match="given once, as objectives"):
        pareto_front(robot, path, ("energy", "transmission"), evaluation=EvaluatorSettings(objective="dexterity"))
    with pytest.raises(PlacementError, match="a sweep maps one objective, got energy, dexterity"):
        sweep(robot, path, {"x": np.zeros(2)}, evaluation=settings)


def test_a_whole_or_half_turn_of_phi_is_periodic_and_a_narrower_range_is_not(case):
    robot = case[0]
    half, full = default_space(robot, half_turn=True), default_space(robot)
    narrow = default_space(robot, bounds={"phi": (-1.0, 1.0)})
    assert half.period[-1] == pytest.approx(np.pi) and full.period[-1] == pytest.approx(2 * np.pi)
    assert not narrow.period.any() and not half.period[:-1].any()
    point = np.array([0.01, 0.02, 0.0, np.pi / 2 + 0.1])
    wrapped = half.wrap(point)
    assert wrapped[-1] == pytest.approx(-np.pi / 2 + 0.1) and np.array_equal(wrapped[:-1], point[:-1])
    np.testing.assert_array_equal(narrow.wrap(point), point)
    np.testing.assert_allclose(half.difference(point, wrapped), 0.0, atol=1e-12)  # a half turn apart: no distance
    assert narrow.difference(point, wrapped)[-1] == pytest.approx(np.pi)


class _Bowl:
    """A search problem whose only basin lies at φ = 89.6°, the path's half-turn past −90.4°: 1 J plus a bowl in
    (x, φ), no limit binding (a stand-in for the groove's, whose polish path round-off decides)."""

    sign = 1.0

    def __init__(self, space):
        self.space = space

    def lookup(self, points):
        points = self.space.wrap(np.atleast_2d(points))
        turn = self.space.difference(points, np.array([0.0, np.radians(89.6)]))
        return 1.0 + (turn[:, 0] / 0.01) ** 2 + turn[:, 1] ** 2, np.ones((len(points), 1))

    def objective(self, points):
        return self.lookup(np.asarray(points).T)[0]

    def margins(self, points):
        _, margins = self.lookup(np.asarray(points).T)
        return margins.T if np.ndim(points) > 1 else margins[0]


def test_a_basin_at_the_edge_of_phi_s_range_is_searched_across_the_edge():
    """From a start just inside −90°, the polish bounded by φ's half-turn range [−90°, 90°) stops on its edge; the
    polish that wraps φ goes on across it and ends in range, in the basin at 89.6°, lower."""
    from placement.search.local import _polish, polish_across
    from placement.search.space import PlacementSpace

    space = PlacementSpace(free=("x", "phi"), lower=np.array([-0.1, -np.pi / 2]), upper=np.array([0.1, np.pi / 2]),
                           fixed=np.zeros(6), periods=np.array([0.0, np.pi]))
    problem = _Bowl(space)
    start = np.array([0.02, -np.pi / 2 + 1e-3])
    bounded = _polish(problem, start, list(zip(space.lower, space.upper)))
    across = polish_across(problem, start, space)
    assert bounded[-1] == pytest.approx(-np.pi / 2, abs=1e-9)
    assert space.lower[-1] <= across[-1] < space.upper[-1]
    assert across == pytest.approx([0.0, np.radians(89.6)], abs=1e-4)
    assert problem.lookup(across)[0][0] < problem.lookup(bounded)[0][0]

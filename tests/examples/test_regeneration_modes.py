"""examples/regeneration_modes.py: searches of several regeneration modes sharing the chain; each mode's numbers
are its own evaluator's and its own search's, with every placement through the chain once."""

import numpy as np
import pytest
from regeneration_modes import SharedChain, optimize_modes

from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.exceptions import PlacementError
from placement.path import load_path
from placement.search.optimize import SearchSettings, optimize_placement
from placement.search.space import default_space
from tests.support.paths import EXAMPLE

MODES = ("clip", "bus", "signed", "absolute")
STEP_S = 0.004


@pytest.fixture(scope="module")
def robot():
    from placement import load_robot

    return load_robot("orthoglide")


def test_a_shared_chain_gives_each_mode_what_its_own_evaluator_gives(robot):
    path = load_path(EXAMPLE)
    space = default_space(robot)
    rng = np.random.default_rng(1)
    placements = space.full(rng.uniform(space.lower, space.upper, (40, len(space.free))))
    placements[30:, :3] *= 4  # out of reach
    shared = SharedChain(Evaluator(robot, path, EvaluatorSettings(time_step_s=STEP_S)), MODES)
    for mode in MODES:
        own = Evaluator(robot, path, EvaluatorSettings(time_step_s=STEP_S, regeneration=mode)).evaluate(placements)
        got = shared.evaluate(placements, mode)
        assert np.array_equal(got.values, own.values) and np.array_equal(got.margins, own.margins)
        assert np.array_equal(got.reachable, own.reachable) and got.limits == own.limits
    assert shared.evaluations == len(placements)  # once through the chain for the four modes
    clip, absolute = (shared.evaluate(placements, mode).value for mode in ("clip", "absolute"))
    assert 0 < (~np.isfinite(clip)).sum() < len(placements)  # unreachable placements are in the test, not all
    assert (absolute[np.isfinite(clip)] > clip[np.isfinite(clip)]).any()  # the modes tell braking apart here


def test_each_modes_optimum_is_its_own_search_s(robot):
    path = load_path(EXAMPLE)
    space = default_space(robot, free=("x", "y", "phi"), half_turn=path.half_turn_symmetric())
    evaluation = EvaluatorSettings(time_step_s=STEP_S, threads=1)
    settings = SearchSettings(population=24, max_generations=12, seed=2)
    shared = optimize_modes(robot, path, ("clip", "absolute"), space=space, evaluation=evaluation, settings=settings)
    for mode, result in shared.items():
        own = optimize_placement(robot, path, space=space, settings=settings,
                                 evaluation=EvaluatorSettings(time_step_s=STEP_S, threads=1, regeneration=mode))
        assert result.regeneration == mode
        for ours, theirs in ((result.best, own.best), (result.worst, own.worst)):
            assert ours is not None and theirs is not None
            assert np.array_equal(ours.detail.placement, theirs.detail.placement)
            assert ours.detail.energy.total_J == theirs.detail.energy.total_J
            assert ours.recheck_value == theirs.recheck_value and ours.evaluations == theirs.evaluations
    assert shared["absolute"].worst.detail.value > shared["clip"].worst.detail.value  # not one mode's twice


def test_the_optimal_timing_law_is_refused(robot, tmp_path):
    file = tmp_path / "rect.yaml"
    file.write_text(EXAMPLE.read_text().replace("mode: paper", "mode: optimal"))
    with pytest.raises(PlacementError, match="optimal"):
        optimize_modes(robot, load_path(file), MODES, evaluation=EvaluatorSettings(time_step_s=STEP_S))

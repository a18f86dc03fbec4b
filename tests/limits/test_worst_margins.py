"""A batch's tightest margin of each limit (what a search ranks by) is the one a placement's detail finds at its
tightest sample and column (an argmin over that placement's samples alone), under either timing law."""

import dataclasses

import numpy as np
import pytest

from placement import load_robot
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.load import load_path
from placement.path.path_file import Timing

PLACEMENTS = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0],
                       [-0.06, 0.03, 0.0, -1.0, 0.0, 0.0]])


@pytest.mark.parametrize("timing", ["paper", "optimal"])
def test_a_batch_s_tightest_margins_are_each_placement_s_own(timing):
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode=timing))
    evaluator = Evaluator(load_robot("orthoglide"), path, EvaluatorSettings(workers=1, threads=1))
    evaluation = evaluator.evaluate(PLACEMENTS)
    kinds = [label.split(": ")[0] for label in evaluation.limits]
    for k, placement in enumerate(PLACEMENTS):
        detail = evaluator.detail(placement).margins  # each kind's tightest sample and column
        assert sorted(margin.kind for margin in detail) == sorted(set(kinds))
        for margin in detail:
            columns = [column for column, kind in enumerate(kinds) if kind == margin.kind]
            assert evaluation.margins[k, columns].min() == margin.margin, margin.kind
            assert evaluation.margins[k, evaluation.limits.index(f"{margin.kind}: {margin.where}")] == margin.margin
        assert len({round(margin.margin, 6) for margin in detail}) > 3  # the limits' margins differ

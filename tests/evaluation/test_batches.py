"""A placement's objectives do not depend on the batch it is evaluated in: alone, or with others (as a cluster's
or a process pool's chunks cut a batch), every value is the same to the last bit."""

import dataclasses

import numpy as np
import pytest

from placement import load_robot
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path.load import load_path
from placement.path.path_file import Timing


@pytest.mark.parametrize(("timing", "objectives"), [("paper", ("energy",)), ("optimal", ("energy", "cycle_time"))])
def test_a_placement_alone_is_valued_as_in_a_batch(timing, objectives):
    robot = load_robot("orthoglide")
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode=timing))
    placements = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0],
                           [-0.06, 0.03, 0.0, -1.0, 0.0, 0.0]])
    evaluator = Evaluator(robot, path, EvaluatorSettings(objective=objectives, workers=1, threads=1))
    together = evaluator.evaluate(placements)
    alone = [evaluator.evaluate(placement[None]) for placement in placements]
    np.testing.assert_array_equal(np.concatenate([one.values for one in alone]), together.values)
    np.testing.assert_array_equal(np.concatenate([one.margins for one in alone]), together.margins)


def test_a_batch_under_another_regeneration_mode_has_that_mode_s_energies():
    robot = load_robot("orthoglide")
    path = load_path("examples/rect.yaml")
    placements = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0]])
    batch = Evaluator(robot, path, EvaluatorSettings(workers=1, threads=1)).batch(placements)
    assert batch.energy.regeneration == "clip"  # computed first: it must not carry over
    totals = {}
    for mode in ("clip", "bus", "signed", "absolute"):
        own = Evaluator(robot, path, EvaluatorSettings(regeneration=mode, workers=1, threads=1)).batch(placements)
        moved = batch.under(mode).energy
        for field in ("total_J", "per_actuator_J", "joule_J", "inductive_J", "back_emf_J", "mechanical_J"):
            np.testing.assert_array_equal(getattr(moved, field), getattr(own.energy, field))
        totals[mode] = moved.total_J
    assert (totals["absolute"] > totals["clip"]).all() and (totals["signed"] < totals["clip"]).all()  # modes differ

"""The optimal timing law evaluates each sample inside a run twice, zero time apart: the limits on position and
velocity check the first copy alone (``EvaluatedBatch.distinct_samples``), and a search's thermal margin is read at
the last sample only. Both give the margins, and a detail's tightest samples, that every sample gives."""

import dataclasses

import numpy as np

from placement import load_robot
from placement.contract.limit import margin_fields, tightest
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings, batch_margins
from placement.path.load import load_path
from placement.path.path_file import Timing

PLACEMENTS = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0], [0.04, -0.02, -0.1, 0.5, 0.0, 0.0],
                       [-0.06, 0.03, 0.0, -1.0, 0.0, 0.0], [0.3, 0.0, 0.0, 0.0, 0.0, 0.0]])  # the last out of reach


def optimal_evaluator() -> Evaluator:
    path = dataclasses.replace(load_path("examples/rect.yaml"), timing=Timing(mode="optimal"))
    return Evaluator(load_robot("orthoglide"), path, EvaluatorSettings(workers=1, threads=1))


def test_a_sample_left_out_repeats_the_one_before_it():
    batch = optimal_evaluator().batch(PLACEMENTS)
    kept = batch.distinct_samples
    assert kept is not None and 0 < len(kept) < len(batch.samples) and kept[0] == 0
    repeats = np.setdiff1d(np.arange(len(batch.samples)), kept)
    assert len(repeats) > 0.4 * len(batch.samples)
    for values in (batch.position, batch.velocity, batch.tool_position_m, batch.motor.speed_rad_s,
                   batch.reachable[..., None]):
        np.testing.assert_array_equal(values[:, repeats], values[:, repeats - 1])
    assert not np.array_equal(batch.acceleration[:, repeats], batch.acceleration[:, repeats - 1])  # s̈ switches


def test_the_distinct_samples_give_every_sample_s_margins_and_tightest_samples():
    evaluator = optimal_evaluator()
    batch = evaluator.batch(PLACEMENTS)
    every = dataclasses.replace(batch, distinct_samples=None)
    margins, labels, reachable = batch_margins(batch)
    assert not reachable.all() and reachable.any()
    np.testing.assert_array_equal(margins, batch_margins(every)[0])
    assert labels == batch_margins(every)[1]
    for placement in PLACEMENTS[:3]:
        exact = evaluator.batch(placement[None], exact=True)
        assert tightest(margin_fields(exact)) == tightest(margin_fields(dataclasses.replace(exact,
                                                                                           distinct_samples=None)))


def test_a_search_s_thermal_margin_is_the_least_over_every_sample():
    batch = optimal_evaluator().batch(PLACEMENTS)
    search = {field.kind: field for field in margin_fields(batch)}["thermal (RMS)"]
    exact = {field.kind: field for field in margin_fields(dataclasses.replace(batch, exact=True))}["thermal (RMS)"]
    assert search.margin.shape[1] == 1 and exact.margin.shape[1] == len(batch.samples)
    np.testing.assert_array_equal(search.margin[:, 0], exact.margin.min(axis=1))
    assert (exact.margin[:, 0] > exact.margin[:, -1]).all()  # the margin falls along the path

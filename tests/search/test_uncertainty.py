"""Error bars: the first-order propagation of the drives' uncertain constants, checked by physics and by sampling."""

import numpy as np
import pytest

from placement import load_robot
from placement.evaluation.evaluator import Evaluator, EvaluatorSettings
from placement.path import load_path
from placement.search import uncertainty
from placement.search.uncertainty import energy_uncertainty, uncertain_parameters
from tests.support.paths import EXAMPLE

BEST = np.array([-0.003, 0.00514, -0.03511, np.radians(89.6), 0.0, 0.0])  # the groove's two basins (J: 4.7672, 4.7683)
ZERO = np.array([-0.00255, 0.00352, -0.03306, np.radians(-0.36), 0.0, 0.0])
WORST = np.array([0.05, 0.05, 0.05, 0.5, 0.0, 0.0])


@pytest.fixture(scope="module")
def groove():
    return load_robot("orthoglide"), load_path(EXAMPLE)


def test_each_estimated_drive_constant_gets_the_stated_range_and_an_efficiency_stays_at_most_one(groove):
    robot, _ = groove
    parameters = {p.field: p for p in uncertain_parameters(robot)}
    assert parameters["resistance_ohm"].status == "EST"  # robots/orthoglide/orthoglide.yaml's sources
    assert parameters["resistance_ohm"].low == pytest.approx(1.5 * 0.8)
    assert parameters["resistance_ohm"].high == pytest.approx(1.5 * 1.2)
    assert parameters["efficiency"].high == 1.0
    assert "coulomb" not in parameters  # at 0: no relative range


def test_the_energy_s_slope_by_the_resistance_is_its_joule_part_over_the_resistance(groove):
    # With full regeneration the energy is the sum of its parts, and the Joule part is linear in R: dE/dR = E_joule/R.
    robot, path = groove
    settings = EvaluatorSettings(regeneration="signed", threads=1, workers=1)
    found = energy_uncertainty(robot, path, settings, BEST)
    k = next(i for i, p in enumerate(found.parameters) if p.field == "resistance_ohm")
    joule = Evaluator(robot, path, settings).detail(BEST).energy.joule_J.sum()
    assert found.slopes[k, 0] == pytest.approx(joule / 1.5, rel=1e-6)


def test_the_first_order_interval_holds_the_sampled_energies_on_small_ranges(groove, monkeypatch):
    # On ±1 % ranges the energy is nearly linear in the constants: every sampled energy lies inside the first-order
    # interval (up to the second-order term), and the sampled range fills most of it.
    robot, path = groove
    monkeypatch.setattr(uncertainty, "SPREADS", {status: 0.01 for status in uncertainty.SPREADS})
    monkeypatch.setattr(uncertainty, "EST_SPREAD", 0.01)
    found = energy_uncertainty(robot, path, EvaluatorSettings(threads=1, workers=1), BEST, WORST, ZERO[None])
    for interval in (found.best, found.worst, found.gain):
        width = interval.high - interval.low
        assert interval.low < interval.value < interval.high
        assert interval.low - 0.02 * width <= interval.sampled_low and interval.sampled_high <= interval.high + 0.02 * width
        assert interval.sampled_high - interval.sampled_low > 0.3 * width
    # The two basins are 0.02 % apart: ±1 % constants move both alike, so the ranking stays in most draws.
    assert 0.0 <= found.other_basin_wins < 0.5

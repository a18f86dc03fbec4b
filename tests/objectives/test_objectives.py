"""The objective family against physics and against the other parts of the model.

- a lossless motor (R = L = 0) turns shaft work into electric power exactly, so under per-axis
  clipping the electric energy equals the mechanical (positive shaft work) objective;
- the Joule energy of each drive is n·R·∫I² dt, so the RMS current follows from it;
- the peak motor torque is where the motor-torque limit is tightest.
"""

import dataclasses

import numpy as np
import pytest

from placement import OBJECTIVES, Evaluator, EvaluatorSettings, Objective, load_path, load_robot
from placement.path.path_file import Timing
from tests.support.paths import EXAMPLE
from tests.support.robot_copies import edited_copy, orthoglide_motor

PLACEMENTS = np.array([[0.0, 0.0, 0.0, 0.0, 0.0, 0.0], [-0.06, 0.02, -0.05, 0.6, 0.0, 0.0],
                       [-0.09, -0.09, -0.1, -0.8, 0.0, 0.0]])


def timed(law: str):
    """The example path under the file's timing law (paper), or each placement timed optimally."""
    path = load_path(EXAMPLE)
    return path if law == "paper" else dataclasses.replace(path, timing=Timing(mode=law))


TIMINGS = pytest.mark.parametrize("law", ["paper", "optimal"])


@TIMINGS
def test_a_lossless_motor_draws_exactly_the_positive_shaft_work(tmp_path, law):
    def lossless(document: dict) -> None:
        orthoglide_motor(document).update(resistance_ohm=0.0, inductance_H=0.0)

    robot, path = load_robot(edited_copy("orthoglide", tmp_path, lossless)), timed(law)
    electric = Evaluator(robot, path, EvaluatorSettings(regeneration="clip", time_step_s=0.002)).evaluate(PLACEMENTS).value
    mechanical = Evaluator(robot, path, EvaluatorSettings(regeneration="clip", time_step_s=0.002,
                                                          objective="mechanical_energy")).evaluate(PLACEMENTS).value
    np.testing.assert_allclose(mechanical, electric, rtol=1e-12)
    assert (mechanical > 0.5).all()


@TIMINGS
def test_rms_current_follows_from_the_joule_energy(law):
    robot, path = load_robot("orthoglide"), timed(law)
    evaluator = Evaluator(robot, path, EvaluatorSettings(regeneration="clip", time_step_s=0.002, objective="rms_current"))
    motor = robot.actuators[0].drive.motor
    for placement, value in zip(PLACEMENTS, evaluator.evaluate(PLACEMENTS).value):
        detail = evaluator.detail(placement)
        duration = float(np.ptp(detail.samples.t_s))  # the paper's pieces tile the path's time
        rms = np.sqrt(detail.energy.joule_J / (motor.phases * motor.resistance_ohm * duration))
        assert value == pytest.approx(rms.max(), rel=1e-12)


def test_peak_torque_is_where_the_motor_torque_limit_is_tightest():
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    evaluator = Evaluator(robot, path, EvaluatorSettings(regeneration="clip", time_step_s=0.002, objective="peak_torque"))
    top = robot.actuators[0].drive.motor.max_torque_Nm  # the same motor on every axis
    for placement, value in zip(PLACEMENTS, evaluator.evaluate(PLACEMENTS).value):
        margin = next(m for m in evaluator.detail(placement).margins if m.kind == "motor torque")
        assert value == pytest.approx(top * (1 - margin.margin), rel=1e-12)
        assert value == pytest.approx(abs(margin.value), rel=1e-12)


def test_the_batch_power_integrates_to_the_energy_with_full_regeneration():
    evaluator = Evaluator(load_robot("orthoglide"), load_path(EXAMPLE),
                          EvaluatorSettings(regeneration="signed", time_step_s=0.002))
    batch = evaluator.batch(PLACEMENTS)
    np.testing.assert_allclose(batch.interval_power_W.sum(axis=-1) @ batch.interval_widths_s, batch.energy.total_J,
                               rtol=1e-12)


class NegatedEnergy(Objective):
    """Minus the electric energy, higher is better: its best placement must be energy's best."""

    title = "negated energy"
    unit = "J"
    better = "higher"

    def __call__(self, batch):
        return -batch.energy.total_J


class Nothing(Objective):
    """Zero everywhere."""

    title = "nothing"
    unit = "J"

    def __call__(self, batch):
        return np.zeros(len(batch))


def test_a_higher_is_better_objective_searches_and_reports_the_other_way(capsys):
    from placement import SearchSettings, default_space, optimize_placement
    from placement.output.report import format_result

    OBJECTIVES.register("negated_energy_for_test", NegatedEnergy())
    robot, path = load_robot("orthoglide"), load_path(EXAMPLE)
    space, settings = default_space(robot, free=("x", "y")), SearchSettings(population=12, max_generations=8)
    energy = optimize_placement(robot, path, space=space, evaluation=EvaluatorSettings(time_step_s=0.004),
                                settings=settings)
    negated = optimize_placement(robot, path, space=space, settings=settings,
                                 evaluation=EvaluatorSettings(time_step_s=0.004, objective="negated_energy_for_test"))
    np.testing.assert_array_equal(negated.best.detail.placement, energy.best.detail.placement)
    np.testing.assert_array_equal(negated.worst.detail.placement, energy.worst.detail.placement)
    assert negated.best.detail.value == -energy.best.detail.energy.total_J and negated.gain == energy.gain
    text = format_result(robot, negated)
    assert "best placement (most negated energy)" in text and "worst placement (least negated energy)" in text
    assert f"raises {negated.gain * 100:.1f} % of the negated energy" in text


def test_an_objective_of_zero_is_reported_without_dividing_by_it(capsys):
    from placement.cli import main

    OBJECTIVES.register("nothing_for_test", Nothing())
    assert main(["--robot", "orthoglide", "--path", str(EXAMPLE), "--time-step", "0.01", "--generations", "2",
                 "--population", "6", "--quiet", "--objective", "nothing_for_test"]) == 0
    out = capsys.readouterr().out
    assert "nothing 0.0000 J (4x denser sampling: 0.0000 J, n/a)" in out and "gain:" not in out

"""The time-optimal timing law, proven by known answers, the chain rule, the exact chain and the other laws."""

from __future__ import annotations

import dataclasses
import json

import numpy as np
import pytest

from placement import Evaluator, EvaluatorSettings, load_path, load_robot
from placement.__main__ import main
from placement.dynamics.inverse import actuator_efforts
from placement.evaluation.evaluator import denser
from placement.exceptions import PlacementError
from placement.path.path_file import Timing
from placement.placing.transform import placed_task
from placement.search.pareto import non_dominated
from placement.timing.exceptions import TimingError
from placement.timing.rules import check_timing, needed_timing, override_timing, timing_for
from tests.support.robot_copies import edited_copy, gantry, orthoglide_motor

PLACEMENTS = np.array([[0.0, 0.0, -0.03, 0.0, 0.0, 0.0],
                       [0.05, 0.03, -0.12, -0.1, 0.0, 0.0],
                       [-0.08, -0.06, -0.02, 0.7, 0.0, 0.0],
                       [0.02, -0.09, -0.1, -1.2, 0.0, 0.0]])

LINE = "units: mm\nshape: {{type: polyline, points: [[0, 0], [{length}, 0]]}}\nfeed_m_s: {feed}\n" \
       "timing: {{mode: optimal}}\ntime_step_s: 0.0005\n"


def optimal(path):
    return dataclasses.replace(path, timing=Timing(mode="optimal"))


@pytest.fixture(scope="module")
def orthoglide_rect():
    return load_robot("orthoglide"), optimal(load_path("examples/rect.yaml"))


@pytest.mark.parametrize("length_mm, feed", [(100.0, 0.3), (20.0, 0.3)])
def test_a_line_with_only_a_speed_and_an_acceleration_bound_takes_the_trapezoidal_time(tmp_path, length_mm, feed):
    robot = load_robot(gantry(tmp_path))
    (tmp_path / "line.yaml").write_text(LINE.format(length=length_mm, feed=feed))
    path = load_path(tmp_path / "line.yaml")
    evaluator = Evaluator(robot, path, EvaluatorSettings(objective="cycle_time", workers=1))
    detail = evaluator.detail(np.zeros(6))
    length, acceleration = length_mm * 1e-3, 2.0
    if length >= feed**2 / acceleration:  # trapezoid: accelerate, cruise at the feed, brake
        expected = length / feed + feed / acceleration
    else:  # triangle: the feed is never reached
        expected = 2 * np.sqrt(length / acceleration)
    assert detail.feasible
    assert detail.value == pytest.approx(expected, rel=0.01)
    speed = np.linalg.norm(detail.samples.velocity_m_s, axis=1)
    assert speed.max() <= feed * (1 + 1e-9)
    assert np.abs(detail.acceleration).max() <= acceleration


def test_efforts_under_the_timing_equal_the_dynamics_of_the_timed_motion(orthoglide_rect):
    """The chain rule (q̇ = q'·ṡ, q̈ = q'·s̈ + q''·ṡ²) and the effort's A·s̈ + B·ṡ² + C form, against the
    kinematics and projected RNEA of the timed tool motion itself."""
    robot, path = orthoglide_rect
    evaluator = Evaluator(robot, path, EvaluatorSettings(workers=1))
    batch = evaluator.batch(PLACEMENTS)
    assert batch.time_law is not None and batch.time_law.timed.all()
    for i, placement in enumerate(PLACEMENTS):
        samples = batch.time_law.timed_samples(evaluator.samples, i)
        task, force = placed_task(robot, samples, placement[None])
        joints, reachable, _ = evaluator.solver.solve(task, 1)
        effort = actuator_efforts(robot, joints, force)
        assert reachable.all()
        scale = np.abs(batch.effort[i]).max()
        np.testing.assert_allclose(batch.effort[i], effort, rtol=0, atol=1e-9 * scale)
        np.testing.assert_allclose(batch.velocity[i], joints.v[:, robot.actuated_v_indices], rtol=0, atol=1e-9)


def test_every_limit_holds_between_the_samples_of_the_timing(orthoglide_rect):
    """The timing found on the path's samples, run on 4x and 8x denser ones: every limit still holds, and
    the energy and cycle time barely move."""
    robot, path = orthoglide_rect
    objectives = ("energy", "cycle_time")
    fine = Evaluator(robot, path, EvaluatorSettings(objective=objectives, workers=1))
    own = fine.evaluate(PLACEMENTS)
    assert own.feasible.all()
    for density in (4, 8):
        check = denser(fine, density).recheck(PLACEMENTS, fine)
        assert (check.margins >= 0).all(), dict(zip(check.limits, check.margins.min(axis=0)))
        np.testing.assert_allclose(check.values[:, 1], own.values[:, 1], rtol=1e-9)  # the same motion
        np.testing.assert_allclose(check.values[:, 0], own.values[:, 0], rtol=0.001)


def test_the_optimal_timing_is_never_slower_than_the_realistic_one(orthoglide_rect):
    robot, path = orthoglide_rect
    realistic = dataclasses.replace(path, timing=Timing(mode="realistic", max_acceleration_m_s2=10,
                                                        max_jerk_m_s3=500))
    feasible = Evaluator(robot, realistic, EvaluatorSettings(workers=1)).evaluate(PLACEMENTS).feasible
    assert feasible.any()
    slow = Evaluator(robot, realistic, EvaluatorSettings(workers=1)).samples.t_s[-1]
    fast = Evaluator(robot, path, EvaluatorSettings(objective="cycle_time", workers=1)).evaluate(PLACEMENTS[feasible])
    assert fast.feasible.all()
    assert (fast.value <= slow).all()
    # Nor faster than the feed allows: the path's length at its feed is a lower bound.
    assert (fast.value > path.length_m / path.feed_m_s).all()


def test_the_cycle_time_converges_as_the_sampling_grows(orthoglide_rect):
    robot, path = orthoglide_rect
    times = [Evaluator(robot, path, EvaluatorSettings(time_step_s=step, objective="cycle_time", workers=1))
             .evaluate(PLACEMENTS[:2]).value
             for step in (0.002, 0.001, 0.0005, 0.00025)]
    changes = np.abs(np.diff(times, axis=0)).max(axis=1)
    assert changes[-1] < changes[0] and changes[-1] < 2e-4 * np.max(times)


def test_a_load_the_motors_cannot_hold_has_no_timing(orthoglide_rect, tmp_path):
    robot, _ = orthoglide_rect
    (tmp_path / "heavy.yaml").write_text("units: mm\nshape: {type: circle, radius: 10}\nfeed_m_s: 0.1\n"
                                         "process_forces_N: {radial: 3000}\ntiming: {mode: optimal}\n")
    evaluator = Evaluator(robot, load_path(tmp_path / "heavy.yaml"), EvaluatorSettings(objective="cycle_time", workers=1))
    detail = evaluator.detail(np.array([0.0, 0.0, -0.03, 0.0, 0.0, 0.0]))
    kinds = {m.kind: m.margin for m in detail.margins}
    assert not detail.feasible and detail.value == np.inf
    assert kinds["optimal timing"] == -1 and kinds["motor torque"] < 0


def test_cycle_time_needs_the_optimal_timing_law(orthoglide_rect):
    robot, _ = orthoglide_rect
    with pytest.raises(PlacementError, match="cycle_time' needs the optimal timing law"):
        Evaluator(robot, load_path("examples/rect.yaml"), EvaluatorSettings(objective=("energy", "cycle_time")))


def test_the_timing_rules_say_which_law_the_objectives_need_once_for_the_library_and_the_command_line():
    path = load_path("examples/rect.yaml")  # the paper's law
    assert needed_timing(("energy", "dexterity")) is None and needed_timing(("energy", "cycle_time")) == "optimal"
    assert timing_for(("energy",), None, path) == (None, None)
    assert timing_for(("energy",), "realistic", path) == ("realistic", None)
    assert timing_for(("energy", "cycle_time"), None, path) == (
        "optimal", "the objective cycle_time needs the optimal timing law")
    assert timing_for(("cycle_time",), "optimal", path) == ("optimal", None)
    assert timing_for(("cycle_time",), None, optimal(path)) == (None, None)
    with pytest.raises(TimingError, match="^--timing paper: the objective cycle_time needs --timing optimal$"):
        timing_for(("cycle_time",), "paper", path)
    check_timing(("energy", "cycle_time"), optimal(path))
    with pytest.raises(TimingError, match="^the objective 'cycle_time' needs the optimal timing law"):
        check_timing(("energy", "cycle_time"), path)


def test_the_timing_overrides_keep_the_path_files_values_where_none_is_given():
    path = load_path("examples/rect.yaml")  # the paper's law, with bounds for the realistic one
    assert override_timing(path) is path
    assert override_timing(path, "realistic").timing == Timing(mode="realistic", max_acceleration_m_s2=10,
                                                              max_jerk_m_s3=500)
    path = dataclasses.replace(path, timing=Timing())  # the paper's law alone
    realistic = override_timing(path, "realistic", 2.0, 50.0)
    assert realistic.timing == Timing(mode="realistic", max_acceleration_m_s2=2.0, max_jerk_m_s3=50.0)
    assert override_timing(realistic, max_jerk_m_s3=80.0).timing.max_acceleration_m_s2 == 2.0
    assert override_timing(realistic, "optimal").timing == Timing(mode="optimal", max_acceleration_m_s2=2.0,
                                                                  max_jerk_m_s3=50.0)
    with pytest.raises(TimingError, match="^--timing: the realistic timing law needs max_acceleration_m_s2 and "
                                          "max_jerk_m_s3; the realistic timing law needs --max-acceleration and "
                                          "--max-jerk > 0, or both in the path file$"):
        override_timing(path, "realistic", max_jerk_m_s3=50.0)


def test_a_bus_voltage_slows_the_timing_until_the_whole_phase_voltage_holds(tmp_path):
    """With a 45 V bus (26 V a phase), the sliders' back-EMF alone would exceed it at the feed: the timing
    slows down until R·I + L·dI/dt + K_e·ω holds at every sample, and on 4x denser ones."""
    def low_bus(document):
        orthoglide_motor(document)["bus_voltage_V"] = 45.0

    robot = load_robot(str(edited_copy("orthoglide", tmp_path, low_bus)))
    path = optimal(load_path("examples/rect.yaml"))
    objectives = ("energy", "cycle_time")
    fine = Evaluator(robot, path, EvaluatorSettings(objective=objectives, workers=1))
    own = fine.evaluate(PLACEMENTS)
    free = Evaluator(load_robot("orthoglide"), path, EvaluatorSettings(objective=objectives, workers=1)).evaluate(PLACEMENTS)
    voltage = [i for i, label in enumerate(own.limits) if label.startswith("drive voltage")]
    assert own.feasible.all() and len(voltage) == 3
    assert (own.values[:, 1] > free.values[:, 1]).all() and (own.values[:, 1] > 1.2 * free.values[:, 1]).any()
    assert own.margins[:, voltage].min() < 0.05  # the voltage is what binds
    check = denser(fine, 4).recheck(PLACEMENTS, fine)
    assert (check.margins >= 0).all(), dict(zip(check.limits, check.margins.min(axis=0)))
    # At the path's own feed, the paper's timing breaks the voltage limit: the bound is real.
    paper = Evaluator(robot, load_path("examples/rect.yaml"), EvaluatorSettings(workers=1)).evaluate(PLACEMENTS)
    assert (paper.margins[:, voltage].min(axis=1) < 0).any()


def test_the_command_line_times_optimally_for_cycle_time_and_writes_the_front(tmp_path, capsys):
    out = tmp_path / "front.json"
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objectives", "energy,cycle_time",
                 "--population", "24", "--generations", "12", "--json", str(out), "--quiet"]) == 0
    printed = capsys.readouterr().out
    assert "note: the objective cycle_time needs the optimal timing law" in printed and "optimal timing" in printed
    document = json.loads(out.read_text())
    values = np.array([[m["values"][name] for name in ("energy", "cycle_time")] for m in document["members"]])
    assert len(values) >= 10 and non_dominated(values).all()
    assert all(m["margin"] >= 0 for m in document["members"])
    assert document["timing"] == "optimal"


def test_cycle_time_under_another_timing_law_is_a_usage_error(capsys):
    assert main(["--robot", "orthoglide", "--path", "examples/rect.yaml", "--objective", "cycle_time",
                 "--timing", "paper"]) == 2
    assert "--timing paper: the objective cycle_time needs --timing optimal" in capsys.readouterr().err


def test_a_timing_whose_inductive_voltage_breaks_the_bus_is_reported(tmp_path):
    """L·dI/dt is checked, not timed: with a 0.2 H winding a fast small circle needs more than a 60 V bus gives."""
    def heavy_winding(document):
        motor = orthoglide_motor(document)
        motor["bus_voltage_V"], motor["inductance_H"] = 60.0, 0.2

    robot = load_robot(str(edited_copy("orthoglide", tmp_path, heavy_winding)))
    (tmp_path / "circle.yaml").write_text("units: mm\nshape: {type: circle, radius: 10}\nfeed_m_s: 0.66\n"
                                          "timing: {mode: optimal}\n")
    detail = Evaluator(robot, load_path(tmp_path / "circle.yaml"), EvaluatorSettings(workers=1)).detail(PLACEMENTS[0])
    worst = min(detail.margins, key=lambda m: m.margin)
    assert not detail.feasible and worst.kind == "drive voltage" and abs(worst.value) > worst.limit
    motor = robot.actuators[0].drive.motor
    steady = motor.resistance_ohm * detail.motor.current_A + motor.back_emf_constant_V_s_per_rad * detail.motor.speed_rad_s
    assert np.abs(steady).max() <= motor.phase_voltage_limit_V  # what the timing keeps; L·dI/dt breaks it


def test_the_speed_never_exceeds_a_move_s_feed_where_the_feed_changes_without_a_stop(tmp_path):
    """A straight G-code line whose middle move is ten times slower: one run, no stop, the slow feed held."""
    robot = load_robot(gantry(tmp_path))
    (tmp_path / "feeds.nc").write_text("G21 G90 G17\nG0 X0 Y0 Z0\nG1 X50 F6000\nG1 X60 F600\nG1 X100 F6000\n")
    (tmp_path / "feeds.yaml").write_text("shape: {type: gcode, file: feeds.nc}\ntiming: {mode: optimal}\n"
                                         "time_step_s: 0.002\n")
    path = load_path(tmp_path / "feeds.yaml")
    assert len(path.geometry().run_starts) == 2  # one run: the tool does not stop where the feed changes
    evaluator = Evaluator(robot, path, EvaluatorSettings(workers=1))
    detail = evaluator.detail(np.zeros(6))
    dense = denser(evaluator, 8)  # the timing between its samples too
    law = evaluator.batch(np.zeros((1, 6))).path_law
    samples = law.resampled(evaluator.geometry, dense.geometry).timed_samples(dense.geometry.samples, 0)
    x = samples.position_m[:, 0] - path.segments[0].start_m[0]
    slow = (x > 0.050 - 1e-9) & (x < 0.060 + 1e-9)
    assert detail.feasible and slow.sum() > 10
    assert np.linalg.norm(samples.velocity_m_s[slow], axis=1).max() <= 0.01 * (1 + 1e-9)
